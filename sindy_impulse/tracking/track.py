"""``track(surveys, reference=...)``: which surveys of a structure changed, in which mode, quantity and term.

The steps, each in its own module: the surveys' values (:mod:`.values`), the modes matched across them
(:mod:`.matching`), per mode the series of its quantities (frequency, damping ratio, and the backbone's
departure from them at a common amplitude, :mod:`.averaging`), each new value tested against the reference
and the family of tests of a survey corrected (:mod:`.statistics`), a trend over the new surveys, and for
each changed mode the term of its equation that carries the change (:mod:`.terms`).
"""

from __future__ import annotations

import math
import warnings
from numbers import Integral, Real

import numpy as np
from scipy import stats

from .._utils.params import Interval, check_param
from ..exceptions import DataWarning
from .averaging import backbone_at
from .matching import match_modes
from .result import QUANTITIES, Alarm, ModeEvent, TrackResult, Trend
from .statistics import fit_scatter, holm, mann_kendall, prediction_test
from .terms import ReferenceTerms, changed_terms, named_term
from .values import survey_values

__all__ = ["track"]

#: The fewest new surveys a trend is looked for in (Mann-Kendall's normal law needs a few).
MIN_TREND = 4
#: Fewer reference surveys than this give a warning (the t law's tail is wide with few degrees of freedom).
FEW_REFERENCE = 10
#: The series of each mode besides the quantities tested (the backbone itself at the common amplitude).
SERIES = ("backbone_frequency_hz", "backbone_damping_ratio", "amplitude")


def _reference_indices(reference, n: int) -> np.ndarray:
    if isinstance(reference, (bool, np.bool_)):
        raise TypeError("reference must be an int (the first n surveys) or a sequence of survey indices")
    if isinstance(reference, Integral):
        if not 2 <= reference <= n:
            raise ValueError(f"reference={reference}: the first n surveys, 2 <= n <= {n} (the surveys given)")
        return np.arange(int(reference))
    try:
        idx = np.asarray(list(reference))
    except TypeError:
        raise TypeError(
            f"reference must be an int or a sequence of survey indices, got {type(reference).__name__}"
        ) from None
    if idx.size < 2 or not np.issubdtype(idx.dtype, np.integer):
        raise ValueError("reference must name at least 2 surveys by their integer indices")
    idx = np.where(idx < 0, idx + n, idx)
    if idx.min() < 0 or idx.max() >= n or np.unique(idx).size != idx.size:
        raise ValueError(
            f"reference indices must be distinct and within the {n} surveys, got {list(reference)}"
        )
    return np.sort(idx)


def _series(values, slot: np.ndarray, amplitudes: np.ndarray) -> dict:
    """Per quantity, the arrays (n_surveys, n_tracks) of values and ± (NaN where a survey lacks the mode)."""
    n_s, n_t = slot.shape
    out = {q: np.full((n_s, n_t), np.nan) for q in QUANTITIES + SERIES}
    std = {q: np.full((n_s, n_t), np.nan) for q in QUANTITIES + SERIES}
    proxy = np.full((n_s, n_t), np.nan)
    for s, j in zip(*np.nonzero(slot >= 0)):
        m = values[s].modes[slot[s, j]]
        point = backbone_at(m, amplitudes[j])
        for q, v, e in (
            ("frequency_hz", m.frequency_hz, m.frequency_std_hz),
            ("damping_ratio", m.damping_ratio, m.damping_ratio_std),
            ("backbone_frequency_shift_hz", point.frequency_shift_hz, point.frequency_shift_std_hz),
            ("backbone_damping_shift", point.damping_shift, point.damping_shift_std),
            ("backbone_frequency_hz", point.frequency_hz, point.frequency_std_hz),
            ("backbone_damping_ratio", point.damping_ratio, point.damping_ratio_std),
            ("amplitude", m.amplitude, math.nan),
        ):
            out[q][s, j], std[q][s, j] = v, e
        proxy[s, j] = 10 ** (-m.snr_db / 20) if math.isfinite(m.snr_db) else math.nan
    return {"value": out, "std": std, "proxy": proxy}


def _tests(series: dict, ref_idx, testable) -> tuple:
    """Per quantity and track: the reference fit, and T and p for every survey (n_s, n_t)."""
    value, std, proxy = series["value"], series["std"], series["proxy"]
    n_s, n_t = proxy.shape
    fits = {}
    t = {q: np.full((n_s, n_t), np.nan) for q in QUANTITIES}
    p = {q: np.full((n_s, n_t), np.nan) for q in QUANTITIES}
    for q in QUANTITIES:
        for j in np.flatnonzero(testable):
            ref = fit_scatter(value[q][ref_idx, j], std[q][ref_idx, j], proxy[ref_idx, j])
            fits[q, j] = ref
            if ref is None:
                continue
            t[q][:, j], p[q][:, j] = prediction_test(ref, value[q][:, j], std[q][:, j], proxy[:, j])
    return fits, t, p


def _trends(series: dict, new_idx, testable, alpha: float) -> list:
    """Mann-Kendall over the new surveys per track and quantity, Holm-corrected over them all."""
    if len(new_idx) < MIN_TREND:
        return []
    rows = []
    for j in np.flatnonzero(testable):
        for q in QUANTITIES:
            x = series["value"][q][new_idx, j]
            z, p = mann_kendall(x)
            rows.append((int(j), q, z, p, _theil_sen(x)))
    flags = holm(np.array([[r[3] for r in rows]]), alpha)[0] if rows else []
    return [Trend(j, q, z, p, bool(f), slope) for (j, q, z, p, slope), f in zip(rows, flags)]


def _mode_events(tracks, slot, ref_idx, new_idx, alpha: float) -> list:
    """Modes found less often in the new surveys than in the reference (those the reference found in at
    least half its surveys), or appeared: Fisher's exact test, one-sided, Holm over them."""
    rows = []
    for j, tr in enumerate(tracks):
        a, c = int((slot[ref_idx, j] >= 0).sum()), int((slot[new_idx, j] >= 0).sum())
        n, m = len(ref_idx), len(new_idx)
        if m and tr.in_reference and 2 * a >= n and c * n < a * m:
            rows.append((j, "vanished", a, c, stats.fisher_exact([[a, n - a], [c, m - c]], "greater")[1]))
        elif m and not tr.in_reference and c:
            rows.append((j, "appeared", a, c, stats.fisher_exact([[a, n - a], [c, m - c]], "less")[1]))
    flags = holm(np.array([[r[4] for r in rows]]), alpha)[0] if rows else []
    return [ModeEvent(j, kind, a, len(ref_idx), c, len(new_idx), float(p), bool(f))
            for (j, kind, a, c, p), f in zip(rows, flags)]


def _theil_sen(x) -> float:
    """Median slope per survey of a sequence (NaN values left out, their places kept)."""
    k = np.flatnonzero(np.isfinite(x))
    if k.size < 2:
        return math.nan
    i, j = np.triu_indices(k.size, 1)
    return float(np.median((x[k[j]] - x[k[i]]) / (k[j] - k[i])))


def _alarms(values, slot, series, tests, flags, new_idx, ref_idx, alpha) -> list:
    """One :class:`Alarm` per changed (survey, mode), with the term that carries the change; the terms of
    every changed survey of a mode tested together."""
    _, t, p = tests
    out = []
    for j in np.flatnonzero(flags[new_idx].any(axis=(0, 2))):
        changed = [s for s in new_idx if flags[s, j].any()]
        reference = ReferenceTerms([values[r].modes[slot[r, j]] for r in ref_idx if slot[r, j] >= 0])
        news = [values[s].modes[slot[s, j]] for s in changed]
        for s, new, changes in zip(changed, news, changed_terms(reference, news, alpha)):
            hits = [q for k, q in enumerate(QUANTITIES) if flags[s, j, k]]
            lead = min(hits, key=lambda q: p[q][s, j])
            term, significant = named_term(changes, "damping" if "damping" in lead else "frequency")
            out.append(
                Alarm(
                    int(s),
                    int(j),
                    lead,
                    hits,
                    float(series["value"][lead][s, j]),
                    float(t[lead][s, j]),
                    float(p[lead][s, j]),
                    changes,
                    term,
                    significant,
                    new.frequency_hz,
                    new.damping_ratio,
                    new.amplitude,
                )
            )
    return sorted(out, key=lambda a: (a.survey, a.mode))


def track(
    surveys,
    reference,
    *,
    alpha: float = 0.01,
    labels=None,
    amplitude: float | None = None,
    frequency_tolerance: float = 0.03,
    min_mac: float = 0.8,
    min_reference: int = 5,
) -> TrackResult:
    """Many tests of one structure: which surveys changed beyond their uncertainty, in which mode, which
    quantity and which term of the mode's equation.

    Parameters
    ----------
    surveys : sequence
        One survey per test, in their order (what :func:`~sindy_impulse.identify_modes` or
        :func:`~sindy_impulse.survey_many` return, failed records included, or
        :class:`~sindy_impulse.tracking.SurveyValues`).
    reference : int or sequence of int
        The state to compare with: the first ``reference`` surveys, or their indices. The other surveys
        are the new ones, tested in order.
    alpha : float, default=0.01
        The false-alarm rate: the chance that a survey of the unchanged structure is flagged (every mode
        and quantity of it together), and that a trend is reported where there is none.
    labels : sequence of str, optional
        A name per survey (a file, a date); default the surveys' own, else ``"survey <i>"``.
    amplitude : float, optional
        The amplitude (sensor units) at which the backbones are compared; default per mode the median
        of its reference hits' amplitudes.
    frequency_tolerance : float, default=0.03
        Largest relative frequency difference of two modes matched as the same mode (``|ln(f1 / f2)|``:
        0.03 is 3 %; 1.0 follows a mode whose frequency moved by up to a factor e).
    min_mac : float, default=0.8
        Smallest MAC of two modes matched as the same, where both have a shape.
    min_reference : int, default=5
        A mode found in fewer reference surveys is followed but not tested.

    Returns
    -------
    TrackResult
        ``changed`` (one bool per survey), ``alarms``, ``trends``, ``to_frame()``, ``plot()``,
        ``to_html()``.

    Examples
    --------
    >>> from sindy_impulse.tracking import ModeValues, SurveyValues
    >>> rng = np.random.default_rng(0)
    >>> def test(f):
    ...     f = f * (1 + 3e-4 * rng.standard_normal())
    ...     zeta = 0.01 * (1 + 0.01 * rng.standard_normal())
    ...     return SurveyValues([ModeValues(f, 1e-3, zeta, 1e-4, amplitude=1.0, snr_db=40.0)])
    >>> surveys = [test(100.0) for _ in range(20)] + [test(100.0), test(99.75), test(99.75)]
    >>> result = track(surveys, reference=20)
    >>> result.changed[20:].tolist()
    [False, True, True]
    >>> print(result.alarms[0].text(result))  # doctest: +NORMALIZE_WHITESPACE
    survey 21: mode 0 (99.985 Hz) changed: frequency -0.202 % (t = -7.8, p = 3.5e-07); the linear
    stiffness changed (-0.403 % ± 0.002 %): -0.202 % frequency at the hit's amplitude; the linear damping
    unchanged
    """
    check_param("alpha", alpha, [Interval(Real, 0, 0.5, "neither")], "track")
    check_param("frequency_tolerance", frequency_tolerance, [Interval(Real, 0, None, "neither")], "track")
    check_param("min_mac", min_mac, [Interval(Real, 0, 1, "both")], "track")
    check_param("min_reference", min_reference, [Interval(Integral, 2, None, "left")], "track")
    check_param("amplitude", amplitude, [None, Interval(Real, 0, None, "neither")], "track")
    surveys = list(surveys)
    if labels is not None and len(labels) != len(surveys):
        raise ValueError(f"labels has {len(labels)} entries for {len(surveys)} surveys")
    values = [survey_values(s, str(labels[i]) if labels is not None else "") for i, s in enumerate(surveys)]
    values = [v if v.label else type(v)(v.modes, f"survey {i}", v.failed) for i, v in enumerate(values)]
    ref_idx = _reference_indices(reference, len(values))
    if ref_idx.size < FEW_REFERENCE:
        _warn_few(ref_idx.size)
    new_idx = np.array([i for i in range(len(values)) if i not in set(ref_idx.tolist())], dtype=int)
    tracks, slot = match_modes(values, ref_idx, frequency_tolerance, min_mac)
    in_ref = (slot[ref_idx] >= 0).sum(axis=0)
    testable = np.array([tr.in_reference for tr in tracks], dtype=bool) & (in_ref >= min_reference)
    amplitudes = _common_amplitudes(values, slot, ref_idx, amplitude)
    series = _series(values, slot, amplitudes)
    tests = _tests(series, ref_idx, testable)
    p = np.stack([tests[2][q] for q in QUANTITIES], axis=2)  # (n_s, n_t, n_q)
    flags = np.zeros(p.shape, bool)
    if new_idx.size:
        flat = holm(p[new_idx].reshape(new_idx.size, -1), alpha)
        flags[new_idx] = flat.reshape(new_idx.size, *p.shape[1:])
    alarms = _alarms(values, slot, series, tests, flags, new_idx, ref_idx, alpha)
    trends = _trends(series, new_idx, testable, alpha)
    events = _mode_events(tracks, slot, ref_idx, new_idx, alpha)
    return TrackResult(values, ref_idx, new_idx, tracks, slot, testable, amplitudes, series, tests, flags,
                       alarms, trends, alpha, events)


def _warn_few(n: int) -> None:
    warnings.warn(
        f"the reference has {n} surveys: its scatter is estimated with {n - 1} degrees of freedom, so a "
        "change is flagged only when it is several times that scatter; 10-20 reference surveys make the "
        "tests much more sensitive",
        DataWarning,
        stacklevel=3,
    )


def _common_amplitudes(values, slot, ref_idx, amplitude) -> np.ndarray:
    """Per track, the amplitude its backbone is compared at."""
    out = np.full(slot.shape[1], np.nan)
    for j in range(slot.shape[1]):
        rows = ref_idx if np.any(slot[ref_idx, j] >= 0) else np.arange(slot.shape[0])
        amps = [values[s].modes[slot[s, j]].amplitude for s in rows if slot[s, j] >= 0]
        amps = [a for a in amps if math.isfinite(a) and a > 0]
        out[j] = amplitude if amplitude is not None else (float(np.median(amps)) if amps else math.nan)
    return out

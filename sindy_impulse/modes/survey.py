"""A raw hammer-test record in, a modal table out: :func:`identify_modes`.

For each record (one hit; several sensors allowed): :func:`~sindy_impulse.preprocessing.preprocess` finds
the impact, removes the offset, picks the spectral peaks and extracts one band-passed, decimated signal per
peak; each band becomes one mode by the paper's machinery (:func:`.band_fit.fit_band`: derivative coordinates,
TVRegDiff, the threshold sweep scored on the simulation error -- segment-wise for long records -- and the
bounded refinement); the mode's frequency and damping ratio come from the identified model's linear part.
Peaks too close for their damping (``Preprocessed.groups``) are also fitted jointly in their group's band
(:func:`.band_fit.fit_group`); a joint mode that agrees with its peak's fitted damped sinusoid replaces the
peak's own-band result when that gave no mode or one that agrees less. A peak still without a mode that
agrees with its sinusoid is fitted once more on the record with the other peaks' sinusoids subtracted, in a
wide band (:func:`~sindy_impulse.preprocessing.deflation.deflated_band`; :func:`_deflated`). A band the
band-pass transient leaves too few periods of (a short, strongly damped record), alone and jointly with its
neighbour, is identified without band-pass from the stable pole of the stabilisation diagram inside it, the
other stable modes removed (:mod:`._short`); no stable pole, no mode. A group of
close peaks that one nonlinear oscillator reproduces better is one nonlinear mode (:mod:`._nonlinear`), and a
mode near 2 or 3 times another that is phase-locked to it, its amplitude a power (2 or 3) of the other's, is
that mode's harmonic (:mod:`._harmonics`: decided on the record, not on a model). A weak mode whose band
equation disagrees with its stable pole within the equation's own standard deviations reports the pole's
frequency and damping ratio, and a stable pole left in a refused band is fitted once more on its deflated
band (:mod:`._weak`).
Repeated hits of one structure are matched by frequency and combined by the paper's consensus (section
3.3.2).
"""

from __future__ import annotations

import warnings
from dataclasses import replace
from numbers import Integral, Real

import numpy as np

from .._utils.params import HasMethods, Interval, Options, check_param
from .._utils.validation import check_signal
from ..exceptions import DataWarning, NoDynamicsWarning
from ..preprocessing import extract_band, preprocess
from ..preprocessing.deflation import deflated_band
from ..preprocessing.stable_poles import with_stable_poles
from ._clipped import clipping_report
from ._envelope import small_amplitude_damping
from ._harmonics import split_harmonics
from ._hits import merge_hits
from ._nonlinear import has_nonlinear_terms, merge_chirps
from ._short import MODE_POLE_AGREEMENT, checked_by_poles, from_stable_poles, short_from_poles, stable_modes
from ._short import disagreement as _disagreement
from ._weak import pole_values, refused_by_poles
from .band_fit import default_estimator, fit_band, fit_direct, fit_group
from .result import ModalSurvey, Mode, Rejected, pole_table

__all__ = ["check_options", "identify_modes"]

_SENSORS = Options({"displacement", "velocity", "acceleration"})


def _records(y, force) -> tuple[list[np.ndarray], list]:
    """One (n_samples, n_channels) array per hit, and the force of each (or None)."""
    many = isinstance(y, (list, tuple)) and len(y) > 0 and all(hasattr(r, "shape") for r in y)
    ys = list(y) if many else [y]
    arrays = [check_signal(r, "y" if not many else f"y[{i}]", ndim=(1, 2)) for i, r in enumerate(ys)]
    if force is None:
        return arrays, [None] * len(arrays)
    forces = list(force) if many else [force]
    if len(forces) != len(arrays):
        raise ValueError(f"force has {len(forces)} records but y has {len(arrays)}")
    checked = []
    for i, (f, r) in enumerate(zip(forces, arrays)):
        f = check_signal(f, "force" if not many else f"force[{i}]", ndim=(1, 2), as_2d=False).reshape(-1)
        if f.size != r.shape[0]:
            raise ValueError(f"force has {f.size} samples but y has {r.shape[0]}")
        checked.append(f)
    return arrays, checked


def _times(t, n_records: int):
    if isinstance(t, (list, tuple)) and len(t) == n_records and n_records > 1 and np.ndim(t[0]) == 1:
        return list(t)
    return [t] * n_records


def _reference_channel(record: np.ndarray, channel) -> int:
    if channel is not None:
        check_param("channel", channel, [Interval(Integral, 0, record.shape[1] - 1)], "identify_modes")
        return int(channel)
    centred = record - np.median(record, axis=0)
    return int(np.argmax(np.sqrt(np.mean(centred**2, axis=0))))


def _impulse(force, pre) -> float | None:
    """Impulse of the hammer (N s): the force integrated over the hit's pulses."""
    if force is None or not pre.impact.hits:
        return None
    lo, hi = pre.impact.onset_index, pre.impact.ringdown_index
    return float(np.sum(force[lo : hi + 1]) / pre.fs)


def _first_periods(band, max_periods):
    """The band signal's first ``max_periods`` periods of its centre frequency (all of it for None)."""
    keep = None if max_periods is None else int(np.ceil(max_periods * band.samples_per_period))
    if keep is None or keep >= band.y.size:
        return band
    stop = band.start_index + int(np.ceil(keep * band.decimation / band.upsampling))
    return replace(
        band,
        y=band.y[:keep],
        t=band.t[:keep],
        envelope=band.envelope[:keep],
        stop_index=stop,
        trimmed_end=band.trimmed_end + (band.stop_index - stop),
        end_reason="max_periods",
    )


def _survey_record(index, record, t, fs, force, options, template, sensor, channel, max_periods):
    """Preprocess one hit (its spectral peaks completed by the stable poles of its stabilisation diagram,
    :func:`~sindy_impulse.preprocessing.stable_poles.with_stable_poles`) and fit every band:
    (modes, rejected, preprocessed, notes, pole table).

    A problem of the input (preprocessing refuses it) raises its clear error; a failure of the
    identification after that becomes one :class:`Rejected` row of the record (no band), with the error as
    its evidence, so the other records of a survey stand.
    """
    ref = _reference_channel(record, channel)
    pre = preprocess(record[:, ref], t, fs=fs, force=force, **options)
    table = pole_table(pre)
    pre, found = with_stable_poles(pre, table.modes(), len(table.orders),
                                   samples_per_period=options["samples_per_period"])
    notes = [f"record {index}: {note}" for note in found]
    clipped, products = clipping_report(pre, index)
    notes += clipped
    if pre.impact.double_hit:
        notes.append(f"record {index}: double hit at {', '.join(f'{h[0]:.4g} s' for h in pre.impact.hits)}")
    try:
        modes, rejected, found = _fit_record(index, record, pre, force, template, sensor, ref, max_periods,
                                             options["samples_per_period"], table)
    except Exception as err:  # noqa: BLE001 - one record's failure must not abort the survey
        evidence = {"error": type(err).__name__, "message": str(err)}
        reason = f"the identification of record {index} failed ({type(err).__name__}: {err})"
        return [], [Rejected(None, reason, index, evidence)] + products, pre, notes, table
    return modes, rejected + products, pre, notes + found, table


def _fit_record(index, record, pre, force, template, sensor, ref, max_periods, samples_per_period, table):
    """Every band of a preprocessed hit fitted: (modes, rejected, notes)."""
    impulse = _impulse(force, pre)
    if len(pre.peaks) == 0:
        return from_stable_poles(index, pre, template, table)
    if len(pre.peaks) == 1 and not pre.bands:  # one mode the band-pass cannot keep: strongly damped, short
        return _single_short(index, pre, template, table)
    modes, rejected = [], []
    resampled = [
        f"record {index}: band {b.band_hz[0]:.4g}-{b.band_hz[1]:.4g} Hz has "
        f"{b.samples_per_period / b.upsampling:.3g} samples per period at fs; its signal was resampled "
        f"x{b.upsampling} (the model is fitted at {b.fs:.6g} Hz)"
        for b in pre.bands
        if b.upsampling > 1
    ]
    for band in (_first_periods(b, max_periods) for b in pre.bands):
        out = fit_band(
            band,
            template,
            onset_time=pre.impact.onset_time,
            record=record,
            channel=ref,
            impulse=impulse,
            sensor=sensor,
            index=index,
        )
        (modes if not isinstance(out, Rejected) else rejected).append(out)
    grouped = _grouped(pre, {m.band_hz: m for m in modes}, template, index)
    modes = [m for m in modes if m.band_hz not in grouped] + list(grouped.values())
    rejected = [r for r in rejected if r.band_hz not in grouped]
    short = []
    for skipped, why in pre.skipped:
        if tuple(skipped) in grouped:
            continue
        out = _joint(pre, tuple(skipped), template, index) if "periods remain" in why else None
        if isinstance(out, Mode):
            modes.append(out)
        elif "periods remain" in why:
            short.append((tuple(skipped), out.reason if isinstance(out, Rejected) else why))
        else:
            rejected.append(out if isinstance(out, Rejected) else Rejected(tuple(skipped), why, index))
    found, refused, notes = short_from_poles(pre, short, template, index, table)
    modes, rejected = modes + found, rejected + refused
    modes, rejected = _deflated(pre, modes, rejected, template, index, samples_per_period)
    modes, rejected, checked = checked_by_poles(pre, modes, rejected, template, index, table)
    fit_options = dict(template=template, onset_time=pre.impact.onset_time, record=record, channel=ref,
                       impulse=impulse, sensor=sensor, index=index)
    modes, rejected, merged = merge_chirps(pre, modes, rejected, fit_options,
                                           lambda band: _first_periods(band, max_periods))
    modes, damping = small_amplitude_damping(modes)
    modes, rejected, harmonics = split_harmonics(pre, modes, rejected)
    modes, rejected, refused = refused_by_poles(pre, modes, rejected, template, index, table,
                                                samples_per_period)
    modes, weak = pole_values(modes, table, index)
    return modes, rejected, resampled + notes + checked + merged + damping + harmonics + refused + weak


#: Largest disagreement (:func:`_disagreement`) of a jointly fitted mode with its peak's damped sinusoid.
_AGREEMENT = 0.5


def _single_short(index, pre, template, table):
    """The only peak of a record whose band the band-pass cannot keep (strongly damped, short). A record
    of one stable mode (the paper's oscillator) takes the paper's single-sensor route
    (:func:`.band_fit.fit_direct`) first; a record of several stable modes with one inside the peak's band
    is identified from them on the free decay first (:func:`._short.short_from_poles`: no adaptive
    simulation). The other route is tried when the first gives no mode or, for the direct fit, one that
    disagrees with the stable pole inside the band (:func:`._short.disagreement` over
    :data:`._short.MODE_POLE_AGREEMENT`). (modes, rejected, notes)."""
    band = tuple(pre.peaks.band_hz[0])
    stable = stable_modes(table)
    inside = [m for m in stable if band[0] <= m.frequency_hz <= band[1]]
    short = None
    if inside and len(stable) > 1:
        short = short_from_poles(pre, [(band, "the band-pass transient leaves too few periods")], template,
                                 index, table)
        if short[0]:
            return short
    out = fit_direct(pre, band, template, index=index)
    agrees = isinstance(out, Mode) and any(
        _disagreement(out, m.frequency_hz * np.sqrt(1 - m.damping_ratio**2), m.damping_ratio)
        <= MODE_POLE_AGREEMENT for m in inside)
    if agrees or (isinstance(out, Mode) and not inside):
        return [out], [], []
    if short is not None or not inside:
        return short or ([], [out], [])
    why = out.reason if isinstance(out, Rejected) else (
        f"its direct fit ({out.frequency_hz:.4g} Hz) disagrees with the stable pole")
    return short_from_poles(pre, [(band, why)], template, index, table)


def _grouped(pre, own: dict, template, index: int) -> dict:
    """Peaks of each group too close for their damping (``pre.groups``) fitted jointly in the group's band
    (:func:`.band_fit.fit_group`): {own band: Mode} where the joint mode agrees with the peak's fitted damped
    sinusoid (``pre.peaks``; :func:`_disagreement` at most ``_AGREEMENT``) and better than the mode of its
    own band (``own``: {own band: Mode}), or the own band gave none. An own-band mode with nonlinear terms
    that fits its band better than the joint model stays (e.g. a nonlinear mode grouped with the broad
    peak of its own third harmonic)."""
    found = {}
    for group, band in pre.groups:
        members = [tuple(pre.peaks.band_hz[i]) for i in group]
        joint = fit_group(band, members, template, onset_time=pre.impact.onset_time, index=index)
        for i, b, out in zip(group, members, joint):
            f, zeta = pre.peaks.frequency_hz[i], pre.peaks.damping_ratio[i]
            if not isinstance(out, Mode) or not _disagreement(out, f, zeta) <= _AGREEMENT:
                continue
            if b in own and has_nonlinear_terms(own[b].model) and own[b].fit_error < out.fit_error:
                continue  # a nonlinear mode (its sinusoid is a poor yardstick) better fitted in its own band
            if b not in own or _disagreement(out, f, zeta) < _disagreement(own[b], f, zeta):
                found[b] = out
    return found


#: A mode within this :func:`_disagreement` of its peak's damped sinusoid is not fitted again on the
#: deflated record.
_AGREES = 0.1


def _deflated(pre, modes: list, rejected: list, template, index: int, samples_per_period: float):
    """Peaks without a mode close to their fitted damped sinusoid (:func:`_disagreement` over ``_AGREES``)
    fitted again on the record with the other peaks removed
    (:func:`~sindy_impulse.preprocessing.deflation.deflated_band`: a wide band, so a short filter
    transient, for a strongly damped mode next to lightly damped ones; never narrower than the peak's own
    band, whose transient already costs the largest amplitudes, where an amplitude-dependent damping shows
    most: an x^2 x' damper refitted in a 10 % band instead of its own 21 % kept 0.58 of them, not 0.92).
    That mode replaces the peak's
    (the modes nearest the peak in frequency) when it agrees with the peak's sinusoid within
    ``_AGREEMENT`` and better; the peak's rejections are then dropped."""
    f, zeta = pre.peaks.frequency_hz, pre.peaks.damping_ratio
    if len(f) < 2:
        return modes, rejected
    nearest = [int(np.argmin(np.abs(np.log(f / m.damped_frequency_hz)))) for m in modes]
    for i in np.flatnonzero(np.isfinite(zeta)):  # (bands given by the user: no sinusoid to agree with)
        mine = [m for m, k in zip(modes, nearest) if k == i]
        best = min((_disagreement(m, f[i], zeta[i]) for m in mine), default=np.inf)
        if best <= _AGREES:
            continue
        try:
            own = pre.peaks.band_hz[i][1] / f[i] - 1  # never narrower than the peak's own band
            band = deflated_band(pre, i, samples_per_period=samples_per_period, min_width=max(own, 0.1))
        except ValueError:  # too few periods above the noise: the peak keeps what it had
            continue
        out = fit_band(band, template, onset_time=pre.impact.onset_time, index=index)
        if not isinstance(out, Mode) or not _disagreement(out, f[i], zeta[i]) < min(best, _AGREEMENT):
            continue
        keep = [j for j, m in enumerate(modes) if all(m is not x for x in mine)]
        modes, nearest = [modes[j] for j in keep] + [out], [nearest[j] for j in keep] + [i]
        rejected = [r for r in rejected if tuple(r.band_hz) != tuple(pre.peaks.band_hz[i])]
    return modes, rejected


def _joint(pre, skipped: tuple, template, index: int):
    """A peak whose own band is too narrow for its damping, fitted jointly with its closest neighbour in
    one wide band holding both (see :func:`.band_fit.fit_group`); None when it has no neighbour.

    The joint band reaches out to the geometric midpoints towards the next peaks outside the pair: the
    wider the band, the shorter the band-pass transient that would otherwise swallow a strongly damped mode.
    """
    bands = sorted((tuple(b) for b in pre.peaks.band_hz), key=lambda b: b[0])
    centres = [float(np.sqrt(b[0] * b[1])) for b in bands]
    k = bands.index(skipped)
    if len(bands) < 2:
        return None
    j = min(
        (i for i in (k - 1, k + 1) if 0 <= i < len(bands)), key=lambda i: abs(np.log(centres[i] / centres[k]))
    )
    lo_i, hi_i = min(j, k), max(j, k)
    low = np.sqrt(centres[lo_i] * centres[lo_i - 1]) if lo_i > 0 else 0.5 * centres[lo_i]
    high = np.sqrt(centres[hi_i] * centres[hi_i + 1]) if hi_i + 1 < len(bands) else 2.0 * centres[hi_i]
    joint = (float(low), float(min(high, 0.45 * pre.fs)))
    try:
        band = extract_band(pre.y, pre.fs, joint, start=pre.impact.ringdown_index, t0=pre.t0)
    except ValueError as err:
        return Rejected(skipped, f"jointly with its neighbour: {err}", index)
    return fit_group(band, [skipped, bands[j]], template, onset_time=pre.impact.onset_time, index=index)[0]


def check_options(sensor=None, estimator=None, max_periods=200.0) -> None:
    """The checks of :func:`identify_modes`' options that concern no record (a batch runs them once,
    before any record: :func:`~sindy_impulse.modes.batch.survey_many`).

    Examples
    --------
    >>> check_options(sensor="acceleration")
    >>> try:
    ...     check_options(sensor="laser")
    ... except ValueError as err:
    ...     print(str(err)[:40])
    identify_modes: sensor must be None or o
    """
    check_param("sensor", sensor, [None, _SENSORS], "identify_modes")
    check_param("estimator", estimator, [None, HasMethods("fit", "an ImpulseSINDy")], "identify_modes")
    check_param("max_periods", max_periods, [None, Interval(Real, 10, None)], "identify_modes")


def identify_modes(
    y,
    t=None,
    *,
    fs: float | None = None,
    force=None,
    n_modes: int | None = None,
    bands=None,
    sensor: str | None = None,
    estimator=None,
    channel: int | None = None,
    onset="auto",
    offset="auto",
    samples_per_period: float = 16.0,
    max_periods: float | None = 200.0,
) -> ModalSurvey:
    """Identify the modes of a hammer-test record: a modal table with one equation per mode.

    Parameters
    ----------
    y : array-like (n_samples,) or (n_samples, n_channels), or a list of them
        One record (several synchronous sensors allowed), or a list of records (repeated hits of the same
        test, combined by consensus). Raw: pre-trigger, offset and all modes included.
    t : array-like (n_samples,) or float, optional
        Time vector (uniform) or step (a list of vectors for several records); or give ``fs``.
    fs : float, optional
        Sampling rate (Hz).
    force : array-like (n_samples,) or list, optional
        The hammer's force: the onset and the end of contact come from it, double hits are reported, and
        with ``sensor`` the driving-point residues are computed.
    n_modes : int, optional
        Keep the ``n_modes`` strongest spectral peaks.
    bands : sequence of (low_hz, high_hz), optional
        The bands to identify, instead of the detected peaks' bands.
    sensor : {"displacement", "velocity", "acceleration"}, optional
        The kind of sensor (for the residues).
    estimator : ImpulseSINDy, optional
        Template of the per-mode identification (cloned per mode); default: a cubic polynomial library on
        the states ``[y, dy]`` (see :func:`~sindy_impulse.modes.band_fit.default_estimator`).
    channel : int, optional
        Reference channel (peaks and bands are found on it); default: the strongest.
    onset, offset, samples_per_period
        Passed to :func:`~sindy_impulse.preprocessing.preprocess` (every automatic choice can be
        overridden).
    max_periods : float or None, default=200
        Each mode is identified on the first ``max_periods`` periods of its band signal (the strongest
        part of the ring-down; None: all of it). 200 periods resolve the frequency and the damping ratio
        well inside the marks of ``benchmarks/accuracy/modes.py`` and bound the cost of long records.

    Returns
    -------
    ModalSurvey
        ``.modes`` (sorted by frequency), ``.table()``, ``.plot()``, ``.rejected``, ``.preprocessing``.

    Examples
    --------
    >>> from sindy_impulse import identify_modes, impact_record
    >>> rec = impact_record([120.0, 240.0], [0.005, 0.01], fs=5000, duration=1.0, snr_db=50, random_state=0)
    >>> survey = identify_modes(rec.y, fs=rec.fs)
    >>> [round(m.frequency_hz, 1) for m in survey.modes], [round(m.damping_ratio, 3) for m in survey.modes]
    ([120.0, 240.0], [0.005, 0.01])
    """
    check_options(sensor=sensor, estimator=estimator, max_periods=max_periods)
    records, forces = _records(y, force)
    options = {
        "n_modes": n_modes,
        "bands": bands,
        "onset": onset,
        "offset": offset,
        "samples_per_period": samples_per_period,
    }
    template = default_estimator() if estimator is None else estimator
    per_record, rejected, preps, notes, tables = [], [], [], [], []
    for i, (record, ti, fi) in enumerate(zip(records, _times(t, len(records)), forces)):
        modes, rej, pre, note, table = _survey_record(
            i, record, ti, fs, fi, options, template, sensor, channel, max_periods
        )
        tables.append(table)
        per_record.append(modes)
        rejected += rej
        preps.append(pre)
        notes += note
    modes = merge_hits(per_record) if len(records) > 1 else per_record[0]
    modes.sort(key=lambda m: m.frequency_hz)
    for note in notes:
        warnings.warn(note, DataWarning, stacklevel=2)
    notes += [
        f"mode at {m.frequency_hz:.6g} Hz: no standard deviation from the fit ({m.uncertainty_note})"
        for m in modes
        if m.uncertainty_note
    ]
    if not modes:
        warnings.warn(
            "no mode found: "
            + ("; ".join(r.reason for r in rejected) or "no ring-down in the record")
            + " (check the sensor, the sampling rate fs, or give bands=)",
            NoDynamicsWarning,
            stacklevel=2,
        )
    survey = ModalSurvey(modes, rejected, preps, notes)
    survey.__dict__["poles"] = tables  # computed once: survey.poles reads them
    return survey

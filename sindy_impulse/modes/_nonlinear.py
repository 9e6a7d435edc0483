"""A nonlinear mode seen as several spectral peaks: one mode.

The spectrum of a strongly nonlinear ring-down is not one peak per mode. A hardening spring whose frequency
falls by 2-4 % along the decay smears its peak over that range, and the damped-sinusoid refinement of the
peaks splits it in two (e.g. 159.3 and 161.7 Hz for a 158.6 Hz mode); its odd harmonics (3 f) stand out as
peaks of their own. A linear model per peak then reports two close linear modes and a "mode" at 3 f, all
looking right and all wrong (measured: 3 of 20 hammer tests of ``benchmarks/accuracy/model_backbone.py``'s
cubic row before this step).

- :func:`merge_chirps`: each group of close peaks (``Preprocessed.groups``) is also fitted as *one*
  oscillator with the mode template (``[y, dy]``, cubic library) on the group's band. When that model
  carries a nonlinear term and reproduces the band better (a smaller fit error) than the modes found in the
  band, or better than the worst of them with every one on its backbone (:func:`_on_its_backbone`), the
  peaks are one nonlinear mode: it replaces them. Two linear modes that close beat, which no
  single two-state oscillator can reproduce, so they keep their joint fit.

Its harmonics are named on the data (phase locking and amplitude exponent): :mod:`._harmonics`.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..feature_library.terms import term_table
from ..preprocessing.band import extract_band
from ..preprocessing.partition import at_harmonic_place, resolved
from .band_fit import fit_band
from .result import Mode

__all__ = ["merge_chirps", "has_nonlinear_terms"]


def has_nonlinear_terms(model) -> bool:
    """Whether the fitted model uses a term other than the states themselves (False if unknown)."""
    try:
        coef = np.asarray(model.coefficients())
        library = getattr(model, "feature_library_", None) or model.feature_library
        terms = term_table(library, coef.shape[0])
    except (AttributeError, TypeError, ValueError):
        return False
    return bool(np.any(coef[:, ~terms.linear]))


#: Least relative margin around the one oscillator's backbone within which a mode of the group lies on it
#: (else its own damping ratio: its half-power half-width).
_BACKBONE_MARGIN = 0.005


def _on_its_backbone(single, inside: list) -> bool:
    """Whether every mode of ``inside`` lies on the frequency range of ``single``'s backbone (within its
    own damping ratio, at least :data:`_BACKBONE_MARGIN`): the pieces of one chirp. Fit errors of modes
    fitted on bands of their own are no yardstick then: family (e) record 45 of
    ``benchmarks/accuracy/modes.py``, a hardening mode falling from 212 to 206.9 Hz, came out as three linear
    modes (206.9, 208.3, 212.1 Hz), one of them fitted on a 4 Hz band over 34 periods (fit error 0.004);
    the one oscillator on the group's band (a cubic spring, 0.014) passes through all three."""
    from ..analysis import backbone

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            f = backbone(single.model, coordinate=single.coordinate_).frequency_hz
    except (ValueError, AttributeError, ArithmeticError, np.linalg.LinAlgError):
        return False  # no backbone: no evidence of one chirp
    f = f[np.isfinite(f)]
    if not f.size:
        return False
    margins = [max(_BACKBONE_MARGIN, m.damping_ratio) for m in inside]
    return all(f.min() * (1 - e) <= m.frequency_hz <= f.max() * (1 + e) for m, e in zip(inside, margins))


def merge_chirps(pre, modes: list, rejected: list, fit_options: dict, first_periods) -> tuple:
    """Groups of close peaks, and clusters of modes closer than half their half-power bandwidth
    (:func:`_clusters`), that are one nonlinear mode (module docstring): ``(modes, rejected, notes)``.

    ``fit_options`` are passed to :func:`.band_fit.fit_band` (template, onset time, record, ...);
    ``first_periods(band)`` cuts a band signal to the periods a mode is identified on.
    """
    notes = []
    for group, band in pre.groups:
        modes, rejected, single = _merged(band, modes, rejected, fit_options, first_periods)
        if single is not None:
            modes, single = _refitted(pre, group, band, modes, single, fit_options, first_periods)
            peaks = ", ".join(f"{pre.peaks.frequency_hz[i]:.4g}" for i in group)
            notes.append(
                f"record {single.record}: the peaks at {peaks} Hz are one nonlinear mode at "
                f"{single.frequency_hz:.4g} Hz (its frequency changes with amplitude: see its backbone), not "
                f"{len(group)} modes"
            )
    for cluster in _clusters(modes):
        try:
            band = extract_band(pre.y, pre.fs, _cluster_band(cluster, modes, pre.fs),
                                start=pre.impact.ringdown_index, t0=pre.t0)
        except ValueError:
            continue
        modes, rejected, single = _merged(band, modes, rejected, fit_options, first_periods)
        if single is not None:
            found = ", ".join(f"{m.frequency_hz:.5g}" for m in cluster)
            notes.append(
                f"record {single.record}: the modes at {found} Hz, closer than half their half-power "
                f"bandwidth, are one nonlinear mode at {single.frequency_hz:.4g} Hz (its frequency changes "
                "with amplitude: see its backbone)"
            )
    return modes, rejected, notes


#: The one oscillator of a merged group of peaks is fitted again on the peaks' extent and this many
#: half-power widths of the widest beyond it, within the group's band. The group's band reaches to the
#: midpoints towards the next peaks (right for deciding, beside the joint linear fit, whether the peaks are
#: one mode); for a hardening mode cut into peaks by the stabilisation diagram (issue 25's detection on
#: stable poles, d10cdad) it reached 63.5-110.4 Hz for a 70 Hz mode, and the cubic spring's backbones of
#: ``benchmarks/accuracy/model_backbone.py`` went from 49 to 39 of 50 (seeds 12, 16, 22, 30: shift errors
#: 12-24 %; refitted with this reach 2-5 %, with 4 widths one backbone undefined at its ends, with 8 widths
#: 5-10 %). Deciding on the narrow band instead merged a linear close pair of family (f) (record 42) and
#: missed a mode of another (25).
_MERGE_REACH = 6.0


def _narrow_band(pre, group, band):
    """The band signal of ``group``'s peaks' extent and :data:`_MERGE_REACH` half-power widths of the
    widest beyond it, within the group's ``band``; None when that is the group's band or cannot be
    extracted."""
    k = list(group)
    f, width = pre.peaks.frequency_hz[k], pre.peaks.half_power_width_hz[k]
    lo, hi = band.band_hz
    reach = _MERGE_REACH * float(np.max(width))
    narrow = (max(lo, float(np.min(f)) - reach), min(hi, float(np.max(f)) + reach))
    if narrow == (lo, hi):
        return None
    try:
        return extract_band(pre.y, pre.fs, narrow, start=pre.impact.ringdown_index, t0=pre.t0)
    except ValueError:
        return None


def _refitted(pre, group, band, modes: list, single: Mode, fit_options: dict, first_periods) -> tuple:
    """``(modes, single)`` with the merged oscillator ``single`` of ``group`` fitted again on the narrow
    band of :data:`_MERGE_REACH`; unchanged when that band is the group's, cannot be extracted, or its fit
    is not a nonlinear mode, and when ``single`` lies at 2 or 3 times a lower mode
    (:func:`~sindy_impulse.preprocessing.partition.at_harmonic_place`): it is left as decided for the
    harmonic test, which reads its decay rate (family (e) record 71 of ``benchmarks/accuracy/modes.py``: a
    softening mode's third harmonic, split in two poles and merged, decayed 2.92 times as fast as its mode
    on the group's band and 2.63 times on the narrow one, and became a spurious mode)."""
    if at_harmonic_place(single.frequency_hz, [m.frequency_hz for m in modes]):
        return modes, single
    narrow_band = _narrow_band(pre, group, band)
    if narrow_band is None:
        return modes, single
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a failed refit keeps the first fit
        refit = fit_band(first_periods(narrow_band), **fit_options)
    if not isinstance(refit, Mode) or not has_nonlinear_terms(refit.model):
        return modes, single
    return [refit if m is single else m for m in modes], refit


def _merged(band, modes: list, rejected: list, fit_options: dict, first_periods) -> tuple:
    """The modes inside ``band`` (a band signal) replaced by one oscillator fitted on it, when that has a
    nonlinear term and fits better than them all, or than the worst with every one on its backbone
    (:func:`_on_its_backbone`); the band's rejected rows dropped then. ``(modes, rejected, single or
    None)``."""
    lo, hi = band.band_hz
    inside = [m for m in modes if lo <= m.frequency_hz <= hi]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a failed merge leaves the modes as they were
        single = fit_band(first_periods(band), **fit_options)
    if not isinstance(single, Mode) or not has_nonlinear_terms(single.model):
        return modes, rejected, None
    if inside and not (single.fit_error < min(m.fit_error for m in inside) or (
            single.fit_error < max(m.fit_error for m in inside) and _on_its_backbone(single, inside))):
        return modes, rejected, None
    modes = [m for m in modes if all(m is not x for x in inside)] + [single]
    rejected = [r for r in rejected if r.band_hz is None or not lo <= np.sqrt(np.prod(r.band_hz)) <= hi]
    return modes, rejected, single


#: A cluster's band reaches this many half-power half-widths (``zeta f``, the widest member's) beyond its
#: lowest and highest frequencies, never past the geometric midpoints to the modes outside it.
_CLUSTER_REACH = 4.0


def _cluster_band(cluster: list, modes: list, fs: float) -> tuple:
    """The band a cluster's one oscillator is fitted on (see :data:`_CLUSTER_REACH`).

    Examples
    --------
    >>> from types import SimpleNamespace as Mode
    >>> found = [(341.4, 0.008), (343.5, 0.023), (385.9, 0.048), (389.1, 0.005)]
    >>> modes = [Mode(frequency_hz=f, damping_ratio=z) for f, z in found]
    >>> [round(b, 1) for b in _cluster_band(modes[2:], modes, 10000.0)]
    [364.1, 463.2]
    """
    f = [m.frequency_hz for m in cluster]
    reach = _CLUSTER_REACH * max(m.damping_ratio * m.frequency_hz for m in cluster)
    lo, hi = min(f) - reach, max(f) + reach
    for m in modes:
        if all(m is not x for x in cluster):
            g = m.frequency_hz
            lo = max(lo, np.sqrt(g * min(f))) if g < min(f) else lo
            hi = min(hi, np.sqrt(g * max(f))) if g > max(f) else hi
    return float(max(lo, 0.5 * min(f))), float(min(hi, 0.45 * fs))


def _clusters(modes: list) -> list:
    """Runs of modes (by frequency) each not :func:`~sindy_impulse.preprocessing.partition.resolved` from
    the next (closer than half the wider one's half-power bandwidth, ``zeta f``): the pieces of a chirp
    that the stabilisation diagram and the peaks cut in two or three (family (g) of
    ``benchmarks/accuracy/modes.py``: 593.0 Hz as 594.2 and 596.2 Hz, 341.2 Hz as 341.4 and 343.5 Hz), never a
    pair of modes the record resolves (family (f) draws them 1-3 bandwidths apart).

    Examples
    --------
    >>> from types import SimpleNamespace as Mode
    >>> found = [(341.4, 0.008), (343.5, 0.023), (389.1, 0.005)]
    >>> modes = [Mode(frequency_hz=f, damping_ratio=z) for f, z in found]
    >>> [[m.frequency_hz for m in c] for c in _clusters(modes)]
    [[341.4, 343.5]]
    """
    ordered = sorted(modes, key=lambda m: m.frequency_hz)
    runs, run = [], ordered[:1]
    for previous, mode in zip(ordered, ordered[1:]):
        pair = (previous, mode)
        if not resolved(tuple(m.frequency_hz for m in pair), tuple(m.damping_ratio for m in pair)):
            run.append(mode)
        else:
            runs.append(run)
            run = [mode]
    runs.append(run)
    return [r for r in runs if len(r) > 1]

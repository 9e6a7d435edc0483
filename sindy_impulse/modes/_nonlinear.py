"""A nonlinear mode seen as several spectral peaks: one mode, its harmonics named as such.

The spectrum of a strongly nonlinear ring-down is not one peak per mode. A hardening spring whose frequency
falls by 2-4 % along the decay smears its peak over that range, and the damped-sinusoid refinement of the
peaks splits it in two (e.g. 159.3 and 161.7 Hz for a 158.6 Hz mode); its odd harmonics (3 f) stand out as
peaks of their own. A linear model per peak then reports two close linear modes and a "mode" at 3 f, all
looking right and all wrong (measured: 3 of 20 hammer tests of ``benchmarks/bench_model_backbone.py``'s
cubic row before this step).

- :func:`merge_chirps`: each group of close peaks (``Preprocessed.groups``) is also fitted as *one*
  oscillator with the mode template (``[y, dy]``, cubic library) on the group's band. When that model
  carries a nonlinear term and reproduces the band better (a smaller fit error) than the modes found in the
  band, the peaks are one nonlinear mode: it replaces them. Two linear modes that close beat, which no
  single two-state oscillator can reproduce, so they keep their joint fit.
- :func:`name_harmonics`: a mode whose frequency is 2 or 3 times a frequency the backbone of a nonlinear
  mode passes through (within :data:`HARMONIC_TOLERANCE`, or within the candidate's own half-power band,
  ``2 zeta``, if wider: a harmonic of an amplitude-dependent damper decays fast and is fitted 0.7 % off
  3 f; the curve's top extended by :data:`HARMONIC_REACH` of its span) is that mode's harmonic: it is
  moved to the rejected peaks with that reason.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..feature_library.terms import term_table
from .band_fit import fit_band
from .result import Mode, Rejected

__all__ = ["merge_chirps", "name_harmonics", "has_nonlinear_terms", "HARMONIC_TOLERANCE"]

#: Relative margin around a nonlinear mode's backbone frequencies times 2 or 3 that marks a harmonic.
HARMONIC_TOLERANCE = 0.005
#: Share of a nonlinear mode's backbone span by which its top is extended when its harmonics are named. The
#: model's backbone covers the data's amplitudes up to about 0.93 of the largest (``analysis.backbone``), and
#: a harmonic's wider band is trimmed less after the hit, so the harmonic is seen at amplitudes the curve
#: does not reach; a hardening spring (shift ~ a^2) rises over that top by about 1 - 0.93^2 = 14 % of the
#: span the curve shows. Measured (``bench_model_backbone.py``, cubic row, seed 37): the third harmonic at
#: 3 x 150.37 Hz of a mode whose backbone tops out at 149.57 Hz (0.03 % beyond the margin above).
HARMONIC_REACH = 0.25


def has_nonlinear_terms(model) -> bool:
    """Whether the fitted model uses a term other than the states themselves (False if unknown)."""
    try:
        coef = np.asarray(model.coefficients())
        library = getattr(model, "feature_library_", None) or model.feature_library
        terms = term_table(library, coef.shape[0])
    except (AttributeError, TypeError, ValueError):
        return False
    return bool(np.any(coef[:, ~terms.linear]))


def merge_chirps(pre, modes: list, rejected: list, fit_options: dict, first_periods) -> tuple:
    """Groups of close peaks that are one nonlinear mode (module docstring): ``(modes, rejected, notes)``.

    ``fit_options`` are passed to :func:`.band_fit.fit_band` (template, onset time, record, ...);
    ``first_periods(band)`` cuts a band signal to the periods a mode is identified on.
    """
    notes = []
    for group, band in pre.groups:
        lo, hi = band.band_hz
        inside = [m for m in modes if lo <= m.frequency_hz <= hi]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # a failed merge leaves the group as it was
            single = fit_band(first_periods(band), **fit_options)
        if not isinstance(single, Mode) or not has_nonlinear_terms(single.model):
            continue
        if inside and not single.fit_error < min(m.fit_error for m in inside):
            continue
        peaks = ", ".join(f"{pre.peaks.frequency_hz[i]:.4g}" for i in group)
        modes = [m for m in modes if all(m is not x for x in inside)] + [single]
        rejected = [r for r in rejected if not (lo <= np.sqrt(np.prod(r.band_hz)) <= hi)]
        notes.append(
            f"record {single.record}: the peaks at {peaks} Hz are one nonlinear mode at "
            f"{single.frequency_hz:.4g} Hz (its frequency changes with amplitude: see its backbone), not "
            f"{len(group)} modes"
        )
    return modes, rejected, notes


def _backbone_range(mode) -> tuple[float, float] | None:
    from ..analysis import backbone

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            f = backbone(mode.model, coordinate=mode.coordinate_).frequency_hz
    except ValueError:
        return None
    f = f[np.isfinite(f)]
    return (float(f.min()), float(f.max())) if f.size else None


def name_harmonics(modes: list, rejected: list) -> tuple:
    """Modes that are the 2nd or 3rd harmonic of a nonlinear mode (module docstring), moved to ``rejected``:
    ``(modes, rejected, notes)``."""
    notes = []
    for mode in [m for m in modes if has_nonlinear_terms(m.model)]:
        if all(m is not mode for m in modes):  # already named a harmonic of another mode
            continue
        span = _backbone_range(mode)
        if span is None:
            continue
        for other in [m for m in modes if m is not mode and m.record == mode.record]:
            margin = max(HARMONIC_TOLERANCE, 2 * other.damping_ratio)  # or within its half-power band
            lo, hi = span[0] * (1 - margin), (span[1] + HARMONIC_REACH * (span[1] - span[0])) * (1 + margin)
            order = next((k for k in (2, 3) if lo <= other.frequency_hz / k <= hi), None)
            if order is None:
                continue
            modes = [m for m in modes if m is not other]
            why = (
                f"harmonic {order} of the nonlinear mode at {mode.frequency_hz:.4g} Hz (its backbone "
                f"passes {other.frequency_hz / order:.4g} Hz), not a mode"
            )
            rejected.append(Rejected(tuple(other.band_hz), why, other.record))
            notes.append(f"record {other.record}: the peak at {other.frequency_hz:.4g} Hz is the {why}")
    return modes, rejected, notes

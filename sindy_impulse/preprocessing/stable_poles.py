"""Modes the spectral peaks missed, taken from the stabilisation diagram and tested as the peaks are.

The spectral peaks (:mod:`.detection`) start from the spectrum: a weak mode in a strong one's skirt, or one
of two modes 1-3 half-power bandwidths apart, may give no peak of its own. The stabilisation diagram
(:func:`~sindy_impulse.poles.stabilisation`) has no bin limit: a physical pole stays put in frequency and
damping across model orders. :func:`with_stable_poles` takes each stable mode of the diagram found at
:data:`PERSISTENCE` of its orders or more (noise poles that pass the stability rule by chance recur at a
few orders) that lies outside every peak's joint half-power band -- or exactly two such modes inside one
peak's, which is then two modes fitted as one (they replace it; three or more trace one mode whose
frequency moves with amplitude; a peak at 2 or 3 times a lower one is left whole for the harmonic test, a
peak in a group of close peaks for the nonlinear merge) -- fits it together with the peaks as
damped sinusoids (:func:`~.sinusoids.fit_damped_sinusoids`, started at the pole) and keeps it when its
height over the floor of the fit's residual passes the peaks' detection threshold -- the test every
spectral peak passed -- and its fitted frequency stayed within the pole's half-power band. The kept poles
join the peaks: the bands (:func:`~.partition.peak_bands`) and the groups of peaks too close for their
damping (:func:`~.partition.band_groups`) are cut again and extracted as :func:`~.pipeline.preprocess`
does, so each becomes the band or the group the per-mode identification works on.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .detection import _heights, _residual_spectrum, _tolerances
from .partition import at_harmonic_place, band_groups, peak_bands, resolved
from .peaks import SpectralPeaks
from .pipeline import Preprocessed, _extract_all, _noise_spectrum
from .sinusoids import fit_damped_sinusoids
from .spectrum import peak_threshold_db, search_range

__all__ = ["with_stable_poles", "PERSISTENCE"]

#: Share of the diagram's orders a stable mode must be found at to be a candidate.
PERSISTENCE = 0.5
#: Largest damping ratio of a candidate (as for the peaks' damped sinusoids; family (d) of
#: ``benchmarks/accuracy/modes.py`` draws damping ratios up to 0.25: a 0.246 mode stable at every order was
#: left out at 0.2).
_MAX_DAMPING = 0.3


def _pair_inside(peaks: SpectralPeaks, k: int, poles: list) -> bool:
    """Whether peak ``k`` holds exactly two poles (three or more trace a frequency that moves along the
    decay: one nonlinear mode), not at a harmonic's place (:func:`~.partition.at_harmonic_place`: left
    whole for the harmonic test; a harmonic of a mode whose frequency moves is cut into several poles by
    the diagram), and not in a group of close peaks (the group is
    fitted jointly and :func:`sindy_impulse.modes._nonlinear.merge_chirps` tests it as one nonlinear mode: a
    hardening mode's smeared peak, split in two, gave two poles in each)."""
    if any(k in group for group in peaks.groups) or len(poles) != 2:
        return False
    return not at_harmonic_place(peaks.frequency_hz[k], peaks.frequency_hz)


def _splittable(peaks: SpectralPeaks, k: int, poles: list) -> bool:
    """Whether peak ``k`` is two modes fitted as one: a pair of poles inside it (:func:`_pair_inside`) that
    are :func:`~.partition.resolved`. An amplitude-dependent damping gives two poles at one frequency, a
    slow and a fast decay, and a chirp two close ones: one mode, whose peak is fitted with its two poles
    when the candidates are tested (a single damped sinusoid leaves it in the residual and raises the
    floor the candidates are measured over: family (e) record 7 of ``benchmarks/accuracy/modes.py`` lost its
    third harmonic's pole) but stays one peak."""
    if not _pair_inside(peaks, k, poles):
        return False
    (f1, s1), (f2, s2) = poles
    return resolved((f1, f2), (s1 / np.hypot(2 * np.pi * f1, s1), s2 / np.hypot(2 * np.pi * f2, s2)))


def _missing(peaks: SpectralPeaks, stable: list, n_orders: int, lo: float, hi: float) -> tuple:
    """Candidates: stable modes found at PERSISTENCE of the orders, in the searched range, outside every
    peak's joint half-power band (and 0.5 % away), or two inside one peak's (that peak is two modes: its
    poles replace it; :func:`_splittable`). ``([(f, decay, peak or -1)], peaks replaced, [(f, decay)] of
    the pairs of poles of one mode, their peaks)``: those peaks are fitted as their pairs, never replaced."""
    sigma_peaks = np.pi * peaks.half_power_width_hz
    inside, out = {}, []
    for m in stable:
        fd = m.frequency_hz * np.sqrt(1 - m.damping_ratio**2)
        sigma = m.damping_ratio * 2 * np.pi * m.frequency_hz
        if m.n_orders < PERSISTENCE * n_orders or not lo <= fd <= hi or m.damping_ratio > _MAX_DAMPING:
            continue
        gap = np.abs(peaks.frequency_hz - fd)
        near = np.flatnonzero(gap <= np.maximum((sigma + sigma_peaks) / (2 * np.pi), 0.005 * fd))
        if near.size:
            inside.setdefault(int(near[np.argmin(gap[near])]), []).append((fd, sigma))
        else:
            out.append((fd, sigma, -1))
    replaced = {k for k, poles in inside.items() if _splittable(peaks, k, poles)}
    pairs = {k for k, poles in inside.items() if k not in replaced and _pair_inside(peaks, k, poles)}
    return (out + [(fd, sigma, k) for k in sorted(replaced) for fd, sigma in inside[k]],
            replaced, [(fd, sigma) for k in sorted(pairs) for fd, sigma in inside[k]], pairs)


def _tested(pre: Preprocessed, missing: list, replaced: set, pairs: tuple = ([], set())) -> tuple[list, list]:
    """The candidates that pass the detection threshold when fitted with the other peaks (a peak holding
    a pair of poles of one mode, ``pairs``, fitted as that pair): ``(kept peaks, [(f, decay, height)])``; a
    replaced peak none of whose poles pass stays."""
    peaks, ring = pre.peaks, pre.y[pre.impact.ringdown_index :]
    poles, paired = pairs
    base = [i for i in range(len(peaks)) if i not in replaced and i not in paired]
    fitted = [(f, d) for f, d in zip(peaks.frequency_hz[base], np.pi * peaks.half_power_width_hz[base])]
    fitted += [(f, d) for f, d in poles] + [(c[0], c[1]) for c in missing]
    f0, decay0 = (np.array([c[i] for c in fitted], float) for i in (0, 1))
    tol = _tolerances(f0, decay0, peaks.spectrum.resolution_hz)
    fit = fit_damped_sinusoids(ring, pre.fs, f0, decay0, frequency_tol_hz=tol)
    residual = _residual_spectrum(fit.residual, pre.fs, fit.frequency_hz)
    heights = _heights(fit, pre.fs, residual)
    needed = peak_threshold_db(fit.frequency_hz, peaks.spectrum, peaks.threshold_db)
    kept, found = [], set()
    for k, (_, _, peak) in zip(range(len(base) + len(poles), f0.size), missing):
        stayed = abs(fit.frequency_hz[k] - f0[k]) <= decay0[k] / (2 * np.pi)
        if heights[k] >= needed[k] and stayed and fit.damping_ratio[k] <= _MAX_DAMPING:
            kept.append((float(fit.frequency_hz[k]), float(fit.decay_rate[k]), float(heights[k])))
            found.add(peak)
    return sorted(base + sorted(paired) + [i for i in replaced if i not in found]), kept


def _joined(peaks: SpectralPeaks, base: list, kept: list, fs: float) -> SpectralPeaks:
    """The peaks ``base`` with the kept candidates, sorted by frequency, bands and groups cut again."""
    f = np.concatenate([peaks.frequency_hz[base], [k[0] for k in kept]])
    decay = np.concatenate([np.pi * peaks.half_power_width_hz[base], [k[1] for k in kept]])
    height = np.concatenate([peaks.height_db[base], [k[2] for k in kept]])
    order = np.argsort(f)
    f, decay, height = f[order], decay[order], height[order]
    width = decay / np.pi
    groups, group_bands = band_groups(f, decay, width, fs)
    return SpectralPeaks(f, height, width, peak_bands(f, width, fs), peaks.threshold_db, peaks.spectrum,
                         decay / np.hypot(2 * np.pi * f, decay), groups, group_bands)


def with_stable_poles(pre: Preprocessed, stable: list, n_orders: int, *, samples_per_period: float = 16.0
                      ) -> tuple[Preprocessed, list[str]]:
    """The preprocessed record with the stable modes the peaks missed added as peaks (see the module).

    Parameters
    ----------
    pre : Preprocessed
        From :func:`~.pipeline.preprocess` with detected peaks (given bands are left as they are).
    stable : list of StableMode
        ``stabilisation(...).modes()`` of the record's free decay.
    n_orders : int
        The number of orders of that diagram.
    samples_per_period : float
        As given to :func:`~.pipeline.preprocess` (the bands are extracted again).

    Returns
    -------
    (Preprocessed, list of str)
        The record (the same object when nothing was added) and one note per added mode.

    Examples
    --------
    A weak mode on the skirt of a strong one, 2.5 % above it:

    >>> from sindy_impulse.datasets import impact_record
    >>> from sindy_impulse.poles import stabilisation
    >>> from sindy_impulse.preprocessing import preprocess
    >>> rec = impact_record([100.0, 102.5], [0.004, 0.004], [1.0, 0.05], fs=1000.0, duration=4.0,
    ...                     snr_db=60, pre_trigger=0.05, random_state=0)
    >>> pre = preprocess(rec.y, fs=rec.fs, quality_warnings=False)
    >>> table = stabilisation(pre.y[pre.impact.ringdown_index:], fs=pre.fs)
    >>> out, notes = with_stable_poles(pre, table.modes(), len(table.orders))
    >>> len(pre.peaks) <= len(out.peaks), [round(float(f), 1) for f in out.peaks.frequency_hz]
    (True, [100.0, 102.5])
    """
    peaks = pre.peaks
    if not np.isfinite(peaks.threshold_db) or len(peaks) == 0:
        return pre, []
    missing, replaced, poles, paired = _missing(peaks, stable, n_orders, *search_range(peaks.spectrum))
    base, kept = _tested(pre, missing, replaced, (poles, paired)) if missing else ([], [])
    if not kept:
        return pre, []
    joined = _joined(peaks, base, kept, pre.fs)
    options = dict(samples_per_period=samples_per_period, min_samples_per_period=8.0, method="fft",
                   end_snr_db=10.0)
    noise = _noise_spectrum(pre.y, pre.impact, pre.fs, joined)
    bands, skipped, groups = _extract_all(pre.y, pre.fs, pre.t0, pre.impact, joined, noise, options)
    notes = [f"a mode at {f:.5g} Hz without a spectral peak of its own, found by the stabilisation diagram "
             f"({h:.0f} dB over the noise floor when fitted with the peaks)" for f, _, h in kept]
    return replace(pre, peaks=joined, bands=bands, skipped=skipped, groups=groups), notes

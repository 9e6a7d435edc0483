"""Which spectral peaks of a ring-down are modes: damped sinusoids fitted and tested against the noise.

The spectrum of a ring-down alone misleads in three ways: the skirts of lightly damped modes that ring
through the whole record cover the noise, so its floor is overestimated (by 60 dB and more) and no peak
stands out; a weak mode a few percent from a strong one shows as a shoulder, not a peak; and the peak of
a strongly damped mode is pulled off its frequency (by 1-2 %) by its neighbours' skirts. So the peaks
are taken as starting points of a model of the record, and decided on what the model leaves:

1. candidates: the spectrum's peaks above its floor (:func:`~.spectrum.candidate_peaks`), or its
   highest prominent peak when none is (a fallback: it must then pass the threshold of step 3 by 3 dB
   more, as the fit's freedom in frequency and decay lifts a noise peak over the residual's floor by up
   to 3 dB, measured on pink noise, while a mode whose skirts hid the floor stands tens of dB over it);
2. all candidates are fitted together as damped sinusoids (:func:`~.sinusoids.fit_damped_sinusoids`);
   the residual is the noise, free of the skirts: its spectrum gives the noise floor (the bins within 3
   resolution bins of a fitted component left out: the fit took the noise there);
3. each component's height is the PSD of the residual plus that component alone at its frequency over
   that floor; a component is kept when its height passes the detection threshold and no stronger one
   lies within their joint half-power band (``|f1 - f2| < (sigma1 + sigma2) / 2 pi``: one mode fitted
   twice);
4. peaks of the residual's spectrum above its floor, away from the components and from earlier
   candidates, are the next candidates (at most 4 per round, the highest); back to 2 until none is new
   and every component is kept (at most 8 rounds).

The modes are the kept components with a damping ratio up to 0.2 (faster decays are transients). When
none is kept, :func:`fit_peaks_after_spike` looks once more, after the spike of the hammer's contact.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from scipy.signal import find_peaks, hilbert

from .noise_floor import noise_floor
from .sinusoids import DampedSinusoids, fit_damped_sinusoids
from .spectrum import (
    Spectrum,
    candidate_peaks,
    half_power_width,
    peak_threshold_db,
    refined_frequency,
    ringdown_spectrum,
    search_range,
    window_psd,
)

__all__ = ["ModeCandidates", "fit_peaks", "fit_peaks_after_spike"]

#: Rounds of fitting at most, and new candidates per round at most.
_ROUNDS, _NEW_PER_ROUND = 8, 4
#: Largest damping ratio of a reported mode.
_MODE_DAMPING = 0.2
#: Resolution bins around a fitted component left out of the residual's floor.
_FIT_BINS = 3.0
#: Extra height (dB) a fallback candidate (the highest peak when none passes the threshold) needs.
_FALLBACK_DB = 3.0
#: Half-power width (resolution bins) of an undamped tone under the window: removed from the measured
#: width to start the decay rate.
_TONE_WIDTH = 1.28


@dataclass(frozen=True)
class ModeCandidates:
    """The modes :func:`fit_peaks` found, sorted by frequency.

    Attributes
    ----------
    frequency_hz, decay_rate, damping_ratio, height_db : ndarray
        Damped frequency, decay rate (1/s), damping ratio and height over the noise floor (dB) per mode.
    spectrum : Spectrum
        The ring-down's PSD with the noise floor of the fit's residual.
    fit : DampedSinusoids or None
        The last fit (None when there was no candidate).
    """

    frequency_hz: np.ndarray
    decay_rate: np.ndarray
    damping_ratio: np.ndarray
    height_db: np.ndarray
    spectrum: Spectrum = field(repr=False)
    fit: DampedSinusoids | None = field(default=None, repr=False)


def _start_decay(width_hz: np.ndarray, resolution_hz: float) -> np.ndarray:
    """Decay rates whose windowed peak has the measured half-power widths."""
    return np.pi * np.sqrt(np.maximum(width_hz**2 - (_TONE_WIDTH * resolution_hz) ** 2,
                                      (0.1 * resolution_hz) ** 2))


def _first_candidates(spectrum: Spectrum, lo: float, hi: float, threshold_db: float, prominence_db: float):
    idx, _ = candidate_peaks(spectrum, lo, hi, threshold_db, prominence_db)
    if idx.size == 0:  # the floor may be overestimated: try the highest prominent peak
        level = 10.0 * np.log10(np.maximum(spectrum.psd, np.finfo(float).tiny))
        idx = find_peaks(level, prominence=prominence_db)[0]
        f = spectrum.frequency_hz[idx]
        idx = idx[(f >= lo) & (f <= hi)]
        idx = idx[np.argsort(spectrum.floor[idx] / spectrum.psd[idx])[:1]]
        extra = np.full(idx.size, _FALLBACK_DB)
    else:
        extra = np.zeros(idx.size)
    width = np.array([half_power_width(spectrum, i) for i in idx])
    return refined_frequency(spectrum, idx), _start_decay(width, spectrum.resolution_hz), extra


def _tolerances(f: np.ndarray, decay: np.ndarray, resolution_hz: float) -> np.ndarray:
    """How far each frequency may move: half its half-power width (at least 1.5 resolution bins), at most
    half the frequency (a broad candidate near 0 Hz once wandered below it), and less than half the way
    to the nearest other candidate."""
    tol = np.minimum(np.maximum(1.5 * resolution_hz, 0.5 * decay / np.pi), 0.5 * f)  # f stays positive
    if f.size > 1:
        gap = np.abs(f[:, None] - f[None, :]) + np.diag(np.full(f.size, np.inf))
        tol = np.minimum(tol, 0.45 * gap.min(axis=1))
    return tol


def _residual_spectrum(residual: np.ndarray, fs: float, f: np.ndarray) -> Spectrum:
    spectrum = ringdown_spectrum(residual, fs)
    fitted = np.zeros(spectrum.psd.size, bool)
    for fk in f:
        fitted |= np.abs(spectrum.frequency_hz - fk) <= _FIT_BINS * spectrum.resolution_hz
    return replace(spectrum, floor=noise_floor(spectrum.psd, pad_factor=spectrum.pad_factor, exclude=fitted))


def _heights(fit: DampedSinusoids, fs: float, spectrum: Spectrum) -> np.ndarray:
    """Height (dB) of each component alone over the floor: residual plus component, at its frequency."""
    n = fit.residual.size
    heights = np.empty(fit.frequency_hz.size)
    for k, fk in enumerate(fit.frequency_hz):
        grid = fk + np.array([-0.25, 0.0, 0.25]) * spectrum.resolution_hz
        level = window_psd(fit.residual + fit.component(k, n, fs), fs, grid).max()
        heights[k] = 10.0 * np.log10(level / np.interp(fk, spectrum.frequency_hz, spectrum.floor))
    return heights


def _kept(fit: DampedSinusoids, heights: np.ndarray, needed: np.ndarray) -> np.ndarray:
    """Components above the threshold and without a stronger one inside their joint half-power band."""
    keep = heights >= needed
    f, sigma = fit.frequency_hz, fit.decay_rate
    for a in np.argsort(-heights):
        if keep[a]:
            close = np.abs(f - f[a]) < (sigma + sigma[a]) / (2.0 * np.pi)
            close[a] = False
            keep[close & (heights <= heights[a])] = False
    return keep


def _new_candidates(spectrum, lo, hi, threshold_db, prominence_db, near: np.ndarray):
    idx, height = candidate_peaks(spectrum, lo, hi, threshold_db, prominence_db)
    f = refined_frequency(spectrum, idx)
    away = np.array([near.size == 0 or np.min(np.abs(near - g)) > 2.0 * spectrum.resolution_hz for g in f],
                    bool)
    best = np.argsort(-height[away])[:_NEW_PER_ROUND]
    idx, f = idx[away][best], f[away][best]
    width = np.array([half_power_width(spectrum, i) for i in idx])
    return f, _start_decay(width, spectrum.resolution_hz)


def _result(ring_spectrum: Spectrum, fit, heights, keep, residual_spectrum) -> ModeCandidates:
    mode = keep & (fit.damping_ratio <= _MODE_DAMPING)
    order = np.argsort(fit.frequency_hz[mode])
    spectrum = replace(ring_spectrum, floor=residual_spectrum.floor)
    return ModeCandidates(fit.frequency_hz[mode][order], fit.decay_rate[mode][order],
                          fit.damping_ratio[mode][order], heights[mode][order], spectrum, fit)


def fit_peaks(y, fs: float, spectrum: Spectrum, lo: float, hi: float, threshold_db: float,
              prominence_db: float = 3.0) -> ModeCandidates:
    """The modes of a ring-down: its spectrum's peaks refined and tested as damped sinusoids (see the
    module).

    Parameters
    ----------
    y : ndarray (n,)
        The ring-down (from the end of the hammer contact, offset removed).
    fs : float
        Sampling rate (Hz).
    spectrum : Spectrum
        ``ringdown_spectrum(y, fs)``.
    lo, hi : float
        The frequencies searched (Hz).
    threshold_db, prominence_db : float
        See :func:`~.spectrum.candidate_peaks`.

    Returns
    -------
    ModeCandidates

    Examples
    --------
    A weak mode 50 dB under a lightly damped one: the spectrum's floor (raised by the strong mode's skirt)
    hides it, the fit's residual does not.

    >>> t = np.arange(8000) / 2000
    >>> from sindy_impulse.preprocessing.spectrum import search_range
    >>> y = np.exp(-0.6 * t) * np.cos(2 * np.pi * 100 * t)
    >>> y += 3e-3 * np.exp(-3 * t) * np.sin(2 * np.pi * 163 * t)
    >>> y += 1e-5 * np.random.default_rng(0).standard_normal(t.size)
    >>> s = ringdown_spectrum(y, 2000.0)
    >>> len(candidate_peaks(s, *search_range(s), 14.0, 3.0)[0])
    1
    >>> modes = fit_peaks(y, 2000.0, s, *search_range(s), 14.0)
    >>> modes.frequency_hz.round(3).tolist(), modes.decay_rate.round(2).tolist()
    ([100.0, 163.0], [0.6, 3.0])
    """
    f, decay, extra = _first_candidates(spectrum, lo, hi, threshold_db, prominence_db)
    tried = f.copy()
    for _ in range(_ROUNDS):
        if f.size == 0:
            return ModeCandidates(*(np.empty(0) for _ in range(4)), spectrum)
        tol = _tolerances(f, decay, spectrum.resolution_hz)
        fit = fit_damped_sinusoids(y, fs, f, decay, frequency_tol_hz=tol)
        residual_spectrum = _residual_spectrum(fit.residual, fs, fit.frequency_hz)
        heights = _heights(fit, fs, residual_spectrum)
        keep = _kept(fit, heights, peak_threshold_db(fit.frequency_hz, spectrum, threshold_db) + extra)
        new_f, new_decay = _new_candidates(residual_spectrum, lo, hi, threshold_db, prominence_db,
                                           np.concatenate([fit.frequency_hz, tried]))
        if keep.all() and new_f.size == 0:
            break
        f = np.concatenate([fit.frequency_hz[keep], new_f])
        decay = np.concatenate([fit.decay_rate[keep], new_decay])
        extra = np.concatenate([extra[keep], np.zeros(new_f.size)])
        tried = np.concatenate([tried, new_f])
    return _result(spectrum, fit, heights, keep, residual_spectrum)


#: Farthest into the ring-down (share of its samples) the retry of :func:`fit_peaks_after_spike` starts.
_SPIKE_SHARE = 0.02


def fit_peaks_after_spike(y, fs: float, threshold_db: float, prominence_db: float = 3.0,
                          f_range=None) -> ModeCandidates | None:
    """:func:`fit_peaks` again from where the envelope has fallen below ``1/e`` of its early maximum, when
    that is within the first :data:`_SPIKE_SHARE` of the ring-down; None otherwise.

    For a ring-down in which :func:`fit_peaks` kept nothing: the tail of the hammer's contact on an
    accelerometer is a broadband spike in the first samples, and on a strongly damped mode (whose decay
    rate changes 2x with amplitude) the damped-sinusoid fit follows the spike and loses the mode (measured:
    8 of 50 simulated hammer tests of single modes with an ``x^2 x'`` damper; skipping 2-7 samples found the
    mode in all 8). A second look at nearly the same data adds little to the false-alarm rate.
    """
    envelope = np.abs(hilbert(y))
    early = envelope[: max(len(y) // 10, 1)].max()
    start = int(np.argmax(envelope < early / np.e))
    if not 0 < start <= _SPIKE_SHARE * len(y):
        return None
    rest = y[start:]
    spectrum = ringdown_spectrum(rest, fs)
    lo, hi = search_range(spectrum, f_range)
    found = fit_peaks(rest, fs, spectrum, lo, hi, threshold_db, prominence_db)
    return found if found.frequency_hz.size else None


def spectrum_peaks(spectrum: Spectrum, lo: float, hi: float, threshold_db: float,
                   prominence_db: float = 3.0) -> ModeCandidates:
    """The spectrum's significant peaks as mode candidates, without the damped-sinusoid test of
    :func:`fit_peaks` (decay rates from the half-power widths): a quick look at where a signal's energy is,
    for checks that run on every fit (:mod:`sindy_impulse.diagnostics`).

    Examples
    --------
    >>> t = np.arange(4000) / 2000
    >>> s = ringdown_spectrum(np.exp(-2.0 * t) * np.cos(2 * np.pi * 100.3 * t), 2000.0)
    >>> spectrum_peaks(s, 1.0, 900.0, 13.0).frequency_hz.round(1).tolist()
    [100.3]
    """
    idx, height = candidate_peaks(spectrum, lo, hi, threshold_db, prominence_db)
    f = refined_frequency(spectrum, idx)
    width = np.array([half_power_width(spectrum, i) for i in idx])
    decay = _start_decay(width, spectrum.resolution_hz)
    return ModeCandidates(f, decay, decay / np.hypot(2 * np.pi * f, decay), height, spectrum)

"""Spectrum of a ring-down, its noise floor, the detection threshold and candidate peaks.

- Spectrum: one-sided PSD of the ring-down under the right half of a Hann window (1 at the onset, 0 at
  the end: a ring-down starts abruptly by nature, so only its end needs a taper), zero-padded 4x.
- Noise floor: :func:`~sindy_impulse.preprocessing.noise_floor.noise_floor` (the rough, noisy bins' level).
- Candidate peaks: local maxima whose PSD exceeds the floor by ``threshold_db`` and which stand out of
  their surroundings (the deepest point towards any higher peak) by 3 dB (half power) and by more than
  noise added to their own level could make them (this merges noise ripples on a broad peak into it).
  They are searched from 3 periods over the record to 0.45 fs (below 8 periods the floor is least
  certain and a peak needs 6 dB more). The default threshold is ``10 log10(ln(1000 M / 1e-3))`` for
  ``M`` resolution bins searched (13-14 dB for 1,000-100,000 samples): a noise periodogram bin exceeds
  ``x`` times its mean with probability ``exp(-x)``; the factor 1000 covers the zero padding and the
  scatter of the floor. Which candidates are modes is decided in
  :mod:`~sindy_impulse.preprocessing.detection`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from numbers import Integral, Real

import numpy as np
from scipy.signal import find_peaks, peak_prominences

from .._utils.params import Interval, check_param
from ._record import check_fs, check_signal_1d
from .noise_floor import noise_floor

__all__ = [
    "Spectrum",
    "ringdown_spectrum",
    "window_psd",
    "detection_threshold_db",
    "half_power_width",
    "search_range",
    "peak_threshold_db",
    "candidate_peaks",
    "refined_frequency",
]

_PAD = 4
#: Independent-bin equivalents per resolution bin assumed by the detection threshold (measured: 2-4,
#: with a heavier tail than independent bins: 1000 keeps the false-alarm rate near 1e-4 per record).
_EFFECTIVE_BINS = 1000
#: Noise power (over the floor) a ripple on a peak is allowed, in the prominence a peak needs.
_RIPPLE = 5.0
#: Periods of the lowest frequency searched over the ring-down, and the highest frequency over fs.
_MIN_PERIODS, _MAX_FRACTION = 3.0, 0.45
#: Below this many periods over the record the floor is least certain: peaks there need _LOW_EXTRA_DB more.
_LOW_PERIODS, _LOW_EXTRA_DB = 8.0, 6.0


@dataclass(frozen=True)
class Spectrum:
    """One-sided PSD (units**2 / Hz) of a ring-down, its noise floor and frequency resolution (1/T)."""

    frequency_hz: np.ndarray = field(repr=False)
    psd: np.ndarray = field(repr=False)
    floor: np.ndarray = field(repr=False)
    resolution_hz: float
    pad_factor: int = _PAD


def _window(n: int) -> np.ndarray:
    """The right half of a Hann window: 1 at the first sample, 0 after the last."""
    return 0.5 * (1.0 + np.cos(np.pi * np.arange(n) / n))


def ringdown_spectrum(y, fs: float, *, pad_factor: int = _PAD) -> Spectrum:
    """PSD of a ring-down (right half of a Hann window, zero-padded) and its noise floor.

    Parameters
    ----------
    y : array-like (n,)
        The ring-down, from the onset, offset removed.
    fs : float
        Sampling rate (Hz).
    pad_factor : int
        Zero padding: the FFT length is the next power of two above ``pad_factor * n``.

    Returns
    -------
    Spectrum

    Examples
    --------
    >>> t = np.arange(4000) / 2000
    >>> s = ringdown_spectrum(np.exp(-2 * t) * np.sin(2 * np.pi * 100 * t), 2000.0)
    >>> round(float(s.frequency_hz[np.argmax(s.psd)]), 1), s.resolution_hz
    (100.0, 0.5)
    """
    arr = check_signal_1d(y, "y")
    rate = check_fs(fs)
    check_param("pad_factor", pad_factor, [Interval(Integral, 1, 64)], "ringdown_spectrum")
    n = arr.size
    window = _window(n)
    n_fft = 1 << int(np.ceil(np.log2(pad_factor * n)))
    psd = np.abs(np.fft.rfft(arr * window, n_fft)) ** 2 * (2.0 / (rate * np.sum(window**2)))
    psd[0] /= 2.0
    freq = np.fft.rfftfreq(n_fft, 1.0 / rate)
    pad = n_fft // n
    return Spectrum(freq, psd, noise_floor(psd, pad_factor=pad), rate / n, pad)


def window_psd(y, fs: float, frequency_hz) -> np.ndarray:
    """The PSD of :func:`ringdown_spectrum` at any frequencies (a direct Fourier sum: for a few).

    Examples
    --------
    >>> t = np.arange(2000) / 1000
    >>> y = np.cos(2 * np.pi * 100.25 * t)
    >>> s = ringdown_spectrum(y, 1000.0)
    >>> bool(window_psd(y, 1000.0, [100.25])[0] > s.psd.max())  # between the bins of the spectrum
    True
    """
    arr = np.asarray(y, dtype=float)
    window = _window(arr.size)
    t = np.arange(arr.size) / fs
    sums = np.exp(-2j * np.pi * np.outer(np.asarray(frequency_hz, dtype=float), t)) @ (arr * window)
    return np.abs(sums) ** 2 * (2.0 / (fs * np.sum(window**2)))


def detection_threshold_db(n_bins: int, false_alarm: float = 1e-3) -> float:
    """Height over the noise floor that a noise spectrum of ``n_bins`` resolution bins exceeds anywhere
    with probability about ``false_alarm``: ``10 log10(ln(1000 n_bins / false_alarm))``.

    A periodogram bin of noise exceeds ``x`` times its mean with probability ``exp(-x)``. The zero-padded
    spectrum (maxima between bins) and the estimated floor behave like 2-4 times ``n_bins`` independent
    bins with a heavier tail (measured on white and pink noise); the factor 1000 leaves a margin.

    Examples
    --------
    >>> round(detection_threshold_db(10000), 1)
    13.6
    """
    check_param("n_bins", n_bins, [Interval(Integral, 1, None)], "detection_threshold_db")
    check_param("false_alarm", false_alarm, [Interval(Real, 0, 1, "neither")], "detection_threshold_db")
    return float(10.0 * np.log10(np.log(_EFFECTIVE_BINS * n_bins / false_alarm)))


def half_power_width(spectrum: Spectrum, index: int) -> float:
    """Width (Hz) of the peak at bin ``index`` where it falls to half its height over the floor.

    Interpolated between bins; a side that never falls (the end of the spectrum) mirrors the other.
    Resolution-limited: at least about ``0.7 / T`` for a ring-down of duration ``T``.
    """
    p, f = spectrum.psd, spectrum.frequency_hz
    level = spectrum.floor[index] + 0.5 * (p[index] - spectrum.floor[index])
    below_left = np.flatnonzero(p[:index] <= level)
    below_right = np.flatnonzero(p[index:] <= level)
    sides = []
    if below_left.size:
        i = below_left[-1]
        sides.append(f[index] - (f[i] + (level - p[i]) / (p[i + 1] - p[i]) * (f[i + 1] - f[i])))
    if below_right.size:
        i = index + below_right[0]
        sides.append((f[i - 1] + (p[i - 1] - level) / (p[i - 1] - p[i]) * (f[i] - f[i - 1])) - f[index])
    return float(2.0 * np.mean(sides)) if sides else float(f[-1])


def search_range(spectrum: Spectrum, f_range=None) -> tuple[float, float]:
    """Frequencies searched for peaks: ``f_range`` checked, or from 3 periods over the record to 0.45 fs.

    Examples
    --------
    >>> s = ringdown_spectrum(np.random.default_rng(0).standard_normal(4000), 2000.0)
    >>> search_range(s), search_range(s, (10, 500))
    ((1.5, 900.0), (10.0, 500.0))
    """
    nyquist = spectrum.frequency_hz[-1]
    if f_range is None:
        return float(_MIN_PERIODS * spectrum.resolution_hz), float(_MAX_FRACTION * 2 * nyquist)
    lo, hi = (float(v) for v in f_range)
    if not 0 <= lo < hi <= nyquist:
        raise ValueError(f"f_range must be (low, high), 0 <= low < high <= fs/2 = {nyquist:g}; got {f_range}")
    return lo, hi


def _noise_prominence_db(height_db: np.ndarray) -> np.ndarray:
    """Prominence (dB) noise can give a bump standing ``height_db`` over the floor: noise of power up to
    ``_RIPPLE`` times the floor added to a level ``S`` moves it by a factor ``((1 + r) / (1 - r))**2``,
    ``r = sqrt(_RIPPLE * floor / S)``."""
    r = np.sqrt(_RIPPLE / 10.0 ** (np.asarray(height_db) / 10.0))
    return np.where(r < 1, 20.0 * np.log10((1 + r) / np.maximum(1 - r, 1e-12)), np.inf)


def peak_threshold_db(frequency_hz, spectrum: Spectrum, threshold_db: float) -> np.ndarray:
    """The height over the floor a peak needs at each frequency: 6 dB more below 8 periods.

    Examples
    --------
    >>> s = ringdown_spectrum(np.random.default_rng(0).standard_normal(4000), 2000.0)  # 2 s
    >>> peak_threshold_db([2.0, 100.0], s, 13.0).tolist()
    [19.0, 13.0]
    """
    low = np.asarray(frequency_hz) < _LOW_PERIODS * spectrum.resolution_hz
    return threshold_db + np.where(low, _LOW_EXTRA_DB, 0.0)


def candidate_peaks(spectrum: Spectrum, lo: float, hi: float, threshold_db: float, prominence_db: float):
    """Bins of the local maxima in ``[lo, hi]`` above the floor by ``threshold_db`` (see
    :func:`peak_threshold_db`) that stand out of their surroundings by ``prominence_db`` and by more than
    noise could make them (merges noise ripples on a peak), and their heights (dB) over the floor.

    Examples
    --------
    >>> t = np.arange(4000) / 2000
    >>> y = np.exp(-2.0 * t) * np.cos(2 * np.pi * 100.3 * t)
    >>> s = ringdown_spectrum(y + 1e-4 * np.random.default_rng(0).standard_normal(t.size), 2000.0)
    >>> idx, height = candidate_peaks(s, *search_range(s), 13.0, 3.0)
    >>> s.frequency_hz[idx].round(1).tolist(), bool(height[0] > 13)
    ([100.3], True)
    >>> refined_frequency(s, idx).round(2).tolist()  # between the bins
    [100.3]
    """
    level_db = 10.0 * np.log10(np.maximum(spectrum.psd, np.finfo(float).tiny))
    height_db = level_db - 10.0 * np.log10(spectrum.floor)
    idx = find_peaks(level_db)[0]
    f = spectrum.frequency_hz[idx]
    idx = idx[(f >= lo) & (f <= hi) & (height_db[idx] >= peak_threshold_db(f, spectrum, threshold_db))]
    # prominences of the maxima high enough only (each measured on the whole spectrum, as find_peaks
    # would: a long spectrum holds thousands of noise ripples, each a walk to its bases)
    needed = np.maximum(prominence_db, _noise_prominence_db(height_db[idx]))
    keep = peak_prominences(level_db, idx)[0] >= needed
    return idx[keep], height_db[idx[keep]]


def refined_frequency(spectrum: Spectrum, idx: np.ndarray) -> np.ndarray:
    """Peak frequencies refined between bins by a parabola through the log PSD at the top three bins
    (example: :func:`candidate_peaks`)."""
    i = np.clip(idx, 1, spectrum.psd.size - 2)
    a, b, c = (np.log(np.maximum(spectrum.psd[i + k], np.finfo(float).tiny)) for k in (-1, 0, 1))
    curvature = a - 2 * b + c
    shift = np.where(curvature < 0, 0.5 * (a - c) / np.where(curvature < 0, curvature, -1.0), 0.0)
    step = spectrum.frequency_hz[1] - spectrum.frequency_hz[0]
    return spectrum.frequency_hz[i] + np.clip(shift, -0.5, 0.5) * step



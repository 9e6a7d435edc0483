"""Spectrum of a ring-down, its noise floor, significant peaks and one frequency band per peak.

- Spectrum: one-sided PSD of the ring-down under the right half of a Hann window (1 at the onset, 0 at
  the end: a ring-down starts abruptly by nature, so only its end needs a taper), zero-padded 4x.
- Noise floor: noise makes a periodogram rough, peaks and skirts are smooth. The floor is the median of
  the log PSD over the rough bins of a window one octave wide, divided by ln 2 (see :func:`noise_floor`);
  where no noise shows (the skirts of lightly damped modes fill the spectrum), it follows the valleys.
- Peaks: local maxima whose PSD exceeds the floor by ``threshold_db`` and which stand out of their
  surroundings (the deepest point towards any higher peak) by 3 dB (half power) and by more than noise
  added to their own level could make them (this merges noise ripples on a broad peak into it). They are
  searched from 3 periods over the record to 0.45 fs (below 8 periods the floor is least certain and a
  peak needs 6 dB more: a strongly damped short ring-down still shows). The default threshold is
  ``10 log10(ln(1000 M / 1e-3))`` for ``M`` resolution bins searched (13-14 dB for 1,000-100,000
  samples): a noise periodogram bin exceeds ``x`` times its mean with probability ``exp(-x)``; the factor
  1000 covers the zero padding and the scatter of the floor. Measured false peaks
  (``python benchmarks/bench_preprocessing.py``): 1 in 1,300 white, 0 in 1,300 pink and 1 in 1,300
  brown noise records of 1,000 to 20,000 samples (none in 3,900 more with another seed).
- Bands: ``(f / (1 + q), f (1 + q))`` with ``q = max(width_factor * hpw / f, min_half_width)``, limited
  by the geometric midpoints to the neighbouring peaks (symmetric in log frequency, so a close neighbour
  narrows both edges and stays in the filter's stop band).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from numbers import Integral, Real

import numpy as np
from scipy.signal import find_peaks

from .._params import Interval, check_param
from ..exceptions import DataWarning
from ._record import check_fs, check_signal_1d
from .floor import noise_floor

__all__ = [
    "Spectrum",
    "SpectralPeaks",
    "ringdown_spectrum",
    "detection_threshold_db",
    "half_power_width",
    "peak_bands",
    "spectral_peaks",
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
    window = 0.5 * (1.0 + np.cos(np.pi * np.arange(n) / n))
    n_fft = 1 << int(np.ceil(np.log2(pad_factor * n)))
    psd = np.abs(np.fft.rfft(arr * window, n_fft)) ** 2 * (2.0 / (rate * np.sum(window**2)))
    psd[0] /= 2.0
    freq = np.fft.rfftfreq(n_fft, 1.0 / rate)
    pad = n_fft // n
    return Spectrum(freq, psd, noise_floor(psd, pad_factor=pad), rate / n, pad)


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


def peak_bands(frequency_hz, half_power_width_hz, fs: float, *, width_factor: float = 5.0,
               min_half_width: float = 0.1) -> list[tuple[float, float]]:
    """One band ``(low, high)`` in Hz per peak, not overlapping its neighbours.

    Each band is ``(f / (1 + q), f (1 + q))``, ``q = max(width_factor * hpw / f, min_half_width)``, with
    ``1 + q`` at most ``sqrt(f_neighbour / f)`` (the geometric midpoint) and ``high`` below Nyquist.

    Examples
    --------
    >>> [tuple(round(e, 1) for e in b) for b in peak_bands([100.0, 103.0, 300.0], [0.5, 0.5, 2.0], 2000)]
    [(98.5, 101.5), (101.5, 104.5), (272.7, 330.0)]
    """
    f = np.asarray(frequency_hz, dtype=float)
    width = np.asarray(half_power_width_hz, dtype=float)
    rate = check_fs(fs)
    order = np.argsort(f)
    ratio = 1.0 + np.maximum(width_factor * width[order] / f[order], min_half_width)
    gaps = np.sqrt(f[order][1:] / f[order][:-1])
    ratio[1:] = np.minimum(ratio[1:], gaps)
    ratio[:-1] = np.minimum(ratio[:-1], gaps)
    bands = [None] * f.size
    for k, i in enumerate(order):
        fk = f[order][k]
        bands[i] = (float(fk / ratio[k]), float(min(fk * ratio[k], 0.499 * rate)))
    return bands


@dataclass(frozen=True)
class SpectralPeaks:
    """Peaks of a ring-down spectrum, sorted by frequency, with a band each.

    Attributes
    ----------
    frequency_hz, height_db, half_power_width_hz : ndarray
        Frequency of each peak, its height over the noise floor and its half-power width.
    band_hz : list of (float, float)
        The band of each peak (given or automatic).
    threshold_db : float
        The detection threshold used (NaN when the bands were given).
    spectrum : Spectrum
        The spectrum and floor the peaks were picked from.
    """

    frequency_hz: np.ndarray
    height_db: np.ndarray
    half_power_width_hz: np.ndarray
    band_hz: list
    threshold_db: float
    spectrum: Spectrum = field(repr=False)

    def __len__(self) -> int:
        return self.frequency_hz.size

    def __repr__(self) -> str:
        rows = [
            f"  {f:10.4g} Hz  {h:5.1f} dB  hpw {w:.3g} Hz  band ({b[0]:.4g}, {b[1]:.4g}) Hz"
            for f, h, w, b in zip(self.frequency_hz, self.height_db, self.half_power_width_hz, self.band_hz)
        ]
        head = f"SpectralPeaks({len(self)} peak(s), threshold {self.threshold_db:.1f} dB over the floor)"
        return "\n".join([head, *rows])


def _search_range(spectrum: Spectrum, f_range, n: int) -> tuple[float, float]:
    nyquist = spectrum.frequency_hz[-1]
    if f_range is None:
        return _MIN_PERIODS * spectrum.resolution_hz, _MAX_FRACTION * 2 * nyquist
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


def _significant(spectrum: Spectrum, lo: float, hi: float, threshold_db: float, prominence_db: float):
    """Bins of the local maxima above the floor by ``threshold_db`` that stand out of their surroundings
    by ``prominence_db`` and by more than noise could make them (merges noise ripples on a peak)."""
    level_db = 10.0 * np.log10(np.maximum(spectrum.psd, np.finfo(float).tiny))
    height_db = level_db - 10.0 * np.log10(spectrum.floor)
    idx, props = find_peaks(level_db, prominence=prominence_db)
    f = spectrum.frequency_hz[idx]
    needed = np.maximum(prominence_db, _noise_prominence_db(height_db[idx]))
    low = f < _LOW_PERIODS * spectrum.resolution_hz
    threshold = threshold_db + np.where(low, _LOW_EXTRA_DB, 0.0)
    keep = (f >= lo) & (f <= hi) & (height_db[idx] >= threshold) & (props["prominences"] >= needed)
    return idx[keep], height_db[idx[keep]]


def _refined_frequency(spectrum: Spectrum, idx: np.ndarray) -> np.ndarray:
    """Peak frequencies refined between bins by a parabola through the log PSD at the top three bins."""
    i = np.clip(idx, 1, spectrum.psd.size - 2)
    a, b, c = (np.log(np.maximum(spectrum.psd[i + k], np.finfo(float).tiny)) for k in (-1, 0, 1))
    curvature = a - 2 * b + c
    shift = np.where(curvature < 0, 0.5 * (a - c) / np.where(curvature < 0, curvature, -1.0), 0.0)
    step = spectrum.frequency_hz[1] - spectrum.frequency_hz[0]
    return spectrum.frequency_hz[i] + np.clip(shift, -0.5, 0.5) * step


def _check_bands(bands, fs: float) -> list[tuple[float, float]]:
    out = []
    for i, band in enumerate(bands):
        try:
            lo, hi = (float(v) for v in band)
        except (TypeError, ValueError):
            raise ValueError(f"bands[{i}] must be a pair (low, high) in Hz, got {band!r}") from None
        if not 0 < lo < hi < fs / 2:
            raise ValueError(f"bands[{i}] = {band!r} must satisfy 0 < low < high < fs/2 = {fs / 2:g} Hz")
        out.append((lo, hi))
    return out


def spectral_peaks(y, fs: float, *, n_modes: int | None = None, bands=None, threshold_db: float | None = None,
                   prominence_db: float = 3.0, f_range=None, width_factor: float = 5.0,
                   min_half_width: float = 0.1) -> SpectralPeaks:
    """Significant peaks of a ring-down's spectrum and a band for each.

    Parameters
    ----------
    y : array-like (n,)
        The ring-down (from the onset, offset removed).
    fs : float
        Sampling rate (Hz).
    n_modes : int, optional
        Keep the ``n_modes`` highest peaks (warns when fewer are significant).
    bands : sequence of (low, high), optional
        Given bands (Hz): one peak each, the highest bin inside; overrides the detection.
    threshold_db : float, optional
        Height over the floor a peak needs; default from a 1e-3 false-alarm rate per record
        (:func:`detection_threshold_db`).
    prominence_db : float
        Dip (dB) separating a peak from any higher one; 3 dB: the half-power points lie between them.
    f_range : (float, float), optional
        Frequencies searched; default from 3 periods over the record to 0.45 ``fs``.
    width_factor, min_half_width : float
        See :func:`peak_bands`.

    Returns
    -------
    SpectralPeaks

    Examples
    --------
    >>> t = np.arange(8000) / 4000
    >>> y = sum(np.exp(-2 * np.pi * 0.005 * f * t) * np.sin(2 * np.pi * f * t) for f in (150, 420))
    >>> y = y + 1e-3 * np.random.default_rng(0).standard_normal(t.size)
    >>> peaks = spectral_peaks(y, 4000.0)
    >>> peaks.frequency_hz.round(1).tolist(), [tuple(round(e) for e in b) for b in peaks.band_hz]
    ([150.0, 420.0], [(136, 165), (382, 462)])
    """
    rate = check_fs(fs)
    arr = check_signal_1d(y, "y")
    check_param("n_modes", n_modes, [None, Interval(Integral, 1, None)], "spectral_peaks")
    check_param("threshold_db", threshold_db, [None, Real], "spectral_peaks")
    check_param("prominence_db", prominence_db, [Interval(Real, 0, None)], "spectral_peaks")
    check_param("width_factor", width_factor, [Interval(Real, 0, None)], "spectral_peaks")
    check_param("min_half_width", min_half_width, [Interval(Real, 0, 1, "neither")], "spectral_peaks")
    spectrum = ringdown_spectrum(arr, rate)
    if bands is not None:
        return _given_bands(spectrum, _check_bands(bands, rate), n_modes)
    lo, hi = _search_range(spectrum, f_range, arr.size)
    if threshold_db is None:
        threshold_db = detection_threshold_db(max(int((hi - lo) / spectrum.resolution_hz), 1))
    idx, height = _significant(spectrum, lo, hi, threshold_db, prominence_db)
    width = np.array([half_power_width(spectrum, i) for i in idx])
    freq = _refined_frequency(spectrum, idx)
    band = peak_bands(freq, width, rate, width_factor=width_factor, min_half_width=min_half_width)
    if n_modes is not None:
        if idx.size < n_modes:
            warnings.warn(
                f"n_modes={n_modes} but only {idx.size} peak(s) stand {threshold_db:.1f} dB over the noise "
                "floor; pass bands or a lower threshold_db to force more",
                DataWarning,
                stacklevel=2,
            )
        keep = np.sort(np.argsort(-height, kind="stable")[:n_modes])
        freq, height, width, band = freq[keep], height[keep], width[keep], [band[k] for k in keep]
    return SpectralPeaks(freq, height, width, band, float(threshold_db), spectrum)


def _given_bands(spectrum: Spectrum, bands: list, n_modes) -> SpectralPeaks:
    if n_modes is not None and n_modes != len(bands):
        raise ValueError(f"n_modes={n_modes} but {len(bands)} band(s) were given; give one of them")
    f = spectrum.frequency_hz
    idx = []
    for lo, hi in bands:
        inside = np.flatnonzero((f >= lo) & (f <= hi))
        if inside.size == 0:
            raise ValueError(f"band ({lo:g}, {hi:g}) Hz holds no spectral line; widen it")
        idx.append(int(inside[np.argmax(spectrum.psd[inside])]))
    idx = np.asarray(idx)
    height = 10.0 * np.log10(spectrum.psd[idx] / spectrum.floor[idx])
    width = np.array([half_power_width(spectrum, i) for i in idx])
    freq = _refined_frequency(spectrum, idx)
    return SpectralPeaks(freq, height, width, list(bands), float("nan"), spectrum)

"""Zero-phase band-pass, decimation and the filter's transient length.

Two zero-phase filters:

- ``"fft"`` (default): the FFT of the zero-padded record times a rectangle smoothed by a Gaussian of
  standard deviation ``w = (high - low) / 8``: ``0.5 [erf((f - low) / (sqrt 2 w)) - erf((f - high) /
  (sqrt 2 w))]``.
  Its impulse response is a band-limited sinc under a Gaussian envelope: short, and no ripple.
- ``"butter"``: a Butterworth band-pass in second-order sections run forwards and backwards
  (``sosfiltfilt``), order 4 (8 after the two passes).

Both preserve the frequency and decay rate of a damped sinusoid exactly once their transient has passed
(the response to ``exp(s t)`` is ``H(s) exp(s t)``); what remains is the transient's tail and the leak
of neighbouring modes. Measured on noise-free ring-downs at 5 kHz (first mode at 150 Hz, bands from
:func:`~sindy_impulse.preprocessing.partition.peak_bands`, transient trimmed at a 1e-3 tolerance, kept
down to -80 dB; ``python -m benchmarks preprocessing``), worst of 6 phases: relative errors of a
log-envelope fit, trim in periods, residual of the best exact damped sinusoid over its envelope (RMS):

===================================  =================================  =================================
case                                 fft: freq / decay / trim / resid.  butter: freq / decay / trim / res.
===================================  =================================  =================================
one mode, damping 0.05 - 1 %         4e-8 / 4e-6 / 19 / 4e-5            2e-7 / 3e-5 / 27 / 5e-4
one mode, damping 3 %                2e-6 / 5e-5 / 7 / 5e-5             3e-6 / 1e-4 / 11 / 1.4e-3
two modes 3 % apart, damping 0.2 %   1e-7 / 1.2e-4 / 125 / 1.5e-4       3e-6 / 1.9e-3 / 171 / 3e-3
two modes 10 % apart, damping 1 %    5e-7 / 9e-5 / 39 / 4e-4            4e-6 / 9e-4 / 53 / 5e-3
===================================  =================================  =================================

``"fft"`` distorts 5-20 times less with a 30 % shorter transient: it is the default.
"""

from __future__ import annotations

import functools
from numbers import Integral, Real

import numpy as np
from scipy.fft import irfft, next_fast_len
from scipy.signal import butter, hilbert, sosfiltfilt, sosfreqz
from scipy.special import erf

from .._utils.params import Interval, Options, check_param
from ._record import check_fs, check_signal_1d

__all__ = ["bandpass", "filter_gain", "transient_samples", "decimation_factor", "check_band"]

_METHODS = [Options({"fft", "butter"})]
_ORDER = [Interval(Integral, 1, 12)]
#: Standard deviation of the Gaussian smoothing the FFT filter's edges, over the bandwidth.
_EDGE = 1.0 / 8.0


def check_band(band_hz, fs: float, name: str = "band_hz") -> tuple[float, float]:
    """A band ``(low, high)`` in Hz with ``0 < low < high < fs / 2``.

    Examples
    --------
    >>> check_band([90, 110], 1000.0)
    (90.0, 110.0)
    """
    try:
        lo, hi = (float(v) for v in band_hz)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a pair (low, high) in Hz, got {band_hz!r}") from None
    if not (np.isfinite(lo) and np.isfinite(hi) and 0 < lo < hi < fs / 2):
        raise ValueError(f"{name} = {band_hz!r} must satisfy 0 < low < high < fs/2 = {fs / 2:g} Hz")
    return lo, hi


def filter_gain(frequency_hz, fs: float, band_hz, *, method: str = "fft", order: int = 4) -> np.ndarray:
    """Gain of the zero-phase band-pass at the given frequencies (both passes for ``"butter"``).

    Examples
    --------
    >>> filter_gain([50.0, 100.0, 200.0], 1000.0, (90, 110)).round(3)
    array([0., 1., 0.])
    """
    rate = check_fs(fs)
    lo, hi = check_band(band_hz, rate)
    check_param("method", method, _METHODS, "filter_gain")
    f = np.abs(np.asarray(frequency_hz, dtype=float))
    if method == "fft":
        width = np.sqrt(2.0) * _EDGE * (hi - lo)
        return 0.5 * (erf((f - lo) / width) - erf((f - hi) / width))
    check_param("order", order, _ORDER, "filter_gain")
    sos = butter(order, [lo, hi], btype="bandpass", fs=rate, output="sos")
    return np.abs(sosfreqz(sos, worN=f, fs=rate)[1]) ** 2


def _fft_gain(n_bins: int, spacing: float, band: tuple) -> np.ndarray:
    """:func:`filter_gain` (method ``"fft"``) at the frequencies ``0, spacing, ..., (n_bins - 1) spacing``,
    evaluated on the band and its edges only: 10 edge widths outside the band the gain is below 1e-40, and
    zero is returned there."""
    lo, hi = band
    width = np.sqrt(2.0) * _EDGE * (hi - lo)
    first = max(int(np.floor((lo - 10 * width) / spacing)), 0)
    stop = min(int(np.ceil((hi + 10 * width) / spacing)) + 1, n_bins)
    gain = np.zeros(n_bins)
    if first < stop:
        f = np.arange(first, stop) * spacing
        gain[first:stop] = 0.5 * (erf((f - lo) / width) - erf((f - hi) / width))
    return gain


def _analytic_fft(x: np.ndarray, fs: float, band: tuple, pad: int) -> np.ndarray:
    """Analytic signal of the FFT band-pass of ``x`` (zero-padded by ``pad`` samples at each end): the
    positive frequencies of the real record's transform, doubled and weighted by the gain, transformed back
    (the zero and Nyquist frequencies and the negative ones get no weight)."""
    n_fft = next_fast_len(x.size + 2 * pad)
    half = np.fft.rfft(x, n_fft)
    n_positive = (n_fft + 1) // 2  # bins 1 .. n_positive - 1 are the positive frequencies below Nyquist
    spectrum = np.zeros(n_fft, dtype=complex)
    gain = _fft_gain(n_positive, fs / n_fft, band)
    spectrum[1:n_positive] = half[1:n_positive] * (2.0 * gain[1:])
    return np.fft.ifft(spectrum)[: x.size]


def bandpass(y, fs: float, band_hz, *, method: str = "fft", order: int = 4, analytic: bool = False):
    """Zero-phase band-pass of a record (see the module docstring for the two methods).

    Parameters
    ----------
    y : array-like (n,)
        The record (zero is assumed before and after it).
    fs : float
        Sampling rate (Hz).
    band_hz : (float, float)
        Pass band edges (Hz), ``0 < low < high < fs / 2``.
    method : {"fft", "butter"}
        The filter.
    order : int
        Butterworth order (``"butter"`` only).
    analytic : bool
        Return the complex analytic signal (real part: the filtered record; modulus: its envelope).

    Returns
    -------
    ndarray (n,), float or complex

    Examples
    --------
    >>> t = np.arange(2000) / 1000
    >>> y = np.sin(2 * np.pi * 50 * t) + np.sin(2 * np.pi * 200 * t)
    >>> out = bandpass(y, 1000.0, (180, 220))
    >>> bool(np.max(np.abs(out[300:-300] - np.sin(2 * np.pi * 200 * t[300:-300]))) < 1e-3)
    True
    """
    arr = check_signal_1d(y, "y")
    rate = check_fs(fs)
    band = check_band(band_hz, rate)
    check_param("method", method, _METHODS, "bandpass")
    check_param("analytic", analytic, ["boolean"], "bandpass")
    if method == "fft":
        out = _analytic_fft(arr, rate, band, transient_samples(rate, band))
        return out if analytic else out.real
    check_param("order", order, _ORDER, "bandpass")
    out = sosfiltfilt(butter(order, band, btype="bandpass", fs=rate, output="sos"), arr)
    return hilbert(out) if analytic else out


def _impulse_response(fs: float, band: tuple, method: str, order: int, n: int) -> np.ndarray:
    impulse = np.zeros(n)
    impulse[n // 2] = 1.0
    if method == "fft":
        return np.fft.fftshift(irfft(_fft_gain(n // 2 + 1, fs / n, band), n))  # SciPy's: n is seldom fast
    return sosfiltfilt(butter(order, band, btype="bandpass", fs=fs, output="sos"), impulse)


def transient_samples(fs: float, band_hz, *, method: str = "fft", order: int = 4, tol: float = 1e-3) -> int:
    """Half-length (samples) of the filter's impulse response down to ``tol`` of its peak.

    The samples within this distance of the start of the ring-down (or of the end of the record) are
    distorted by the filter and must be trimmed.

    Examples
    --------
    >>> n = transient_samples(5000.0, (136.4, 165.0))  # a +-10 % band around 150 Hz
    >>> n, round(n * 150 / 5000, 1)  # samples, periods
    (647, 19.4)
    """
    rate = check_fs(fs)
    band = check_band(band_hz, rate)
    check_param("method", method, _METHODS, "transient_samples")
    check_param("order", order, _ORDER, "transient_samples")
    check_param("tol", tol, [Interval(Real, 1e-9, 1, "neither")], "transient_samples")
    return _transient(rate, band, method, order, tol)


@functools.lru_cache(maxsize=4096)
def _transient(rate: float, band: tuple, method: str, order: int, tol: float) -> int:
    """:func:`transient_samples` once per filter (a survey asks for the same band several times)."""
    n = 2 * int(8.0 * rate / (band[1] - band[0])) + 1
    while True:
        h = np.abs(_impulse_response(rate, band, method, order, n))
        above = np.flatnonzero(h >= tol * h.max())
        half = int(max(n // 2 - above[0], above[-1] - n // 2))
        if half < n // 2 - 1 or n > 2**26:
            return half
        n = 2 * n + 1


def decimation_factor(fs: float, frequency_hz: float, *, samples_per_period: float = 16.0,
                      min_samples_per_period: float = 8.0) -> int:
    """Integer factor leaving at least ``samples_per_period`` samples per period of ``frequency_hz``.

    Raises a ValueError when the record itself has fewer than ``min_samples_per_period``.

    Examples
    --------
    >>> decimation_factor(10000.0, 150.0)  # 66.7 samples per period -> 4 (16.7 per period)
    4
    >>> decimation_factor(1000.0, 150.0)
    Traceback (most recent call last):
    ...
    ValueError: 150 Hz has only 6.67 samples per period at fs = 1000 Hz; at least 8 are needed ...
    """
    rate = check_fs(fs)
    check_param("frequency_hz", frequency_hz, [Interval(Real, 0, rate / 2, "neither")], "decimation_factor")
    check_param("samples_per_period", samples_per_period, [Interval(Real, 2, None, "neither")],
                "decimation_factor")
    check_param("min_samples_per_period", min_samples_per_period, [Interval(Real, 2, None, "neither")],
                "decimation_factor")
    available = rate / frequency_hz
    if available < min_samples_per_period:
        raise ValueError(
            f"{frequency_hz:g} Hz has only {available:.3g} samples per period at fs = {rate:g} Hz; at least "
            f"{min_samples_per_period:g} are needed (min_samples_per_period): record faster or lower "
            "min_samples_per_period"
        )
    return max(1, int(available // samples_per_period))

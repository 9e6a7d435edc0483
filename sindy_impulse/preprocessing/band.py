"""One mode's signal: band-pass, trim the filter transient, stop at the noise floor, decimate.

What :func:`extract_band` does to a record ``y`` (offset removed) for a band ``(low, high)``:

1. band-pass ``y[start:]`` (``start``: first sample of the free ring-down, zero assumed before it) with
   a zero-phase filter (:func:`~sindy_impulse.preprocessing.filters.bandpass`), keeping the envelope;
2. trim the filter's transient: :func:`~sindy_impulse.preprocessing.filters.transient_samples` at each
   end (about ``4.2 / (high - low)`` seconds for the default filter);
3. stop where the envelope, smoothed over ``max(2 periods, 1 / bandwidth)``, falls to the level at which
   the local signal-to-noise ratio is ``end_snr_db`` (10 dB), the noise being the spectrum's floor
   through the filter (:func:`band_noise_rms`): the identification does not fit noise;
4. keep every ``q``-th sample, ``q`` the largest integer leaving ``samples_per_period`` (16) samples per
   period of the band's centre ``sqrt(low high)``. The band-pass is the anti-alias filter: above
   ``high`` its gain falls as a Gaussian, far below the new Nyquist frequency (8 times the centre).
   A band whose centre has fewer than ``min_samples_per_period`` (8) samples per period at the record's
   rate is **resampled** instead, by the integer factor that gives it ``samples_per_period``: the band
   signal's complex envelope about the centre, ``z(t) exp(-2 pi i f_c t)``, holds frequencies up to the
   band's half-width only, far below the record's rate, so a quintic spline interpolates it (error 4e-12
   of the amplitude for a component 10 Hz off the centre at 1 kHz, 7e-5 at 150 Hz off) and it is
   modulated back (``upsampling`` says by how much). Analysers
   record up to ``fs / 2.56``: a band centred above that (up to ``fs / 2``) is tried, with a
   :class:`~sindy_impulse.exceptions.DataWarning`.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from numbers import Integral, Real

import numpy as np
from scipy.interpolate import make_interp_spline
from scipy.ndimage import uniform_filter1d

from .._utils.params import Interval, check_param
from ..exceptions import DataWarning
from ._record import check_fs, check_signal_1d
from .filters import _METHODS, _ORDER, bandpass, check_band, decimation_factor, filter_gain, transient_samples
from .spectrum import Spectrum, ringdown_spectrum

__all__ = ["BandSignal", "band_noise_rms", "record_end", "extract_band", "resample_band"]


@dataclass(frozen=True)
class BandSignal:
    """One band of a record, band-passed, trimmed and decimated, and what was done to get it.

    Attributes
    ----------
    y, t, envelope : ndarray
        The band signal, its times (the record's clock) and its envelope, at the decimated rate.
    fs : float
        The decimated sampling rate (Hz).
    band_hz : (float, float)
        The pass band.
    decimation : int
        Every ``decimation``-th sample was kept.
    samples_per_period : float
        At the decimated rate, per period of the band's centre.
    start_index, stop_index : int
        The kept stretch ``[start_index, stop_index)`` in samples of the original record.
    trimmed_start : int
        Samples (original rate) dropped after the ring-down start for the filter transient.
    trimmed_end : int
        Samples (original rate) dropped at the end (noise floor and filter transient).
    end_reason : str
        ``"noise floor"`` or ``"filter transient"`` (the record ended before the noise floor).
    upsampling : int
        The band signal is at ``upsampling`` times the record's rate (1: not resampled; see the module).
    noise_rms, snr_db : float
        Noise standard deviation in the band, and the signal-to-noise ratio at the first kept sample
        (``20 log10(envelope / (sqrt 2 noise_rms))``).
    """

    y: np.ndarray  # the arrays stay out of the repr: __repr__ below says what they hold
    t: np.ndarray
    envelope: np.ndarray
    fs: float
    band_hz: tuple
    decimation: int
    samples_per_period: float
    start_index: int
    stop_index: int
    trimmed_start: int
    trimmed_end: int
    end_reason: str
    noise_rms: float
    snr_db: float
    upsampling: int = 1

    @property
    def record_fs(self) -> float:
        """The sampling rate (Hz) of the record the band was extracted from."""
        return self.fs * self.decimation / self.upsampling

    @property
    def n_periods(self) -> float:
        """Periods of the band's centre in the kept stretch."""
        return self.y.size / self.samples_per_period

    def __repr__(self) -> str:
        lo, hi = self.band_hz
        return (
            f"BandSignal({lo:.4g}-{hi:.4g} Hz: {self.y.size} samples at {self.fs:.6g} Hz "
            f"(decimation {self.decimation}, {self.samples_per_period:.1f} per period, {self.n_periods:.0f} "
            f"periods), samples {self.start_index}-{self.stop_index} kept, {self.trimmed_start} "
            f"({self.trimmed_start / (self.decimation * self.samples_per_period):.1f} periods) trimmed for "
            f"the filter, ended by the {self.end_reason}, SNR {self.snr_db:.1f} dB)"
        )


def band_noise_rms(spectrum: Spectrum, band_hz, *, method: str = "fft", order: int = 4) -> float:
    """Standard deviation of the noise in a band: the spectrum's floor through the filter's gain,
    integrated on a grid fine enough for narrow bands (the floor interpolated).

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> s = ringdown_spectrum(rng.standard_normal(20000), 1000.0)  # unit white noise: 0.002 / Hz
    >>> round(band_noise_rms(s, (100, 150)), 2)  # sqrt(0.002 * 50 * 0.86): noise bandwidth 0.86 x 50 Hz
    0.29
    """
    if not isinstance(spectrum, Spectrum):
        raise TypeError(f"spectrum must be a Spectrum (from ringdown_spectrum), got {type(spectrum)}")
    fs = 2.0 * spectrum.frequency_hz[-1]
    lo, hi = check_band(band_hz, fs)
    grid = np.linspace(max(0.0, lo - 6 * (hi - lo)), min(fs / 2, hi + 6 * (hi - lo)), 4001)
    gain = filter_gain(grid, fs, (lo, hi), method=method, order=order)
    floor = np.interp(grid, spectrum.frequency_hz, spectrum.floor)
    return float(np.sqrt(np.sum(floor * gain**2) * (grid[1] - grid[0])))


def record_end(envelope, noise_rms: float, *, fs: float, frequency_hz: float, bandwidth_hz: float,
               end_snr_db: float = 10.0, start: int = 0) -> int:
    """First sample after ``start`` where the smoothed envelope reaches the noise (``envelope.size`` if
    never): the local SNR ``(A**2 / 2) / noise_rms**2`` has fallen to ``end_snr_db``.

    The envelope is averaged over ``max(2 periods, 1 / bandwidth_hz)`` first.

    Examples
    --------
    >>> t = np.arange(5000) / 1000
    >>> record_end(np.exp(-t), 0.01, fs=1000.0, frequency_hz=50.0, bandwidth_hz=10.0)  # exp(-3.107) = 0.0447
    3109
    """
    env = check_signal_1d(envelope, "envelope", 1)
    check_param("noise_rms", noise_rms, [Interval(Real, 0, None)], "record_end")
    check_param("end_snr_db", end_snr_db, [Real], "record_end")
    rate = check_fs(fs)
    width = max(2.0 * rate / frequency_hz, rate / bandwidth_hz, 1.0)
    smooth = uniform_filter1d(env, size=int(round(width)), mode="nearest")
    level = np.sqrt(2.0) * noise_rms * 10.0 ** (end_snr_db / 20.0)
    below = np.flatnonzero(smooth[start:] < level)
    return int(start + below[0]) if below.size else int(env.size)


#: Highest band centre, as a fraction of the sampling rate, identified without a warning: analysers record
#: up to ``fs / 2.56`` (their anti-alias filter's pass band).
ANALYSER_LIMIT = 1 / 2.56
#: Samples of the band signal resampled beyond each end of the kept stretch (the interpolator's edges).
_RESAMPLE_PAD = 32


def _check_extract(arr, rate, band_hz, start, samples_per_period, min_samples_per_period, min_periods):
    """The band, its centre, the decimation factor and the upsampling factor (one of them is 1)."""
    band = check_band(band_hz, rate)
    check_param("start", start, [Interval(Integral, 0, arr.size - 1)], "extract_band")
    check_param("min_periods", min_periods, [Interval(Real, 1, None)], "extract_band")
    centre = float(np.sqrt(band[0] * band[1]))
    if rate / centre >= min_samples_per_period:
        q = decimation_factor(rate, centre, samples_per_period=samples_per_period,
                              min_samples_per_period=min_samples_per_period)
        return band, centre, q, 1
    positive = [Interval(Real, 2, None, "neither")]
    check_param("samples_per_period", samples_per_period, positive, "extract_band")
    if centre > ANALYSER_LIMIT * rate:
        limit = ANALYSER_LIMIT * rate
        warnings.warn(
            f"band ({band[0]:.4g}, {band[1]:.4g}) Hz is centred above fs / 2.56 = {limit:.4g} Hz, where an "
            "analyser's anti-alias filter may already act on it: its mode is identified, but check its "
            "damping against a record sampled faster",
            DataWarning,
            stacklevel=4,
        )
    return band, centre, 1, math.ceil(samples_per_period * centre / rate)


def resample_band(z: np.ndarray, first: int, stop: int, rate: float, centre: float, up: int):
    """``z[first:stop]`` (the analytic band signal) at ``up`` times the rate: its complex envelope about
    ``centre`` interpolated (quintic spline) and modulated back. Returns the signal, its envelope and the
    sample times (in samples of the record's rate, from ``z[0]``)."""
    lo, hi = max(first - _RESAMPLE_PAD, 0), min(stop + _RESAMPLE_PAD, z.size)
    k = np.arange(lo, hi)
    carrier = np.exp(-2j * np.pi * centre * k / rate)
    position = np.arange(first * up, stop * up) / up
    envelope = make_interp_spline(k, z[lo:hi] * carrier, k=5)(position)
    signal = (envelope * np.exp(2j * np.pi * centre * position / rate)).real
    return signal, np.abs(envelope), position


def _too_short(band: tuple, periods: float, trim: int, min_periods: float):
    raise ValueError(
        f"band ({band[0]:.4g}, {band[1]:.4g}) Hz: {max(periods, 0.0):.1f} periods remain after trimming the "
        f"filter transient ({trim} samples at each end) and stopping at the noise floor; at least "
        f"{min_periods:g} are needed (min_periods). Widen the band, lower end_snr_db or use a longer record"
    )


def extract_band(y, fs: float, band_hz, *, start: int = 0, t0: float = 0.0, samples_per_period: float = 16.0,
                 min_samples_per_period: float = 8.0, method: str = "fft", order: int = 4,
                 transient_tol: float = 1e-3, noise_rms: float | None = None, end_snr_db: float | None = 10.0,
                 min_periods: float = 10.0, max_periods: float | None = None,
                 analytic_signal: np.ndarray | None = None) -> BandSignal:
    """Band-pass one band of a record, trim the filter transient, stop at the noise floor and decimate.

    See the module docstring for the steps.

    Parameters
    ----------
    y : array-like (n,)
        The record, offset removed.
    fs : float
        Sampling rate (Hz).
    band_hz : (float, float)
        The band (Hz).
    start : int
        First sample of the free ring-down (end of the hammer contact).
    t0 : float
        Time of ``y[0]``.
    samples_per_period, min_samples_per_period : float
        Target after decimation, and the least the record must offer (else a ValueError).
    method, order : str, int
        The filter (see :func:`~sindy_impulse.preprocessing.filters.bandpass`).
    transient_tol : float
        Impulse-response tolerance defining the transient to trim.
    noise_rms : float, optional
        Noise standard deviation in the band; default: the smaller of the spectrum's floor through the
        filter (:func:`band_noise_rms`; an upper bound under the skirts of strong modes) and the band
        signal's RMS over its last tenth (an upper bound while the mode still rings there).
    end_snr_db : float or None
        Local SNR at which the band ends; None keeps everything up to the end transient.
    min_periods : float
        Fewest periods that must remain (else a ValueError).
    max_periods : float, optional
        Most periods kept (``end_reason`` "max_periods" when they end the band): the strongest part of a
        long ring-down, at a bounded cost.
    analytic_signal : ndarray of complex, optional
        The band-pass of ``y[start:]`` as an analytic signal (:func:`~.filters.bandpass` with
        ``analytic=True``, this ``method`` and ``order``) when the caller has it already: it is used
        instead of filtering again.

    Returns
    -------
    BandSignal

    Examples
    --------
    A 150 Hz mode (damping ratio 0.3 %) sampled at 5 kHz for 4 s, noise 1e-3:

    >>> t = np.arange(20000) / 5000
    >>> y = np.exp(-2 * np.pi * 0.003 * 150 * t) * np.sin(2 * np.pi * 150 * t)
    >>> y += 1e-3 * np.random.default_rng(0).standard_normal(t.size)
    >>> band = extract_band(y, 5000.0, (136.4, 165.0))
    >>> band.decimation, band.trimmed_start, band.stop_index, band.end_reason, round(band.snr_db)
    (2, 647, 13101, 'noise floor', 73)
    """
    arr = check_signal_1d(y, "y")
    rate = check_fs(fs)
    band, centre, q, up = _check_extract(
        arr, rate, band_hz, start, samples_per_period, min_samples_per_period, min_periods
    )
    check_param("method", method, _METHODS, "extract_band")
    check_param("order", order, _ORDER, "extract_band")
    check_param("noise_rms", noise_rms, [None, Interval(Real, 0, None)], "extract_band")
    check_param("end_snr_db", end_snr_db, [None, Real], "extract_band")
    check_param("transient_tol", transient_tol, [Interval(Real, 1e-9, 1, "neither")], "extract_band")
    check_param("max_periods", max_periods, [None, Interval(Real, 0, None, "neither")], "extract_band")
    segment = arr[start:]
    trim = transient_samples(rate, band, method=method, order=order, tol=transient_tol)
    if analytic_signal is None:
        z = bandpass(segment, rate, band, method=method, order=order, analytic=True)
    else:
        z = np.asarray(analytic_signal)
        if z.shape != segment.shape:
            raise ValueError(f"analytic_signal holds {z.size} samples, y[start:] {segment.size}")
    env = np.abs(z)
    stop, reason = segment.size - trim, "filter transient"
    if stop - trim < min_periods * rate / centre:
        _too_short(band, 0.0, trim, min_periods)
    if noise_rms is None:
        tail = z.real[trim + int(0.9 * (stop - trim)) : stop]
        noise_rms = min(band_noise_rms(ringdown_spectrum(segment, rate), band, method=method, order=order),
                        float(np.sqrt(np.mean(tail**2))))
    if end_snr_db is not None:
        end = record_end(env, noise_rms, fs=rate, frequency_hz=centre, bandwidth_hz=band[1] - band[0],
                         end_snr_db=end_snr_db, start=trim)
        if end < stop:
            stop, reason = end, "noise floor"
    if stop - trim < min_periods * rate / centre:
        _too_short(band, (stop - trim) * centre / rate, trim, min_periods)
    if max_periods is not None and stop - trim > max_periods * rate / centre:
        stop, reason = trim + int(np.ceil(max_periods * rate / centre)), "max_periods"
    if up > 1:
        signal, envelope, keep = resample_band(z, trim, stop, rate, centre, up)
    else:
        keep = np.arange(trim, stop, q)
        signal, envelope = z.real[keep].copy(), env[keep]
    return BandSignal(
        y=signal, t=t0 + (start + keep) / rate, envelope=envelope, fs=rate * up / q, band_hz=band,
        decimation=q, samples_per_period=rate * up / (q * centre), start_index=int(start + trim),
        stop_index=int(start + stop), trimmed_start=int(trim), trimmed_end=int(segment.size - stop),
        end_reason=reason, noise_rms=float(noise_rms),
        snr_db=float(20.0 * np.log10(env[trim] / (np.sqrt(2.0) * noise_rms))) if noise_rms > 0 else np.inf,
        upsampling=up,
    )

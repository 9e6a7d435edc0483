"""Instantaneous amplitude, natural frequency and damping ratio along one free decay (engine of backbone.py).

The estimator of :func:`sindy_impulse.analysis.hilbert_backbone`, in the spirit of FREEVIB (Feldman 1994):

1. carrier frequency ``fc`` = the largest spectral peak; offset = Hann-weighted mean of the last
   ``max(4 periods, 10 %)`` of the record (removed); optional zero-phase Butterworth band-pass;
2. analytic signal ``z`` by the FFT Hilbert transform, zero-padded to twice the length and computed as
   ``e H[y / e]`` with a rough envelope ``e`` (same signal by Bedrosian's theorem, but the large start's
   end effects do not swamp the small end of a long decay); ``ln A = ln|z|``, ``phi = unwrap(arg z)``;
3. :data:`TRIM_PERIODS` periods dropped at each end (end effects), plus the filter's settling time
   ``2 / bandwidth`` after a band-pass;
4. first pass, local quadratic fits over :data:`FIRST_WINDOW_PERIODS` periods: the residual
   ``y - A cos(phi)`` gives the noise level (robust standard deviation); the decay starts at the envelope's
   maximum (a pre-trigger stretch and the impact are skipped) and ends where the envelope falls below
   ``min_snr`` times the noise (the floor); a straight line through ``ln A`` gives a rough decay rate;
5. second pass, local quadratic (Savitzky-Golay) fits of ``ln A`` and ``phi``: slopes ``sigma = -d ln A/dt``
   and ``w_d = d phi / dt``. The shortest window ``K`` spans a drop of :data:`WINDOW_DECAY` in ``ln A``
   (at least :data:`MIN_WINDOW_PERIODS` periods, at most a third of the decay); where the noise makes
   its decay rate imprecise (predicted relative standard error above :data:`DAMPING_PRECISION`), the
   next longer window of :data:`LADDER` (up to ``5 K``, and a third of the decay) is used. Half a
   window at each end has no fit (the top of the curve starts ``trim + K / 2`` periods in). The fits
   reach past the floor by half the longest window, so the curve can end at the floor;
6. ``w_n = sqrt(w_d^2 + sigma^2)``, ``zeta = sigma / w_n``: first order in the slow variation (FREEVIB's
   corrections with the derivatives of the frequency are not applied); the curve stops at the floor.

The fits are FFT convolutions (``scipy.signal.oaconvolve``): O(n log n) whatever the window, so a
60,000-sample record takes some 10-30 ms.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from scipy import fft, ndimage, signal

from .._utils.robust import robust_std
from ..exceptions import DataWarning

#: Periods dropped at each end of the record (Hilbert transform end effects).
TRIM_PERIODS = 3.0
#: Window of the first pass (noise level and rough damping), in periods.
FIRST_WINDOW_PERIODS = 4.0
#: Shortest smoothing window of the second pass, in periods.
MIN_WINDOW_PERIODS = 4.0
#: Target drop of ``ln A`` across the automatic smoothing window.
WINDOW_DECAY = 0.25
#: Window lengths tried (multiples of the shortest) where the noise needs longer windows.
LADDER = (1.0, 1.5, 2.25, 3.4, 5.0)
#: Target relative standard error of the decay rate that selects the window.
DAMPING_PRECISION = 0.01
#: Smallest fall of ``ln A`` over the decay (5 %): less is not a free decay.
MIN_DECAY = 0.05
#: A fall of ``ln A`` below this (a factor 2) warns of a narrow amplitude range.
NARROW_DECAY = np.log(2.0)
#: Envelopes below this fraction of the largest are not analysed (round-off of the FFT).
NUMERIC_FLOOR = 1e-9
#: Order of the Butterworth band-pass (applied forwards and backwards).
BAND_ORDER = 4
#: Fewest samples per period the analysis accepts (below 6 it warns).
MIN_SAMPLES_PER_PERIOD = 3.0
#: Warn below this many samples per period.
FEW_SAMPLES_PER_PERIOD = 6.0


@dataclass
class DecayCurve:
    """Instantaneous values along the decay, in time order (one entry per analysed sample)."""

    amplitude: np.ndarray
    frequency_hz: np.ndarray
    damping_ratio: np.ndarray
    noise: float
    window_periods: float


def carrier_hz(y: np.ndarray, dt: float, band: tuple[float, float] | None = None) -> float:
    """Frequency of the largest spectral peak of ``y`` (mean removed), within ``band`` if given."""
    n = fft.next_fast_len(2 * len(y))
    spectrum = np.abs(fft.rfft(y - y.mean(), n))
    freqs = fft.rfftfreq(n, dt)
    valid = freqs > 0
    if band is not None:
        valid &= (freqs >= band[0]) & (freqs <= band[1])
    if not np.any(valid) or not np.any(spectrum[valid] > 0):
        raise ValueError("y has no oscillation to analyse (its spectrum is zero in the analysed band)")
    return float(freqs[valid][np.argmax(spectrum[valid])])


def offset(y: np.ndarray, spp: float) -> float:
    """The offset: Hann-weighted mean of the last ``max(4 periods, 10 %)`` of the record.

    The end of a decay oscillates least (or is noise about the offset), and the Hann weights cancel the
    remaining oscillation to a fraction of its amplitude, where the mean of the whole record would leave
    up to ``A0 / (2 pi n_periods)`` of the initial amplitude: more than the end's amplitude on a decay
    spanning many decades.
    """
    m = min(len(y), max(int(4 * spp), len(y) // 10))
    w = signal.windows.hann(m + 2)[1:-1]
    return float(np.dot(w, y[-m:]) / w.sum())


def bandpass(y: np.ndarray, dt: float, band: tuple[float, float]) -> np.ndarray:
    """Zero-phase Butterworth band-pass (low-pass when ``band[0] == 0``, high-pass at Nyquist)."""
    nyquist = 0.5 / dt
    low, high = band
    if low <= 0 and high >= nyquist:
        return y
    if low <= 0:
        sos = signal.butter(BAND_ORDER, high, "lowpass", fs=1 / dt, output="sos")
    elif high >= nyquist:
        sos = signal.butter(BAND_ORDER, low, "highpass", fs=1 / dt, output="sos")
    else:
        sos = signal.butter(BAND_ORDER, [low, high], "bandpass", fs=1 / dt, output="sos")
    return signal.sosfiltfilt(sos, y)


def _analytic(y: np.ndarray, spp: float) -> np.ndarray:
    """Analytic signal by the FFT Hilbert transform, zero-padded to twice the length (no wrap-around).

    Computed as ``e H[y / e]`` with ``e`` a rough envelope (first-pass ``|z|`` averaged over a period in
    ``ln``): the same analytic signal for a slowly varying envelope (Bedrosian's theorem), but the end
    effects of the large start no longer swamp the small end of a decay spanning many decades.
    """
    n = len(y)
    size = fft.next_fast_len(2 * n)
    rough = np.abs(signal.hilbert(y, size)[:n])
    tiny = np.finfo(float).tiny
    e = np.exp(ndimage.uniform_filter1d(np.log(np.maximum(rough, tiny)), max(1, int(round(spp)))))
    return e * signal.hilbert(y / e, size)[:n]


def _odd(n: float) -> int:
    return max(3, int(round(n)) // 2 * 2 + 1)


def _local_fit(v: np.ndarray, window: int, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Value and slope of local quadratic least-squares fits over ``window`` samples (full windows only).

    Closed-form Savitzky-Golay weights for the centre of a symmetric window ``j = -h..h``: the value is
    ``sum (S4 - S2 j^2) v_j / (S0 S4 - S2^2)``, the slope ``sum j v_j / (S2 dt)`` (``Sk = sum j^k``).
    """
    j = np.arange(-(window // 2), window // 2 + 1, dtype=float)
    s0, s2, s4 = len(j), np.sum(j**2), np.sum(j**4)
    value = (s4 - s2 * j**2) / (s0 * s4 - s2**2)
    slope = -j / (s2 * dt)  # reversed for the convolution
    return signal.oaconvolve(v, value, mode="valid"), signal.oaconvolve(v, slope, mode="valid")


def _noise_level(y: np.ndarray, ln_a: np.ndarray, phase: np.ndarray, window: int, dt: float):
    """Robust noise standard deviation and the first-pass smoothed envelope."""
    h = window // 2
    smooth_ln_a, _ = _local_fit(ln_a, window, dt)
    smooth_phase, _ = _local_fit(phase, window, dt)
    envelope = np.exp(smooth_ln_a)
    residual = y[h : len(y) - h] - envelope * np.cos(smooth_phase)
    return robust_std(residual), envelope


def _window_periods(envelope: np.ndarray, dt: float, w0: float, n_periods: float) -> tuple[float, float]:
    """Rough decay rate of the first-pass envelope (above the floor) and the smoothing window (periods)."""
    sigma = -np.polyfit(np.arange(len(envelope)) * dt, np.log(envelope), 1)[0]
    drop = sigma * len(envelope) * dt  # fall of ln A over the decay
    if not drop > MIN_DECAY:
        raise ValueError(
            f"the envelope does not decay (it falls by {100 * (1 - np.exp(-max(drop, 0))):.1f} % over "
            f"{n_periods:.0f} periods): y is not a free decay; a steady or forced response has no backbone "
            "from this estimator"
        )
    if drop < NARROW_DECAY:
        warnings.warn(
            f"the envelope falls by only {100 * (1 - np.exp(-drop)):.0f} % over the record: the backbone "
            "covers a narrow amplitude range; record a longer decay",
            DataWarning,
            stacklevel=4,
        )
    k = WINDOW_DECAY / (2 * np.pi * sigma / w0)
    return float(sigma), float(np.clip(k, MIN_WINDOW_PERIODS, max(MIN_WINDOW_PERIODS, n_periods / 3)))


def _prepare(y: np.ndarray, dt: float, band, trim_periods: float):
    """Trimmed signal (offset removed, band-passed), its ``ln A``, detrended phase, ``w0``, samples/period."""
    fc = carrier_hz(y, dt, band)
    spp = 1.0 / (fc * dt)
    y = y - offset(y, spp)
    settle = 0
    if band is not None:
        y = bandpass(y, dt, band)
        settle = int(np.ceil(2.0 / ((band[1] - band[0]) * dt)))
    if spp < MIN_SAMPLES_PER_PERIOD:
        raise ValueError(
            f"the dominant frequency {fc:.4g} has {spp:.1f} samples per period (near the Nyquist frequency); "
            f"at least {MIN_SAMPLES_PER_PERIOD:g} are needed: check the sampling step t or pass band"
        )
    if spp < FEW_SAMPLES_PER_PERIOD:
        warnings.warn(
            f"only {spp:.1f} samples per period at {fc:.4g} (1/time unit): the envelope and phase are "
            "coarse; sample faster or do not decimate below 6-8 samples per period",
            DataWarning,
            stacklevel=4,
        )
    n = len(y)
    k = int(np.ceil(trim_periods * spp)) + settle
    need = 2 * k + int(3 * MIN_WINDOW_PERIODS * spp)
    if n < need:
        raise ValueError(
            f"y has {n} samples ({n / spp:.1f} periods at {fc:.4g} Hz); a free decay of at least "
            f"{need} samples ({need / spp:.0f} periods, {trim_periods:g} trimmed at each end) is needed"
        )
    z = _analytic(y, spp)[k : n - k]
    w0 = 2 * np.pi * fc
    ln_a = np.log(np.maximum(np.abs(z), np.finfo(float).tiny))
    phase = np.unwrap(np.angle(z)) - w0 * dt * np.arange(len(z))  # detrended: better conditioned fits
    return y[k : n - k], ln_a, phase, w0, spp


def _decay_region(envelope: np.ndarray, half: int, floor: float, trim: int) -> tuple[int, int]:
    """Samples ``[start, stop)`` of the decay above the floor (``envelope`` starts ``half`` samples in)."""
    peak = int(np.argmax(envelope))
    below = envelope[peak:] <= floor
    end = peak + (int(np.argmax(below)) if below.any() else len(below))
    start = 0 if peak == 0 else peak + half + trim  # after a pre-trigger stretch: skip the impact
    return start, end + half


def _ladder_fit(ln_a, phase, windows, dt, noise, sigma_rough):
    """Per sample, the fits of the shortest window whose damping is precise enough (else the longest).

    The predicted relative standard error of the decay rate from a window of ``n`` samples (duration
    ``W``) at envelope ``A`` is ``sqrt(12 / n) * noise / (A * W * sigma)`` (least-squares slope of ``ln A``,
    whose noise is ``noise / A`` per sample); ``sigma`` is the longest window's estimate, at least a
    fifth of the rough decay rate.
    """
    n = len(ln_a)
    fits = []
    for w in windows:
        pad = np.full(w // 2, np.nan)
        value, slope = _local_fit(ln_a, w, dt)
        fits.append([np.concatenate([pad, v, pad]) for v in (value, slope, _local_fit(phase, w, dt)[1])])
    sigma_ref = np.maximum(-np.nan_to_num(fits[-1][1], nan=-sigma_rough), 0.2 * sigma_rough)
    out = [np.full(n, np.nan) for _ in range(3)]
    chosen = np.zeros(n, dtype=bool)
    for w, (value, slope, phase_slope) in zip(windows, fits):
        valid = np.isfinite(value)
        write = valid & ~chosen
        for o, v in zip(out, (value, slope, phase_slope)):
            o[write] = v[write]
        error = np.sqrt(12.0 / w) * noise / (np.exp(value[valid]) * w * dt * sigma_ref[valid])
        chosen[np.flatnonzero(valid)[error <= DAMPING_PRECISION]] = True
    return out


def instantaneous(
    y: np.ndarray,
    dt: float,
    *,
    band: tuple[float, float] | None,
    trim_periods: float,
    smooth_periods: float | None,
    min_snr: float,
) -> DecayCurve:
    """Smoothed instantaneous amplitude, undamped natural frequency and damping ratio (module docstring)."""
    y, ln_a, phase, w0, spp = _prepare(y, dt, band, trim_periods)
    first = _odd(FIRST_WINDOW_PERIODS * spp)
    noise, envelope = _noise_level(y, ln_a, phase + w0 * dt * np.arange(len(y)), first, dt)
    floor = max(min_snr * noise, NUMERIC_FLOOR * float(envelope.max()))
    start, stop = _decay_region(envelope, first // 2, floor, int(np.ceil(trim_periods * spp)))
    if start > len(y) / 2:
        raise ValueError(
            f"the envelope does not decay (it is largest {start / spp:.0f} periods into the record of "
            f"{len(y) / spp:.0f}): y is not a free decay, or a growing (unstable) response"
        )
    if stop - start < first:
        raise ValueError(
            f"the decay above the noise floor ({min_snr:g} x the noise level {noise:.3g}) lasts "
            f"{max(stop - start, 0) / spp:.1f} periods; at least {first / spp:.0f} are needed (check the "
            "band, lower min_snr or record a stronger response)"
        )
    h = first // 2
    sigma_rough, k = _window_periods(envelope[max(start - h, 0) : stop - h], dt, w0, (stop - start) / spp)
    k = smooth_periods or k
    windows = [_odd(k * spp)]
    if smooth_periods is None:  # longer windows where the noise needs them, up to a third of the decay
        windows += [_odd(k * spp * g) for g in LADDER[1:] if k * g <= (stop - start) / (3 * spp)]
    stop = min(len(y), stop + windows[-1] // 2)
    if stop - start < windows[0] + 8:
        raise ValueError(
            f"the decay above the noise floor lasts {(stop - start) / spp:.1f} periods, fewer than the "
            f"smoothing window of {windows[0] / spp:.1f} periods: record a longer decay or pass a smaller "
            "smooth_periods"
        )
    fits = _ladder_fit(ln_a[start:stop], phase[start:stop], windows, dt, noise, sigma_rough)
    value, slope, phase_slope = fits
    ok = np.isfinite(value)
    amplitude, sigma, omega_d = np.exp(value[ok]), -slope[ok], phase_slope[ok] + w0
    below = amplitude <= floor
    keep = int(np.argmax(below)) if below.any() else len(amplitude)
    if keep < 2:
        raise ValueError(
            f"no point of the smoothed decay is above the noise floor ({min_snr:g} x the noise level "
            f"{noise:.3g}): record a stronger response or lower min_snr"
        )
    omega_n = np.sqrt(omega_d[:keep] ** 2 + sigma[:keep] ** 2)
    return DecayCurve(amplitude[:keep], omega_n / (2 * np.pi), sigma[:keep] / omega_n, noise, k)


def bin_by_amplitude(curve: DecayCurve, n_points: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Means over ``n_points`` log-spaced amplitude bins, by increasing amplitude (empty bins dropped)."""
    a = curve.amplitude
    if a.size == 0:
        return np.empty(0), np.empty(0), np.empty(0)
    lo, hi = float(a.min()), float(a.max())
    if hi <= lo * (1 + 1e-12):
        return tuple(np.array([v.mean()]) for v in (a, curve.frequency_hz, curve.damping_ratio))
    edges = np.geomspace(lo, hi, n_points + 1)
    idx = np.clip(np.searchsorted(edges, a, side="right") - 1, 0, n_points - 1)
    counts = np.bincount(idx, minlength=n_points)
    used = counts > 0

    def mean(v):
        return (np.bincount(idx, weights=v, minlength=n_points)[used]) / counts[used]

    return mean(a), mean(curve.frequency_hz), mean(curve.damping_ratio)

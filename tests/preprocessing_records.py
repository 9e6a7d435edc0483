"""Generated hammer-test records for the preprocessing and mode tests (no files)."""

from __future__ import annotations

import numpy as np

FS = 5000.0


def modes_response(t, modes, phase=0.5):
    """Sum of ``a exp(-zeta w t) sin(w_d t + phase)`` for ``(frequency_hz, zeta, a)`` in ``modes``, zero for
    ``t < 0``."""
    out = np.zeros_like(t)
    after = t >= 0
    for f, zeta, a in modes:
        w = 2 * np.pi * f
        tt = t[after]
        out[after] += a * np.exp(-zeta * w * tt) * np.sin(w * np.sqrt(1 - zeta**2) * tt + phase)
    return out


def record(modes, *, duration=3.0, onset=0.2, offset=0.0, noise=1e-4, fs=FS, seed=0, phase=0.5):
    """A record: ``(t, y)`` with a pre-trigger of ``onset`` seconds, an offset and white noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(round(duration * fs))) / fs
    y = offset + modes_response(t - onset, modes, phase) + noise * rng.standard_normal(t.size)
    return t, y


def half_sine(n, start, width, amplitude=1.0):
    """A half-sine force pulse of ``width`` samples starting at ``start``, in ``n`` samples."""
    f = np.zeros(n)
    k = np.arange(width + 1)
    f[start : start + width + 1] = amplitude * np.sin(np.pi * k / width)
    return f


def pink_noise(n, rng, exponent=1.0):
    """Gaussian noise with a ``1 / f**exponent`` power spectrum, unit variance."""
    spectrum = np.fft.rfft(rng.standard_normal(n))
    f = np.fft.rfftfreq(n)
    f[0] = f[1]
    x = np.fft.irfft(spectrum / f ** (exponent / 2), n)
    return x / x.std()


def envelope_fit(y, fs, frequency_hz, weighted=True):
    """Frequency (Hz) and decay rate (1/s) of a single damped sinusoid: complex demodulation at
    ``frequency_hz``, moving average over 3 periods, straight lines through the phase and the log
    amplitude (weighted by the amplitude)."""
    t = np.arange(y.size) / fs
    z = y * np.exp(-2j * np.pi * frequency_hz * t)
    m = int(round(3 * fs / frequency_hz))
    zz = np.convolve(z, np.ones(m) / m, mode="valid")
    tt = t[(m - 1) // 2 : (m - 1) // 2 + zz.size]
    w = np.abs(zz) if weighted else None
    slope_phase = np.polyfit(tt, np.unwrap(np.angle(zz)), 1, w=w)[0]
    slope_amp = np.polyfit(tt, np.log(np.abs(zz)), 1, w=w)[0]
    return frequency_hz + slope_phase / (2 * np.pi), -slope_amp


def damper_record(case: dict):
    """The single-mode hammer test (``impact_record``) of a mode with an ``x^2 x'`` damper, from a dict of
    ``f0, zeta, fs, duration, snr_db, c2, seed`` (the cases of ``benchmarks/accuracy/model_backbone.py``'s
    damping row)."""
    from sindy_impulse import impact_record

    c = case
    return impact_record(c["f0"], c["zeta"], [1.0], fs=c["fs"], duration=c["duration"], snr_db=c["snr_db"],
                         damping_amplitude=c["c2"], random_state=c["seed"])

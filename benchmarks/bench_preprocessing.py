"""Benchmark of the hammer-test preprocessing: filter distortion, transient lengths, false peaks.

1. Distortion of a damped sinusoid by the zero-phase band-pass (FFT with Gaussian edges against
   Butterworth order 4 with sosfiltfilt): noise-free ring-downs at 5 kHz, 3 s (the modes decay to e^-7
   or the record ends), 6 random phases per case, band from ``peak_bands`` with the true half-power
   widths, transient trimmed at the 1e-3 impulse-response tolerance, kept until the mode is 80 dB down.
   Frequency and decay rate from a log-envelope fit (complex demodulation at the mode's frequency,
   3-period moving average, straight lines through phase and log amplitude), and the residual of the
   best fit of the exact mode ``exp(-sigma t) (a cos + b sin)(omega_d t)`` relative to its envelope: at
   the first kept sample and RMS over the kept samples. Worst over the phases.
2. False peaks of ``spectral_peaks`` on white, pink (1/f) and brown (1/f^2) Gaussian noise records of
   1,000, 4,000 and 20,000 samples (800, 400 and 100 records).

Run (from the repository root):
      PYTHONPATH=. python benchmarks/bench_preprocessing.py            (about a minute)
      PYTHONPATH=. python benchmarks/bench_preprocessing.py --quick    (distortion only)
"""

from __future__ import annotations

import argparse

import numpy as np

from sindy_impulse.preprocessing import bandpass, peak_bands, spectral_peaks, transient_samples

FS = 5000.0
CASES = {
    "one mode, damping 0.05 %": [(150.0, 0.0005)],
    "one mode, damping 0.3 %": [(150.0, 0.003)],
    "one mode, damping 1 %": [(150.0, 0.01)],
    "one mode, damping 3 %": [(150.0, 0.03)],
    "two modes 3 % apart, damping 0.2 %": [(150.0, 0.002), (154.5, 0.002)],
    "two modes 10 % apart, damping 1 %": [(150.0, 0.01), (165.0, 0.01)],
    "three modes (150, 230, 470 Hz)": [(150.0, 0.003), (230.0, 0.005), (470.0, 0.01)],
}


def envelope_fit(y, fs, f0):
    t = np.arange(y.size) / fs
    m = int(round(3 * fs / f0))
    z = np.convolve(y * np.exp(-2j * np.pi * f0 * t), np.ones(m) / m, mode="valid")
    tt = t[(m - 1) // 2 : (m - 1) // 2 + z.size]
    phase = np.polyfit(tt, np.unwrap(np.angle(z)), 1)[0]
    decay = -np.polyfit(tt, np.log(np.abs(z)), 1)[0]
    return f0 + phase / (2 * np.pi), decay


def relative_residual(y, t, sigma, omega_d):
    """Residual of the best exact damped sinusoid, over its envelope: (first sample, RMS)."""
    envelope = np.exp(-sigma * t)
    basis = np.column_stack([np.cos(omega_d * t), np.sin(omega_d * t)])
    coef = np.linalg.lstsq(basis, y / envelope, rcond=None)[0]
    r = (y / envelope - basis @ coef) / np.hypot(*coef)
    return abs(r[0]), float(np.sqrt(np.mean(r**2)))


def distortion(modes, method, rng, duration=3.0):
    t = np.arange(int(duration * FS)) / FS
    f, zeta = modes[0]
    band = peak_bands([m[0] for m in modes], [2 * m[1] * m[0] for m in modes], FS)[0]
    trim = transient_samples(FS, band, method=method)
    sigma, omega_d = zeta * 2 * np.pi * f, 2 * np.pi * f * np.sqrt(1 - zeta**2)
    stop = min(t.size - trim, int(np.log(1e4) / sigma * FS))
    errors = []
    for _ in range(6):
        phases = rng.uniform(0, 2 * np.pi, len(modes))
        y = sum(np.exp(-z * 2 * np.pi * fk * t) * np.sin(2 * np.pi * fk * np.sqrt(1 - z * z) * t + p)
                for (fk, z), p in zip(modes, phases))
        out = bandpass(y, FS, band, method=method)[trim:stop]
        f_hat, sigma_hat = envelope_fit(out, FS, f)
        errors.append((abs(f_hat * 2 * np.pi / omega_d - 1), abs(sigma_hat / sigma - 1),
                       *relative_residual(out, t[trim:stop], sigma, omega_d)))
    return np.max(errors, axis=0), trim * f / FS


def distortion_table():
    rng = np.random.default_rng(0)
    print("1. Band-pass distortion of the first mode (worst of 6 phases); trim in periods; residual relative")
    print("   to the envelope at the first kept sample / RMS over the kept samples")
    for method in ("fft", "butter"):
        print(f"\n   {method}\n   {'case':38s} {'df/f':>8s} {'dsig/sig':>9s} {'trim':>6s} {'residual':>17s}")
        for name, modes in CASES.items():
            (df, ds, r0, rr), trim = distortion(modes, method, rng)
            print(f"   {name:38s} {df:8.1e} {ds:9.1e} {trim:6.1f} {r0:8.1e} /{rr:8.1e}")


def pink(n, rng, exponent):
    spectrum = np.fft.rfft(rng.standard_normal(n))
    f = np.fft.rfftfreq(n)
    f[0] = f[1]
    return np.fft.irfft(spectrum / f ** (exponent / 2), n)


def false_peaks():
    rng = np.random.default_rng(5)
    print("\n2. False peaks on pure noise records (spectral_peaks, default threshold)")
    for name, exponent in (("white", 0.0), ("pink", 1.0), ("brown", 2.0)):
        found = records = 0
        for n, count in ((1000, 800), (4000, 400), (20000, 100)):
            for _ in range(count):
                found += len(spectral_peaks(pink(n, rng, exponent), FS))
                records += 1
        print(f"   {name:6s}: {found} false peak(s) in {records} records")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    distortion_table()
    if not args.quick:
        false_peaks()


if __name__ == "__main__":
    main()

"""A first classical look at the shipped flutter-rig free decays (numpy/scipy only).

For each record and channel (zero = rest level, decay window = from the first sample until the 0.5-s
moving peak falls below 20 x the rest noise):

* spectrum peaks: zero-padded Hann FFT of the decay window, peaks above 1 % of the largest in 0.5-30 Hz;
* per mode (band edges at the midpoint between the two modes): zero-phase Butterworth band-pass, then
  - Hilbert: damping ratio from a straight-line fit of log-envelope vs time where the envelope lies between
    70 % and 5 % of its maximum (0.5 s trimmed at both ends), and separately over its upper half
    (70-25 %) and lower half (25-5 %): a ratio that grows as the amplitude falls means amplitude-dependent
    (e.g. dry-friction) damping; frequency from the unwrapped-phase slope over the same samples;
  - log decrement: ln(A_k / A_k+n) / n over the same stretch of positive peaks;
  - half-power bandwidth of the (Hann-free) decay spectrum, zeta = df / (2 f);
* ESPRIT (Hankel SVD, 4 complex pairs) on the centered 2-channel record decimated to 50 Hz, first 8 s.

Run: python -m benchmarks flutter_rig_classical
"""

from __future__ import annotations

import argparse

import numpy as np
from scipy.signal import butter, find_peaks, hilbert, sosfiltfilt

from sindy_impulse.datasets import load_flutter_rig

TRIM_S = 0.5


def decay_window(y: np.ndarray, fs: float, noise: float) -> int:
    """Index where the 0.5-s moving peak of |y| first drops below 20 x the rest noise."""
    blk = int(0.5 * fs)
    peaks = np.array([np.abs(y[i : i + blk]).max() for i in range(0, y.size - blk, blk)])
    below = np.nonzero(peaks < 20 * noise)[0]
    return int(below[0] * blk) if below.size else y.size


def spectrum_peaks(y: np.ndarray, fs: float, n_fft: int = 2**18) -> list:
    spec = np.abs(np.fft.rfft(y * np.hanning(y.size), n_fft))
    f = np.fft.rfftfreq(n_fft, 1 / fs)
    band = (f > 0.5) & (f < 30)
    spec, f = spec[band], f[band]
    idx, _ = find_peaks(spec, prominence=0.01 * spec.max())
    return [(float(f[i]), 20 * np.log10(spec[i] / spec.max())) for i in idx]


def band(y: np.ndarray, fs: float, lo: float, hi: float) -> np.ndarray:
    return sosfiltfilt(butter(3, [lo, hi], "bandpass", fs=fs, output="sos"), y)


def envelope_fit(yb: np.ndarray, fs: float, upper: float, lower: float) -> tuple:
    """(zeta, f_d, n_samples) from log-envelope and phase slopes where upper > env/max > lower."""
    analytic = hilbert(yb)
    env = np.abs(analytic)
    n_trim = int(TRIM_S * fs)
    idx = np.arange(yb.size)
    rel = env / env[n_trim:-n_trim].max()
    sel = (idx > n_trim) & (idx < yb.size - n_trim) & (rel < upper) & (rel > lower)
    sel &= idx >= np.argmax(rel)
    if sel.sum() < 2 * fs / 10:
        return np.nan, np.nan, 0
    t = idx[sel] / fs
    sigma = -np.polyfit(t, np.log(env[sel]), 1)[0]
    omega_d = np.polyfit(t, np.unwrap(np.angle(analytic))[sel], 1)[0]
    return sigma / np.hypot(sigma, omega_d), omega_d / (2 * np.pi), int(sel.sum())


def log_decrement(yb: np.ndarray, fs: float, upper: float = 0.7, lower: float = 0.05) -> float:
    pk, _ = find_peaks(yb, distance=int(0.25 * fs / 3))
    pk = pk[(pk > TRIM_S * fs) & (pk < yb.size - TRIM_S * fs)]
    amp = yb[pk]
    keep = (amp < upper * amp.max()) & (amp > lower * amp.max()) & (pk >= pk[np.argmax(amp)])
    amp = amp[keep]
    if amp.size < 3:
        return np.nan
    delta = np.log(amp[0] / amp[-1]) / (amp.size - 1)
    return delta / np.sqrt(4 * np.pi**2 + delta**2)


def half_power(y: np.ndarray, fs: float, lo: float, hi: float, n_fft: int = 2**18) -> tuple:
    spec = np.abs(np.fft.rfft(y, n_fft)) ** 2
    f = np.fft.rfftfreq(n_fft, 1 / fs)
    sel = np.nonzero((f > lo) & (f < hi))[0]
    i = sel[np.argmax(spec[sel])]
    half = spec[i] / 2
    left, right = i, i
    while left > sel[0] and spec[left] > half:
        left -= 1
    while right < sel[-1] and spec[right] > half:
        right += 1
    if left == sel[0] or right == sel[-1]:
        return float(f[i]), np.nan
    return float(f[i]), (f[right] - f[left]) / (2 * f[i])


def esprit(x: np.ndarray, fs: float, order: int = 8) -> list:
    """(frequency Hz, damping ratio) of the complex poles of a multichannel free decay (Hankel SVD)."""
    n, rows = x.shape[0], x.shape[0] // 3
    blocks = [np.column_stack([x[i : i + n - rows, c] for i in range(rows)]) for c in range(x.shape[1])]
    hankel = np.vstack(blocks)
    _, _, vt = np.linalg.svd(hankel, full_matrices=False)
    v = vt[:order].T
    phi = np.linalg.lstsq(v[:-1], v[1:], rcond=None)[0]
    s = np.log(np.linalg.eigvals(phi).astype(complex)) * fs
    out = sorted({(round(abs(z.imag) / (2 * np.pi), 4), round(-z.real / abs(z), 4)) for z in s if z.imag > 0})
    return [p for p in out if 0.5 < p[0] < 20]


def backbone(yb: np.ndarray, fs: float, t_max: float) -> list:
    """Period-by-period (amplitude, frequency Hz, damping ratio) from successive positive peaks."""
    pk, _ = find_peaks(yb, distance=int(0.25 * fs))
    pk = pk[(pk > TRIM_S * fs) & (pk < t_max * fs) & (yb[pk] > 0)]
    a = yb[pk]
    d = np.log(a[:-1] / a[1:])
    return list(zip(a[:-1], fs / np.diff(pk), d / np.sqrt(4 * np.pi**2 + d**2)))


def survey_mode(name: str, y: np.ndarray, fs: float, lo: float, hi: float, t_max: float) -> dict:
    seg = y[: int(t_max * fs)]
    yb = band(seg, fs, lo, hi)
    z_all, fd, n = envelope_fit(yb, fs, 0.7, 0.05)
    z_hi, _, _ = envelope_fit(yb, fs, 0.7, 0.25)
    z_lo, _, _ = envelope_fit(yb, fs, 0.25, 0.05)
    f_hp, z_hp = half_power(seg, fs, lo, hi)
    print(
        f"    {name} ({lo:.2f}-{hi:.2f} Hz, first {t_max:.1f} s): f_d {fd:.3f} Hz; zeta Hilbert {z_all:.4f} "
        f"(envelope 70-25 %: {z_hi:.4f}, 25-5 %: {z_lo:.4f}); log-dec {log_decrement(yb, fs):.4f}; "
        f"half-power {z_hp:.4f} at {f_hp:.3f} Hz; {n / fs * fd:.0f} periods fitted"
    )
    rows = backbone(yb, fs, t_max - TRIM_S)
    if rows:
        a0 = rows[0][0]
        text = "; ".join(f"{a / a0:5.3f}: {f:.3f} Hz {z:.3f}" for a, f, z in rows[::2])
        print(f"      period by period (amplitude / first, f, zeta): {text}")
    return {"damped_frequency_hz": fd, "zeta_hilbert": z_all, "zeta_upper_half": z_hi,
            "zeta_lower_half": z_lo, "zeta_log_decrement": log_decrement(yb, fs), "zeta_half_power": z_hp,
            "half_power_hz": f_hp}


def survey_channel(y: np.ndarray, fs: float, noise: float) -> int:
    end = decay_window(y, fs, noise)
    seg = y[:end]
    snr = 20 * np.log10(np.abs(seg).max() / noise)
    peaks = ", ".join(f"{f:.3f} Hz ({db:.0f} dB)" for f, db in spectrum_peaks(seg, fs))
    print(f"    decay to 20 x noise in {end / fs:.2f} s, SNR {snr:.0f} dB (peak / rest-noise std)")
    print(f"    spectrum peaks: {peaks}")
    return end


def main(argv=None) -> dict:
    argparse.ArgumentParser(description=__doc__.splitlines()[0]).parse_args(argv)
    rig = load_flutter_rig()
    out = {}
    y = rig.centered()
    fs = rig.fs
    quiet = int(4.0 * fs)
    for r, name in enumerate(rig.records):
        nom = rig.nominal_frequency_hz[r]
        print(f"{name}: source's nominal uncoupled frequencies: heave {nom[0]:.2f} Hz, pitch {nom[1]:.2f} Hz")
        ends = []
        for c, (ch, unit) in enumerate(zip(rig.channels, rig.units)):
            noise = float(y[r, -quiet:, c].std())
            first = np.abs(y[r, :250, c]).max()
            print(f"  {ch} ({unit}): rest noise std {noise:.2e} {unit}, first peak {first:.3g}")
            ends.append(survey_channel(y[r, :, c], fs, noise))
        f1 = max(spectrum_peaks(y[r, : ends[0], 0], fs), key=lambda p: p[1])[0]
        split = f1 + 0.25
        print("  per mode:")
        out[name] = {
            "mode 1 in heave": survey_mode("mode 1 in heave", y[r, :, 0], fs, 1.6, split, ends[0] / fs),
            "mode 1 in pitch": survey_mode("mode 1 in pitch", y[r, :, 1], fs, 1.6, split, ends[1] / fs),
            "mode 2 in pitch": survey_mode("mode 2 in pitch", y[r, :, 1], fs, split, 3.6, 3.0)}
        dec = y[r, : int(8 * fs) : 10] / np.abs(y[r, : int(8 * fs)]).max(axis=0)
        poles = ", ".join(f"{f:.3f} Hz / {z:.4f}" for f, z in esprit(dec, fs / 10))
        print(f"  ESPRIT (both channels, 50 Hz, 8 s, 4 pole pairs; frequency / zeta): {poles}")
        out[name]["esprit"] = esprit(dec, fs / 10)
    return out


if __name__ == "__main__":
    main()

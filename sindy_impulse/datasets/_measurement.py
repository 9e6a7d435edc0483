"""The measurement chain of a synthetic record: a constant offset, white or pink noise, saturation."""

from __future__ import annotations

import numpy as np

__all__ = ["measure"]


def measure(y_clean, t, onset, offset_rel, snr_db, noise, rng, clip=None):
    """``y`` with offset and noise, the offset and the noise std per channel (all 2-D / 1-D per channel).

    ``offset`` is in units of each channel's peak clean amplitude; the noise std is the RMS of the clean
    signal over the first 10 % of the ring-down (from ``onset`` to the end) divided by ``10**(snr_db/20)``.
    ``clip`` (a fraction in (0, 1], or None) saturates the sensor after the noise is added:
    ``y = offset + np.clip(y - offset, -c, c)`` with ``c = clip * peak`` per channel.
    """
    peak = np.abs(y_clean).max(axis=0)
    offset = offset_rel * peak
    noise_std = np.zeros(y_clean.shape[1])
    y = y_clean + offset
    if snr_db is not None:
        ring = y_clean[int(np.searchsorted(t, onset)) :]
        first = ring[: max(1, int(np.ceil(0.1 * ring.shape[0])))]
        noise_std = np.sqrt(np.mean(first**2, axis=0)) / 10 ** (snr_db / 20)
        y = y + _noise(noise, y.shape, rng) * noise_std
    if clip is not None:
        c = clip * peak  # offset + clip(y - offset, -c, c); samples within the range stay bit for bit
        y = np.clip(y, offset - c, offset + c)
    return y, offset, noise_std


def _noise(kind: str, shape: tuple, rng) -> np.ndarray:
    """Unit-variance Gaussian white noise, or pink (1/f power) noise scaled to unit sample std."""
    if kind == "white":
        return rng.standard_normal(shape)
    n = shape[0]
    spec = rng.standard_normal((n // 2 + 1, shape[1])) + 1j * rng.standard_normal((n // 2 + 1, shape[1]))
    spec[0] = 0.0
    spec[1:] /= np.sqrt(np.arange(1, n // 2 + 1))[:, None]
    x = np.fft.irfft(spec, n=n, axis=0)
    return x / x.std(axis=0)

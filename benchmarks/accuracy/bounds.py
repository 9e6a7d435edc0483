"""Cramer-Rao standard deviations of a hammer record's modal values (used by
``benchmarks/accuracy/family_bounds.py``, which says what they mean): :func:`bound` for a free decay of
damped sinusoids, :func:`nonlinear_bound` for a record of :func:`impact_record` with a nonlinear element,
from the generator's own parameters."""

from __future__ import annotations

import numpy as np

from sindy_impulse import impact_record

#: The nonlinear element's parameters of family g, where drawn (zero: not in the record).
ELEMENT = ("cubic_stiffness", "damping_amplitude")


def free_decay(params: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """Sum of damped sinusoids; ``params`` rows ``(f_n, zeta, a, b)`` per mode, then the offset."""
    modes, offset = params[:-1].reshape(-1, 4), params[-1]
    y = np.full(tau.size, offset)
    for f, zeta, a, b in modes:
        omega = 2 * np.pi * f
        wd = omega * np.sqrt(max(1 - zeta**2, 0.0))
        y += np.exp(-zeta * omega * tau) * (a * np.cos(wd * tau) + b * np.sin(wd * tau))
    return y


def true_parameters(rec, tau: np.ndarray, clean: np.ndarray) -> np.ndarray:
    """The true frequencies and damping ratios, the amplitudes fitted to the clean free decay."""
    f = np.asarray(rec.modes.frequency_hz, float)
    z = np.asarray(rec.modes.damping_ratio, float)
    columns = [np.ones(tau.size)]
    for fi, zi in zip(f, z):
        omega = 2 * np.pi * fi
        wd, decay = omega * np.sqrt(1 - zi**2), np.exp(-zi * omega * tau)
        columns += [decay * np.cos(wd * tau), decay * np.sin(wd * tau)]
    coef = np.linalg.lstsq(np.column_stack(columns), clean, rcond=None)[0]
    rows = [(fi, zi, coef[1 + 2 * i], coef[2 + 2 * i]) for i, (fi, zi) in enumerate(zip(f, z))]
    return np.append(np.ravel(rows), coef[0])


def bound(rec) -> tuple[np.ndarray, np.ndarray]:
    """Cramer-Rao standard deviations of each mode's frequency and damping ratio (channel 0)."""
    start = rec.free_decay_index
    clean = rec.y_clean if rec.y_clean.ndim == 1 else rec.y_clean[:, 0]
    sigma = float(np.atleast_1d(rec.noise_std)[0])
    tau = (np.arange(clean.size - start)) / rec.fs
    theta = true_parameters(rec, tau, clean[start:])
    J = np.empty((tau.size, theta.size))
    for k in range(theta.size):
        h = 1e-6 * max(abs(theta[k]), 1e-12)
        up, down = theta.copy(), theta.copy()
        up[k] += h
        down[k] -= h
        J[:, k] = (free_decay(up, tau) - free_decay(down, tau)) / (2 * h)
    crb = np.linalg.pinv(J.T @ J / sigma**2)
    sd = np.sqrt(np.clip(np.diag(crb)[:-1].reshape(-1, 4), 0, None))
    return sd[:, 0], sd[:, 1]


def _clean_free_decay(config: dict) -> np.ndarray:
    rec = impact_record(**config)
    clean = rec.y_clean if rec.y_clean.ndim == 1 else rec.y_clean[:, 0]
    return clean[rec.free_decay_index:]


def nonlinear_bound(config: dict) -> tuple[np.ndarray, np.ndarray]:
    """Cramer-Rao standard deviations of each mode's linear natural frequency and damping ratio in a record
    of :func:`impact_record` with a nonlinear element (channel 0): its parameters are each mode's
    frequency, damping ratio and amplitude, the element's nonzero coefficients and the offset."""
    rec = impact_record(**config)
    sigma = float(np.atleast_1d(rec.noise_std)[0])
    n_modes = len(config["frequencies_hz"])
    names = [(key, i) for key in ("frequencies_hz", "damping_ratios", "amplitudes") for i in range(n_modes)]
    names += [(key, None) for key in ELEMENT if config.get(key, 0.0)]
    base = _clean_free_decay(config)
    J = np.empty((base.size, len(names) + 1))
    for k, (key, i) in enumerate(names):
        value = config[key][i] if i is not None else config[key]
        h = 1e-6 * abs(value)
        columns = []
        for step in (h, -h):
            moved = {**config, key: float(value + step)}
            if i is not None:
                moved[key] = list(config[key])
                moved[key][i] = float(value + step)
            columns.append(_clean_free_decay(moved))
        J[:, k] = (columns[0] - columns[1]) / (2 * h)
    J[:, -1] = 1.0  # the offset
    crb = np.linalg.pinv(J.T @ J / sigma**2)
    sd = np.sqrt(np.clip(np.diag(crb), 0, None))
    return sd[:n_modes], sd[n_modes:2 * n_modes]

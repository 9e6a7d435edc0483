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


def _clean(rec) -> np.ndarray:
    """The clean record's free decay (channel 0)."""
    clean = rec.y_clean if rec.y_clean.ndim == 1 else rec.y_clean[:, 0]
    return clean[rec.free_decay_index:]


def _standard_deviations(J: np.ndarray, rec) -> np.ndarray:
    """Square roots of the diagonal of the inverse Fisher information ``J^T J / sigma^2`` (the record's noise
    of channel 0)."""
    sigma = float(np.atleast_1d(rec.noise_std)[0])
    return np.sqrt(np.clip(np.diag(np.linalg.pinv(J.T @ J / sigma**2)), 0, None))


def bound(rec) -> tuple[np.ndarray, np.ndarray]:
    """Cramer-Rao standard deviations of each mode's frequency and damping ratio (channel 0)."""
    clean = _clean(rec)
    tau = np.arange(clean.size) / rec.fs
    theta = true_parameters(rec, tau, clean)
    J = np.empty((tau.size, theta.size))
    for k in range(theta.size):
        h = 1e-6 * max(abs(theta[k]), 1e-12)
        up, down = theta.copy(), theta.copy()
        up[k] += h
        down[k] -= h
        J[:, k] = (free_decay(up, tau) - free_decay(down, tau)) / (2 * h)
    sd = _standard_deviations(J, rec)[:-1].reshape(-1, 4)
    return sd[:, 0], sd[:, 1]


def _moved(config: dict, key: str, i: int | None, value: float) -> dict:
    """``config`` with ``config[key]`` (its ``i``-th value where given) set to ``value``."""
    moved = dict(config)
    if i is None:
        moved[key] = value
    else:
        moved[key] = list(config[key])
        moved[key][i] = value
    return moved


def nonlinear_bound(config: dict) -> tuple[np.ndarray, np.ndarray]:
    """Cramer-Rao standard deviations of each mode's linear natural frequency and damping ratio in a record
    of :func:`impact_record` with a nonlinear element (channel 0): its parameters are each mode's
    frequency, damping ratio and amplitude, the element's nonzero coefficients and the offset."""
    rec = impact_record(**config)
    n_modes = len(config["frequencies_hz"])
    names = [(key, i) for key in ("frequencies_hz", "damping_ratios", "amplitudes") for i in range(n_modes)]
    names += [(key, None) for key in ELEMENT if config.get(key, 0.0)]
    J = np.empty((_clean(rec).size, len(names) + 1))
    for k, (key, i) in enumerate(names):
        value = float(config[key] if i is None else config[key][i])
        h = 1e-6 * abs(value)
        up, down = (_clean(impact_record(**_moved(config, key, i, value + s))) for s in (h, -h))
        J[:, k] = (up - down) / (2 * h)
    J[:, -1] = 1.0  # the offset
    sd = _standard_deviations(J, rec)
    return sd[:n_modes], sd[n_modes:2 * n_modes]

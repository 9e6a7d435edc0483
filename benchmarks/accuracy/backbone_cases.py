"""The free decays of the backbone benchmark and their true backbones (first-order averaging).

The decays of ``x'' + (c0 + c2 x^2) x' + w0^2 x + k3 x^3 = 0`` at 10 Hz, 20 samples per period, integrated
by the compiled simulator (:class:`~sindy_impulse.simulation.CompiledModel`) from amplitude 1; the true
backbone is ``w(a)^2 = w0^2 + 3/4 k3 a^2``, ``zeta(a) = (c0 + c2 a^2 / 4) / (2 w(a))``. The same cases as
``tests/test_backbone.py`` (which keeps its own copy: tests do not import benchmarks): :data:`CASES`,
:func:`noisy` (40 dB), :class:`TrueModel` (the true equations as a fitted model) and :func:`errors` (the
errors over the middle 80 % of a curve's amplitude range).
"""

from __future__ import annotations

import functools

import numpy as np

from sindy_impulse.datasets import add_noise
from sindy_impulse.feature_library import TermTable
from sindy_impulse.simulation import CompiledModel

F0, SPP = 10.0, 20
W0 = 2 * np.pi * F0
TERMS = TermTable.polynomial([[1, 0], [0, 1], [3, 0], [2, 1]])  # x, v, x^3, x^2 v

#: name: (zeta0, frequency shift at a=1, damping-ratio factor at a=1, periods)
CASES = {
    "duffing": (0.002, 0.05, 1.0, 1500),
    "amplitude_damping": (0.001, 0.0, 2.5, 3000),
    "combined": (0.005, 0.04, 2.5, 600),
    "combined_1pct": (0.01, 0.1, 5.0, 300),
}
#: what each case tests: the frequency shift, the damping change, or both
SHIFTS = {"duffing": ("f",), "amplitude_damping": ("z",), "combined": ("f", "z"), "combined_1pct": ("f", "z")}


def coefficients(zeta, shift, factor):
    k3 = ((1 + shift) ** 2 - 1) * W0**2 / 0.75
    c0 = 2 * zeta * W0
    return np.array([[0.0, 1.0, 0.0, 0.0], [-(W0**2), -c0, -k3, -(factor - 1) * 4 * c0]])


def truth_of(zeta, shift, factor):
    coef = coefficients(zeta, shift, factor)
    k3, c0, c2 = -coef[1, 2], -coef[1, 1], -coef[1, 3]

    def truth(a):
        w = np.sqrt(W0**2 + 0.75 * k3 * a**2)
        return w / (2 * np.pi), (c0 + c2 * a**2 / 4) / (2 * w)

    return truth


@functools.cache
def decay(name, phase=0.0):
    """Clean free decay from amplitude 1 (states x, v) and its time vector."""
    zeta, shift, factor, periods = CASES[name]
    compiled = CompiledModel(coefficients(zeta, shift, factor), TERMS)
    t = np.arange(periods * SPP) / (SPP * F0)
    w = W0 * (1 + shift)
    x = compiled.simulate([np.cos(phase), -w * np.sin(phase)], t)
    return t, x


def noisy(name, seed=0, phase=0.0):
    t, x = decay(name, phase)
    return t, add_noise(x[:, 0], 40, random_state=seed)


class TrueModel:
    """A stand-in for a fitted model: the true equations, with simulate/coefficients/t_/x_filtered_."""

    def __init__(self, name, order=(0, 1)):
        zeta, shift, factor, _ = CASES[name]
        self.order = list(order)
        self.compiled = CompiledModel(coefficients(zeta, shift, factor), TERMS)
        self.t_, x = decay(name)
        self.x_filtered_ = x[:, self.order]

    def simulate(self, x0, t):
        back = np.argsort(self.order)
        return self.compiled.simulate(np.asarray(x0)[back], t)[:, self.order]

    def coefficients(self):
        return self.compiled.full_coefficients


def errors(curve, truth):
    """Largest relative errors over the middle 80 % of the amplitude range, and of the total shifts."""
    a = curve.amplitude
    lo, hi = a.min(), a.max()
    mid = (a >= lo + 0.1 * (hi - lo)) & (a <= hi - 0.1 * (hi - lo))
    f_true, z_true = truth(a)
    i, j = np.argmin(a), np.argmax(a)
    true_f_shift, true_z_shift = f_true[j] / f_true[i] - 1, z_true[j] / z_true[i] - 1
    return {
        "f": np.max(np.abs(curve.frequency_hz[mid] / f_true[mid] - 1)),
        "z": np.max(np.abs(curve.damping_ratio[mid] / z_true[mid] - 1)),
        "f_shift": abs(curve.frequency_shift / true_f_shift - 1) if true_f_shift else np.inf,
        "z_shift": abs(curve.damping_ratio_shift / true_z_shift - 1) if true_z_shift else np.inf,
        "true_f_shift": true_f_shift,
        "true_z_shift": true_z_shift,
        "n_mid": int(mid.sum()),
    }

"""Reference simulations for the speed figures of ``benchmarks/speed/speed.py``.

- :func:`minimal_rk4`: the minimal numba RK4 of a given polynomial model -- its right-hand side written out
  by hand with scalar states (what one would write for this one model), the same sub-steps as ours. It is
  the floor a general simulator can approach.
- :func:`python_rk4`: the same RK4 as a plain Python loop (the naive baseline).
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def _rk4_linear(x0, t, substeps, a, b, c, out):
    """x0' = a x1, x1' = b x0 + c x1 (the paper's 3-term model)."""
    p, q = x0[0], x0[1]
    out[0, 0], out[0, 1] = p, q
    for s in range(1, t.shape[0]):
        h = (t[s] - t[s - 1]) / substeps
        for _ in range(substeps):
            k1p, k1q = a * q, b * p + c * q
            y0, y1 = p + 0.5 * h * k1p, q + 0.5 * h * k1q
            k2p, k2q = a * y1, b * y0 + c * y1
            y0, y1 = p + 0.5 * h * k2p, q + 0.5 * h * k2q
            k3p, k3q = a * y1, b * y0 + c * y1
            y0, y1 = p + h * k3p, q + h * k3q
            k4p, k4q = a * y1, b * y0 + c * y1
            p += h / 6.0 * (k1p + 2.0 * k2p + 2.0 * k3p + k4p)
            q += h / 6.0 * (k1q + 2.0 * k2q + 2.0 * k3q + k4q)
        out[s, 0], out[s, 1] = p, q
    return out


@njit(cache=True)
def _rk4_duffing(x0, t, substeps, a, b, c, d, out):
    """x0' = a x1, x1' = b x0 + c x1 + d x0^3 (a 4-term nonlinear model)."""
    p, q = x0[0], x0[1]
    out[0, 0], out[0, 1] = p, q
    for s in range(1, t.shape[0]):
        h = (t[s] - t[s - 1]) / substeps
        for _ in range(substeps):
            k1p, k1q = a * q, b * p + c * q + d * p * p * p
            y0, y1 = p + 0.5 * h * k1p, q + 0.5 * h * k1q
            k2p, k2q = a * y1, b * y0 + c * y1 + d * y0 * y0 * y0
            y0, y1 = p + 0.5 * h * k2p, q + 0.5 * h * k2q
            k3p, k3q = a * y1, b * y0 + c * y1 + d * y0 * y0 * y0
            y0, y1 = p + h * k3p, q + h * k3q
            k4p, k4q = a * y1, b * y0 + c * y1 + d * y0 * y0 * y0
            p += h / 6.0 * (k1p + 2.0 * k2p + 2.0 * k3p + k4p)
            q += h / 6.0 * (k1q + 2.0 * k2q + 2.0 * k3q + k4q)
        out[s, 0], out[s, 1] = p, q
    return out


def minimal_rk4(coefficients: dict, x0, t, substeps: int) -> np.ndarray:
    """The hand-written numba RK4 of ``{"a": .., "b": .., "c": .., "d": ..}`` (``d`` the cubic term)."""
    out = np.empty((len(t), 2))
    x0 = np.ascontiguousarray(x0, dtype=float)
    t = np.ascontiguousarray(t, dtype=float)
    a, b, c, d = (float(coefficients.get(k, 0.0)) for k in "abcd")
    if d == 0.0:
        return _rk4_linear(x0, t, int(substeps), a, b, c, out)
    return _rk4_duffing(x0, t, int(substeps), a, b, c, d, out)


def python_rk4(coefficients: dict, x0, t, substeps: int) -> np.ndarray:
    """The same RK4 as a plain Python loop."""
    a, b, c, d = (float(coefficients.get(k, 0.0)) for k in "abcd")

    def f(p, q):
        return a * q, b * p + c * q + d * p**3

    p, q = float(x0[0]), float(x0[1])
    out = [(p, q)]
    for s in range(1, len(t)):
        h = (t[s] - t[s - 1]) / substeps
        for _ in range(substeps):
            k1 = f(p, q)
            k2 = f(p + 0.5 * h * k1[0], q + 0.5 * h * k1[1])
            k3 = f(p + 0.5 * h * k2[0], q + 0.5 * h * k2[1])
            k4 = f(p + h * k3[0], q + h * k3[1])
            p += h / 6.0 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            q += h / 6.0 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        out.append((p, q))
    return np.array(out)

"""Integrators of a compiled model: fixed-step RK4 kernels (the hot path) and an adaptive fallback.

The numba kernels integrate ``x' = coef @ Theta([x, u(t)])`` on the data's time grid with ``substeps``
equal classical Runge-Kutta steps per sample interval; control inputs ``u`` given on the same grid are
interpolated linearly inside each interval. A trajectory that leaves the admissible box (``bound`` per
state) or becomes non-finite is stopped at once, so every simulation takes bounded time.

``weighted_l1`` is the fused kernel every built-in error measure uses: it restarts the simulation from the
reference state at each segment start (one segment: the paper's simulation from the first sample; several:
multiple shooting) and accumulates ``sum weights[segment, state] * |x_sim - x_ref|`` without storing the
trajectory, for a batch of coefficient matrices in one call.

``solve_ivp_simulate`` is the adaptive path: SciPy's ``solve_ivp`` on the compiled right-hand side, used for
stiff models (more RK4 sub-steps than :data:`MAX_SUBSTEPS` would be needed) and when a caller asks for
PySINDy's integrator options.

Numba is a dependency because it pays: one simulation of the paper's 401-sample oscillator takes tens of
microseconds against seconds for ``pysindy.SINDy.simulate`` (``benchmarks/``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["rk4_simulate", "weighted_l1", "rhs_points", "solve_ivp_simulate", "MAX_SUBSTEPS", "NO_INPUT"]

#: Most RK4 sub-steps per sample interval; a model that needs more is stiff (adaptive path).
MAX_SUBSTEPS = 256
#: The empty input array (a model without control inputs).
NO_INPUT = np.empty((0, 0))


@njit(cache=True, inline="always")
def _rhs(z, coef, fp, fs, fn, fst, fpar, out):
    """``coef @ Theta(z)`` over the active terms (see :mod:`sindy_impulse.simulation.terms`)."""
    for i in range(coef.shape[0]):
        out[i] = 0.0
    for k in range(fp.shape[0] - 1):
        v = 1.0
        for q in range(fp[k], fp[k + 1]):
            v *= z[fs[q]]
        f = fn[k]
        if f != 0:
            zv = z[fst[k]]
            if f == 1:
                v *= zv * abs(zv)
            elif f == 2:
                v *= math.tanh(zv / fpar[k])
            elif f == 3:
                v *= abs(zv)
            elif f == 4:
                v *= math.sin(fpar[k] * zv)
            else:
                v *= math.cos(fpar[k] * zv)
        for i in range(coef.shape[0]):
            out[i] += coef[i, k] * v


@njit(cache=True)
def rhs_points(Z, coef, fp, fs, fn, fst, fpar):
    """Right-hand side at every row of ``Z`` (n_points, n_inputs)."""
    out = np.empty((Z.shape[0], coef.shape[0]))
    for r in range(Z.shape[0]):
        _rhs(Z[r], coef, fp, fs, fn, fst, fpar, out[r])
    return out


@njit(cache=True, inline="always")
def _inputs_at(z, n, u, s, frac):
    """Control inputs interpolated linearly at ``t[s-1] + frac * (t[s] - t[s-1])`` into ``z[n:]``."""
    for q in range(u.shape[1]):
        a = u[s - 1, q]
        z[n + q] = a + frac * (u[s, q] - a)


@njit(cache=True, inline="always")
def _advance(x, t, s, substeps, coef, fp, fs, fn, fst, fpar, u, k1, k2, k3, k4, z):
    """Integrate ``x`` in place from ``t[s-1]`` to ``t[s]`` with ``substeps`` RK4 steps."""
    n = x.shape[0]
    h = (t[s] - t[s - 1]) / substeps
    has_u = u.shape[0] > 0
    for j in range(substeps):
        for i in range(n):
            z[i] = x[i]
        if has_u:
            _inputs_at(z, n, u, s, j / substeps)
        _rhs(z, coef, fp, fs, fn, fst, fpar, k1)
        for i in range(n):
            z[i] = x[i] + 0.5 * h * k1[i]
        if has_u:
            _inputs_at(z, n, u, s, (j + 0.5) / substeps)
        _rhs(z, coef, fp, fs, fn, fst, fpar, k2)
        for i in range(n):
            z[i] = x[i] + 0.5 * h * k2[i]
        _rhs(z, coef, fp, fs, fn, fst, fpar, k3)
        for i in range(n):
            z[i] = x[i] + h * k3[i]
        if has_u:
            _inputs_at(z, n, u, s, (j + 1.0) / substeps)
        _rhs(z, coef, fp, fs, fn, fst, fpar, k4)
        for i in range(n):
            x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])


@njit(cache=True)
def rk4_simulate(x0, t, substeps, coef, fp, fs, fn, fst, fpar, bound, u, out):
    """RK4 from ``x0`` over the grid ``t`` into ``out`` (len(t), n_states); returns the valid rows.

    Rows after a divergence (a state beyond ``bound`` or not finite) are NaN.
    """
    n = x0.shape[0]
    n_z = n + u.shape[1]
    k1, k2, k3, k4, z = np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n_z)
    x = x0.copy()
    out[0, :] = x
    for s in range(1, t.shape[0]):
        _advance(x, t, s, substeps, coef, fp, fs, fn, fst, fpar, u, k1, k2, k3, k4, z)
        for j in range(n):
            if not (abs(x[j]) <= bound[j]):  # also true for NaN
                out[s:, :] = np.nan
                return s
            out[s, j] = x[j]
    return t.shape[0]


@njit(cache=True)
def weighted_l1(ref, t, starts, weights, substeps, coefs, fp, fs, fn, fst, fpar, bound, u):
    """Weighted L1 error of simulations restarted from ``ref`` at each segment start, per model.

    Segment ``k`` starts at sample ``starts[k]`` from ``ref[starts[k]]`` and runs through the next start
    (or the last sample); each sample's error ``|x - ref|`` of state ``j`` is weighted by
    ``weights[k, j]``. Returns ``(errors, rows)`` per coefficient matrix of ``coefs``: the error (``inf`` if
    a segment diverged) and the number of sample intervals simulated (the work done).
    """
    n = ref.shape[1]
    n_t = t.shape[0]
    n_seg = starts.shape[0]
    k1, k2, k3, k4, z = np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n + u.shape[1])
    x = np.empty(n)
    errors = np.empty(coefs.shape[0])
    rows = np.zeros(coefs.shape[0], dtype=np.int64)
    for b in range(coefs.shape[0]):
        total = 0.0
        for k in range(n_seg):
            s0 = starts[k]
            s1 = starts[k + 1] if k + 1 < n_seg else n_t - 1
            for j in range(n):
                x[j] = ref[s0, j]
            for s in range(s0 + 1, s1 + 1):
                _advance(x, t, s, substeps, coefs[b], fp, fs, fn, fst, fpar, u, k1, k2, k3, k4, z)
                rows[b] += 1
                for j in range(n):
                    if not (abs(x[j]) <= bound[j]):
                        total = np.inf
                        break
                    total += weights[k, j] * abs(x[j] - ref[s, j])
                if total == np.inf:
                    break
            if total == np.inf:
                break
        errors[b] = total
    return errors, rows


#: Most right-hand-side evaluations per output sample the adaptive integrator may spend (a stiff solver on a
#: smooth response needs a few; a model that needs more is treated as diverged, so nothing runs unbounded).
MAX_EVALUATIONS_PER_SAMPLE = 40


class _TooManyEvaluations(Exception):
    pass


def solve_ivp_simulate(rhs, x0, t, u=None, bound=None, max_evaluations=None, **kws) -> tuple[np.ndarray, int]:
    """Adaptive integration with :func:`scipy.integrate.solve_ivp` (LSODA by default).

    Parameters
    ----------
    rhs : callable
        ``rhs(z) -> x_dot`` for one input vector ``z = [x, u]``.
    x0 : ndarray (n_states,)
    t : ndarray (n_times,)
    u : ndarray (n_times, n_inputs) or callable ``u(t)``, optional
        Inputs on the grid (interpolated linearly) or a function of time.
    bound : ndarray (n_states,), optional
        Stop (NaN rows) once a state exceeds its bound.
    max_evaluations : int, optional
        Stop (NaN rows) after this many right-hand-side evaluations (default
        ``MAX_EVALUATIONS_PER_SAMPLE * len(t)``); None-equivalent for callers passing ``float("inf")``.
    **kws
        Passed to ``solve_ivp`` (default ``method="LSODA", rtol=1e-10, atol=1e-12``).

    Returns
    -------
    (states, n_evaluations)
        ``states`` (len(t), n_states) with NaN rows after a divergence or a failure.
    """
    from scipy.integrate import solve_ivp

    x0 = np.asarray(x0, dtype=float)
    if u is None:
        u_at = None
    elif callable(u):
        u_at = u
    else:
        u_arr = np.asarray(u, dtype=float)

        def u_at(tt):
            return np.array([np.interp(tt, t, u_arr[:, q]) for q in range(u_arr.shape[1])])

    limit = MAX_EVALUATIONS_PER_SAMPLE * len(t) if max_evaluations is None else max_evaluations
    count = [0]

    def f(tt, x):
        count[0] += 1
        if count[0] > limit:
            raise _TooManyEvaluations
        z = x if u_at is None else np.concatenate([x, np.ravel(u_at(tt))])
        return rhs(z)

    events = None
    if bound is not None:

        def escaped(tt, x):
            return float(np.min(bound - np.abs(x))) if np.all(np.isfinite(x)) else -1.0

        escaped.terminal = True
        events = escaped
    options = {"method": "LSODA", "rtol": 1e-10, "atol": 1e-12}
    options.update(kws)
    out = np.full((len(t), x0.size), np.nan)
    try:
        sol = solve_ivp(f, (t[0], t[-1]), x0, t_eval=t, events=events, **options)
        m = sol.y.shape[1]
        out[:m] = sol.y.T
    except (_TooManyEvaluations, ValueError, ArithmeticError, np.linalg.LinAlgError):
        pass
    return out, count[0]

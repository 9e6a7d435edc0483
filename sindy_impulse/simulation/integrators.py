"""Integrators of a compiled model: the fixed-step RK4 kernel (the hot path) and an adaptive fallback.

:func:`integrate` integrates ``x' = coef @ Theta([x, u(t)])`` on a time grid with ``substeps`` equal
classical Runge-Kutta steps per grid interval; control inputs ``u`` given on the same grid are interpolated
linearly inside each interval. A trajectory that leaves the admissible box (``bound`` per state) or becomes
non-finite is stopped at once, so every simulation takes bounded time. It either stores the trajectory
(``simulate``) or, the fused path every built-in error measure uses, restarts the simulation from the
reference state at each segment start (one segment: the paper's simulation from the first sample;
several: multiple shooting) and accumulates ``sum weights[segment, state] * |x_sim - x_ref|`` without
storing the trajectory, for a batch of coefficient rows in one call.

A model reaches the kernel as a *program* (:mod:`.program`): its monomials as a product tree
(``theta[q] = theta[parent[q]] * z[var[q]]``, ``theta[0] = 1``), so a term costs one multiplication
whatever its degree; its non-polynomial factors (``x|x|``, ``tanh``, ``|x|``, ``sin``, ``cos``) appended
after the monomials; and its non-zero coefficients per equation in compressed rows (``eq_ptr``,
``slot``) with one row of values per model of a batch. Only non-zero coefficients cost work.

A linear model without inputs (every term ``x_j`` or the constant) integrated by RK4 is a linear map per
grid interval: ``x_s = M x_{s-1}`` with ``M = P(hA)^substeps`` and ``P`` RK4's stability polynomial.
The kernel then applies ``M`` (the *propagator*) instead of the stages: the same RK4 solution (to
rounding) at a fraction of the cost; :func:`integrate_linear` is that loop on its own.

The kernel allocates nothing (the caller passes scratch space), which keeps its compilation short, and is
cached on disk by numba (:mod:`sindy_impulse._utils.warmup` builds the cache in the background on a machine's
first import).

``solve_ivp_simulate`` is the adaptive path: SciPy's ``solve_ivp`` on the right-hand side, used for stiff
models (more RK4 sub-steps than :data:`MAX_SUBSTEPS` would be needed) and when a caller asks for
PySINDy's integrator options.
"""

from __future__ import annotations

import math

import numpy as np

from .._utils.jit import jit, kernel

__all__ = [
    "integrate",
    "integrate_batch",
    "integrate_linear",
    "segment_loop",
    "solve_ivp_simulate",
    "scratch_size",
    "MAX_SUBSTEPS",
    "NO_INPUT",
    "NO_PROPAGATOR",
]

#: Most RK4 sub-steps per sample interval; a model that needs more is stiff (adaptive path).
MAX_SUBSTEPS = 256
#: The empty input array (a model without control inputs).
NO_INPUT = np.empty((0, 0))
#: The empty propagator batch (a model integrated stage by stage).
NO_PROPAGATOR = np.empty((0, 0, 0))


def scratch_size(n_z: int, n_values: int) -> int:
    """Floats of scratch space the kernels need for ``n_z`` inputs and ``n_values`` term values.

    Layout: the stage accumulator, the state at a step's start, the current state and a stage's
    derivative (``n_z`` each), then the term values (the constant 1, the inputs of a stage, the other
    monomials and terms).
    """
    return 4 * n_z + n_values


@jit(cache=False, inline="always")
def _scratch(work, n, u):
    """The parts of the scratch space ``work`` (rows: the layout of :func:`scratch_size`) for ``n`` states
    and the inputs ``u``: ``(n_z, acc, x_old, x, dx, theta, z)``, ``z`` the inputs' slots in ``theta``.

    The RK4 steps' one place of that layout (the kernels slice only the state's slots ``x_old`` and
    ``x``: through this helper they compiled to slightly slower code, about 2-3 % in one measurement).
    Inlined where it is called (numba's ``inline="always"``), so the views are made as if sliced in the
    caller, without a call.
    """
    n_z = n + u.shape[1]
    acc = work[0:n]
    x_old = work[n_z : n_z + n]
    x = work[2 * n_z : 2 * n_z + n]
    dx = work[3 * n_z : 3 * n_z + n]
    theta = work[4 * n_z :]
    z = theta[1 : 1 + n_z]  # the inputs are the first monomials
    return n_z, acc, x_old, x, dx, theta, z


@kernel
def integrate(ref, t, starts, weights, substeps, prog, vals, props, bound, u, work, out, errors, rows):
    """Simulate a batch of models over the grid ``t``, restarted from ``ref`` at each segment start.

    Segment ``k`` starts at sample ``starts[k]`` from ``ref[starts[k]]`` and runs through the next start
    (or the last sample). Model ``b`` has the coefficient row ``vals[b]`` (and propagator ``props[b]``,
    if ``props`` is not empty). With an empty ``out`` each sample's error ``|x - ref|`` of state ``j`` is
    weighted by ``weights[k, j]`` and summed into ``errors[b]`` (``inf`` once a segment diverged); else
    the trajectory of the (single) model is written into ``out``, NaN after a divergence. ``rows[b]`` is
    the number of grid intervals simulated (the work done). The loop is :func:`segment_loop`'s with
    :func:`_rk4_interval`; two-state cubic models take :func:`.two_state_cubic.integrate_cubic2`.
    """
    n = ref.shape[1]
    n_z = n + u.shape[1]
    x_old = work[n_z : n_z + n]
    x = work[2 * n_z : 2 * n_z + n]
    model = (prog, vals, u, work)
    n_models = vals.shape[0]
    _integrate_program(
        ref, t, starts, weights, substeps, n_models, model, props, bound, x, x_old, out, errors, rows
    )


@kernel
def integrate_linear(ref, t, starts, weights, props, bound, out, errors, rows):
    """:func:`integrate` for linear models, by their propagators ``props`` (one per model of the batch,
    for the grid intervals of ``t``).

    :func:`segment_loop`'s loop on its own, its :func:`propagate` and :func:`account` inlined: the same
    errors, rows and trajectories to the last bit as the general kernel's, in half the time (a linear
    model's interval is a few multiplications: the general kernel's calls cost as much).
    """
    n = ref.shape[1]
    x = np.empty(n)
    x_old = np.empty(n)
    _propagated(ref, t, starts, weights, 0, props.shape[0], 0, props, bound, x, x_old, out, errors, rows)


def segment_loop(interval):
    """The loop of the simulation kernels over models, segments and grid intervals, around one interval step.

    ``interval(x, t, s, substeps, model, b)`` integrates the state ``x`` of model ``b`` of the batch
    ``model`` (its coefficients and whatever else the step needs) in place from ``t[s-1]`` to ``t[s]``.
    The returned function runs :func:`integrate`'s loop with it: ``loop(ref, t, starts, weights, substeps,
    n_models, model, props, bound, x, x_old, out, errors, rows)``, the arguments of :func:`integrate`
    plus the number of models and the state's two slots of scratch space ``x`` and ``x_old``.

    Each kind of model (the general program, the two-state cubic) has one kernel: this loop around its own
    step, so that neither kernel compiles the other's arithmetic and the step is called directly. The loop
    is inlined into the kernel when the kernel compiles (numba's ``inline="always"``) and cached on disk as
    part of it: compiled on its own it cost each kernel one more optimisation of all its code (measured:
    +1.1 s and +2.0 s of compile time for the two-state cubic and the general kernel), and numba cannot
    cache a function that closes over another. As for any function a kernel calls, numba's cache of a
    kernel follows its own source file only: after editing this loop, clear the cache of
    :func:`.two_state_cubic.integrate_cubic2`.
    """

    @jit(cache=False, inline="always")
    def loop(ref, t, starts, weights, substeps, n_models, model, props, bound, x, x_old, out, errors, rows):
        store = out.shape[0] > 0
        for b in range(n_models):
            total = 0.0
            done = 0
            for k in range(starts.shape[0]):
                s0 = starts[k]
                s1 = starts[k + 1] if k + 1 < starts.shape[0] else t.shape[0] - 1
                for i in range(x.shape[0]):
                    x[i] = ref[s0, i]
                    if store:
                        out[s0, i] = x[i]
                for s in range(s0 + 1, s1 + 1):
                    if props.shape[0] > 0:  # RK4's map over the interval
                        propagate(x, x_old, props, b)
                    else:
                        interval(x, t, s, substeps, model, b)
                    done += 1
                    total = account(x, s, k, ref, weights, bound, out, total)
                    if total == np.inf:
                        break
                if total == np.inf:
                    break
            errors[b] = total
            rows[b] = done

    return loop


@jit(cache=False, _nrt=False, inline="always")
def propagate(x, x_old, props, b):
    """One grid interval of a linear model: ``x <- props[b] @ [x, 1]`` (RK4's map, see the module)."""
    n = x.shape[0]
    for i in range(n):
        x_old[i] = x[i]
    for i in range(n):
        d = props[b, i, n] if props.shape[2] > n else 0.0
        for q in range(n):
            d += props[b, i, q] * x_old[q]
        x[i] = d


@jit(cache=False, _nrt=False, inline="always")
def account(x, s, k, ref, weights, bound, out, total):
    """The state ``x`` at sample ``s`` of segment ``k``: stored in ``out`` (if not empty) or its weighted
    error added to ``total``; ``inf`` (and NaN rows from ``s`` on) once it left the bounds."""
    for i in range(x.shape[0]):
        if not (abs(x[i]) <= bound[i]):  # diverged (also true for NaN)
            for r in range(s, out.shape[0]):  # (loops, not slicing: less code to compile)
                for q in range(x.shape[0]):
                    out[r, q] = np.nan
            return np.inf
        if out.shape[0] > 0:
            out[s, i] = x[i]
        else:
            total += weights[k, i] * abs(x[i] - ref[s, i])
    return total


# The RK4 interval runs without numba's reference counting (``_nrt=False``): with it, every call passing
# arrays would cost more than the arithmetic of a small model.


@jit(_nrt=False)
def _rk4_interval(x, t, s, substeps, model, b):
    """Integrate ``x`` in place from ``t[s-1]`` to ``t[s]`` with ``substeps`` RK4 steps of model ``b`` of
    ``model = (prog, vals, u, work)`` (:func:`integrate`'s arguments)."""
    prog, values, u, work = model
    vals = values[b]
    parent, var, fcode, fslot, finput, fparam, eq_ptr, slot = prog
    n = x.shape[0]
    n_z, acc, x_old, _, dx, theta, z = _scratch(work, n, u)
    n_mono = parent.shape[0]
    theta[0] = 1.0
    h = (t[s] - t[s - 1]) / substeps
    for j in range(substeps):
        for i in range(n):
            x_old[i] = x[i]
            z[i] = x[i]
            acc[i] = 0.0
        for stage in range(4):
            if n_z > n:
                frac = (j + (0.0 if stage == 0 else (1.0 if stage == 3 else 0.5))) / substeps
                for q in range(n_z - n):
                    z[n + q] = u[s - 1, q] + frac * (u[s, q] - u[s - 1, q])
            for q in range(1 + n_z, n_mono):  # monomials by the product tree, then the other terms
                theta[q] = theta[parent[q]] * z[var[q]]
            for f in range(fcode.shape[0]):
                theta[n_mono + f] = theta[fslot[f]] * _factor(fcode[f], z[finput[f]], fparam[f])
            for i in range(n):
                d = 0.0
                for p in range(eq_ptr[i], eq_ptr[i + 1]):
                    d += vals[p] * theta[slot[p]]
                dx[i] = d
            step = h if stage == 2 else 0.5 * h
            weight = 1.0 if (stage == 0 or stage == 3) else 2.0
            for i in range(n):  # after every equation: z is part of theta
                acc[i] += weight * dx[i]
                z[i] = x_old[i] + step * dx[i]
        for i in range(n):
            x[i] = x_old[i] + h / 6.0 * acc[i]


_integrate_program = segment_loop(_rk4_interval)


@jit(cache=False, inline="always")
def _no_interval(x, t, s, substeps, model, b):
    """The interval step of a loop over linear models only (never called: they take their propagators)."""


_propagated = segment_loop(_no_interval)


@kernel
def integrate_batch(ref, t, starts, weights, substeps, prog, vals, bound, u, work, errors, rows):
    """:func:`integrate`'s weighted error for a batch of models stepped together, stage by stage.

    One model's RK4 stages wait on memory; several models interleaved fill the wait (the gradient of the
    refinement scores one model per coefficient) and the innermost loops run over the models, side by side
    in memory. The arithmetic of each model is :func:`integrate`'s, in the same order: the same errors and
    work. ``vals`` is (n_values, n_models) (one column per model), ``work`` (scratch rows, n_models). Not
    for two-state cubic models (:func:`.two_state_cubic.integrate_cubic2` steps those faster, one after the
    other).
    """
    n = ref.shape[1]
    n_z = n + u.shape[1]
    x = work[2 * n_z : 2 * n_z + n]
    for b in range(vals.shape[1]):
        errors[b] = 0.0
        rows[b] = 0
    for k in range(starts.shape[0]):
        s0 = starts[k]
        s1 = starts[k + 1] if k + 1 < starts.shape[0] else t.shape[0] - 1
        for i in range(n):
            for b in range(vals.shape[1]):
                x[i, b] = ref[s0, i]
        for s in range(s0 + 1, s1 + 1):
            _rk4_interval_batch(x, t, s, substeps, prog, vals, u, work)
            alive = 0
            for b in range(vals.shape[1]):
                if errors[b] == np.inf:
                    continue
                rows[b] += 1
                total = errors[b]
                for i in range(n):
                    if not (abs(x[i, b]) <= bound[i]):  # diverged (also true for NaN)
                        total = np.inf
                        break
                    total += weights[k, i] * abs(x[i, b] - ref[s, i])
                errors[b] = total
                alive += total != np.inf
            if alive == 0:
                return


@jit(_nrt=False)
def _rk4_interval_batch(x, t, s, substeps, prog, vals, u, work):
    """:func:`_rk4_interval` for the columns of ``x`` (n_states, n_models), each with its ``vals`` column."""
    parent, var, fcode, fslot, finput, fparam, eq_ptr, slot = prog
    n, n_b = x.shape
    n_z, acc, x_old, _, dx, theta, z = _scratch(work, n, u)
    n_mono = parent.shape[0]
    h = (t[s] - t[s - 1]) / substeps
    for b in range(n_b):
        theta[0, b] = 1.0
    for j in range(substeps):
        for i in range(n):
            for b in range(n_b):
                x_old[i, b] = x[i, b]
                z[i, b] = x[i, b]
                acc[i, b] = 0.0
        for stage in range(4):
            if n_z > n:
                frac = (j + (0.0 if stage == 0 else (1.0 if stage == 3 else 0.5))) / substeps
                for q in range(n_z - n):
                    for b in range(n_b):
                        z[n + q, b] = u[s - 1, q] + frac * (u[s, q] - u[s - 1, q])
            for q in range(1 + n_z, n_mono):
                for b in range(n_b):
                    theta[q, b] = theta[parent[q], b] * z[var[q], b]
            for f in range(fcode.shape[0]):
                for b in range(n_b):
                    theta[n_mono + f, b] = theta[fslot[f], b] * _factor(fcode[f], z[finput[f], b], fparam[f])
            for i in range(n):
                for b in range(n_b):
                    dx[i, b] = 0.0
                for p in range(eq_ptr[i], eq_ptr[i + 1]):
                    for b in range(n_b):
                        dx[i, b] += vals[p, b] * theta[slot[p], b]
            step = h if stage == 2 else 0.5 * h
            weight = 1.0 if (stage == 0 or stage == 3) else 2.0
            for i in range(n):
                for b in range(n_b):
                    acc[i, b] += weight * dx[i, b]
                    z[i, b] = x_old[i, b] + step * dx[i, b]
        for i in range(n):
            for b in range(n_b):
                x[i, b] = x_old[i, b] + h / 6.0 * acc[i, b]


@jit
def _factor(code, zv, param):
    """The non-polynomial factor ``g(z_v)`` of a term (codes of :mod:`.terms`)."""
    if code == 1:
        return zv * abs(zv)
    if code == 2:
        return math.tanh(zv / param)
    if code == 3:
        return abs(zv)
    if code == 4:
        return math.sin(param * zv)
    return math.cos(param * zv)


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

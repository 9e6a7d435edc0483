"""Exact gradients of a two-state cubic model's simulation: forward sensitivities in the same RK4 kernel.

The refinement (:func:`sindy_impulse.identification.refinement.refine`) and the output-error fit
(:func:`sindy_impulse.identification.output_error.fit_output_error`) need the derivatives of a simulation
with respect to the model's coefficients (and initial state). Finite differences cost one simulation per
unknown; here the simulation carries its sensitivities ``S = dx/dp`` along: for a coefficient ``c`` of
monomial ``phi`` in equation ``e``, ``S' = J(x) S + phi(x) u_e`` (``J`` the model's state Jacobian), for an
initial state ``S(0) = I`` and ``S' = J S``. The classical RK4 stages are applied to the augmented system
``(x, S)``; differentiating an explicit Runge-Kutta step gives exactly that (the stage Jacobians are taken
at the stage values), so ``S`` is the exact derivative of the discrete RK4 solution the other kernels
compute, not an approximation of it: the gradients agree with finite differences of the simulated
objective to the differences' own error (``tests/test_sensitivity.py``).

:func:`cubic2_sensitivity` is the kernel (one model, a fraction of a plain simulation per unknown more):
it either stores the trajectory and its sensitivities (the output-error fit's Jacobian) or accumulates the
weighted L1 error of segment-restarted simulations (:class:`~sindy_impulse.simulation.scoring.WeightedL1`)
and its gradient, ``sum w sign(x - x_ref) S``, without storing anything.
"""

from __future__ import annotations

import numpy as np

from .._utils.jit import jit, kernel

__all__ = ["cubic2_sensitivity", "SENSITIVITY_COST"]

#: Work (in plain simulations of the model) of carrying one sensitivity along: each RK4 stage adds a 2x2
#: Jacobian-vector product and one monomial per unknown (measured, CPU time: 5 unknowns cost 3.4 plain
#: simulations of a 5-term cubic model of ``identify_modes``, 4069 samples, 16 sub-steps).
SENSITIVITY_COST = 0.5


@jit(_nrt=False)
def _equation(p, q, c, o, quadratic, cubic):
    """One equation of a dense row at ``(p, q)``: its value and its derivatives by ``p`` and ``q`` (the
    quadratic and cubic parts only where present)."""
    value = c[o] + c[o + 1] * p + c[o + 2] * q
    dp, dq = c[o + 1], c[o + 2]
    if quadratic:
        value += p * (c[o + 3] * p + c[o + 4] * q) + c[o + 5] * (q * q)
        dp += 2.0 * c[o + 3] * p + c[o + 4] * q
        dq += c[o + 4] * p + 2.0 * c[o + 5] * q
    if cubic:
        value += (p * p) * (c[o + 6] * p + c[o + 7] * q) + (q * q) * (c[o + 8] * p + c[o + 9] * q)
        dp += 3.0 * c[o + 6] * (p * p) + 2.0 * c[o + 7] * (p * q) + c[o + 8] * (q * q)
        dq += c[o + 7] * (p * p) + 2.0 * c[o + 8] * (p * q) + 3.0 * c[o + 9] * (q * q)
    return value, dp, dq


@jit(_nrt=False)
def _rk4_sensitivity(x, t, s, substeps, c, params, n_s, work):
    """One grid interval of RK4 on ``(x, S)`` in place. ``work`` rows: ``S`` (2 rows, (n_sens,)), a stage's
    sensitivities (2), their weighted sum (2), a stage's derivative (2) and the monomials' values (10);
    ``n_s`` columns are used;
    the first ``len(params)`` columns of ``S`` belong to the coefficients at dense positions ``params``,
    the others are not forced."""
    n_p = params.shape[0]
    S0, S1, Y0, Y1, A0, A1, D0, D1, phi = work[0], work[1], work[2], work[3], work[4], work[5], work[6], \
        work[7], work[8]
    h = (t[s] - t[s - 1]) / substeps
    quadratic0, quadratic1 = c[20] != 0.0, c[23] != 0.0
    cubic0, cubic1 = c[21] != 0.0 or c[22] != 0.0, c[24] != 0.0 or c[25] != 0.0
    p, q = x[0], x[1]
    for _ in range(substeps):
        y0, y1, acc0, acc1 = p, q, 0.0, 0.0
        for j in range(n_s):
            Y0[j], Y1[j], A0[j], A1[j] = S0[j], S1[j], 0.0, 0.0
        for stage in range(4):
            k0, a00, a01 = _equation(y0, y1, c, 0, quadratic0, cubic0)
            k1, a10, a11 = _equation(y0, y1, c, 10, quadratic1, cubic1)
            phi[0], phi[1], phi[2], phi[3], phi[4], phi[5] = 1.0, y0, y1, y0 * y0, y0 * y1, y1 * y1
            phi[6], phi[7], phi[8], phi[9] = phi[3] * y0, phi[3] * y1, phi[4] * y1, phi[5] * y1
            for j in range(n_s):
                D0[j] = a00 * Y0[j] + a01 * Y1[j]
                D1[j] = a10 * Y0[j] + a11 * Y1[j]
            for j in range(n_p):
                if params[j] < 10:
                    D0[j] += phi[params[j]]
                else:
                    D1[j] += phi[params[j] - 10]
            weight = 1.0 if (stage == 0 or stage == 3) else 2.0
            step = h if stage == 2 else 0.5 * h
            for j in range(n_s):
                A0[j] += weight * D0[j]
                A1[j] += weight * D1[j]
                Y0[j] = S0[j] + step * D0[j]
                Y1[j] = S1[j] + step * D1[j]
            acc0, acc1 = acc0 + weight * k0, acc1 + weight * k1
            y0, y1 = p + step * k0, q + step * k1
        p, q = p + h / 6.0 * acc0, q + h / 6.0 * acc1
        for j in range(n_s):
            S0[j] += h / 6.0 * A0[j]
            S1[j] += h / 6.0 * A1[j]
    x[0], x[1] = p, q


@kernel
def cubic2_sensitivity(ref, t, starts, weights, substeps, dense, params, initial, props, dprops, bound, x,
                       work, out, sens, grad, result):
    """Simulate one two-state cubic model (dense row ``dense``, :func:`.two_state_cubic.dense_coefficients`)
    with the sensitivities to its coefficients at dense positions ``params`` and, if ``initial``, to the
    initial state of the first segment (the last two columns).

    Segments as :func:`.integrators.integrate` (restarted from ``ref`` at ``starts``, sensitivities from
    zero). With a non-empty ``out`` (n_times, 2) the trajectory and its sensitivities (``sens``: n_times, 2,
    n_sens) are stored, NaN after a divergence; else the weighted L1 error is accumulated with its
    gradient (``grad``: n_sens). ``result`` receives the error (``inf`` once diverged) and the grid
    intervals simulated. ``work``: (9, max(n_sens, 10)) floats; ``x``: 2.

    A linear model on a uniform grid is stepped by RK4's map over an interval instead (``props``: (2, 3),
    the state's and the constant's columns) and its sensitivities by the map's derivatives by the
    coefficients (``dprops``: (n_params, 2, 3)): the same numbers as the stages, without the sub-steps.
    """
    S = work[0:2]
    n_s = grad.shape[0]
    store = out.shape[0] > 0
    total, done = 0.0, 0
    for j in range(grad.shape[0]):
        grad[j] = 0.0
    for k in range(starts.shape[0]):
        s0 = starts[k]
        s1 = starts[k + 1] if k + 1 < starts.shape[0] else t.shape[0] - 1
        x[0], x[1] = ref[s0, 0], ref[s0, 1]
        for j in range(n_s):
            S[0, j], S[1, j] = 0.0, 0.0
        if initial and k == 0:
            S[0, n_s - 2], S[1, n_s - 1] = 1.0, 1.0
        if store:
            _store(x, S, s0, out, sens)
        for s in range(s0 + 1, s1 + 1):
            if props.shape[0] > 0:
                _propagate_sensitivity(x, props, dprops, n_s, work)
            else:
                _rk4_sensitivity(x, t, s, substeps, dense, params, n_s, work)
            done += 1
            if not (abs(x[0]) <= bound[0] and abs(x[1]) <= bound[1]):  # diverged (also for NaN)
                total = np.inf
                for r in range(s, out.shape[0]):
                    for i in range(2):
                        out[r, i] = np.nan
                        for j in range(n_s):
                            sens[r, i, j] = np.nan
                break
            if store:
                _store(x, S, s, out, sens)
                continue
            for i in range(2):
                e = x[i] - ref[s, i]
                total += weights[k, i] * abs(e)
                sign = weights[k, i] * (1.0 if e > 0 else (-1.0 if e < 0 else 0.0))
                for j in range(n_s):
                    grad[j] += sign * S[i, j]
        if total == np.inf:
            break
    result[0], result[1] = total, done


@jit(_nrt=False)
def _propagate_sensitivity(x, props, dprops, n_s, work):
    """One interval of a linear model by RK4's map: ``x <- M [x, 1]``, ``S <- M S + dM_j [x, 1]`` (the
    forcing only for the coefficient columns ``j < len(dprops)``)."""
    S0, S1 = work[0], work[1]
    p, q = x[0], x[1]
    for j in range(n_s):
        a, b = S0[j], S1[j]
        S0[j] = props[0, 0] * a + props[0, 1] * b
        S1[j] = props[1, 0] * a + props[1, 1] * b
        if j < dprops.shape[0]:
            S0[j] += dprops[j, 0, 0] * p + dprops[j, 0, 1] * q + dprops[j, 0, 2]
            S1[j] += dprops[j, 1, 0] * p + dprops[j, 1, 1] * q + dprops[j, 1, 2]
    x[0] = props[0, 0] * p + props[0, 1] * q + props[0, 2]
    x[1] = props[1, 0] * p + props[1, 1] * q + props[1, 2]


@jit(_nrt=False)
def _store(x, S, s, out, sens):
    for i in range(2):
        out[s, i] = x[i]
        for j in range(sens.shape[2]):
            sens[s, i, j] = S[i, j]


def _unwrapped(model):
    """The compiled two-state cubic model behind ``model`` and its rest level (None if it has no exact
    gradients: another library, control inputs, or a model measured from a rest level of another kind)."""
    level = getattr(model, "level", None)
    inner = getattr(model, "inner", model) if level is not None else model
    if getattr(inner, "_dense_positions", None) is None or getattr(inner, "n_inputs", 1) != 0:
        return None, None
    return inner, (np.zeros(2) if level is None else np.asarray(level, dtype=float))


def _run(model, ref, t, starts, weights, c, entries, initial: bool, store: bool):
    """Prepare and run :func:`cubic2_sensitivity` for the ``entries`` (boolean mask) of the coefficient
    matrix ``c``; charges the work to ``model``."""
    from .two_state_cubic import dense_coefficients

    steps = model.substeps(t)
    # read-only arrays (e.g. memory-mapped data) would compile another kernel: copy them
    ref, t, starts, weights = (a if a.flags.writeable else a.copy() for a in (ref, t, starts, weights))
    rows, cols = np.nonzero(c != 0 if entries is None else np.asarray(entries, dtype=bool))
    params = (10 * rows + model._dense_positions[cols]).astype(np.int64)
    n_s = params.size + (2 if initial else 0)
    dense = dense_coefficients(c[None], model._dense_positions)[0]
    bound = np.maximum(model.bound, 10 * np.max(np.abs(ref[starts]), axis=0))
    n_out = len(t) if store else 0
    out, sens = np.empty((n_out, 2)), np.empty((n_out, 2, n_s))
    grad, result = np.empty(n_s), np.empty(2)
    props, dprops = _linear_map(model, c, dense, params, t, steps)
    work = np.empty((9, max(n_s, 10)))
    cubic2_sensitivity(ref, t, starts, weights, steps, dense, params, initial, props, dprops, bound,
                       np.empty(2), work, out, sens, grad, result)
    charged = 1 if props.size else steps  # (a linear model's map: one step per interval, as in integrate)
    model.work_done += model.work(t, charged, int(result[1])) * (1.0 + SENSITIVITY_COST * n_s)
    return (rows, cols), out, sens, grad, float(result[0])


_NO_MAP, _NO_MAPS = np.empty((0, 3)), np.empty((0, 0, 3))


def _linear_map(model, c, dense, params, t, steps):
    """RK4's map over one interval of a linear model on a uniform grid, (2, 3), and its derivatives by the
    coefficients at ``params``, (n_params, 2, 3), from the stages over one interval started at the unit
    states and at the origin (empty arrays for other models and grids)."""
    from .program import propagators

    dt = model._grid(t)[1]
    if not model.is_linear or dt is None:
        return _NO_MAP, _NO_MAPS
    m = propagators(model.program, c[None], dt, steps)[0]
    props = np.zeros((2, 3))
    props[:, : m.shape[1]] = m[:2]
    grid, n_p = np.array([0.0, dt]), params.size
    no_weights, first, work = np.zeros((1, 2)), np.zeros(1, dtype=np.int64), np.empty((9, max(n_p, 10)))
    columns = np.empty((3, 2, n_p))
    for j, start in enumerate(np.vstack([np.eye(2), np.zeros(2)])):
        out, sens = np.empty((2, 2)), np.empty((2, 2, n_p))
        cubic2_sensitivity(start[None], grid, first, no_weights, steps, dense, params, False, _NO_MAP,
                           _NO_MAPS, np.full(2, np.inf), np.empty(2), work, out, sens, np.empty(n_p),
                           np.empty(2))
        columns[j] = sens[1]
    dprops = np.empty((n_p, 2, 3))
    dprops[:, :, 2] = columns[2].T
    dprops[:, :, 0], dprops[:, :, 1] = (columns[0] - columns[2]).T, (columns[1] - columns[2]).T
    return props, dprops


def weighted_l1_gradient(model, reference, t, starts, weights, coef=None, entries=None):
    """The weighted L1 error of segment-restarted simulations (``model.weighted_l1``) of one
    active-coefficient matrix ``coef`` (default: the model's) and its gradient by the ``entries`` of it
    (a boolean mask; default: its non-zero entries); None where no exact gradient is available (see
    :func:`has_sensitivities`).

    Returns
    -------
    (error, gradient) : float, ndarray (n_states, n_active)
        The gradient is NaN outside ``entries`` (not computed) and zero when the simulation diverged (the
        error is then ``inf``).

    Examples
    --------
    >>> from sindy_impulse.simulation import CompiledModel, TermTable
    >>> from sindy_impulse.datasets import damped_oscillator
    >>> t, x, _ = damped_oscillator()
    >>> model = CompiledModel([[0, 1.0], [-60.0, -3.2]], TermTable.polynomial([[1, 0], [0, 1]]), x)
    >>> error, gradient = weighted_l1_gradient(model, x, t, [0], 1 / np.max(np.abs(x), axis=0)[None])
    >>> bool(error > 1), bool(gradient[1, 0] > 0)   # a softer spring than the data's: stiffen it
    (True, True)
    """
    t = np.ascontiguousarray(t, dtype=float)
    inner, level = _unwrapped(model)
    if inner is None or inner.is_stiff(t):
        return None
    c = inner.coef if coef is None else np.ascontiguousarray(coef, dtype=float)
    ref = np.ascontiguousarray(np.asarray(reference, dtype=float) - level)
    starts = np.ascontiguousarray(starts, dtype=np.int64)
    weights = np.ascontiguousarray(weights, dtype=float)
    (rows, cols), _, _, grad, error = _run(inner, ref, t, starts, weights, c, entries, False, False)
    out = np.full(c.shape, np.nan)
    out[rows, cols] = grad if np.isfinite(error) else 0.0
    return error, out


def simulate_sensitivity(model, x0, t, coef=None, entries=None):
    """A simulation from ``x0`` with its derivatives by the ``entries`` (boolean mask; default: the non-zero
    ones) of the active-coefficient matrix ``coef`` (default: the model's) and by ``x0``; None where no
    exact gradient is available (see :func:`has_sensitivities`).

    Returns
    -------
    (x, by_coefficient, by_initial_state) : ndarrays (n_times, 2), (n_times, 2, 2, n_active), (n_times, 2, 2)
        NaN after a divergence; ``by_coefficient`` is zero outside ``entries``.

    Examples
    --------
    >>> from sindy_impulse.simulation import CompiledModel, TermTable
    >>> model = CompiledModel([[0, 1.0], [-64.0, -3.2]], TermTable.polynomial([[1, 0], [0, 1]]))
    >>> x, by_coef, by_x0 = simulate_sensitivity(model, [1.0, 0.0], np.arange(401) * 0.01)
    >>> by_coef.shape, np.round(by_x0[0], 6).tolist()
    ((401, 2, 2, 2), [[1.0, 0.0], [0.0, 1.0]])
    """
    t = np.ascontiguousarray(t, dtype=float)
    inner, level = _unwrapped(model)
    if inner is None or inner.is_stiff(t):
        return None
    c = inner.coef if coef is None else np.ascontiguousarray(coef, dtype=float)
    ref = np.ascontiguousarray(np.asarray(x0, dtype=float).reshape(1, 2) - level)
    starts, weights = np.zeros(1, dtype=np.int64), np.zeros((1, 2))
    (rows, cols), x, sens, _, _ = _run(inner, ref, t, starts, weights, c, entries, True, True)
    by_coef = np.zeros((len(t), 2) + c.shape)
    by_coef[:, :, rows, cols] = sens[:, :, :-2]
    return x + level, by_coef, sens[:, :, -2:]


def has_sensitivities(model, t) -> bool:
    """Whether :func:`weighted_l1_gradient` and :func:`simulate_sensitivity` serve ``model`` on the grid
    ``t``: a compiled two-state polynomial of degree <= 3 without control inputs, not stiff there.

    Examples
    --------
    >>> from sindy_impulse.simulation import CompiledModel, TermTable
    >>> model = CompiledModel([[0, 1.0], [-64.0, -3.2]], TermTable.polynomial([[1, 0], [0, 1]]))
    >>> has_sensitivities(model, np.arange(401) * 0.01)
    True
    """
    inner, _ = _unwrapped(model)
    return inner is not None and not inner.is_stiff(np.ascontiguousarray(t, dtype=float))

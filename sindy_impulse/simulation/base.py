"""What every simulated model shares: its coefficients, the reference it was fitted to, its time scale
(the RK4 sub-steps it needs), its work accounting and the adaptive integrator.

:class:`Reference` is computed once per fit and shared by all its candidate models; ``_SparseModel`` is the
base of :class:`~.compile.CompiledModel` and :class:`~.compile.FallbackModel`.
"""

from __future__ import annotations

import math

import numpy as np

from .integrators import MAX_EVALUATIONS_PER_SAMPLE, MAX_SUBSTEPS, NO_INPUT, solve_ivp_simulate
from .program import uniform_step

__all__ = ["Reference", "STEP_SCALE", "SMOOTH_STEP_SCALE", "ADAPTIVE_CALL_COST"]

#: Work units charged per right-hand-side evaluation through the adaptive integrator on top of the terms'
#: cost: SciPy's step, the event and the Python call take about 150 us an evaluation, ~2,000 RK4 kernel
#: term evaluations (``benchmarks/robustness/work_bounds.py``). Charged at 25 units a term alone, a stiff
#: model's refinement on 150 samples ran 394 s within its budget.
ADAPTIVE_CALL_COST = 2000.0

#: Target of ``h * rho`` per Runge-Kutta sub-step (``h`` the sub-step, ``rho`` the spectral radius).
#: 0.02 keeps RK4's global error below 1e-7 relative on the paper's oscillator. It is the scale of linear
#: models (stepped by a propagator, whose cost does not depend on the sub-steps) and of models with
#: non-polynomial terms (a friction term's ``tanh`` switches within a sub-step).
STEP_SCALE = 0.02
#: The scale of nonlinear polynomial models, whose cost is the sub-steps: RK4's error per radian of phase
#: is about ``(h rho)**4 / 120``, so 0.1 keeps the global error about 1e-6 of the amplitude; against
#: 0.02 it moved a fitted frequency by about 1e-8 and a damping ratio by 1e-5 relative, at half the
#: survey's time (issue 26: ``python -m benchmarks speed --only "survey speed"``).
SMOOTH_STEP_SCALE = 0.1


def _as_inputs(u, n_times: int, n_inputs: int) -> np.ndarray:
    """Control inputs on the time grid as a contiguous (n_times, n_inputs) array (empty without inputs)."""
    if n_inputs == 0:
        return NO_INPUT
    if u is None:
        raise ValueError(f"the model has {n_inputs} control input(s): u is required")
    arr = np.ascontiguousarray(np.asarray(u, dtype=float).reshape(n_times, -1))
    if arr.shape[1] != n_inputs:
        raise ValueError(f"u has {arr.shape[1]} input(s) but the model has {n_inputs}")
    return arr


class Reference:
    """What a model takes from the data it was fitted to, computed once for every model of a fit.

    Parameters
    ----------
    states : array (n_samples, n_states)
        The reference states (e.g. the filtered states of a fit).
    inputs : array (n_samples, n_inputs), optional
        The control inputs along them (zeros if the models have inputs and none are given).
    n_inputs : int, default=0
        Number of control inputs of the models.

    Attributes
    ----------
    scale : ndarray (n_states,)
        Largest absolute value of each state (1 for a state that is zero throughout).
    probe : ndarray (<= 64, n_states + n_inputs)
        Samples along the reference at which the model's fastest time scale is estimated.

    Examples
    --------
    >>> Reference([[1.0, 0.0], [0.0, -8.0]]).scale.tolist()
    [1.0, 8.0]
    """

    def __init__(self, states, inputs=None, n_inputs: int = 0):
        ref = np.atleast_2d(np.asarray(states, dtype=float))
        scale = np.maximum(ref.max(axis=0), -ref.min(axis=0))  # max |ref| without a temporary array
        self.scale = np.where(scale > 0, scale, 1.0)
        idx = np.unique(np.linspace(0, ref.shape[0] - 1, min(64, ref.shape[0])).astype(int))
        probe = ref[idx]
        if inputs is not None:
            probe = np.hstack([probe, np.asarray(inputs, dtype=float).reshape(ref.shape[0], -1)[idx]])
        elif n_inputs:
            probe = np.hstack([probe, np.zeros((probe.shape[0], n_inputs))])
        self.probe = np.ascontiguousarray(probe)


class _SparseModel:
    """What both model kinds share: coefficients, admissible box, time scale, work accounting."""

    def __init__(self, coefficients, n_inputs_total: int, reference, divergence_factor: float, reference_u):
        coef = np.atleast_2d(np.asarray(coefficients, dtype=float))
        self.n_states = coef.shape[0]
        self.n_inputs = n_inputs_total - self.n_states
        if self.n_inputs < 0:
            raise ValueError(
                f"the library acts on {n_inputs_total} inputs but there are {self.n_states} equations"
            )
        self.full_coefficients = coef
        self.active = np.flatnonzero(np.any(coef != 0, axis=0))
        self.coef = np.ascontiguousarray(coef[:, self.active])
        if not isinstance(reference, Reference):
            states = np.zeros((1, self.n_states)) if reference is None else reference
            reference = Reference(states, reference_u, self.n_inputs)
        if reference.probe.shape[1] != n_inputs_total:
            raise ValueError(
                f"the reference has {reference.probe.shape[1]} states and inputs, the model {n_inputs_total}"
            )
        self.bound = divergence_factor * reference.scale
        self._probe = reference.probe
        self._last_grid = None
        self.work_done = 0.0
        #: ``work_done`` past which the scoring's adaptive simulations stop (NaN rows); set by ``WorkBudget``.
        self.work_limit = math.inf
        #: ``h * rho`` per RK4 sub-step (:data:`STEP_SCALE`; a compiled polynomial model's is larger).
        self.step_scale = STEP_SCALE

    # -- time scale and cost ---------------------------------------------------------------------------
    def _spectral_radius(self, coef) -> float:
        """Largest |eigenvalue| of the state Jacobian over the probe points (central differences)."""
        Z = self._probe
        n = self.n_states
        h = 1e-6 * np.maximum(np.max(np.abs(Z[:, :n]), axis=0), 1e-12)
        steps = np.zeros((n, Z.shape[1]))
        steps[np.arange(n), np.arange(n)] = h
        # every probe moved by +-h along each state, evaluated in one call: (2, n, n_probes, n)
        moved = np.concatenate([Z[None] + steps[:, None], Z[None] - steps[:, None]]).reshape(-1, Z.shape[1])
        values = self._rhs_z(moved, coef).reshape(2, n, Z.shape[0], n)
        jac = np.transpose((values[0] - values[1]) / (2 * h[:, None, None]), (1, 2, 0))
        if not np.all(np.isfinite(jac)):
            return np.inf
        return float(np.max(np.abs(np.linalg.eigvals(jac))))

    @property
    def spectral_radius(self) -> float:
        """Fastest time scale of the model along the reference (sets the RK4 sub-steps).

        Assignable: the refinement fixes it for the whole optimization (a smooth objective needs a fixed
        integration grid).
        """
        if not hasattr(self, "_radius"):
            self._radius = self._spectral_radius(self.coef)
        return self._radius

    @spectral_radius.setter
    def spectral_radius(self, value: float) -> None:
        self._radius = float(value)

    def _grid(self, t) -> tuple[float, float | None]:
        """Largest step of the grid ``t`` and its step if uniform (kept for the last grid seen)."""
        if self._last_grid is None or self._last_grid[0] is not t:
            dt_max = float(np.max(np.diff(t))) if len(t) > 1 else 0.0
            self._last_grid = (t, (dt_max, uniform_step(t)))  # holds t: its id cannot be reused
        return self._last_grid[1]

    def required_substeps(self, t, radius: float | None = None) -> float:
        """RK4 sub-steps per sample interval for ``h * rho <= step_scale`` (inf if not finite)."""
        rho = self.spectral_radius if radius is None else radius
        dt_max = self._grid(t)[0]
        return math.inf if not np.isfinite(rho) else max(1.0, math.ceil(dt_max * rho / self.step_scale))

    def substeps(self, t, radius: float | None = None) -> int:
        """RK4 sub-steps per sample interval, at most ``MAX_SUBSTEPS``."""
        return int(min(MAX_SUBSTEPS, self.required_substeps(t, radius)))

    def is_stiff(self, t, radius: float | None = None) -> bool:
        """True when RK4 would need more than ``MAX_SUBSTEPS`` sub-steps (the adaptive path is used)."""
        return self.required_substeps(t, radius) > MAX_SUBSTEPS

    def work(self, t, substeps: int | None = None, rows: int | None = None) -> float:
        """Cost of simulating ``rows`` sample intervals of ``t``, in term evaluations per RK4 step."""
        steps = self.substeps(t) if substeps is None else int(substeps)
        rows = len(t) - 1 if rows is None else rows
        return float(max(rows, 0) * steps * max(1, self.coef.shape[1]))

    # -- evaluation ---------------------------------------------------------------------------------------
    def _z(self, x, u) -> np.ndarray:
        X = np.atleast_2d(np.asarray(x, dtype=float))
        if self.n_inputs == 0:
            return np.ascontiguousarray(X)
        return np.ascontiguousarray(np.hstack([X, _as_inputs(u, X.shape[0], self.n_inputs)]))

    def rhs(self, x, u=None, coef=None) -> np.ndarray:
        """Right-hand side at states ``x`` (n_points, n_states) and inputs ``u``; ``coef`` overrides."""
        return self._rhs_z(self._z(x, u), self.coef if coef is None else np.asarray(coef, dtype=float))

    def simulate_segments(self, start_states, t, starts, coef=None) -> np.ndarray:
        """Simulations restarted at the samples ``starts`` from ``start_states`` (one row per start), each
        through the next start, whose sample then holds the next segment's start: the trajectories the
        segment-wise error measures compare. Returns (len(t), n_states); NaN after a divergence.

        Examples
        --------
        >>> from sindy_impulse.simulation import CompiledModel, TermTable
        >>> model = CompiledModel([[0.0, 1.0], [-64.0, -3.2]], TermTable.polynomial([[1, 0], [0, 1]]))
        >>> t = np.arange(401) * 0.01
        >>> x = model.simulate([1.0, 0.0], t)
        >>> bool(np.allclose(model.simulate_segments(x[[0, 200]], t, [0, 200]), x))
        True
        """
        starts = np.asarray(starts, dtype=np.int64)
        x0s = np.asarray(start_states, dtype=float).reshape(starts.size, self.n_states)
        t = np.asarray(t, dtype=float)
        out = np.empty((t.shape[0], self.n_states))
        for x0, lo, hi in zip(x0s, starts, np.append(starts[1:], t.shape[0] - 1)):
            out[lo : hi + 1] = self.simulate(x0, t[lo : hi + 1], coef=coef)
        return out

    def _check_x0(self, x0) -> np.ndarray:
        x0 = np.ascontiguousarray(x0, dtype=float).ravel()
        if x0.shape[0] != self.n_states:
            raise ValueError(f"x0 has {x0.shape[0]} entries but the model has {self.n_states} states")
        return x0

    def _adaptive(self, x0, t, u, c, limited: bool = False, **kws) -> np.ndarray:
        """One adaptive simulation, stopped (NaN rows) at ``MAX_EVALUATIONS_PER_SAMPLE`` evaluations a
        sample or, when ``limited`` (the scoring of a budgeted fit), where the work would pass
        ``work_limit``."""
        bound = np.maximum(self.bound, 10 * np.abs(x0))
        per_evaluation = ADAPTIVE_CALL_COST + max(1, c.shape[1]) * self._eval_cost
        allowed = MAX_EVALUATIONS_PER_SAMPLE * len(t)
        if limited:
            allowed = min(allowed, (self.work_limit - self.work_done) / per_evaluation)
        if allowed < 1:
            return np.full((len(t), len(x0)), np.nan)
        rhs = lambda z: self._rhs_z(z[None], c)[0]  # noqa: E731
        out, n_eval = solve_ivp_simulate(rhs, x0, t, u, bound, max_evaluations=int(allowed), **kws)
        self.work_done += n_eval * per_evaluation
        return out

    def weighted_l1(self, reference, t, starts, weights, coefs=None, u=None, substeps=None):
        """Weighted L1 error of segment-restarted simulations (see :func:`integrators.weighted_l1`).

        Through the adaptive integrator, segment by segment, when the fast kernel cannot be used.
        """
        ref = np.ascontiguousarray(reference, dtype=float)
        t = np.ascontiguousarray(t, dtype=float)
        c = self.coef[None] if coefs is None else np.ascontiguousarray(coefs, dtype=float)
        uu = _as_inputs(u, len(t), self.n_inputs)
        starts = np.ascontiguousarray(starts, dtype=np.int64)
        errors = np.empty(c.shape[0])
        ends = np.append(starts[1:], len(t) - 1)
        for b in range(c.shape[0]):
            total = 0.0
            for k, (s0, s1) in enumerate(zip(starts, ends)):
                seg_u = None if self.n_inputs == 0 else uu[s0 : s1 + 1]
                sim = self._adaptive(ref[s0], t[s0 : s1 + 1], seg_u, c[b], limited=True)
                total += float(np.sum(weights[k] * np.abs(sim[1:] - ref[s0 + 1 : s1 + 1])))
            errors[b] = total if np.isfinite(total) else np.inf
        return errors, np.full(c.shape[0], len(t) - 1, dtype=np.int64)

"""A sparse model ``x' = coef @ Theta([x, u])`` compiled for fast evaluation and simulation.

:class:`CompiledModel` keeps only the active terms of a :class:`~sindy_impulse.simulation.terms.TermTable`
and runs the numba kernels of :mod:`~sindy_impulse.simulation.integrators`; :class:`FallbackModel` does the
same for any other library through a function that evaluates its terms (correct, slower). Both count the
work they do (``work_done``, in term evaluations per RK4 step), which the work budget of a fit reads, and
choose their RK4 sub-steps from the model's fastest time scale (the Jacobian's spectral radius along the
data); a model that would need more than ``MAX_SUBSTEPS`` is stiff and goes to the adaptive integrator.
"""

from __future__ import annotations

import math

import numpy as np

from . import integrators as kernels
from .integrators import MAX_SUBSTEPS, NO_INPUT, scratch_size, solve_ivp_simulate
from .program import build_program, pack, propagators, term_values, uniform_step
from .terms import TermTable

__all__ = ["CompiledModel", "FallbackModel", "Reference", "compile_model", "STEP_SCALE", "FALLBACK_COST"]

#: Target of ``h * rho`` per Runge-Kutta sub-step (``h`` the sub-step, ``rho`` the spectral radius).
#: 0.02 keeps RK4's global error below 1e-7 relative on the paper's oscillator.
STEP_SCALE = 0.02
#: Work units charged per right-hand-side evaluation and term by the fallback (Python is ~100x slower).
FALLBACK_COST = 100.0
#: Work units per evaluation and term of a compiled model called from the adaptive integrator (through
#: Python, about 25x a kernel RK4 step).
ADAPTIVE_COST = 25.0

_FIRST = np.zeros(1, dtype=np.int64)  # one segment from the first sample
_NO_WEIGHTS = np.zeros((1, 0))
_NO_OUTPUT = np.empty((0, 0))


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

    # -- time scale and cost ---------------------------------------------------------------------------
    def _spectral_radius(self, coef) -> float:
        """Largest |eigenvalue| of the state Jacobian over the probe points (central differences)."""
        Z = self._probe
        n = self.n_states
        h = 1e-6 * np.maximum(np.max(np.abs(Z[:, :n]), axis=0), 1e-12)
        jac = np.empty((Z.shape[0], n, n))
        for j in range(n):
            dz = np.zeros(Z.shape[1])
            dz[j] = h[j]
            jac[:, :, j] = (self._rhs_z(Z + dz, coef) - self._rhs_z(Z - dz, coef)) / (2 * h[j])
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
        """RK4 sub-steps per sample interval for ``h * rho <= STEP_SCALE`` (inf if not finite)."""
        rho = self.spectral_radius if radius is None else radius
        dt_max = self._grid(t)[0]
        return math.inf if not np.isfinite(rho) else max(1.0, math.ceil(dt_max * rho / STEP_SCALE))

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

    def _check_x0(self, x0) -> np.ndarray:
        x0 = np.ascontiguousarray(x0, dtype=float).ravel()
        if x0.shape[0] != self.n_states:
            raise ValueError(f"x0 has {x0.shape[0]} entries but the model has {self.n_states} states")
        return x0

    def _adaptive(self, x0, t, u, c, **kws) -> np.ndarray:
        bound = np.maximum(self.bound, 10 * np.abs(x0))
        out, n_eval = solve_ivp_simulate(lambda z: self._rhs_z(z[None], c)[0], x0, t, u, bound, **kws)
        self.work_done += n_eval * max(1, c.shape[1]) * self._eval_cost
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
                sim = self._adaptive(ref[s0], t[s0 : s1 + 1], seg_u, c[b])
                total += float(np.sum(weights[k] * np.abs(sim[1:] - ref[s0 + 1 : s1 + 1])))
            errors[b] = total if np.isfinite(total) else np.inf
        return errors, np.full(c.shape[0], len(t) - 1, dtype=np.int64)


class CompiledModel(_SparseModel):
    """A sparse model compiled for the numba kernels.

    Parameters
    ----------
    coefficients : array of shape (n_states, n_features)
        The model's coefficients (rows: equations, columns: library terms).
    terms : TermTable
        The library's terms over the states and control inputs (see
        :func:`sindy_impulse.feature_library.term_table`).
    reference : array of shape (n_samples, n_states), optional
        States along which the fastest time scale is estimated (the data the model was fitted to); also
        sets the admissible box. Defaults to the origin.
    divergence_factor : float, default=100
        A simulation stops as diverged once a state exceeds this factor times the reference's largest
        absolute value of that state.
    reference_u : array of shape (n_samples, n_inputs), optional
        Control inputs along the reference (for the time scale estimate).

    Examples
    --------
    >>> import numpy as np
    >>> terms = TermTable.polynomial([[1, 0], [0, 1]])
    >>> model = CompiledModel([[0.0, 1.0], [-64.0, -3.2]], terms, reference=[[1.0, 0.0], [0.0, 8.0]])
    >>> x = model.simulate([1.0, 0.0], np.arange(401) * 0.01)
    >>> x.shape, bool(abs(x[-1, 0]) < 0.01)
    ((401, 2), True)
    """

    _eval_cost = ADAPTIVE_COST

    def __init__(
        self,
        coefficients,
        terms: TermTable,
        reference=None,
        divergence_factor: float = 100.0,
        reference_u=None,
    ):
        coef = np.atleast_2d(np.asarray(coefficients, dtype=float))
        if coef.shape[1] != terms.n_features:
            raise ValueError(
                f"coefficients have {coef.shape[1]} columns but the library has {terms.n_features} terms"
            )
        super().__init__(coef, terms.n_inputs, reference, divergence_factor, reference_u)
        self.terms = terms.subset(self.active)
        self.program = build_program(self.terms, self.n_states)
        self._scratch = np.empty(scratch_size(terms.n_inputs, self.program.n_values))
        self._own = None  # (grid key, packed arrays) of the model's own coefficients

    def __getstate__(self):
        state = self.__dict__.copy()
        for name in ("program", "_scratch", "_own", "_last_grid"):  # rebuilt on unpickling (writable)
            state.pop(name, None)
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)
        self.program = build_program(self.terms, self.n_states)
        self._scratch = np.empty(scratch_size(self.terms.n_inputs, self.program.n_values))
        self._own = self._last_grid = None

    @property
    def is_linear(self) -> bool:
        """True for a linear model without inputs: simulated by its RK4 propagator (same solution)."""
        return self.program.linear_state is not None

    def _rhs_z(self, Z, coef) -> np.ndarray:
        Z = np.asarray(Z, dtype=float)
        return term_values(self.program, Z) @ np.asarray(coef, dtype=float).T

    def _packed(self, c, dt, steps):
        """The kernel program, coefficient rows and propagators of a batch (the model's own: cached)."""
        own = c is None
        if own and self._own is not None and self._own[0] == (dt, steps):
            return self._own[1]
        batch = self.coef[None] if own else c
        prog, vals = pack(self.program, batch)
        packed = (prog, vals, propagators(self.program, batch, dt, steps))
        if own:
            self._own = ((dt, steps), packed)
        return packed

    def _integrate(self, ref, t, starts, weights, c, u, substeps, out):
        """Run the kernel (see :func:`integrators.integrate`); returns ``(errors, rows)``."""
        steps = self.substeps(t) if substeps is None else int(substeps)
        prog, vals, props = self._packed(c, self._grid(t)[1], steps)
        bound = np.maximum(self.bound, 10 * np.max(np.abs(ref[starts]), axis=0))
        errors = np.empty(vals.shape[0])
        rows = np.empty(vals.shape[0], dtype=np.int64)
        uu = _as_inputs(u, len(t), self.n_inputs)
        # read-only arrays (e.g. memory-mapped data) would compile another kernel: copy them
        arrays = (ref, t, starts, weights, uu)
        ref, t, starts, weights, uu = (a if a.flags.writeable else a.copy() for a in arrays)
        if vals.shape[0] > 2 and props.size == 0 and out.size == 0:  # models stepped together
            work = np.empty((self._scratch.shape[0], vals.shape[0]))
            kernels.integrate_batch(ref, t, starts, weights, steps, prog, vals, bound, uu, work, errors, rows)
        else:
            kernels.integrate(
                ref, t, starts, weights, steps, prog, vals, props, bound, uu, self._scratch, out, errors, rows
            )
        self.work_done += self.work(t, 1 if props.size else steps, int(rows.sum()))
        return errors, rows

    def simulate(self, x0, t, u=None, coef=None, substeps: int | None = None, **integrator_kws) -> np.ndarray:
        """Integrate from ``x0`` over the time grid ``t`` (inputs ``u`` on the grid, if the model has any).

        RK4 with sub-steps from the model's time scale (a linear model: RK4's map over a sample interval,
        the same solution); the adaptive integrator when the model is stiff or when ``integrator_kws``
        (options of ``scipy.integrate.solve_ivp``) are given. Returns an array (len(t), n_states); rows
        after a divergence are NaN.
        """
        t = np.ascontiguousarray(t, dtype=float)
        x0 = self._check_x0(x0)
        c = None if coef is None else np.ascontiguousarray(coef, dtype=float)[None]
        if integrator_kws or callable(u) or (substeps is None and self.is_stiff(t)):
            c = self.coef if coef is None else c[0]
            uu = u if callable(u) or self.n_inputs == 0 else _as_inputs(u, len(t), self.n_inputs)
            return self._adaptive(x0, t, None if self.n_inputs == 0 else uu, c, **integrator_kws)
        out = np.empty((t.shape[0], self.n_states))
        self._integrate(x0[None], t, _FIRST, _NO_WEIGHTS, c, u, substeps, out)
        return out

    def weighted_l1(self, reference, t, starts, weights, coefs=None, u=None, substeps=None):
        """Weighted L1 error of segment-restarted simulations for a batch of active-coefficient matrices.

        Parameters
        ----------
        reference : ndarray (n_times, n_states)
        t : ndarray (n_times,)
        starts : ndarray of int (n_segments,)
            First sample of each segment (the first is 0 for a simulation from the first sample).
        weights : ndarray (n_segments, n_states)
            Weight of each state's absolute error in each segment.
        coefs : ndarray (n_models, n_states, n_active), optional
            Active coefficients to score (default: the model's own).
        u : ndarray (n_times, n_inputs), optional
        substeps : int, optional

        Returns
        -------
        (errors, rows) : ndarrays (n_models,)
        """
        t = np.ascontiguousarray(t, dtype=float)
        if substeps is None and self.is_stiff(t):
            return super().weighted_l1(reference, t, starts, weights, coefs, u)
        return self._integrate(
            np.ascontiguousarray(reference, dtype=float),
            t,
            np.ascontiguousarray(starts, dtype=np.int64),
            np.ascontiguousarray(weights, dtype=float),
            None if coefs is None else np.ascontiguousarray(coefs, dtype=float),
            u,
            substeps,
            _NO_OUTPUT,
        )


class FallbackModel(_SparseModel):
    """A sparse model over a library the kernels cannot evaluate (e.g. a ``CustomLibrary``).

    ``evaluate(Z)`` returns the library's terms at inputs ``Z`` (n_points, n_states + n_inputs); the model is
    simulated with the adaptive integrator. Correct for any library, slower than :class:`CompiledModel`
    (its work is charged ``FALLBACK_COST`` times a compiled evaluation).

    Examples
    --------
    >>> import numpy as np
    >>> model = FallbackModel([[0.0, 1.0], [-64.0, -3.2]], lambda Z: Z, n_inputs_total=2)
    >>> x = model.simulate([1.0, 0.0], np.arange(401) * 0.01)
    >>> bool(abs(x[-1, 0]) < 0.01)
    True
    """

    _eval_cost = FALLBACK_COST

    def __init__(
        self,
        coefficients,
        evaluate,
        n_inputs_total: int,
        reference=None,
        divergence_factor: float = 100.0,
        reference_u=None,
    ):
        self._evaluate = evaluate
        super().__init__(coefficients, n_inputs_total, reference, divergence_factor, reference_u)

    def _rhs_z(self, Z, coef) -> np.ndarray:
        coef = np.asarray(coef, dtype=float)
        full = np.zeros((coef.shape[0], self.full_coefficients.shape[1]))
        full[:, self.active] = coef
        return np.asarray(self._evaluate(np.atleast_2d(Z)), dtype=float) @ full.T

    def simulate(self, x0, t, u=None, coef=None, substeps: int | None = None, **integrator_kws) -> np.ndarray:
        """Integrate with the adaptive integrator (``integrator_kws`` go to ``solve_ivp``)."""
        t = np.ascontiguousarray(t, dtype=float)
        c = self.coef if coef is None else np.asarray(coef, dtype=float)
        uu = u if callable(u) or self.n_inputs == 0 else _as_inputs(u, len(t), self.n_inputs)
        return self._adaptive(self._check_x0(x0), t, None if self.n_inputs == 0 else uu, c, **integrator_kws)


def compile_model(
    coefficients, terms, reference=None, divergence_factor: float = 100.0, reference_u=None, n_inputs: int = 0
):
    """A :class:`CompiledModel` for a :class:`TermTable`, a :class:`FallbackModel` for an evaluator.

    ``terms`` is what :func:`sindy_impulse.feature_library.library_terms` returns for the fitted library;
    ``n_inputs`` (control inputs) is needed for an evaluator only (a table knows its inputs).

    Examples
    --------
    >>> model = compile_model([[0.0, 1.0], [-64.0, -3.2]], TermTable.polynomial([[1, 0], [0, 1]]))
    >>> type(model).__name__
    'CompiledModel'
    """
    if isinstance(terms, TermTable):
        return CompiledModel(coefficients, terms, reference, divergence_factor, reference_u)
    if not callable(terms):
        raise TypeError(f"terms must be a TermTable or a function Z -> Theta(Z), got {type(terms).__name__}")
    coef = np.atleast_2d(np.asarray(coefficients, dtype=float))
    return FallbackModel(
        coef, terms, coef.shape[0] + int(n_inputs), reference, divergence_factor, reference_u
    )

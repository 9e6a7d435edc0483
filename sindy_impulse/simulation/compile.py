"""A sparse model ``x' = coef @ Theta([x, u])`` compiled for fast evaluation and simulation.

:class:`CompiledModel` keeps only the active terms of a :class:`~sindy_impulse.simulation.terms.TermTable`
and runs the numba kernels of :mod:`~sindy_impulse.simulation.integrators`; :class:`FallbackModel` does the
same for any other library through a function that evaluates its terms (correct, slower). Both count the
work they do (``work_done``, in term evaluations per RK4 step), which the work budget of a fit reads, and
choose their RK4 sub-steps from the model's fastest time scale (the Jacobian's spectral radius along the
data); a model that would need more than ``MAX_SUBSTEPS`` is stiff and goes to the adaptive integrator.
"""

from __future__ import annotations

import numpy as np

from . import integrators as kernels
from .base import SMOOTH_STEP_SCALE, STEP_SCALE, Reference, _as_inputs, _SparseModel
from .integrators import NO_PROPAGATOR, scratch_size
from .program import build_program, pack, propagators, term_values
from .terms import PLAIN, TermTable
from .two_state_cubic import dense_coefficients, dense_positions, integrate_cubic2, is_cubic2

__all__ = [
    "CompiledModel",
    "FallbackModel",
    "Reference",
    "compile_model",
    "AtRestLevel",
    "at_rest_level",
    "STEP_SCALE",
    "SMOOTH_STEP_SCALE",
    "FALLBACK_COST",
]

#: Work units charged per right-hand-side evaluation and term by the fallback (Python is ~100x slower).
FALLBACK_COST = 100.0
#: Pieces a bounded scoring (:meth:`CompiledModel.weighted_l1_until`) simulates a record in: a sum is
#: checked against its cutoff after each.
PIECES = 8
#: Work units per evaluation and term of a compiled model called from the adaptive integrator (through
#: Python, about 25x a kernel RK4 step).
ADAPTIVE_COST = 25.0

_FIRST = np.zeros(1, dtype=np.int64)  # one segment from the first sample
_NO_WEIGHTS = np.zeros((1, 0))
_NO_OUTPUT = np.empty((0, 0))


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
        # a two-state cubic model is stepped with its monomials in registers (cubic2.integrate_cubic2)
        self._dense_positions = dense_positions(self.terms) if is_cubic2(self.terms, self.n_states) else None
        polynomial = bool(np.all(self.terms.func == PLAIN))
        if polynomial and np.any(self.terms.powers.sum(axis=1) > 1):  # smooth, nonlinear
            self.step_scale = SMOOTH_STEP_SCALE

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

    def _spectral_radius(self, coef) -> float:
        """A linear model's Jacobian is its matrix everywhere: the largest |eigenvalue| of that matrix
        (what the probes of the general estimate would all find)."""
        state = self.program.linear_state
        if state is None:
            return super()._spectral_radius(coef)
        A = np.zeros((self.n_states, self.n_states))
        for k, j in enumerate(state):
            if j >= 0:
                A[:, j] += coef[:, k]
        if not np.all(np.isfinite(A)):
            return np.inf
        return float(np.max(np.abs(np.linalg.eigvals(A)))) if self.n_states else 0.0

    @property
    def is_linear(self) -> bool:
        """True for a linear model without inputs: simulated by its RK4 propagator (same solution)."""
        return self.program.linear_state is not None

    def _rhs_z(self, Z, coef) -> np.ndarray:
        Z = np.asarray(Z, dtype=float)
        return term_values(self.program, Z) @ np.asarray(coef, dtype=float).T

    def _packed(self, c, dt, steps):
        """The kernel program, coefficient rows, propagators and dense rows of a batch (the model's own:
        cached)."""
        own = c is None
        if own and self._own is not None and self._own[0] == (dt, steps):
            return self._own[1]
        batch = self.coef[None] if own else c
        props = propagators(self.program, batch, dt, steps)
        if props.size and self._dense_positions is None:  # a linear model: by its propagators alone
            prog, vals, dense = None, batch, None  # (integrate_linear; a two-state one as below)
        elif self._dense_positions is None:
            prog, vals = pack(self.program, batch)
            dense = None
        else:  # a two-state cubic model: its dense rows (stepped by integrate_cubic2), no program (the batch
            # stands for the values: one row per model)
            prog, vals = None, batch
            dense = dense_coefficients(batch, self._dense_positions)
        packed = (prog, vals, props, dense)
        if own:
            self._own = ((dt, steps), packed)
        return packed

    def _integrate(self, ref, t, starts, weights, c, u, substeps, out):
        """Run the kernel (see :func:`integrators.integrate`); returns ``(errors, rows)``."""
        steps = self.substeps(t) if substeps is None else int(substeps)
        prog, vals, props, dense = self._packed(c, self._grid(t)[1], steps)
        bound = np.maximum(self.bound, 10 * np.max(np.abs(ref[starts]), axis=0))
        errors = np.empty(vals.shape[0])
        rows = np.empty(vals.shape[0], dtype=np.int64)
        uu = _as_inputs(u, len(t), self.n_inputs)
        # read-only arrays (e.g. memory-mapped data) would compile another kernel: copy them
        arrays = (ref, t, starts, weights, uu)
        ref, t, starts, weights, uu = (a if a.flags.writeable else a.copy() for a in arrays)
        if dense is not None:  # a two-state cubic model (linear ones too: the kernel the first fit needs)
            scratch = self._scratch
            integrate_cubic2(ref, t, starts, weights, steps, props, dense, bound, scratch, out, errors, rows)
        elif props.size:  # a linear model of more states: its propagators alone
            kernels.integrate_linear(ref, t, starts, weights, props, bound, out, errors, rows)
        elif vals.shape[0] > 2 and props.size == 0 and out.size == 0:  # models stepped together
            work = np.empty((self._scratch.shape[0], vals.shape[0]))
            kernels.integrate_batch(ref, t, starts, weights, steps, prog, np.ascontiguousarray(vals.T), bound,
                                    uu, work, errors, rows)
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

    def simulate_segments(self, start_states, t, starts, coef=None) -> np.ndarray:
        """Simulations restarted at ``starts`` from ``start_states``, in one run of the kernel (see
        ``_SparseModel.simulate_segments`` in ``simulation/base.py``).

        Examples
        --------
        >>> model = CompiledModel([[0.0, 1.0], [-64.0, -3.2]], TermTable.polynomial([[1, 0], [0, 1]]))
        >>> t = np.arange(401) * 0.01
        >>> x = model.simulate([1.0, 0.0], t)
        >>> bool(np.allclose(model.simulate_segments(x[[0, 100, 300]], t, [0, 100, 300]), x))
        True
        """
        t = np.ascontiguousarray(t, dtype=float)
        starts = np.ascontiguousarray(starts, dtype=np.int64)
        if self.n_inputs or self.is_stiff(t):
            return super().simulate_segments(start_states, t, starts, coef)
        ref = np.zeros((t.shape[0], self.n_states))
        ref[starts] = np.asarray(start_states, dtype=float).reshape(starts.size, self.n_states)
        c = None if coef is None else np.ascontiguousarray(coef, dtype=float)[None]
        out = np.empty_like(ref)
        self._integrate(ref, t, starts, _NO_WEIGHTS, c, None, None, out)
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

    def weighted_l1_until(self, reference, t, starts, weights, cutoff, u=None, resume=None,
                          pieces: int = PIECES):
        """:meth:`weighted_l1` of the model's own coefficients, stopped once the sum passes ``cutoff``.

        The error is a sum of non-negative terms in time order, so a partial sum above ``cutoff`` is a
        lower bound above it: the rest of the simulation need not run. The record is simulated in about
        ``pieces`` pieces (each segment cut where a piece ends, the state carried over), and the sum is
        accumulated in the kernel's order, so a simulation that runs to the end gives :meth:`weighted_l1`'s
        error to the last bit and does the same work, also when resumed. Linear models (one propagator per
        interval: a simulation costs little), two-state cubic and stiff ones run whole.

        Parameters
        ----------
        reference, t, starts, weights, u
            As :meth:`weighted_l1`.
        cutoff : float
            Stop once the error passes it (``inf``: run to the end).
        resume : tuple, optional
            The ``progress`` of a stopped call with the same arguments: continue from there.
        pieces : int, default=PIECES

        Returns
        -------
        (error, finished, progress)
            The error (``inf`` if the simulation diverged), or, ``finished`` False, the partial sum that
            passed ``cutoff`` (a lower bound of the error) and where it stopped (``resume``).
        """
        t = np.ascontiguousarray(t, dtype=float)
        ref = np.ascontiguousarray(reference, dtype=float)
        starts = np.ascontiguousarray(starts, dtype=np.int64)
        weights = np.ascontiguousarray(weights, dtype=float)
        if (self.is_linear or self._dense_positions is not None or self.is_stiff(t)
                or len(t) < 2 * max(pieces, 1)):
            return float(self.weighted_l1(ref, t, starts, weights, None, u)[0][0]), True, None
        steps = self.substeps(t)
        prog, vals, _, _ = self._packed(None, self._grid(t)[1], steps)
        bound = np.maximum(self.bound, 10 * np.max(np.abs(ref[starts]), axis=0))
        uu = _as_inputs(u, len(t), self.n_inputs)
        if not ref.flags.writeable or not t.flags.writeable:  # as in _integrate: one compiled kernel
            ref, t = ref.copy(), t.copy()
        cuts = np.linspace(0, len(t) - 1, max(pieces, 1) + 1).astype(np.int64)
        cuts = cuts[cuts >= starts[0]]  # the kernel starts at the first segment
        edges = np.union1d(np.append(starts, len(t) - 1), cuts)
        segment_of = np.searchsorted(starts, edges, side="right") - 1
        restarts = np.isin(edges, starts)
        errors, rows = np.empty(1), np.empty(1, dtype=np.int64)
        first, x, total = (0, ref[0], np.zeros(1)) if resume is None else resume
        for e in range(first, edges.size - 1):
            a, b, k = edges[e], edges[e + 1], segment_of[e]
            x0 = ref[a : a + 1] if restarts[e] else x[None]
            out = np.empty((b - a + 1, self.n_states))
            piece_u = uu if uu.size == 0 else uu[a : b + 1]
            kernels.integrate(x0, t[a : b + 1], _FIRST, _NO_WEIGHTS, steps, prog, vals, NO_PROPAGATOR, bound,
                              piece_u, self._scratch, out, errors, rows)
            self.work_done += self.work(t, steps, int(rows[0]))
            if not np.all(np.isfinite(out[-1])):  # diverged (the kernel fills NaN from there on)
                return np.inf, True, None
            terms = (weights[k] * np.abs(out[1:] - ref[a + 1 : b + 1])).ravel()
            total = np.cumsum(np.concatenate([total[-1:], terms]))[-1:]  # in order, as the kernel adds
            x = out[-1]
            if total[0] > cutoff and e + 2 < edges.size:
                return float(total[0]), False, (e + 1, x, total)
        return float(total[0]), True, None


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


class AtRestLevel:
    """A compiled model whose equations are written in the deviations from a rest level.

    ``rhs(x) = f(x - level)``; simulations start from ``x0 - level`` and come back with the level added,
    scores compare ``reference - level`` with the simulation. Everything else (coefficients, work counting,
    time scale) is the wrapped model's, read and written through.

    Examples
    --------
    >>> from sindy_impulse.simulation import CompiledModel, TermTable
    >>> inner = CompiledModel([[0.0, 1.0], [-64.0, -3.2]], TermTable.polynomial([[1, 0], [0, 1]]))
    >>> model = AtRestLevel(inner, np.array([5.0, 0.0]))
    >>> model.rhs(np.array([[5.0, 0.0], [6.0, 0.0]])).tolist()
    [[0.0, 0.0], [0.0, -64.0]]
    >>> bool(abs(model.simulate([6.0, 0.0], np.arange(401) * 0.01)[-1, 0] - 5.0) < 0.01)
    True
    """

    def __init__(self, model, level):
        object.__setattr__(self, "inner", model)
        object.__setattr__(self, "level", np.asarray(level, dtype=float))

    def __getattr__(self, name):
        if name in ("inner", "level") or name.startswith("__"):  # not yet set (copy, pickle)
            raise AttributeError(name)
        return getattr(self.inner, name)

    def __setattr__(self, name, value):
        setattr(self.inner, name, value)

    def rhs(self, x, u=None, coef=None):
        """The right-hand side at measured states ``x``."""
        shifted = np.asarray(x, dtype=float) - self.level
        return self.inner.rhs(shifted, u) if coef is None else self.inner.rhs(shifted, u, coef)

    def simulate(self, x0, t, *args, **kwargs):
        """A simulation from the measured state ``x0``, in measured coordinates."""
        x0 = np.asarray(x0, dtype=float).ravel()
        return self.inner.simulate(x0 - self.level, t, *args, **kwargs) + self.level

    def simulate_segments(self, start_states, t, starts, coef=None) -> np.ndarray:
        """Segment-restarted simulations from measured start states, in measured coordinates."""
        shifted = np.asarray(start_states, dtype=float) - self.level
        return self.inner.simulate_segments(shifted, t, starts, coef) + self.level

    def weighted_l1(self, reference, t, *args, **kwargs):
        """The fused error kernel against a measured reference."""
        return self.inner.weighted_l1(np.asarray(reference, dtype=float) - self.level, t, *args, **kwargs)

    def weighted_l1_until(self, reference, t, *args, **kwargs):
        """The bounded error (:meth:`CompiledModel.weighted_l1_until`) against a measured reference."""
        shifted = np.asarray(reference, dtype=float) - self.level
        return self.inner.weighted_l1_until(shifted, t, *args, **kwargs)

    def __repr__(self) -> str:
        return f"AtRestLevel({self.inner!r}, level={self.level.tolist()})"


def at_rest_level(model, level):
    """``model`` measured from ``level`` (:class:`AtRestLevel`), or ``model`` itself when the level is 0."""
    level = np.asarray(level, dtype=float)
    return model if not np.any(level) else AtRestLevel(model, level)

"""The compiled right-hand side and integrator: the hot path of the sweep and the refinement.

A sparse model ``x' = Xi Theta(x)`` is compiled into arrays holding only its active terms; a numba
kernel evaluates them and integrates with the classical fourth-order Runge-Kutta scheme on the data's
time grid, with ``substeps`` equal sub-steps per sample interval chosen from the model's fastest
time scale (its Jacobian's spectral radius along the data). A trajectory that leaves the admissible
box (``divergence_factor`` times the data's range) or becomes non-finite is stopped at once, so every
simulation takes bounded time.

Numba is a dependency because it pays: one simulation of the paper's 401-sample oscillator takes tens
of microseconds here against seconds for ``pysindy.SINDy.simulate`` (see ``benchmarks/``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .feature_library.terms import SIGNED_SQUARE, SMOOTH_SIGN, TermTable

__all__ = ["CompiledModel", "STEP_SCALE"]

#: Target of ``h * rho`` per Runge-Kutta sub-step (``h`` the sub-step, ``rho`` the spectral radius).
#: 0.02 keeps RK4's global error below 1e-7 relative on the paper's oscillator.
STEP_SCALE = 0.02
_NO_REF = np.empty((0, 0))
_NO_SCALE = np.empty(0)
MAX_SUBSTEPS = 256


@njit(cache=True, inline="always")
def _rhs(x, coef, factor_ptr, factor_state, func, func_state, func_param, out):
    """Evaluate ``coef @ Theta(x)`` for the active terms only.

    Term ``k`` is the product of the states ``factor_state[factor_ptr[k]:factor_ptr[k + 1]]`` (a state
    repeated once per power) times a scalar function ``func[k]`` of the state ``func_state[k]``.
    """
    for i in range(coef.shape[0]):
        out[i] = 0.0
    for k in range(factor_ptr.shape[0] - 1):
        v = 1.0
        for q in range(factor_ptr[k], factor_ptr[k + 1]):
            v *= x[factor_state[q]]
        f = func[k]
        if f == SIGNED_SQUARE:
            xv = x[func_state[k]]
            v *= xv * abs(xv)
        elif f == SMOOTH_SIGN:
            v *= math.tanh(x[func_state[k]] / func_param[k])
        for i in range(coef.shape[0]):
            out[i] += coef[i, k] * v


@njit(cache=True)
def _rhs_many(X, coef, fp, fs, fn, fst, fpar):
    out = np.empty((X.shape[0], coef.shape[0]))
    for r in range(X.shape[0]):
        _rhs(X[r], coef, fp, fs, fn, fst, fpar, out[r])
    return out


@njit(cache=True)
def _integrate(x0, t, substeps, coef, fp, fs, fn, fst, fpar, bound, out, ref, inv_scale):
    """RK4 on the grid ``t``.

    Writes the states to ``out`` unless it has no rows, and accumulates Gamma against ``ref`` (each state
    weighted by ``inv_scale``) unless ``ref`` has no rows. Returns ``(rows, gamma)``: the number of valid
    rows (``len(t)`` if the simulation completed) and Gamma (``inf`` if it diverged).
    """
    n = x0.shape[0]
    write = out.shape[0] > 0
    score = ref.shape[0] > 0
    k1 = np.empty(n)
    k2 = np.empty(n)
    k3 = np.empty(n)
    k4 = np.empty(n)
    tmp = np.empty(n)
    x = x0.copy()
    gamma = 0.0
    for j in range(n):
        if write:
            out[0, j] = x[j]
        if score:
            gamma += abs(x[j] - ref[0, j]) * inv_scale[j]
    for s in range(1, t.shape[0]):
        h = (t[s] - t[s - 1]) / substeps
        for _ in range(substeps):
            _rhs(x, coef, fp, fs, fn, fst, fpar, k1)
            for j in range(n):
                tmp[j] = x[j] + 0.5 * h * k1[j]
            _rhs(tmp, coef, fp, fs, fn, fst, fpar, k2)
            for j in range(n):
                tmp[j] = x[j] + 0.5 * h * k2[j]
            _rhs(tmp, coef, fp, fs, fn, fst, fpar, k3)
            for j in range(n):
                tmp[j] = x[j] + h * k3[j]
            _rhs(tmp, coef, fp, fs, fn, fst, fpar, k4)
            for j in range(n):
                x[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j])
        for j in range(n):
            # "not (a <= b)" is also true for NaN
            if not (abs(x[j]) <= bound[j]):
                if write:
                    for r in range(s, t.shape[0]):
                        for q in range(n):
                            out[r, q] = np.nan
                return s, np.inf
            if write:
                out[s, j] = x[j]
            if score:
                gamma += abs(x[j] - ref[s, j]) * inv_scale[j]
    return t.shape[0], gamma


@njit(cache=True)
def _gamma_batch(x0, t, substeps, coefs, fp, fs, fn, fst, fpar, bound, ref, inv_scale):
    """Gamma and simulated rows for each coefficient matrix of ``coefs`` (one kernel call)."""
    gammas = np.empty(coefs.shape[0])
    rows = np.empty(coefs.shape[0], dtype=np.int64)
    no_out = np.empty((0, x0.shape[0]))
    for b in range(coefs.shape[0]):
        rows[b], gammas[b] = _integrate(
            x0, t, substeps, coefs[b], fp, fs, fn, fst, fpar, bound, no_out, ref, inv_scale
        )
    return gammas, rows


def _kernel_arrays(terms: TermTable) -> tuple:
    """The term table in the sparse form the kernels read."""
    counts = terms.powers.sum(axis=1)
    factor_ptr = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    factor_state = np.concatenate(
        [np.zeros(0, np.int64)] + [np.repeat(np.arange(terms.powers.shape[1]), row) for row in terms.powers]
    ).astype(np.int64)
    return (
        factor_ptr,
        factor_state,
        np.ascontiguousarray(terms.func, dtype=np.int64),
        np.ascontiguousarray(terms.func_state, dtype=np.int64),
        np.ascontiguousarray(terms.func_param, dtype=float),
    )


class CompiledModel:
    """A sparse model ``x' = coef @ Theta(x)`` compiled for fast evaluation and simulation.

    Parameters
    ----------
    coefficients : array of shape (n_states, n_features)
        The model's coefficients (rows: equations, columns: library terms).
    terms : TermTable
        The library's terms (see :func:`sindy_impulse.feature_library.term_table`).
    reference : array of shape (n_samples, n_states), optional
        States along which the fastest time scale is estimated (the data the model was fitted to).
        Defaults to the origin.
    divergence_factor : float, default=100
        A simulation stops as diverged once a state exceeds this factor times the reference's largest
        absolute value of that state.

    Examples
    --------
    >>> import numpy as np
    >>> from sindy_impulse.feature_library import TermTable
    >>> terms = TermTable.polynomial([[1, 0], [0, 1]])
    >>> model = CompiledModel([[0.0, 1.0], [-64.0, -3.2]], terms, reference=[[1.0, 0.0], [0.0, 8.0]])
    >>> x = model.simulate([1.0, 0.0], np.arange(401) * 0.01)
    >>> x.shape, bool(abs(x[-1, 0]) < 0.01)
    ((401, 2), True)
    """

    def __init__(self, coefficients, terms: TermTable, reference=None, divergence_factor: float = 100.0):
        coef = np.atleast_2d(np.asarray(coefficients, dtype=float))
        if coef.shape[1] != terms.n_features:
            raise ValueError(
                f"coefficients have {coef.shape[1]} columns but the library has {terms.n_features} terms"
            )
        self.n_states = coef.shape[0]
        if terms.powers.shape[1] != self.n_states:
            raise ValueError(
                f"the library acts on {terms.powers.shape[1]} states but there are {self.n_states} equations"
            )
        self.full_coefficients = coef
        self.active = np.flatnonzero(np.any(coef != 0, axis=0))
        self.terms = terms.subset(self.active)
        self.coef = np.ascontiguousarray(coef[:, self.active])
        self._kernel = _kernel_arrays(self.terms)
        ref = (
            np.zeros((1, self.n_states)) if reference is None else np.atleast_2d(np.asarray(reference, float))
        )
        scale = np.max(np.abs(ref), axis=0)
        scale = np.where(scale > 0, scale, 1.0)
        self.bound = divergence_factor * scale
        # Sample at most 64 reference points for the time scale estimate.
        idx = np.unique(np.linspace(0, ref.shape[0] - 1, min(64, ref.shape[0])).astype(int))
        self._probe = np.ascontiguousarray(ref[idx])
        self.spectral_radius = self._spectral_radius(self.coef)

    # -- evaluation ---------------------------------------------------------------------------------
    def _args(self, coef):
        return (coef, *self._kernel)

    def rhs(self, x, coef=None) -> np.ndarray:
        """Right-hand side at states ``x`` (n_samples, n_states); ``coef`` overrides the active ones."""
        X = np.ascontiguousarray(np.atleast_2d(np.asarray(x, dtype=float)))
        c = self.coef if coef is None else np.ascontiguousarray(coef, dtype=float)
        return _rhs_many(X, *self._args(c))

    def _spectral_radius(self, coef) -> float:
        """Largest |eigenvalue| of the Jacobian over the probe points (central differences)."""
        X = self._probe
        n = self.n_states
        h = 1e-6 * np.maximum(np.max(np.abs(X), axis=0), 1e-12)
        jac = np.empty((X.shape[0], n, n))
        for j in range(n):
            dx = np.zeros(n)
            dx[j] = h[j]
            jac[:, :, j] = (self.rhs(X + dx, coef) - self.rhs(X - dx, coef)) / (2 * h[j])
        if not np.all(np.isfinite(jac)):
            return np.inf
        return float(np.max(np.abs(np.linalg.eigvals(jac))))

    def substeps(self, t, radius: float | None = None) -> int:
        """RK4 sub-steps per sample interval so that ``h * rho <= STEP_SCALE``."""
        rho = self.spectral_radius if radius is None else radius
        dt_max = float(np.max(np.diff(t))) if len(t) > 1 else 0.0
        if not np.isfinite(rho):
            return MAX_SUBSTEPS
        return int(min(MAX_SUBSTEPS, max(1, math.ceil(dt_max * rho / STEP_SCALE))))

    def work(self, t, substeps: int | None = None, rows: int | None = None) -> float:
        """Cost of a simulation over ``t`` (its first ``rows`` samples), in term evaluations per RK4 step.

        ``(rows - 1) * substeps * max(1, n_active_terms)``: what a
        :class:`~sindy_impulse.refinement.WorkBudget` counts (deterministic, unlike wall time).
        """
        steps = self.substeps(t) if substeps is None else int(substeps)
        rows = len(t) if rows is None else rows
        return float(max(rows - 1, 0) * steps * max(1, self.coef.shape[1]))

    def simulate(self, x0, t, coef=None, substeps: int | None = None) -> np.ndarray:
        """Integrate from ``x0`` over the time grid ``t``.

        Returns an array (len(t), n_states); rows after a divergence are NaN.
        """
        t = np.ascontiguousarray(t, dtype=float)
        x0 = np.ascontiguousarray(x0, dtype=float).ravel()
        if x0.shape[0] != self.n_states:
            raise ValueError(f"x0 has {x0.shape[0]} entries but the model has {self.n_states} states")
        c = self.coef if coef is None else np.ascontiguousarray(coef, dtype=float)
        steps = self.substeps(t) if substeps is None else int(substeps)
        out = np.empty((t.shape[0], self.n_states))
        bound = np.maximum(self.bound, 10 * np.abs(x0))
        _integrate(x0, t, steps, *self._args(c), bound, out, _NO_REF, _NO_SCALE)
        return out

    def gamma(self, reference, t, coefs=None, substeps: int | None = None):
        """Gamma of simulations from ``reference[0]`` against ``reference`` over ``t``, without storing them.

        Parameters
        ----------
        reference : ndarray (len(t), n_states)
        t : ndarray
        coefs : ndarray (n_models, n_states, n_active), optional
            Several active-coefficient matrices scored in one kernel call (default: the model's own).
        substeps : int, optional

        Returns
        -------
        (gammas, rows) : ndarrays (n_models,)
            Gamma (``inf`` if diverged) and the number of samples simulated (the work done).
        """
        ref = np.ascontiguousarray(reference, dtype=float)
        t = np.ascontiguousarray(t, dtype=float)
        c = self.coef[None] if coefs is None else np.ascontiguousarray(coefs, dtype=float)
        steps = self.substeps(t) if substeps is None else int(substeps)
        scale = np.max(np.abs(ref), axis=0)
        inv_scale = 1.0 / np.where(scale > 0, scale, 1.0)
        bound = np.maximum(self.bound, 10 * np.abs(ref[0]))
        return _gamma_batch(ref[0].copy(), t, steps, c, *self._kernel, bound, ref, inv_scale)

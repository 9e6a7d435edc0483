"""Bounded nonlinear refinement of the non-zero coefficients (paper section 2.5).

SINDy finds the location of the non-zero coefficients but, being piecewise constant in lambda, not their
best values for the simulated response. The refinement minimizes an error measure of the simulation over
the non-zero coefficients with SciPy's SLSQP (the analogue of MATLAB's fmincon 'sqp'), each coefficient
bounded to ``[0, 1.5 xi]`` (``[1.5 xi, 0]`` for negative ones), so a term may shrink to zero and drop out,
but never change sign. Internally the unknowns are the multipliers ``w = xi_new / xi`` in ``[0, 1.5]``,
which makes the problem unit-free. The gradient is by forward differences, or, with
:data:`EXACT_GRADIENTS`, exact where the model and the measure allow (a two-state cubic model scored by a
built-in measure: one simulation carrying its sensitivities, :mod:`sindy_impulse.simulation.sensitivity`).

:func:`refine` works on any scoring function it is handed (a bound
:class:`~sindy_impulse.simulation.ErrorMeasure`); :func:`refine_coefficients` is the convenience form that
binds a measure to reference trajectories.

:func:`sindy_impulse.identification.output_error.fit_output_error` is the output-error fit that may follow it.
"""

from __future__ import annotations

import inspect
import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import minimize

from ..simulation import OutOfBudget, WorkBudget, get_error_measure

__all__ = ["refine", "refine_coefficients", "RefinementResult", "Multipliers", "REFINE_FTOL"]

#: Whether the refinement and the output-error fit use exact gradients where a model has them
#: (:mod:`sindy_impulse.simulation.sensitivity`). Off: measured (CPU time, ``identify_modes`` on issue 26's
#: records, median of 3) they cost as much as the batched forward differences per gradient (78 vs 73 ms on
#: the two-mode record) and SLSQP takes more iterations with them (65 gradients against 39), so the two-mode
#: survey took 1.25 s against 1.07 s, the three-mode one 1.73 s against 1.27 s, the nonlinear one 2.45 s
#: against 2.22 s (its work budget runs out either way).
EXACT_GRADIENTS = False
#: Forward-difference step on the multipliers (of order 1), for models without exact gradients.
_STEP = 1e-7
#: Largest change of a multiplier SLSQP's first step may propose: the objective is scaled by its initial
#: gradient so that the first quasi-Newton step (identity Hessian) is this long, whatever the record's length.
_FIRST_STEP = 0.1
#: SLSQP's stop: a change of the score between iterations below this fraction of the starting score. The
#: forward differences (:data:`_STEP`) resolve no finer; a parameter one standard deviation off raises the
#: score by about one over the samples compared (1e-4 to 1e-3 here), so 1e-7 leaves the coefficients a few
#: hundredths of a standard deviation from where 1e-10 stops. On issue 26's 50 three-mode records
#: (``benchmarks/speed/batch.py``) 1e-10 -> 1e-7 took 12 % of the survey's CPU time off and moved no
#: frequency by more than 2e-11 and no damping ratio by more than 3e-9 (relative).
REFINE_FTOL = 1e-7


@dataclass
class RefinementResult:
    """Outcome of :func:`refine`.

    Attributes
    ----------
    coefficients : ndarray (n_states, n_features)
        Refined coefficients (terms that reached zero removed).
    score : float
        The error measure of the refined model.
    score_initial : float
        The error measure before refinement.
    history : dict
        ``"score"`` (list of float) and ``"coefficients"`` (list of arrays), one entry per SLSQP iteration,
        starting with the initial model.
    success : bool
        Whether SLSQP reported convergence.
    message : str
        SLSQP's message, or why the initial model was kept (e.g. the work budget ran out).
    """

    coefficients: np.ndarray
    score: float
    score_initial: float
    history: dict = field(default_factory=dict)
    success: bool = True
    message: str = ""

    @property
    def gamma(self) -> float:
        """The refined score (named after the paper's default measure)."""
        return self.score

    @property
    def gamma_initial(self) -> float:
        return self.score_initial


class Multipliers:
    """A model's non-zero coefficients as multipliers ``w`` of their starting values (the unknowns of the
    refinement and of the output-error fit); terms whose multiplier ends below ``zero_tol`` are removed."""

    def __init__(self, model):
        self.model = model
        self.start = model.coef.copy()
        self.mask = self.start != 0
        self.values = self.start[self.mask]

    def coef_of(self, w) -> np.ndarray:
        """Active-coefficient matrix for multipliers ``w``."""
        c = self.start.copy()
        c[self.mask] = self.values * w
        return c

    def full(self, w) -> np.ndarray:
        """Full coefficient matrix (every library term) for multipliers ``w``."""
        c = self.model.full_coefficients.copy()
        c[:, self.model.active] = self.coef_of(w)
        return c

    @staticmethod
    def removed(w, zero_tol: float) -> np.ndarray:
        """``w`` with the multipliers below ``zero_tol`` set to zero (those terms drop out)."""
        return np.where(w < zero_tol, 0.0, w)


class _Objective(Multipliers):
    """The measure as a function of the multipliers, with the budget charged and the best point kept."""

    def __init__(self, model, measure, budget: WorkBudget, penalty: float, memo: dict | None = None):
        super().__init__(model)
        self.measure, self.budget, self.penalty, self.memo = measure, budget, penalty, memo
        self.best = (np.inf, None)
        self.last = (None, None)
        self.last_gradient = (None, None)
        # whether the model and the measure have exact gradients (None: not yet known; False: not used)
        self.exact = None if EXACT_GRADIENTS else False

    def scores(self, coefs, check_budget: bool = True) -> np.ndarray:
        """The measure of a batch of active-coefficient matrices, the model's work charged to the budget.

        With a ``memo``, a batch scored before is not simulated again: its scores are returned and its
        work is counted and charged as if it had been (the budget runs out where it would without the
        memo).
        """
        if check_budget and self.budget.exhausted:
            raise OutOfBudget
        key = None
        if self.memo is not None:
            coefs = np.ascontiguousarray(coefs, dtype=float)
            key = (coefs.shape, coefs.tobytes())
            if key in self.memo:
                out, work = self.memo[key]
                self.model.work_done += work
                self.budget.charge_model(self.model)
                return out.copy()
        before = self.model.work_done
        out = self.measure(self.model, coefs)
        if key is not None:
            self.memo[key] = (np.array(out, dtype=float, copy=True), self.model.work_done - before)
        self.budget.charge_model(self.model)
        return out

    def __call__(self, w) -> float:
        w = np.asarray(w, dtype=float)
        if self.last[0] is not None and np.array_equal(w, self.last[0]):
            return self.last[1]
        g = float(self.scores(self.coef_of(w)[None])[0])
        if g < self.best[0]:
            self.best = (g, w.copy())
        g = g if np.isfinite(g) else self.penalty
        self.last = (w.copy(), g)
        return g

    def gradient(self, w) -> np.ndarray:
        """The exact gradient (forward sensitivities, :meth:`exact_gradient`) where the model and the
        measure have one, else forward differences, all perturbed models scored in one call."""
        w = np.asarray(w, dtype=float)
        if self.last_gradient[0] is not None and np.array_equal(w, self.last_gradient[0]):
            return self.last_gradient[1]
        g = self(w)
        exact = self.exact_gradient(w, g)
        if exact is not None:
            self.last_gradient = (w.copy(), exact)
            return exact
        perturbed = np.repeat(self.coef_of(w)[None], self.values.size, axis=0)
        rows, cols = np.nonzero(self.mask)
        perturbed[np.arange(self.values.size), rows, cols] += self.values * _STEP
        gp = self.scores(perturbed)
        out = (np.where(np.isfinite(gp), gp, self.penalty) - g) / _STEP
        self.last_gradient = (w.copy(), out)
        return out


    def exact_gradient(self, w, g: float):
        """The measure's gradient by the multipliers from the model's sensitivities (None where there are
        none: another library, control inputs, a measure other than the built-in weighted L1 ones)."""
        if self.exact is False:
            return None
        if self.budget.exhausted:
            raise OutOfBudget
        exact = getattr(self.measure, "gradient", None)
        out = None if exact is None else exact(self.model, self.coef_of(w), self.mask)
        self.budget.charge_model(self.model)
        self.exact = out is not None
        if out is None:
            return None
        return out[1][self.mask] * self.values if np.isfinite(g) and np.isfinite(out[0]) else np.zeros(w.size)


def _check(bound_factor, max_iter, name: str = "max_iter") -> None:
    if isinstance(bound_factor, bool) or not (np.isfinite(bound_factor) and bound_factor > 0):
        raise ValueError(f"bound_factor must be a positive number, got {bound_factor!r}")
    if isinstance(max_iter, bool) or not (isinstance(max_iter, (int, np.integer)) and max_iter > 0):
        raise ValueError(f"{name} must be a positive integer, got {max_iter!r}")


def refine(
    model,
    measure,
    bound_factor: float = 1.5,
    max_iter: int = 100,
    zero_tol: float = 1e-3,
    budget: WorkBudget | None = None,
    penalty: float | None = None,
    ftol: float = REFINE_FTOL,
    resolution: float = 0.0,
    memo: dict | None = None,
) -> RefinementResult:
    """Minimize ``measure(model, coefs)`` over the model's non-zero coefficients within sign-keeping bounds.

    Parameters
    ----------
    model : CompiledModel or FallbackModel
        The model to refine; its non-zero coefficients are the unknowns. Its time scale is fixed for the
        whole optimization (a smooth objective), allowing for coefficients up to ``bound_factor``.
    measure : callable
        ``measure(model, coefs) -> errors`` for a batch of active-coefficient matrices (a bound
        :class:`~sindy_impulse.simulation.ErrorMeasure`).
    bound_factor : float, default=1.5
        Upper bound of each coefficient's magnitude relative to its start (the paper's 1.5).
    max_iter : int, default=100
        SLSQP iterations.
    zero_tol : float, default=1e-3
        A coefficient whose magnitude ends below ``zero_tol`` times its start is removed.
    budget : WorkBudget, optional
        Simulation work allowed (default: a fresh budget). When it runs out the optimization stops at the
        best coefficients found so far (``success=False``).
    penalty : float, optional
        Value used for a diverged simulation (default: ``10 * score_initial + 1``).
    ftol : float, default=REFINE_FTOL
        SLSQP stops once an iteration changes the score by less than this fraction of the starting score
        (a coarser value where only the score's first digits matter, e.g. to compare candidates).
    resolution : float, default=0.0
        The smallest score the measure resolves (its floor per compared value times the values compared,
        as in :func:`~sindy_impulse.identification.selection.tolerance`): the stop is ``ftol`` times the
        larger of it and the starting score. On clean data the starting score can lie far below it, where
        ``ftol`` times that score asks for changes below the rounding of the forward differences and SLSQP
        runs to ``max_iter`` (the paper's noise-free oscillator: 100 iterations and 1,188 calls of the
        measure, where this stop takes 5 and 47 to the same score, 1.8e-5, and the same coefficients to 7
        digits).
    memo : dict, optional
        Scores of the batches of coefficients already simulated, filled in here: refinements of the same
        model (the same starting coefficients and bounds, compiled the same way) on the same measure may
        share one. SLSQP is deterministic, so a refinement to a finer ``ftol`` from the same start repeats
        a coarser one's iterations before it goes on: with a shared memo those are not simulated again.
        The same scores, coefficients and work charged to ``budget`` as without it (used only where the
        scores depend on the coefficients alone: a compiled model integrated by RK4 on a bound measure).

    Returns
    -------
    RefinementResult
        Never worse than the starting model: if SLSQP fails or does not improve, the starting coefficients
        are returned (with a warning on failure).
    """
    _check(bound_factor, max_iter)
    model.spectral_radius = model.spectral_radius * max(1.0, bound_factor)
    budget = WorkBudget() if budget is None else budget
    memo = memo if memo is not None and _reproducible(model, measure) else None
    objective = _Objective(model, measure, budget, np.inf, memo)
    start = model.full_coefficients.copy()
    try:
        g0 = float(objective.scores(model.coef[None])[0])
    except OutOfBudget:
        return RefinementResult(start, np.nan, np.nan, {}, False, "simulation work budget exhausted")
    objective.penalty = penalty if penalty is not None else 10.0 * g0 + 1.0
    history = {"score": [g0], "coefficients": [start.copy()]}
    keep = RefinementResult(start, g0, g0, history, False, "nothing to refine")
    if objective.values.size == 0 or not np.isfinite(g0):
        return keep

    def callback(w, *args):
        history["score"].append(objective(w))
        history["coefficients"].append(objective.full(w))

    try:
        start_w = np.ones(objective.values.size)
        scale = max(float(np.max(np.abs(objective.gradient(start_w)))) / _FIRST_STEP, 1e-12 * g0, 1e-300)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            res = minimize(
                lambda w: objective(w) / scale,
                start_w,
                jac=lambda w: objective.gradient(w) / scale,
                method="SLSQP",
                bounds=[(0.0, bound_factor)] * objective.values.size,
                callback=callback,
                options={"maxiter": max_iter, "ftol": ftol * max(g0, resolution, 1e-12) / scale},
            )
        w, success, message = np.asarray(res.x, float), bool(res.success), str(res.message)
    except OutOfBudget:
        if objective.best[1] is None:
            keep.message = "simulation work budget exhausted"
            return keep
        w, success, message = objective.best[1], False, "simulation work budget exhausted"
    except Exception as err:  # noqa: BLE001 - any optimizer failure keeps the unrefined model
        keep.message = f"{type(err).__name__}: {err}"
        warnings.warn(f"refinement failed ({keep.message}); keeping the unrefined model", RuntimeWarning, 2)
        return keep
    return _finish(objective, w, g0, history, success, message, zero_tol, keep)


def _reproducible(model, measure) -> bool:
    """Whether ``measure``'s scores of ``model`` depend on the coefficients alone (then a memo may serve
    them): a compiled model integrated by RK4 (not stiff) on every grid of a bound measure. An adaptive
    simulation (a stiff or a fallback model) stops where the remaining work budget does, so the same
    coefficients scored later may come out otherwise: those are scored anew."""
    trajectories = getattr(measure, "trajectories_", None)
    if trajectories is None or getattr(model, "program", None) is None:
        return False
    return not any(model.is_stiff(t) for _, t, _ in trajectories)


def _finish(objective, w, g0, history, success, message, zero_tol, keep) -> RefinementResult:
    """Remove the terms that reached zero and keep the result only if it improved."""
    w = objective.removed(w, zero_tol)
    g = float(objective.scores(objective.coef_of(w)[None], check_budget=False)[0])
    if not np.isfinite(g) or g >= g0 or not np.all(np.isfinite(w)):
        keep.success, keep.message = success, "refinement did not improve the score"
        return keep
    history["score"].append(g)
    history["coefficients"].append(objective.full(w))
    return RefinementResult(objective.full(w), g, g0, history, success, message)


def refine_coefficients(
    model, references, times, *options, error_measure="gamma", inputs=None, **keywords
) -> RefinementResult:
    """Refine ``model`` on an error measure of its simulations against reference trajectories.

    Parameters
    ----------
    model : CompiledModel or FallbackModel
    references : list of ndarray (n_i, n_states)
        States the simulations are compared with (each simulation starts at their first sample).
    times : list of ndarray
        Their time grids.
    *options, **keywords
        :func:`refine`'s ``bound_factor``, ``max_iter``, ``zero_tol``, ``budget`` (in that order) and
        ``penalty``.
    error_measure : str, ErrorMeasure or callable, default="gamma"
        The measure (see :mod:`sindy_impulse.simulation.scoring`).
    inputs : list of ndarray, optional
        Control inputs per trajectory.

    Examples
    --------
    >>> import numpy as np
    >>> from sindy_impulse.datasets import damped_oscillator
    >>> from sindy_impulse.simulation import CompiledModel, TermTable
    >>> t, x, _ = damped_oscillator()
    >>> start = CompiledModel([[0, 1.0], [-60.0, -4.0]], TermTable.polynomial([[1, 0], [0, 1]]), x)
    >>> res = refine_coefficients(start, [x], [t])
    >>> bool(res.score < 0.01 * res.score_initial), np.round(res.coefficients[1], 2).tolist()
    (True, [-64.0, -3.2])
    """
    arguments = inspect.signature(refine).bind(model, None, *options, **keywords).arguments
    _check(arguments.get("bound_factor", 1.5), arguments.get("max_iter", 100))  # before the measure's work
    measure = get_error_measure(error_measure, references).bind(list(references), list(times), inputs)
    return refine(model, measure, *options, **keywords)

"""The stages of a fit, in the paper's order (Figure 1, sections 2.3-2.5), as functions.

:class:`~sindy_impulse.ImpulseSINDy` and the nonlinearity test's refits
(:func:`~sindy_impulse.analysis.nonlinearity_test`) run the same functions, so the test sees its data
exactly as a fit would:

1. :func:`prepare`: the regression problem (:class:`Problem`): the library ``Theta`` built on the filtered
   states (:mod:`~sindy_impulse.differentiation`) measured from their rest level, the derivatives with
   clipped samples left out (:mod:`~sindy_impulse.preprocessing.states`), the library's terms as the
   simulator reads them and the reference every candidate model is compiled against;
2. the candidates: the optimizer's threshold path (:func:`~sindy_impulse.optimizers.candidate_path`,
   the estimator) or given supports (:meth:`Problem.on_supports`, the nonlinearity test);
3. :func:`run_stages`: every candidate simulated and scored on an error measure
   (:mod:`~sindy_impulse.simulation.scoring`), one selected (:mod:`.selection`) and refined
   (:mod:`.refinement`), then, if asked, its coefficients and initial states fitted by output error
   (:mod:`.output_error`).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np
from pysindy.utils import AxesArray

from .._utils.trajectories import Trajectories, check_derivatives
from ..differentiation import differentiate
from ..exceptions import DataWarning, NoDynamicsWarning
from ..feature_library.terms import library_terms
from ..optimizers import least_squares
from ..preprocessing.states import leave_out_clipped
from ..simulation import Reference, TermTable, WorkBudget, at_rest_level, compile_model, oscillation_count
from .output_error import OutputErrorResult, fit_output_error
from .refinement import REFINE_FTOL, refine
from .selection import exact_scores_needed, reads_bounds, select_candidate

__all__ = [
    "Problem",
    "StageResult",
    "UnfinishedScores",
    "prepare",
    "run_stages",
    "filter_states",
    "SCREEN_FTOL",
]

#: SLSQP's stop (relative change of the score between iterations, see :data:`.refinement.REFINE_FTOL`)
#: of the refinements a selection rule compares: the rules compare refined scores to within
#: :data:`.selection.REL_TOL` (10 %) of the score, a thousand times coarser. The selected candidate is
#: then refined once more, from its unrefined coefficients, to :data:`.refinement.REFINE_FTOL`: its
#: coefficients are those of a refinement to full precision.
SCREEN_FTOL = 1e-4


def filter_states(method, data: Trajectories, x_dot=None, plain: bool = False):
    """Filtered states and derivatives (section 2.3): ``method``'s, or the measured states with ``x_dot``.

    ``plain`` (PySINDy mode) falls back to finite differences, with a warning, on records too short for
    ``method``. Returns ``(filtered, derivatives)``, lists of arrays.
    """
    if x_dot is None:
        return differentiate(method, data.x, data.t, plain, stacklevel=5)  # the caller of fit
    return [xi.copy() for xi in data.x], check_derivatives(x_dot, data)


@dataclass
class Problem:
    """The regression problem of a fit: what every stage after the differentiation reads.

    Attributes
    ----------
    data : Trajectories
        The measured states, times and inputs.
    filtered, derivs : list of ndarray
        Filtered states (what the library, the simulations and the scores use) and derivatives (NaN rows
        are left out of the regression: trimmed ends, clipped samples).
    level : ndarray (n_states,)
        The rest level the equations are written about (0: none).
    theta : ndarray (n_rows, n_features)
        The library on the filtered states measured from ``level`` (and the inputs).
    y : ndarray (n_rows, n_states)
        The stacked derivatives.
    terms : TermTable or callable
        The fitted library's terms as the simulator reads them.
    excluded : int
        Samples left out of the regression because a state is clipped there.
    divergence_factor : float
        A simulation beyond this factor times the data's range counts as diverged.
    """

    data: Trajectories
    filtered: list
    derivs: list
    level: np.ndarray
    theta: np.ndarray
    y: np.ndarray
    terms: object
    excluded: int = 0
    divergence_factor: float = 100.0
    reference: Reference = field(init=False, repr=False)

    def __post_init__(self):
        inputs = None if self.data.u is None else np.vstack(self.data.u)
        self.reference = Reference(np.vstack(self.filtered) - self.level, inputs, self.data.n_inputs)

    @property
    def n_values(self) -> int:
        """Values a score sums over (samples x states)."""
        return int(sum(f.size for f in self.filtered))

    def compile(self, coef):
        """A model of the coefficients ``coef``, in the measured coordinates (about the rest level)."""
        inputs = None if self.data.u is None else np.vstack(self.data.u)
        model = compile_model(
            coef, self.terms, self.reference, self.divergence_factor, inputs, self.data.n_inputs
        )
        return at_rest_level(model, self.level)

    @property
    def sub_libraries(self) -> list[np.ndarray]:
        """Column masks of the sub-libraries whose threshold paths join the candidates
        (:func:`~sindy_impulse.optimizers.candidate_path`): the library's linear terms (a constant, or one
        state or input itself), when it holds other terms too and describes its terms (a
        :class:`~sindy_impulse.simulation.TermTable`). The linear model is every structure's model at
        small amplitude, and the one the full library's path passes by when nonlinear terms are collinear
        with the linear ones on the data.
        """
        if not isinstance(self.terms, TermTable):
            return []
        linear = self.terms.linear
        return [linear] if linear.any() and not linear.all() else []

    def on_supports(self, supports) -> list[np.ndarray]:
        """Least-squares coefficients of the regression on each given support (boolean masks)."""
        return [least_squares(self.theta, self.y, np.asarray(s, dtype=bool)) for s in supports]


def prepare(
    library,
    data: Trajectories,
    filtered,
    derivs,
    level=None,
    *,
    leave_out_clipped_samples: bool = False,
    divergence_factor: float = 100.0,
    refuse_underdetermined: bool = True,
) -> Problem:
    """The regression problem: the library fitted to the filtered states measured from ``level``.

    Parameters
    ----------
    library : PySINDy feature library
        Fitted here (in place): pass a fresh copy.
    data : Trajectories
        The measured states (their inputs join the library's variables).
    filtered, derivs : list of ndarray
        From :func:`filter_states`.
    level : array (n_states,), optional
        Rest level to measure the states from (:func:`~sindy_impulse.preprocessing.states.rest_level`).
    leave_out_clipped_samples : bool, default=False
        Leave the rows of clipped samples out of the regression
        (:func:`~sindy_impulse.preprocessing.states.leave_out_clipped`).
    divergence_factor : float, default=100
        Passed to every compiled model.
    refuse_underdetermined : bool, default=True
        Fewer usable rows than terms raise ValueError (False: a :class:`DataWarning`, as plain PySINDy
        solves an underdetermined regression).

    Returns
    -------
    Problem

    Examples
    --------
    >>> import pysindy as ps
    >>> from sindy_impulse import TVRegDiff, damped_oscillator
    >>> from sindy_impulse._utils.trajectories import as_trajectories
    >>> ring = damped_oscillator(snr_db=40, random_state=0)
    >>> data = as_trajectories(ring.x, ring.t)
    >>> filtered, derivs = filter_states(TVRegDiff(), data)
    >>> problem = prepare(ps.PolynomialLibrary(degree=3), data, filtered, derivs)
    >>> problem.theta.shape
    (401, 10)
    """
    level = np.zeros(data.n_states) if level is None else np.asarray(level, dtype=float)
    excluded = 0
    if leave_out_clipped_samples:
        derivs, excluded = leave_out_clipped(data.x, derivs)
    shifted = [f - level for f in filtered]
    joined = shifted if data.u is None else [np.hstack([f, ui]) for f, ui in zip(shifted, data.u)]
    library.fit([AxesArray(j, {"ax_time": 0, "ax_coord": 1}) for j in joined])
    # the matrix from the library's terms (checked against its transform); unknown terms: its transform
    terms = library_terms(library, data.n_states + data.n_inputs)
    evaluate = terms.evaluate if isinstance(terms, TermTable) else terms
    theta = np.vstack([np.asarray(evaluate(j)) for j in joined])
    y = np.vstack(derivs)
    usable = int(np.sum(np.all(np.isfinite(y), axis=1) & np.all(np.isfinite(theta), axis=1)))
    if usable < theta.shape[1] + 1:
        message = (
            f"too few samples: {usable} usable derivative samples for a library of {theta.shape[1]} "
            f"terms; at least {theta.shape[1] + 1} are needed"
        )
        if refuse_underdetermined:  # a threshold path of an underdetermined fit means nothing
            raise ValueError(message)
        warnings.warn(
            message + " for a determined regression; use a longer record or a smaller library",
            DataWarning,
            stacklevel=4,
        )
    return Problem(data, filtered, derivs, level, theta, y, terms, excluded, divergence_factor)


@dataclass
class StageResult:
    """What :func:`run_stages` found.

    Attributes
    ----------
    index : int
        The selected candidate.
    coefficients : ndarray
        Its coefficients after the refinement (and the output-error fit).
    score : float
        Its refined score (before the output-error fit).
    scores : ndarray
        Every candidate's unrefined score (``inf``: diverged or not simulated within the budget).
    history : dict
        The refinement's history.
    noise_level : float
        The measure between the measured and the filtered states.
    budget_used : float
        Fraction of the simulation work budget used.
    output_error_fit : OutputErrorResult or None
        The output-error fit, when it ran.
    unfinished : UnfinishedScores or None
        With ``bounded_scores``: the candidates whose simulation stopped once it could no longer be
        selected (their entry of ``scores`` is a lower bound), and how to finish them.
    """

    index: int
    coefficients: np.ndarray
    score: float
    scores: np.ndarray
    history: dict
    noise_level: float
    budget_used: float
    output_error_fit: OutputErrorResult | None = None
    unfinished: UnfinishedScores | None = None


class UnfinishedScores:
    """Candidates of a sweep whose scoring stopped at a lower bound, to be finished when asked for.

    Holds each such candidate's compiled model, where its simulation stopped, and the bound measure (all
    picklable), so that the sweep's full scores can be given later (e.g. when a fitted estimator's
    ``path_`` is first read) without the regression problem: each simulation resumes where it stopped.

    Parameters
    ----------
    models : dict
        ``{index: (model, progress)}`` of the unfinished candidates
        (:meth:`~sindy_impulse.simulation.WeightedL1.bounded`).
    measure : ErrorMeasure
        The bound measure that scored them.
    """

    def __init__(self, models: dict, measure):
        self.models = models
        self.measure = measure

    @property
    def indices(self) -> np.ndarray:
        """The unfinished candidates."""
        return np.array(sorted(self.models), dtype=int)

    def finish(self, scores) -> np.ndarray:
        """``scores`` with the unfinished candidates' full scores (what an unbounded sweep gives)."""
        out = np.array(scores, dtype=float, copy=True)
        for i, (model, progress) in self.models.items():
            out[i] = self.measure.bounded(model, np.inf, progress)[0]
        return out


def run_stages(
    problem: Problem,
    candidates,
    measure,
    *,
    selection="auto",
    refine_selected: bool = True,
    bound_factor: float = 1.5,
    max_iter: int = 100,
    output_error=False,
    budget: WorkBudget | None = None,
    all_diverged: str = "raise",
    bounded_scores: bool = False,
) -> StageResult:
    """Score every candidate, select one, refine it and (if asked) fit it by output error.

    Parameters
    ----------
    problem : Problem
        From :func:`prepare`.
    candidates : sequence of ndarray (n_states, n_features)
        Candidate coefficient matrices (the threshold path, or least squares on given supports).
    measure : ErrorMeasure
        Bound to the problem's filtered states (``measure.bind(filtered, t, u)``).
    selection : str or callable, default="auto"
        The rule (:mod:`.selection`).
    refine_selected : bool, default=True
        Refine the selected candidate (:func:`~.refinement.refine`); never kept when worse.
    bound_factor, max_iter : float, int
        The refinement's bounds and iterations.
    output_error : bool or float, default=False
        Fit the refined coefficients and the initial states by output error; a number ``P`` only when no
        trajectory holds more than ``P`` periods.
    budget : WorkBudget, optional
        Simulation work allowed for scoring and refining (None: unbounded scoring, a fresh budget for the
        refinement).
    all_diverged : {"raise", "keep"}, default="raise"
        When every candidate diverges: raise RuntimeError (a fit), or keep the first candidate with its
        infinite score (a refit of a given support, whose caller compares scores).
    bounded_scores : bool, default=False
        Stop a candidate's simulation once its error passes the least error found so far (scored sparsest
        first), when the selection rule is one whose choice such lower bounds do not change
        (:func:`~.selection.exact_scores_needed`); the candidates the rule then reads are finished. The
        same selection and coefficients, at a fraction of the simulation: on a noisy record most dense
        candidates fall behind a sparse one within the first part of the record. The stopped candidates'
        ``scores`` are lower bounds; ``unfinished`` finishes them.

    Returns
    -------
    StageResult

    Examples
    --------
    The paper's oscillator with its true structure as the only candidate, refined on Gamma:

    >>> import pysindy as ps
    >>> from sindy_impulse import TVRegDiff, damped_oscillator
    >>> from sindy_impulse._utils.trajectories import as_trajectories
    >>> from sindy_impulse.simulation import Gamma
    >>> ring = damped_oscillator(snr_db=40, random_state=0)
    >>> data = as_trajectories(ring.x, ring.t)
    >>> filtered, derivs = filter_states(TVRegDiff(), data)
    >>> linear = ps.PolynomialLibrary(degree=1, include_bias=False)
    >>> problem = prepare(linear, data, filtered, derivs)
    >>> support = [[False, True], [True, True]]  # x' = v, v' = -k x - c v
    >>> result = run_stages(problem, problem.on_supports([support]), Gamma().bind(filtered, data.t))
    >>> np.round(result.coefficients[1]).tolist()  # the paper's -64 and -3.2
    [-64.0, -3.0]
    """
    candidates = [np.asarray(c, dtype=float) for c in candidates]
    n_terms = np.array([np.count_nonzero(c) for c in candidates])
    bounded = bounded_scores and reads_bounds(selection) and hasattr(measure, "bounded")
    scores, unfinished = _score(problem, candidates, n_terms, measure, budget, bounded)
    noise = measure.noise_level(problem.data.x, problem.filtered, problem.data.t)
    if unfinished:  # finish the stopped candidates whose exact score the rule reads
        needed = exact_scores_needed(selection, scores, n_terms, noise, problem.n_values, measure.floor)
        for i in [i for i in unfinished if needed[i]]:
            model, progress = unfinished.pop(i)
            scores[i] = measure.bounded(model, np.inf, progress)[0]
            if budget is not None:
                budget.charge_model(model)
    usable = _usable(scores, n_terms, all_diverged)
    refiner = _Refiner(problem, candidates, scores, measure, bound_factor, max_iter, budget, refine_selected)

    index, (coef, score, history) = select_candidate(
        selection,
        np.where(usable, scores, np.inf),
        n_terms,
        refiner.screened,
        noise,
        problem.n_values,
        measure.floor,
        final=refiner.refined,
    )
    fit = None
    if refine_selected and _output_error_on(output_error, problem.filtered) and np.any(coef):
        data = problem.data
        fit = fit_output_error(problem.compile(coef), problem.filtered, data.t, data.u, bound_factor)
        coef = fit.coefficients
    used = 0.0 if budget is None else budget.used
    unfinished = UnfinishedScores(unfinished, measure) if unfinished else None
    return StageResult(index, np.asarray(coef, dtype=float), float(score), scores, history, noise, used, fit,
                       unfinished)


class _Refiner:
    """The refinements of a sweep's candidates (paper section 2.5) for :func:`run_stages`.

    ``screened(i)``: candidate ``i`` refined to the precision the selection rule compares
    (:data:`SCREEN_FTOL`); ``refined(i)``: refined to :data:`.refinement.REFINE_FTOL`
    (the selected one). Either is never worse than the unrefined candidate. A candidate's refinements
    share a memo of the coefficients they scored (:func:`~.refinement.refine`'s ``memo``): the final
    refinement starts where the screening did and repeats its iterations before it goes on, so those are
    not simulated twice. ``scores`` are the candidates' unrefined scores.
    """

    def __init__(self, problem, candidates, scores, measure, bound_factor, max_iter, budget,
                 may_refine: bool):
        self.problem, self.candidates, self.scores, self.measure = problem, candidates, scores, measure
        self.bound_factor, self.max_iter, self.may_refine = bound_factor, max_iter, may_refine
        self.budget = WorkBudget() if budget is None else budget
        self._memos: dict[int, dict] = {}

    def refined(self, i: int, ftol: float = REFINE_FTOL):
        """``(coefficients, score, history)`` of candidate ``i`` refined on the measure to ``ftol``."""
        candidate, score = self.candidates[i], self.scores[i]
        if not self.may_refine or not np.isfinite(score):
            return candidate, score, {"score": [], "coefficients": []}
        resolution = self.measure.floor * self.problem.n_values
        res = refine(
            self.problem.compile(candidate), self.measure, self.bound_factor, self.max_iter,
            budget=self.budget, ftol=ftol, resolution=resolution, memo=self._memos.setdefault(i, {}),
        )
        if not res.score <= score:
            return candidate, score, res.history
        return res.coefficients, res.score, res.history

    def screened(self, i: int):
        """:meth:`refined` to :data:`SCREEN_FTOL` (:func:`~.selection.select_candidate` asks once per
        candidate)."""
        return self.refined(i, SCREEN_FTOL)


def _score(problem, candidates, n_terms, measure, budget, bounded: bool = False):
    """Score of every candidate's simulation, sparsest first; past the budget, inf (not simulated).

    ``bounded``: a candidate's simulation stops once its error passes the least error of a candidate
    with terms so far (:meth:`~sindy_impulse.simulation.WeightedL1.bounded`); it then has a lower bound
    above that least error, and its model and where its simulation stopped are returned in
    ``{index: (model, progress)}`` (the unfinished candidates).
    """
    scores = np.full(len(candidates), np.inf)
    unfinished = {}
    least = np.inf  # the least finished score of a candidate with terms
    for i in np.argsort(n_terms, kind="stable"):
        if budget is not None and budget.exhausted:
            continue
        model = problem.compile(candidates[i])
        if bounded and np.isfinite(least):
            scores[i], finished, progress = measure.bounded(model, least)
            if not finished:
                unfinished[int(i)] = (model, progress)
        else:
            scores[i] = measure(model)[0]
        if budget is not None:
            budget.charge_model(model)
        if n_terms[i] > 0 and int(i) not in unfinished:
            least = min(least, scores[i])
    return scores, unfinished


def _usable(scores, n_terms, all_diverged: str) -> np.ndarray:
    """Candidates that may be selected: finite score and at least one term.

    The empty model (x' = 0) stays on the path and is selected only when every other candidate diverged
    (e.g. white noise): the honest answer "no deterministic dynamics found", with a warning.
    """
    usable = np.isfinite(scores) & (n_terms > 0)
    if np.any(usable):
        return usable
    if not np.any(np.isfinite(scores)):
        if all_diverged == "keep":
            return np.arange(len(scores)) == 0
        raise RuntimeError(
            "every candidate model diverged when simulated; check the data (units of t, trends, clipping) "
            "or use a smaller feature library"
        )
    if all_diverged == "raise":
        warnings.warn(
            "every non-trivial candidate model diverged when simulated; the fitted model is x' = 0 (no "
            "deterministic dynamics found in the data)",
            NoDynamicsWarning,
            stacklevel=5,
        )
    return np.isfinite(scores)


def _output_error_on(output_error, filtered) -> bool:
    """Whether ``output_error`` asks for the output-error fit of these trajectories."""
    if isinstance(output_error, (bool, np.bool_)):
        return bool(output_error)
    return all(oscillation_count(f) <= output_error for f in filtered)

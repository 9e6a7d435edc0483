"""ImpulseSINDy: PySINDy plus the threshold sweep scored on the simulation error and the bounded refinement.

The estimator reads like the paper's Figure 1 plus sections 2.4-2.5 and holds no algorithm of its own:
validate, filter and differentiate, measure the states from their rest level
(:mod:`~sindy_impulse.preprocessing.states`), check them (:mod:`~sindy_impulse.diagnostics`), build the
regression (:func:`~.stages.prepare`), enumerate the candidates along the threshold path
(:mod:`~sindy_impulse.optimizers`), then score, select, refine and fit by output error
(:func:`~.stages.run_stages`), and keep the result. With ``sweep=False, refine=False`` it is plain PySINDy.
"""

from __future__ import annotations

from dataclasses import replace
from numbers import Integral, Real

import numpy as np
import pysindy as ps

from .._utils.params import HasMethods, Interval, Satisfies, validate_params
from .._utils.threads import one_thread
from .._utils.trajectories import as_trajectories, refuse_unsupported
from ..diagnostics import check_magnitude, clipped_samples, diagnose_fit, screen_states
from ..optimizers import candidate_path
from ..preprocessing.states import rest_level
from ..simulation import ERROR_MEASURES, ErrorMeasure, WorkBudget
from ..simulation import simulation_gamma as _gamma
from .components import ComponentsMixin
from .fitted import FittedModelMixin, SweepPath, fresh_measure
from .initial_state import estimate_initial_states
from .selection import SELECTION_RULES
from .stages import filter_states, prepare, run_stages

__all__ = ["ImpulseSINDy", "SweepPath", "fit_deferred"]


class ImpulseSINDy(ComponentsMixin, FittedModelMixin, ps.SINDy):
    """SINDy for impulse responses: threshold sweep on the simulation error and bounded refinement.

    A drop-in :class:`pysindy.SINDy` (the same constructor arguments and methods: ``fit``, ``predict``,
    ``simulate``, ``score``, ``coefficients``, ``equations``, ``print``; several and ragged trajectories,
    control inputs ``u``, any optimizer and ODE library; PDE, weak-form and implicit problems raise
    :class:`~sindy_impulse.exceptions.UnsupportedProblemError`) and a scikit-learn estimator. Every distinct
    sparse model along the optimizer's threshold path is simulated (driven by ``u``) and scored by an error
    measure (the paper's Gamma for short records, a segment-wise measure for long ones); one is selected
    and its non-zero coefficients refined within ``[0, bound_factor * xi]``. ``score`` is minus that error
    with ``sweep=True`` and PySINDy's R^2 of the derivatives otherwise (see :meth:`score`). Unlike PySINDy,
    a ``None`` component stays ``None`` (scikit-learn's rule): the fitted ones are ``optimizer_``,
    ``feature_library_``, ``differentiation_method_``.

    Parameters
    ----------
    optimizer : PySINDy optimizer, default=ThresholdSweep()
        Its threshold path gives the candidates (see :func:`~sindy_impulse.optimizers.candidate_path`).
    feature_library : PySINDy feature library, default=PolynomialLibrary(degree=3)
        Polynomial, Fourier and :class:`~sindy_impulse.MechanicalLibrary` terms (also concatenated, tensored
        or generalized) run compiled; any other library (e.g. ``CustomLibrary``) is simulated by a fallback.
    differentiation_method : PySINDy differentiation, default=TVRegDiff()
        Its ``smoothed_x_`` (the filtered states) is what the library, the simulations and the error use.
    error_measure : "auto", "gamma", "segmented", a registered name, ErrorMeasure or callable, default="auto"
        How a simulation is scored (:mod:`sindy_impulse.simulation.scoring`); ``"auto"`` is ``"gamma"``
        up to :data:`~sindy_impulse.simulation.AUTO_PERIODS` periods, ``"segmented"`` beyond.
    selection : "auto", "min_gamma", a registered name or callable, default="auto"
        The rule that picks a candidate (:mod:`sindy_impulse.identification.selection`).
    sweep : bool, default=True
        Enumerate and score the threshold path. ``False`` fits the optimizer once, as PySINDy does.
    refine : bool, default=True
        Refine the selected model's non-zero coefficients (SLSQP on the error measure).
    bound_factor : float, default=1.5
        Refinement bounds ``[0, bound_factor * xi]``.
    refine_max_iter : int, default=100
        SLSQP iterations.
    output_error : bool or float, default=False
        After the refinement, fit the non-zero coefficients once more together with each trajectory's
        initial state, by least squares of the free simulation over the whole record
        (:func:`~sindy_impulse.identification.output_error.fit_output_error`): the error measures start
        their simulations
        from the filtered first state, whose noise the coefficients otherwise absorb. A local fit of the
        whole decay, meant for records of up to a hundred periods or so: a number ``P`` turns it on only
        when no trajectory holds more than ``P`` periods (counted as ``"auto"`` counts them;
        ``identify_modes``' default estimator uses
        :data:`~sindy_impulse.modes.band_fit.OUTPUT_ERROR_PERIODS`).
    divergence_factor : float, default=100
        A simulation that exceeds this factor times the data's range counts as diverged.
    dt : float, optional
        Sampling step used when ``fit`` gets no ``t`` (e.g. as a Pipeline step); else one sample.

    Attributes
    ----------
    coef_ : ndarray (n_states, n_features)
        The final coefficients (what :meth:`coefficients` returns).
    gamma_ : float
        The paper's Gamma of the final model against the filtered states (NaN with ``sweep=refine=False``).
    score_ : float
        The error measure ``error_measure_`` of the final model.
    error_measure_ : str
        Name of the measure used.
    gamma_sindy_, score_sindy_ : float
        Gamma and score of the selected candidate before refinement.
    threshold_ : float
        Threshold of the selected candidate.
    path_ : SweepPath
        Every candidate of the sweep.
    refinement_history_ : dict
        ``"score"`` and ``"coefficients"`` per SLSQP iteration.
    output_error_fit_ : OutputErrorResult or None
        The output-error fit (``output_error=True``): costs before and after, fitted initial states.
    noise_level_ : float
        The measure between the measured and the filtered states.
    budget_used_ : float
        Fraction of the simulation work budget the fit used.
    diagnostics_ : FitDiagnostics
        The checks of the fitted model against its data and their verdict
        (:func:`~sindy_impulse.diagnostics.diagnose_fit`); ``fit`` warns when it is not ``"ok"``. A model
        fitted by :func:`fit_deferred` (the modal survey's bands) computes them when first read, without
        a warning.
    x_filtered_, t_ : ndarray or list of ndarray
        The states the library was built from, and their time vectors.
    model_ : CompiledModel or FallbackModel
        The final model, used by ``simulate`` and ``predict``.
    optimizer_, feature_library_, differentiation_method_ : the fitted components
        Copies of the parameters; in plain mode (``sweep=False, refine=False``) the objects given, fitted in
        place as PySINDy does (the one exception to "parameters are not modified").

    Examples
    --------
    >>> from sindy_impulse import ImpulseSINDy, damped_oscillator
    >>> t, x, x_dot = damped_oscillator()
    >>> model = ImpulseSINDy().fit(x, t=t)
    >>> model.print(precision=2)
    (x0)' =  1.00 x1
    (x1)' = -64.00 x0 + -3.20 x1
    """

    _parameter_constraints = {
        "optimizer": [None, HasMethods("fit", "a PySINDy optimizer")],
        "feature_library": [None, HasMethods(["fit", "transform"], "a PySINDy feature library")],
        "differentiation_method": [None, "callable"],
        "error_measure": [
            Satisfies(
                lambda v: v == "auto" or v in ERROR_MEASURES,
                lambda: "one of " + ", ".join(repr(k) for k in ["auto", *sorted(ERROR_MEASURES)]),
            ),
            ErrorMeasure,
            "callable",
        ],
        "selection": [
            Satisfies(
                lambda v: v in SELECTION_RULES,
                lambda: "one of " + ", ".join(map(repr, sorted(SELECTION_RULES))),
            ),
            "callable",
        ],
        "sweep": ["boolean"],
        "refine": ["boolean"],
        "bound_factor": [Interval(Real, 0, None, "neither")],
        "refine_max_iter": [Interval(Integral, 1, None, "left")],
        "output_error": ["boolean", Interval(Real, 0, None, "left")],
        "divergence_factor": [Interval(Real, 0, None, "neither")],
        "dt": [None, Interval(Real, 0, None, "neither")],
    }

    def __init__(
        self,
        optimizer=None,
        feature_library=None,
        differentiation_method=None,
        *,
        error_measure="auto",
        selection="auto",
        sweep: bool = True,
        refine: bool = True,
        bound_factor: float = 1.5,
        refine_max_iter: int = 100,
        output_error: bool | float = False,
        divergence_factor: float = 100.0,
        dt: float | None = None,
    ):
        self.optimizer = optimizer
        self.feature_library = feature_library
        self.differentiation_method = differentiation_method
        self.error_measure = error_measure
        self.selection = selection
        self.sweep = sweep
        self.refine = refine
        self.bound_factor = bound_factor
        self.refine_max_iter = refine_max_iter
        self.output_error = output_error
        self.divergence_factor = divergence_factor
        self.dt = dt

    # ------------------------------------------------------------------------------------------------
    # fit: the paper's pipeline
    # ------------------------------------------------------------------------------------------------
    def fit(self, x, t=None, x_dot=None, u=None, feature_names=None):
        """Fit the model: differentiate, build the library, sweep, score, select, refine.

        Parameters
        ----------
        x : array-like (n_samples, n_states) or list of them
            Measured states; a list means several trajectories (e.g. repeated impacts), possibly ragged.
        t : float, array (n_samples,) or list of arrays, optional
            Time step or time vector(s); defaults to ``dt``. A list holds one entry per trajectory.
        x_dot : array-like or list, optional
            Known derivatives; then ``x`` itself is used as the filtered states.
        u : array-like (n_samples, n_inputs) or list of them, optional
            Measured inputs (e.g. the hammer force), one row per sample of ``x``: the library is built on
            ``[x, u]`` and every simulation of the sweep and the refinement is driven by ``u``.
        feature_names : list of str, optional
            Names of the states (and of the inputs after them), e.g. ``["x", "v"]``.

        Returns
        -------
        self

        Examples
        --------
        A forced oscillator ``x'' + 0.8 x' + 64 x = f(t)`` identified from its measured random force and
        its response (40 dB noise): the sweep and the refinement simulate every candidate driven by ``u``.

        >>> from sindy_impulse.datasets import forced_oscillator
        >>> t, x, force = forced_oscillator(force="random", snr_db=40, random_state=0)
        >>> model = ImpulseSINDy().fit(x, t=t, u=force, feature_names=["x", "v", "f"])
        >>> model.print(precision=2)
        (x)' =  1.00 v
        (v)' = -64.02 x + -0.80 v +  1.00 f
        """
        with one_thread():  # small matrices: one BLAS thread is faster, and reproducible
            self._fit(x, t, x_dot, u, feature_names)
            self.diagnostics_ = diagnose_fit(self, stacklevel=2)  # the verdict; warns once if not "ok"
        return self

    @property
    def diagnostics_(self):
        """The fit's :class:`~sindy_impulse.diagnostics.FitDiagnostics` (see the class's Attributes)."""
        if "_diagnostics" not in self.__dict__:
            if not self.__dict__.get("_diagnose_on_access", False):
                raise AttributeError("'ImpulseSINDy' object has no attribute 'diagnostics_' (not fitted)")
            with one_thread():
                self._diagnostics = diagnose_fit(self, warn=False)
        return self._diagnostics

    @diagnostics_.setter
    def diagnostics_(self, value) -> None:
        self._diagnostics = value

    @property
    def _screening(self):
        """The data checks the diagnostics read (:func:`~sindy_impulse.diagnostics.screen_states`),
        computed when first read: their spectra are a tenth of a survey band's fit."""
        if "_checks" not in self.__dict__:
            self._checks = screen_states(*self._screen_inputs)
        return self._checks

    def _fit(self, x, t, x_dot, u, feature_names):
        self.__dict__.pop("_diagnostics", None)  # a refit's diagnostics are its own
        validate_params(self)
        refuse_unsupported(x, self.feature_library)
        data = as_trajectories(x, t, u, default_dt=1.0 if self.dt is None else self.dt, min_samples=3)
        self._resolve_components()
        self.output_error_fit_ = None
        plain = not (self.sweep or self.refine)  # plain PySINDy: one model, no simulation
        # states that overflow the library: refused before anything squares them (the differentiation does)
        check_magnitude(data.x, refuse_small=not plain)
        filtered, derivs = filter_states(self.differentiation_method_, data, x_dot, plain)
        if x_dot is None and not plain:  # the filter's first sample is its least accurate
            filtered = estimate_initial_states(data.x, filtered, derivs, data.t, data.u)
        rest = rest_level(data.x, data.t, allow_removal=not plain)  # a ring-down's rest level (0: none)
        problem = prepare(
            self.feature_library_,
            data,
            filtered,
            derivs,
            rest.shift,
            leave_out_clipped_samples=bool(clipped_samples(data.x)) and not plain,
            divergence_factor=self.divergence_factor,
            refuse_underdetermined=not plain,
        )
        self._excluded = problem.excluded
        self._screen_inputs = (data, filtered, rest, plain, problem.excluded)
        self.__dict__.pop("_checks", None)
        self._record_data(data, filtered, feature_names, problem.theta.shape[1])
        thresholds, candidates = candidate_path(
            self.optimizer_, problem.theta, problem.y, self.sweep, problem.sub_libraries
        )
        measure = fresh_measure(self.error_measure, filtered)
        if plain:
            self.error_measure_ = measure.name
            return self._keep(candidates, thresholds, 0, candidates[0], problem.compile, None, {},
            np.nan, np.nan)
        measure.bind(filtered, data.t, data.u)  # the inputs drive every simulation that is scored
        stages = run_stages(
            problem,
            candidates,
            measure,
            selection=self.selection,
            refine_selected=self._may_refine(),
            bound_factor=self.bound_factor,
            max_iter=self.refine_max_iter,
            output_error=self.output_error,
            budget=WorkBudget(),
            bounded_scores=True,
        )
        self.noise_level_ = stages.noise_level
        self.budget_used_ = stages.budget_used  # a budget that ran out is a reason of the verdict
        self.output_error_fit_ = stages.output_error_fit
        return self._keep(
            candidates, thresholds, stages.index, stages.coefficients, problem.compile, measure,
            stages.history, stages.scores, stages.score, stages.unfinished,
        )

    @property
    def path_(self) -> SweepPath:
        """Every candidate of the sweep (see the class's Attributes).

        The sweep stops simulating a candidate once it can no longer be selected (``run_stages``'
        ``bounded_scores``); those candidates' scores are finished here, when the path is first read, so
        ``path_.score`` holds every candidate's full score.
        """
        if "_path" not in self.__dict__:
            raise AttributeError("'ImpulseSINDy' object has no attribute 'path_' (not fitted)")
        unfinished = self.__dict__.get("_unfinished_scores")
        if unfinished is not None:
            with one_thread():
                self._path = replace(self._path, score=unfinished.finish(self._path.score))
            self._unfinished_scores = None
        return self._path

    @path_.setter
    def path_(self, value: SweepPath) -> None:
        self._path = value
        self._unfinished_scores = None

    def _may_refine(self) -> bool:
        """Whether coefficients may be fitted to simulations: ``refine`` and no clipped stretches (refining
        would fit them)."""
        return self.refine and not self._excluded

    def _keep(self, candidates, thresholds, index, coef, compile_, measure, history, scores, score,
              unfinished=None):
        """Store the selected model and what led to it (``unfinished``: candidates whose scores in
        ``scores`` are lower bounds, finished when ``path_`` is first read)."""
        self.coef_ = np.asarray(coef, dtype=float)
        self.model_ = compile_(self.coef_)
        n_terms = np.array([np.count_nonzero(c) for c in candidates])
        self.path_ = SweepPath(
            thresholds,
            np.broadcast_to(scores, n_terms.shape).copy(),
            n_terms,
            candidates,
            index,
            self.error_measure_ if measure is None else measure.name,
        )
        self._unfinished_scores = unfinished
        self.threshold_ = float(thresholds[index])
        self.refinement_history_ = history
        if measure is None:
            self.gamma_ = self.gamma_sindy_ = self.score_ = self.score_sindy_ = np.nan
            self.noise_level_, self.budget_used_ = np.nan, 0.0
            return self
        self.error_measure_ = measure.name
        self.score_ = float(measure(self.model_)[0])
        self.score_sindy_ = float(scores[index])
        self.gamma_, self.gamma_sindy_ = self.score_, self.score_sindy_
        if measure.name != "gamma":
            data = [_as_list(v) for v in (self.x_filtered_, self.t_, self.u_)]
            self.gamma_ = _gamma(self.model_, data[0], data[1], inputs=data[2])
            self.gamma_sindy_ = _gamma(compile_(candidates[index]), data[0], data[1], inputs=data[2])
        return self


def fit_deferred(model, x, t=None, x_dot=None, u=None, feature_names=None):
    """``model.fit(...)`` with the diagnostics left until ``diagnostics_`` is first read (then computed
    without a warning); any estimator other than :class:`ImpulseSINDy` is simply fitted.

    The modal survey fits a model per band and reads few verdicts: the diagnostics' term tests and
    spectra are a quarter of a band's fit. The data checks that refuse bad input still run in the fit.

    Examples
    --------
    >>> from sindy_impulse import damped_oscillator
    >>> ring = damped_oscillator(snr_db=40, random_state=0)
    >>> model = fit_deferred(ImpulseSINDy(), ring.x, t=ring.t)
    >>> "_diagnostics" in vars(model), model.diagnostics_.verdict, "_diagnostics" in vars(model)
    (False, 'ok', True)
    """
    if not isinstance(model, ImpulseSINDy):
        return model.fit(x, t=t, x_dot=x_dot, u=u, feature_names=feature_names)
    with one_thread():
        model._fit(x, t, x_dot, u, feature_names)
    model._diagnose_on_access = True
    return model


def _as_list(value):
    return value if isinstance(value, list) or value is None else [value]

"""The paper's Figure 1: from measured states to a sparse, refined model.

One module per stage, and :mod:`.stages` running them in order (the estimator's fit and the nonlinearity
test's refits call the same functions):

- :mod:`.stages`: differentiate, build the regression, score the candidates, select, refine, fit by output
  error (:func:`prepare`, :func:`run_stages`);
- :mod:`.selection`: choosing a candidate on the complexity-error plane (paper 2.5, 3.2);
- :mod:`.refinement`: bounded SLSQP of the non-zero coefficients on a simulation error (paper 2.5);
- :mod:`.output_error`: coefficients and initial states by least squares of whole free decays;
- :mod:`.estimator`: :class:`ImpulseSINDy`, the scikit-learn / PySINDy face, with its components
  (:mod:`.components`) and PySINDy's fitted-model methods (:mod:`.fitted`).
"""

from .estimator import ImpulseSINDy, fit_deferred
from .fitted import SweepPath
from .output_error import OutputErrorResult, fit_output_error
from .refinement import RefinementResult, refine, refine_coefficients
from .selection import SELECTION_RULES, register_selection_rule, select_candidate, tolerance
from .stages import Problem, StageResult, prepare, run_stages

__all__ = [
    "ImpulseSINDy",
    "fit_deferred",
    "SweepPath",
    "fit_output_error",
    "OutputErrorResult",
    "refine",
    "refine_coefficients",
    "RefinementResult",
    "SELECTION_RULES",
    "register_selection_rule",
    "select_candidate",
    "tolerance",
    "Problem",
    "StageResult",
    "prepare",
    "run_stages",
]

"""Simulation and scoring: the hot path of the sweep and the refinement.

Nothing here imports from the rest of the package: a model is coefficients plus a
:class:`~sindy_impulse.simulation.terms.TermTable` (or a function evaluating the terms), the integrators
run it, the error measures score it, and the work budget bounds it.

- :mod:`.terms`: the simulator's description of library terms;
- :mod:`.compile`: :class:`CompiledModel` (numba kernels) and :class:`FallbackModel` (any library);
- :mod:`.integrators`: RK4 kernels, the fused weighted-L1 kernel, the adaptive integrator;
- :mod:`.scoring`: error measures registered by name (``"gamma"``, ``"segmented"``, your own);
- :mod:`.budget`: the deterministic work budget of a fit.
"""

from .budget import WORK_BUDGET, OutOfBudget, WorkBudget
from .compile import STEP_SCALE, CompiledModel, FallbackModel, Reference, compile_model
from .integrators import MAX_SUBSTEPS
from .scoring import (
    AUTO_PERIODS,
    ERROR_MEASURES,
    ErrorMeasure,
    FunctionMeasure,
    Gamma,
    Segmented,
    get_error_measure,
    oscillation_count,
    register_error_measure,
    simulation_gamma,
)
from .terms import TermTable

__all__ = [
    "AUTO_PERIODS",
    "CompiledModel",
    "ERROR_MEASURES",
    "ErrorMeasure",
    "FallbackModel",
    "FunctionMeasure",
    "Gamma",
    "MAX_SUBSTEPS",
    "OutOfBudget",
    "Reference",
    "STEP_SCALE",
    "Segmented",
    "TermTable",
    "WORK_BUDGET",
    "WorkBudget",
    "compile_model",
    "get_error_measure",
    "oscillation_count",
    "register_error_measure",
    "simulation_gamma",
]

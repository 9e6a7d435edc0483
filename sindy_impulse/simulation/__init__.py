"""Simulation and scoring: the hot path of the sweep and the refinement.

Nothing here imports from the rest of the package (but the numba decorator,
:mod:`sindy_impulse._utils.jit`): a
model is coefficients plus a :class:`~sindy_impulse.simulation.terms.TermTable` (or a function evaluating
the terms), the integrators run it, the error measures score it, and the work budget bounds it.

- :mod:`.terms`: the simulator's description of library terms;
- :mod:`.base`: what every model shares (:class:`Reference`, time scale, work, adaptive integrator);
- :mod:`.compile`: :class:`CompiledModel` (numba kernels), :class:`FallbackModel` (any library) and
  :class:`AtRestLevel` (a model written about a rest level);
- :mod:`.two_state_cubic`: the two-state cubic model's kernel (its monomials in registers);
- :mod:`.program`: a model as the kernels read it (product tree, compressed coefficients, propagator);
- :mod:`.integrators`: the RK4 kernel (trajectory or fused weighted-L1 error), the adaptive integrator;
- :mod:`.scoring`: error measures registered by name (``"gamma"``, ``"segmented"``, your own);
- :mod:`.budget`: the deterministic work budget of a fit.
"""

from .base import Reference
from .budget import WORK_BUDGET, OutOfBudget, WorkBudget
from .compile import (
    SMOOTH_STEP_SCALE,
    STEP_SCALE,
    AtRestLevel,
    CompiledModel,
    FallbackModel,
    at_rest_level,
    compile_model,
)
from .integrators import MAX_SUBSTEPS
from .scoring import (
    AUTO_PERIODS,
    ERROR_MEASURES,
    Auto,
    ErrorMeasure,
    FunctionMeasure,
    Gamma,
    Segmented,
    gamma,
    get_error_measure,
    oscillation_count,
    register_error_measure,
    simulation_gamma,
)
from .terms import TermTable

__all__ = [
    "AUTO_PERIODS",
    "AtRestLevel",
    "Auto",
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
    "SMOOTH_STEP_SCALE",
    "Segmented",
    "TermTable",
    "WORK_BUDGET",
    "WorkBudget",
    "at_rest_level",
    "compile_model",
    "gamma",
    "get_error_measure",
    "oscillation_count",
    "register_error_measure",
    "simulation_gamma",
]

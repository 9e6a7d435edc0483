"""From models to answers (paper sections 3.2-3.4): complexity-error plane, consensus over repeated
impacts, parameter tracking, the test for nonlinearity and modal parameters."""

from __future__ import annotations

import importlib

_PUBLIC = {
    "complexity_error": "sindy_impulse.analysis.complexity",
    "ComplexityError": "sindy_impulse.analysis.complexity",
    "consensus": "sindy_impulse.analysis.consensus",
    "Consensus": "sindy_impulse.analysis.consensus",
    "parameter_dependency": "sindy_impulse.analysis.parameters",
    "ParameterDependency": "sindy_impulse.analysis.parameters",
    "nonlinearity_test": "sindy_impulse.analysis.nonlinearity",
    "NonlinearityResult": "sindy_impulse.analysis.nonlinearity",
    "modal_parameters": "sindy_impulse.analysis.modal",
    "ModalParameters": "sindy_impulse.analysis.modal",
}

__all__ = sorted(_PUBLIC)


def __getattr__(name: str):
    if name in _PUBLIC:
        value = getattr(importlib.import_module(_PUBLIC[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'sindy_impulse.analysis' has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + __all__)

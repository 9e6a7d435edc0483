"""sindy-impulse: differential equations from short, strongly damped impulse responses.

An extension layer on PySINDy implementing Stender, Oberst & Hoffmann (2019), "Recovery of Differential
Equations from Impulse Response Time Series Data for Model Identification and Feature Extraction",
Vibration 2(1), 25-46.

Public names are imported lazily, so ``import sindy_impulse`` stays fast; on a machine's first import the
compiled kernels are built in a background process (:mod:`sindy_impulse._utils.warmup`).
"""

from __future__ import annotations

import importlib

from ._version import __version__ as __version__

_PUBLIC = {
    "TVRegDiff": "sindy_impulse.differentiation",
    "DelayEmbedding": "sindy_impulse.embedding",
    "MechanicalLibrary": "sindy_impulse.feature_library",
    "ThresholdSweep": "sindy_impulse.optimizers",
    "ImpulseSINDy": "sindy_impulse.identification",
    "gamma": "sindy_impulse.simulation",
    "CompiledModel": "sindy_impulse.simulation",
    "refine_coefficients": "sindy_impulse.identification",
    "SINDyFeatures": "sindy_impulse.features",
    "damped_oscillator": "sindy_impulse.datasets",
    "add_noise": "sindy_impulse.datasets",
    "load_silverbox": "sindy_impulse.datasets",
    "load_flutter_rig": "sindy_impulse.datasets",
    "impact_record": "sindy_impulse.datasets",
    "identify_modes": "sindy_impulse.modes",
    "survey_many": "sindy_impulse.modes",
    "track": "sindy_impulse.tracking",
    "tracking": "sindy_impulse.tracking",
    "analysis": "sindy_impulse.analysis",
    "preprocessing": "sindy_impulse.preprocessing",
    "preprocess": "sindy_impulse.preprocessing",
    "plotting": "sindy_impulse.plotting",
    "datasets": "sindy_impulse.datasets",
    "poles": "sindy_impulse.poles",
    "identification": "sindy_impulse.identification",
}

__all__ = sorted(_PUBLIC)

try:  # a machine's first import: compile the numba kernels in the background (see _warmup)
    from ._utils import warmup as _warmup

    _warmup.start()
except Exception:  # noqa: BLE001 - never let the warm-up stop an import
    pass


def __getattr__(name: str):
    if name in _PUBLIC:
        module = importlib.import_module(_PUBLIC[name])
        value = module if module.__name__.endswith("." + name) else getattr(module, name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'sindy_impulse' has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + __all__)

"""Numerical differentiation methods for short, noisy ring-downs (PySINDy plug-ins), and the one function
that applies a method to trajectories.

Imported lazily: the compiled building blocks (``_banded``, ``_spline``) load without PySINDy.
"""

from __future__ import annotations

import importlib

__all__ = ["TVRegDiff", "differentiate"]

_PUBLIC = {"TVRegDiff": ".tvregdiff", "differentiate": ".apply"}


def __getattr__(name: str):
    if name in _PUBLIC:
        value = getattr(importlib.import_module(_PUBLIC[name], __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + __all__)

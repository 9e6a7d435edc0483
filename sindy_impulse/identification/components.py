"""The components of an ImpulseSINDy (optimizer, feature library, differentiation) as scikit-learn parameters.

scikit-learn keeps constructor parameters untouched (``None`` stays ``None``), PySINDy builds its defaults in
``__init__`` and fits the objects it is given. This mixin reconciles the two: the defaults are built at fit
(``optimizer_``, ``feature_library_``, ``differentiation_method_``), a nested parameter of a ``None``
component (``feature_library__degree``) first puts the default in place so that grids work from the
defaults, and components that scikit-learn's ``clone`` and ``get_params`` cannot handle (PySINDy's
``CustomLibrary`` stores its functions under another name, ``WrappedOptimizer`` changes its parameters in
``__init__``) are copied instead of cloned and keep no nested parameters.
"""

from __future__ import annotations

import pysindy as ps

from ..optimizers import ThresholdSweep, fresh_copy

__all__ = ["ComponentsMixin", "DEFAULT_COMPONENTS"]


def _tvregdiff():
    from ..differentiation import TVRegDiff

    return TVRegDiff()


#: The default of each component parameter, built when the parameter is None.
DEFAULT_COMPONENTS = {
    "optimizer": ThresholdSweep,
    "feature_library": lambda: ps.PolynomialLibrary(degree=3),
    "differentiation_method": _tvregdiff,
}


class ComponentsMixin:
    """``set_params``/``get_params``/``clone`` for the components, and the components of a fit."""

    def set_params(self, **params):
        """scikit-learn's ``set_params``; a nested parameter of a ``None`` component (e.g.
        ``feature_library__degree``) first puts the default component in place, so grids work from the
        defaults."""
        for key in params:
            name = key.split("__", 1)[0]
            if "__" in key and name in DEFAULT_COMPONENTS and getattr(self, name, None) is None:
                setattr(self, name, DEFAULT_COMPONENTS[name]())
        return super().set_params(**params)

    def get_params(self, deep: bool = True) -> dict:
        """scikit-learn's ``get_params``; a component whose own ``get_params`` fails gives no nested ones."""
        out = super().get_params(deep=False)
        for name, value in list(out.items()) if deep else []:
            if hasattr(value, "get_params") and not isinstance(value, type):
                try:
                    nested = value.get_params(deep=True)
                except (AttributeError, RuntimeError, TypeError):
                    continue
                out.update((f"{name}__{key}", v) for key, v in nested.items())
        return out

    def __sklearn_clone__(self):
        """An unfitted copy with copies of the components (``fresh_copy``: clone, or a deep copy)."""
        return type(self)(**{name: fresh_copy(v) for name, v in self.get_params(deep=False).items()})

    def _resolve_components(self) -> None:
        """The components of this fit: the given objects (plain mode, as PySINDy) or fresh copies."""
        plain = not (self.sweep or self.refine)
        for name, make in DEFAULT_COMPONENTS.items():
            given = getattr(self, name)
            value = make() if given is None else (given if plain else fresh_copy(given))
            setattr(self, name + "_", value)

"""Parameter constraints declared once per estimator and checked at ``fit``, with one message style.

A small equivalent of scikit-learn's (private) parameter validation. An estimator declares

    _parameter_constraints = {"refine": ["boolean"], "bound_factor": [Interval(Real, 0, None, "neither")]}

and calls ``validate_params(self)`` at the start of ``fit``. Each entry lists the accepted forms; a value
is valid when it satisfies any of them. A failure raises
:class:`~sindy_impulse.exceptions.InvalidParameterError` (a ``ValueError`` and a ``TypeError``)
worded ``"<Owner>: <name> must be <forms>; got <value>"``.

Accepted forms: ``None``; ``"boolean"``; ``"callable"``; ``"array-like"``; ``"random_state"``; a type
(``isinstance``); an :class:`Interval`; an :class:`Options` set; a :class:`HasMethods`; a callable
``check(value) -> bool`` wrapped in :class:`Satisfies` with its description.
"""

from __future__ import annotations

from collections.abc import Callable
from numbers import Integral, Real
from typing import Any

import numpy as np

from ..exceptions import InvalidParameterError

__all__ = ["Interval", "Options", "HasMethods", "Satisfies", "validate_params", "check_param"]


class Interval:
    """Numbers of a kind (``Integral`` or ``Real``) in an interval; ``None`` ends are unbounded.

    Examples
    --------
    >>> Interval(Real, 0, None, "neither").describe()
    'a number in (0, inf)'
    >>> 3 in Interval(Integral, 1, None, "left"), 0.5 in Interval(Integral, 1, None, "left")
    (True, False)
    """

    def __init__(self, kind: type, left: float | None, right: float | None, closed: str = "both"):
        if kind not in (Integral, Real):
            raise ValueError("kind must be numbers.Integral or numbers.Real")
        if closed not in ("both", "left", "right", "neither"):
            raise ValueError("closed must be 'both', 'left', 'right' or 'neither'")
        self.kind, self.left, self.right, self.closed = kind, left, right, closed

    def __contains__(self, value: Any) -> bool:
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, self.kind):
            return False
        if isinstance(value, Real) and not np.isfinite(value):
            return False
        if self.left is not None:
            if value < self.left or (value == self.left and self.closed in ("right", "neither")):
                return False
        if self.right is not None:
            if value > self.right or (value == self.right and self.closed in ("left", "neither")):
                return False
        return True

    def describe(self) -> str:
        what = "an integer" if self.kind is Integral else "a number"
        lo = "-inf" if self.left is None else f"{self.left:g}"
        hi = "inf" if self.right is None else f"{self.right:g}"
        lb = "[" if self.closed in ("both", "left") and self.left is not None else "("
        rb = "]" if self.closed in ("both", "right") and self.right is not None else ")"
        return f"{what} in {lb}{lo}, {hi}{rb}"


class Options:
    """One of a fixed set of values (usually strings).

    Examples
    --------
    >>> Options({"auto", "min_gamma"}).describe()
    "one of 'auto', 'min_gamma'"
    """

    def __init__(self, values):
        self.values = frozenset(values)

    def __contains__(self, value: Any) -> bool:
        try:
            return value in self.values
        except TypeError:  # unhashable
            return False

    def describe(self) -> str:
        return "one of " + ", ".join(repr(v) for v in sorted(self.values, key=str))


class HasMethods:
    """An object with the given methods (e.g. a PySINDy optimizer: ``fit``)."""

    def __init__(self, methods, what: str | None = None):
        self.methods = (methods,) if isinstance(methods, str) else tuple(methods)
        self.what = what

    def __contains__(self, value: Any) -> bool:
        return all(callable(getattr(value, m, None)) for m in self.methods)

    def describe(self) -> str:
        return self.what or "an object with " + ", ".join(f"{m}()" for m in self.methods)


class Satisfies:
    """Any value for which ``check(value)`` is true, described in words (or by a function giving them, for
    sets that change, such as registries)."""

    def __init__(self, check: Callable[[Any], bool], description: str | Callable[[], str]):
        self.check, self.description = check, description

    def __contains__(self, value: Any) -> bool:
        try:
            return bool(self.check(value))
        except Exception:  # noqa: BLE001 - a check that cannot run on the value rejects it
            return False

    def describe(self) -> str:
        return self.description() if callable(self.description) else self.description


def _array_like(value: Any) -> bool:
    if isinstance(value, (str, bytes)) or value is None:
        return False
    return hasattr(value, "__len__") or hasattr(value, "__array__") or hasattr(value, "shape")


_NAMED = {
    "boolean": (lambda v: isinstance(v, (bool, np.bool_)), "True or False"),
    "callable": (callable, "a callable"),
    "array-like": (_array_like, "an array-like"),
    "random_state": (
        lambda v: (
            v is None
            or (isinstance(v, Integral) and not isinstance(v, bool) and v >= 0)
            or isinstance(v, (np.random.Generator, np.random.RandomState))
        ),
        "None, a non-negative int or a numpy Generator",
    ),
}


def _accepts(constraint: Any, value: Any) -> bool:
    if constraint is None:
        return value is None
    if isinstance(constraint, str):
        return _NAMED[constraint][0](value)
    if isinstance(constraint, type):
        numeric = constraint in (Real, Integral)
        return isinstance(value, constraint) and not (numeric and isinstance(value, (bool, np.bool_)))
    return value in constraint


def _describe(constraint: Any) -> str:
    if constraint is None:
        return "None"
    if isinstance(constraint, str):
        return _NAMED[constraint][1]
    if isinstance(constraint, type):
        return f"an instance of {constraint.__name__}"
    return constraint.describe()


def check_param(name: str, value: Any, constraints: list, owner: str | None = None) -> Any:
    """Check one value against its accepted forms; return it unchanged or raise.

    Examples
    --------
    >>> check_param("order", 3, [Interval(Integral, 1, 3)])
    3
    >>> check_param("order", 4, [Interval(Integral, 1, 3)], owner="TVRegDiff")
    Traceback (most recent call last):
    ...
    sindy_impulse.exceptions.InvalidParameterError: TVRegDiff: order must be an integer in [1, 3]; got 4
    """
    for constraint in constraints:
        if isinstance(constraint, str) and constraint not in _NAMED:
            raise ValueError(f"unknown constraint {constraint!r} for {name}")
        if _accepts(constraint, value):
            return value
    forms = [_describe(c) for c in constraints]
    expected = forms[0] if len(forms) == 1 else ", ".join(forms[:-1]) + " or " + forms[-1]
    prefix = f"{owner}: " if owner else ""
    shown = repr(value)
    if len(shown) > 80:
        shown = shown[:77] + "..."
    raise InvalidParameterError(f"{prefix}{name} must be {expected}; got {shown}")


def validate_params(obj: Any, constraints: dict | None = None) -> None:
    """Check every declared parameter of ``obj`` (``type(obj)._parameter_constraints`` by default).

    Parameters without an entry are not checked ("no_validation").
    """
    table = type(obj)._parameter_constraints if constraints is None else constraints
    owner = type(obj).__name__
    for name, accepted in table.items():
        check_param(name, getattr(obj, name), accepted, owner)

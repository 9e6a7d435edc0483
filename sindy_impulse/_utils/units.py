"""The unit damping ratios are shown in: a percentage (the modal tables' default) or a fraction.

The Python attributes (``Mode.damping_ratio``, ``survey.table()``'s ``damping_ratio``) are fractions; what a
person reads (the terminal, the figures' titles, the report) and what the command line writes (its JSON)
use one unit, chosen once: :data:`DAMPING_UNITS` maps each unit to its scale, its symbol and the suffix of
the names of the values it gives (``damping_ratio_percent``).
"""

from __future__ import annotations

import math

__all__ = ["DAMPING_UNITS", "DEFAULT_DAMPING_UNIT", "check_damping_unit", "damping_key", "damping_text"]

#: unit -> (scale from a fraction, symbol after the value, suffix of the names of values in that unit).
DAMPING_UNITS = {"percent": (100.0, " %", "_percent"), "fraction": (1.0, "", "")}
#: What a person reads unless told otherwise: a percentage, as modal tables give it.
DEFAULT_DAMPING_UNIT = "percent"


def check_damping_unit(unit) -> str:
    """``unit`` if it is one of :data:`DAMPING_UNITS` (a ValueError naming them otherwise)."""
    if not isinstance(unit, str) or unit not in DAMPING_UNITS:
        raise ValueError(f"damping_unit must be one of {', '.join(map(repr, DAMPING_UNITS))}, got {unit!r}")
    return unit


def damping_key(name: str, unit: str) -> str:
    """The name of a damping value in ``unit``: ``damping_key("damping_ratio", "percent")`` is
    ``"damping_ratio_percent"``; a fraction keeps the name.

    Examples
    --------
    >>> damping_key("damping_ratio_std", "percent"), damping_key("damping_ratio", "fraction")
    ('damping_ratio_std_percent', 'damping_ratio')
    """
    return name + DAMPING_UNITS[check_damping_unit(unit)][2]


def damping_text(fraction: float, unit: str = DEFAULT_DAMPING_UNIT, digits: int = 4) -> str:
    """A damping ratio (given as a fraction) as text in ``unit``, with its symbol.

    Examples
    --------
    >>> damping_text(0.01001), damping_text(0.01001, "fraction")
    ('1.001 %', '0.01001')
    """
    scale, symbol, _ = DAMPING_UNITS[check_damping_unit(unit)]
    value = float(fraction) * scale
    return f"{value:.{digits}g}{symbol}" if math.isfinite(value) else f"{value}{symbol}"

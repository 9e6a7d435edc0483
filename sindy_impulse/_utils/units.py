"""The unit damping ratios are shown in: a percentage (the modal tables' default) or a fraction.

The Python attributes (``Mode.damping_ratio``, ``survey.table()``'s ``damping_ratio``) are fractions; what a
person reads (the terminal, the figures' titles, the report) and what the command line writes (its JSON)
use one unit, chosen once: :data:`DAMPING_UNITS` maps each unit to its scale, its symbol and the suffix of
the names of the values it gives (``damping_ratio_percent``).
"""

from __future__ import annotations

import math
import re

__all__ = [
    "DAMPING_UNITS",
    "DEFAULT_DAMPING_UNIT",
    "check_damping_unit",
    "damping_key",
    "damping_text",
    "damping_in_words",
]

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


#: "damping ratio" followed by a bare number (a fraction): not one already followed by a unit or a "±".
_BARE_DAMPING = re.compile(r"(damping ratio )(-?\d+(?:\.\d+)?(?:e-?\d+)?)(?![\d.eE])(?!\s*[%±])")


def damping_in_words(text: str, unit: str = DEFAULT_DAMPING_UNIT) -> str:
    """A sentence of the library (which gives damping ratios as fractions, "damping ratio 0.00195") with
    its damping ratios in ``unit``.

    Examples
    --------
    >>> damping_in_words("the mode at 597.5 Hz (damping ratio 0.00195) disagrees")
    'the mode at 597.5 Hz (damping ratio 0.195 %) disagrees'
    >>> damping_in_words("damping ratio 1.0 ± 0.1 %, damping ratio 0.01", "fraction")
    'damping ratio 1.0 ± 0.1 %, damping ratio 0.01'
    """
    if DAMPING_UNITS[check_damping_unit(unit)][0] == 1.0:
        return text
    return _BARE_DAMPING.sub(lambda m: m.group(1) + damping_text(float(m.group(2)), unit, 3), text)

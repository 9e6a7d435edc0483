"""Strict number parsing for options and CSV cells.

Python's ``float``/``int`` accept more than a measurement file or an option should contain: ``1_0``
(underscores), ``' 1'`` (surrounding spaces), ``infinity``, non-ASCII digits; ``float('1e400')`` silently
overflows to ``inf``. Here only plain decimal notation passes, and a refusal says why.
"""

from __future__ import annotations

import math
import re

__all__ = ["NumberError", "parse_int", "parse_number"]

_DECIMAL = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?", re.ASCII)
_INTEGER = re.compile(r"[+-]?\d+", re.ASCII)
_NON_FINITE = re.compile(r"[+-]?(?:nan|inf|infinity)", re.ASCII | re.IGNORECASE)
_HEX = re.compile(r"[+-]?0[xX][0-9a-fA-F_]*", re.ASCII)


class NumberError(ValueError):
    """A text that is not a number in plain decimal notation; ``reason`` says why."""

    def __init__(self, text: str, reason: str):
        super().__init__(f"invalid number {text!r}: {reason}")
        self.text, self.reason = text, reason


def _why_not(text: str) -> str:
    if not text:
        return "empty"
    if text != text.strip():
        return "spaces around the number"
    if _HEX.fullmatch(text):
        return "hexadecimal notation"
    if "_" in text:
        return "an underscore digit separator"
    return "not a number"


def parse_number(text: str, *, finite: bool = True) -> float:
    """A float written in plain decimal notation (``-1.5``, ``2e-3``, ``.5``).

    Refused: surrounding spaces, underscores, hexadecimal, non-ASCII digits, values that overflow a
    float (``1e400``) and, when ``finite``, ``nan``/``inf``.

    >>> parse_number("2.5e-3"), parse_number("inf", finite=False)
    (0.0025, inf)
    >>> parse_number("1_0")
    Traceback (most recent call last):
    ...
    sindy_impulse.cli._numbers.NumberError: invalid number '1_0': an underscore digit separator
    """
    if _DECIMAL.fullmatch(text):
        value = float(text)
        if math.isinf(value):
            raise NumberError(text, "too large for a float")
        return value
    if _NON_FINITE.fullmatch(text):
        if finite:
            raise NumberError(text, "not finite")
        return float(text)
    raise NumberError(text, _why_not(text))


def parse_int(text: str) -> int:
    """An integer in plain decimal notation (no spaces, underscores, hexadecimal or decimals).

    >>> parse_int("-3")
    -3
    """
    if _INTEGER.fullmatch(text):
        return int(text)
    reason = _why_not(text)
    if reason == "not a number" and _DECIMAL.fullmatch(text):
        reason = "not a whole number"
    raise NumberError(text, reason)

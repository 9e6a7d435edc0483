"""The words of a report: values with their uncertainty, the verdicts and the diagnostics in plain words.

Every function returns plain text (the page escapes it); nothing here draws or writes.
"""

from __future__ import annotations

import math
import re

__all__ = ["plus_minus", "problem_lines", "nonlinearity_words", "uncertainty"]

#: ``problem: what to do`` in the diagnostics' sentences (a term name such as ``x1' : x0^2`` has a
#: space before its colon, so it is not a split point).
_SPLIT = re.compile(r"(?<! ): ")


def uncertainty(mode, name: str) -> float:
    """``mode.<name>`` as a float (NaN when the mode has no such attribute, e.g. a standard deviation a
    version of the package does not compute).

    Examples
    --------
    >>> class M:
    ...     frequency_std_hz = 0.25
    >>> uncertainty(M(), "frequency_std_hz"), math.isnan(uncertainty(M(), "damping_ratio_std"))
    (0.25, True)
    """
    value = getattr(mode, name, math.nan)
    try:
        return float(value)
    except (TypeError, ValueError):
        return math.nan


def plus_minus(value: float, std: float = math.nan, scale: float = 1.0, digits: int = 6) -> str:
    """``value ± std`` as text, the value rounded to the second significant digit of ``std``; the value
    alone (``digits`` significant digits) when ``std`` is NaN, infinite or zero. ``scale`` multiplies
    both (100 for a percentage).

    Examples
    --------
    >>> plus_minus(120.00123, 0.00042)
    '120.00123 ± 0.00042'
    >>> plus_minus(0.004987, 0.000123, scale=100)
    '0.499 ± 0.012'
    >>> plus_minus(242.98765, float("nan"))
    '242.988'
    """
    value, std = float(value) * scale, float(std) * scale
    if not math.isfinite(value):
        return str(value)
    if not (math.isfinite(std) and std > 0):
        return f"{value:.{digits}g}"
    decimals = max(0, 1 - math.floor(math.log10(std)))
    return f"{value:.{decimals}f} ± {std:.{decimals}f}"


def problem_lines(reasons: dict) -> list[tuple[str, str, str]]:
    """The diagnostics' reasons as ``(check, short line, whole sentence)``: the short line is the problem
    (the sentence up to its ``: what to do``).

    Examples
    --------
    >>> [(check, short) for check, short, _ in problem_lines({"support": "weak term x1' : x0^2: drop it"})]
    [('support', "weak term x1' : x0^2")]
    """
    out = []
    for check, sentence in reasons.items():
        sentence = str(sentence)
        out.append((str(check), _SPLIT.split(sentence, maxsplit=1)[0], sentence))
    return out


def _shift_words(result) -> str:
    parts = []
    for name, value in (("frequency", result.frequency_shift), ("damping ratio", result.damping_ratio_shift)):
        if math.isfinite(value):
            parts.append(f"{name} {100 * value:+.3g} %")
    if not parts:
        return "no nonlinear alternative's backbone to compare (no nonlinear term lowered the error)"
    return "over the decay the nonlinear alternative's backbone moves by " + ", ".join(parts)


def nonlinearity_words(result) -> tuple[str, str]:
    """The test for nonlinearity (:class:`~sindy_impulse.analysis.NonlinearityResult`) as ``(verdict,
    explanation)``: ``"nonlinear"`` or ``"linear"``, and the numbers the decision rests on.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> r = NS(nonlinear=False, statistic=0.2, threshold=1.0, significance=0.2, amplitude_dependence=5.0,
    ...        frequency_shift=0.0001, damping_ratio_shift=0.01, terms=[])
    >>> nonlinearity_words(r)[0]
    'linear'
    """
    verdict = "nonlinear" if result.nonlinear else "linear"
    terms = ", ".join(f"{t.equation} {t.coefficient:+.4g} {t.term}" for t in result.terms[:3])
    comparison = ">" if result.nonlinear else "<="
    text = (
        f"statistic {result.statistic:.3g} {comparison} threshold {result.threshold:.3g} (significance of "
        f"the nonlinear terms {result.significance:.3g}, amplitude dependence "
        f"{result.amplitude_dependence:.3g}); {_shift_words(result)}"
    )
    if terms:
        text += f"; its strongest nonlinear terms: {terms}"
    return verdict, text

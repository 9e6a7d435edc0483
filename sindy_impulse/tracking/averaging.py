"""A mode's backbone at one amplitude from its equation, by first-order averaging (harmonic balance).

For ``y'' + g(y, y') = 0`` vibrating as ``y = A cos(theta)``, ``y' = -A w sin(theta)``, the equivalent
linear stiffness and damping at amplitude ``A`` are

    w_eq^2(A) = 1 / (pi A)   * integral g cos(theta) dtheta,
    c_eq(A)   = -1 / (pi A w) * integral g sin(theta) dtheta,      zeta_eq = c_eq / (2 w_eq),

the first-order averaging that :mod:`sindy_impulse.analysis.backbone` also follows (a cubic spring
``k3 y^3``: ``w^2 + 3/4 k3 A^2``; a damper ``c2 y^2 y'``: ``c + c2 A^2 / 4``). Terms of even total degree
do nothing at first order; a quadratic spring ``k2 y^2`` softens at second order like a cubic one of
``-10/9 k2^2 / w^2``, which is added. The integrals are sums over 64 equally spaced angles (exact for the
polynomials of the survey's library); velocity terms make ``w_eq`` depend on itself, solved by a few
fixed-point steps. One mode costs some tens of microseconds: a backbone evaluated this way for every
survey of a long sequence costs nothing beside the surveys (a simulated free decay,
:func:`~sindy_impulse.analysis.backbone`, would).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .values import LINEAR_TERMS, term_powers

__all__ = ["BackbonePoint", "backbone_at", "term_shift"]

_THETA = np.linspace(0.0, 2 * np.pi, 64, endpoint=False)
_COS, _SIN = np.cos(_THETA), np.sin(_THETA)
_STEPS = 4


def _unit(p: int, q: int, amplitude: float, w: float) -> tuple[float, float]:
    """Equivalent stiffness and damping of the monomial ``y^p y'^q`` (coefficient 1) at ``amplitude``: an
    odd power of ``y'`` only dissipates, an even one only stiffens (the other integral is exactly 0)."""
    m = (amplitude * _COS) ** p * (-amplitude * w * _SIN) ** q
    k = 2 * float(np.mean(m * _COS)) / amplitude if q % 2 == 0 else 0.0
    c = -2 * float(np.mean(m * _SIN)) / (amplitude * w) if q % 2 == 1 else 0.0
    return k, c


def _polynomial(values) -> list:
    """``[(p, q, value, std)]`` of the nonlinear monomial terms (raw terms have no place here)."""
    out = []
    for key, (value, std) in values.terms.items():
        powers = term_powers(key)
        if key not in LINEAR_TERMS and powers is not None and powers != (0, 0) and value != 0:
            out.append((*powers, value, std))
    return out


def _equivalent(w2: float, c: float, terms: list, amplitude: float) -> tuple[float, float, list]:
    """``(w_eq, c_eq, [(dK, dC) per term])`` at ``amplitude`` (``terms`` as :func:`_polynomial`)."""
    w = math.sqrt(max(w2, 0.0))
    if not terms or not (amplitude > 0) or w == 0:
        return w, c, [(0.0, 0.0)] * len(terms)
    units = []
    for _ in range(_STEPS):
        units = [_unit(p, q, amplitude, w) for p, q, _, _ in terms]
        k = w2 + sum(v * u[0] for (_, _, v, _), u in zip(terms, units))
        k -= sum(5 / 6 * v * v * amplitude**2 / w2 for p, q, v, _ in terms if (p, q) == (2, 0))
        w_new = math.sqrt(max(k, 1e-12 * w2))
        if abs(w_new - w) <= 1e-12 * w:
            w = w_new
            break
        w = w_new
    c_eq = c + sum(v * u[1] for (_, _, v, _), u in zip(terms, units))
    return w, c_eq, units


@dataclass(frozen=True)
class BackbonePoint:
    """A mode's backbone at one amplitude (:func:`backbone_at`).

    Attributes
    ----------
    frequency_hz, damping_ratio : float
        Natural frequency and damping ratio at the amplitude.
    frequency_std_hz, damping_ratio_std : float
        Their standard deviations: those of the linear values and of each nonlinear coefficient combined
        as if independent (NaN when one of them is unknown).
    frequency_shift_hz, damping_shift : float
        How far the nonlinear terms move them from the linear values (0 for a linear equation): the
        frequency, and the damping ratio by dissipation (``(c_eq - c) / (2 w_eq)``; a spring that raises
        the frequency lowers the damping ratio too, which is not counted here).
    frequency_shift_std_hz, damping_shift_std : float
        Their standard deviations, from the nonlinear coefficients' alone (0 for a linear equation).
    """

    frequency_hz: float
    damping_ratio: float
    frequency_std_hz: float
    damping_ratio_std: float
    frequency_shift_hz: float
    damping_shift: float
    frequency_shift_std_hz: float
    damping_shift_std: float


def backbone_at(values, amplitude: float) -> BackbonePoint:
    """The mode's natural frequency and damping ratio at ``amplitude``, with their standard deviations.

    Parameters
    ----------
    values : ModeValues
        The mode (:func:`~sindy_impulse.tracking.values.survey_values`).
    amplitude : float
        Amplitude of the measured coordinate (the sensor's units, as ``values.amplitude``).

    Returns
    -------
    BackbonePoint

    Examples
    --------
    A hardening cubic spring that raises ``w^2`` by 3/4 k3 A^2 = 2 % at A = 1:

    >>> from sindy_impulse.tracking.values import ModeValues
    >>> w2 = (2 * math.pi * 50.0) ** 2
    >>> m = ModeValues(50.0, 0.01, 0.01, 1e-4, 1.0, terms={"y": (w2, 1.0), "y'": (2 * 0.01 * 2 * math.pi * 50,
    ...                0.01), "y^3": (0.02 * w2 / 0.75, 10.0)})
    >>> point = backbone_at(m, 1.0)
    >>> round(point.frequency_hz / 50.0, 5), round(point.frequency_shift_hz, 4)  # sqrt(1.02)
    (1.00995, 0.4975)
    >>> round(backbone_at(m, 0.0).frequency_hz, 6)
    50.0
    """
    w2, c = values.terms["y"][0], values.terms["y'"][0]
    terms = _polynomial(values)
    w, c_eq, units = _equivalent(w2, c, terms, amplitude)
    w0 = math.sqrt(max(w2, 0.0))
    f = w / (2 * math.pi)
    zeta = c_eq / (2 * w) if w > 0 else math.nan
    ratio = w0 / w if w > 0 else math.nan
    f_var = z_var = shift_var = 0.0
    for (_, _, _, std), (dk, dc) in zip(terms, units):  # zeta_eq = c_eq / (2 w_eq): both move it
        f_var += (dk / (4 * math.pi * w) * std) ** 2 if dk else 0.0
        z_var += ((dc - zeta * dk / w) / (2 * w) * std) ** 2 if dk or dc else 0.0
        shift_var += (dc / (2 * w) * std) ** 2 if dc else 0.0
    return BackbonePoint(
        f,
        zeta,
        math.sqrt(f_var + (ratio * values.frequency_std_hz) ** 2),
        math.sqrt(z_var + (ratio * values.damping_ratio_std) ** 2),
        f - w0 / (2 * math.pi),
        (c_eq - c) / (2 * w) if w > 0 else math.nan,
        math.sqrt(f_var),
        math.sqrt(shift_var),
    )


def term_shift(values, key: str, reference: float, amplitude: float) -> tuple[float, float]:
    """How much the mode's frequency (Hz) and damping ratio at ``amplitude`` moved because the coefficient
    ``key`` moved from ``reference`` to its value in ``values`` (the other coefficients as they are); the
    damping ratio by dissipation: the change of the equivalent damping over ``2 w`` (a spring moves only
    the frequency).

    Examples
    --------
    >>> from sindy_impulse.tracking.values import ModeValues
    >>> w2 = (2 * math.pi * 50.0) ** 2
    >>> m = ModeValues(50.0, 0.01, 0.01, 1e-4, 1.0)  # the linear stiffness 1 % lower than w2 / 0.99:
    >>> df, dz = term_shift(m, "y", w2 / 0.99, 1.0)
    >>> round(df / 50.0, 5), dz
    (-0.00504, 0.0)
    >>> m.terms["y^3"] = (0.008 * w2 / 0.75, 1.0)  # a cubic spring that appeared: +0.8 % of w^2 at A = 1
    >>> df, _ = term_shift(m, "y^3", 0.0, 1.0)
    >>> round(df / 50.0, 4)
    0.004
    """
    w2, c = values.terms["y"][0], values.terms["y'"][0]
    terms = _polynomial(values)
    w, c_eq, _ = _equivalent(w2, c, terms, amplitude)
    if key == "y":
        w2 = reference
    elif key == "y'":
        c = reference
    else:
        powers = term_powers(key)
        if powers is None or powers == (0, 0):
            return math.nan, math.nan
        terms = [t for t in terms if (t[0], t[1]) != powers] + (
            [(*powers, reference, math.nan)] if reference else []
        )
    w_ref, c_ref, _ = _equivalent(w2, c, terms, amplitude)
    if not (w > 0 and w_ref > 0):
        return math.nan, math.nan
    return (w - w_ref) / (2 * math.pi), (c_eq - c_ref) / (2 * w)

"""The backbone of a single-DOF record: frequency and damping ratio against amplitude (first-order averaging).

The record's generating equation, per unit mass, is

    x'' + 2 zeta0 omega0 x' + omega0**2 x + k2 x**2 + k3 x**3 + c2 x**2 x' + cq |x'| x' = F(t) / m.

Writing ``x = a cos(psi)``, ``x' = -a omega sin(psi)`` and averaging over one period (first order in the
nonlinear and damping terms; Krylov-Bogoliubov) gives the undamped instantaneous natural frequency and the
equivalent viscous damping per unit mass

    omega(a)**2 = omega0**2 + 3/4 k3 a**2                                   (Duffing spring)
    c_eq(a)     = 2 zeta0 omega0 + c2 a**2 / 4 + 8 / (3 pi) cq a omega(a)   (x**2 x' and |x'| x' dampers)

The quadratic spring has no first-order effect on the frequency (its average over a period vanishes); to
second order (Lindstedt-Poincare) it acts like a softening cubic spring of ``-10/9 k2**2 / omega0**2``, so
``k3`` above is replaced by ``k3 - 10/9 k2**2 / omega0**2``. It also adds a second harmonic of amplitude
``k2 a**2 / (6 omega0**2)`` and shifts the mean by ``-k2 a**2 / (2 omega0**2)``; ``a`` is the amplitude
of the fundamental.

so the envelope decays as ``a' = -c_eq(a) a / 2`` and the damping ratio is
``zeta(a) = c_eq(a) / (2 omega(a))``. ``a`` is the displacement amplitude; a velocity record's amplitude is
``a omega(a)`` and an acceleration record's ``a omega(a)**2`` (to the same order).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Backbone"]

_POWER = {"displacement": 0, "velocity": 1, "acceleration": 2}


@dataclass(frozen=True)
class Backbone:
    """True backbone ``amplitude -> (frequency_hz, damping_ratio)`` of a single-DOF record.

    Call it with amplitudes in the record's sensor units. Amplitudes at which the softening spring has no
    oscillation (``omega(a)**2 <= 0``) give NaN.

    Attributes
    ----------
    frequency_hz, damping_ratio : float
        The linear (small-amplitude) values ``omega0 / (2 pi)`` and ``zeta0``.
    cubic_stiffness, damping_amplitude, quadratic_damping : float
        ``k3``, ``c2`` and ``cq`` of the generating equation (per unit mass).
    sensor : str
        ``"displacement"``, ``"velocity"`` or ``"acceleration"``: the units of the amplitude.
    quadratic_stiffness : float
        ``k2`` of the generating equation (per unit mass; default 0).

    Examples
    --------
    >>> bb = Backbone(100.0, 0.01, cubic_stiffness=0.0, damping_amplitude=0.0, quadratic_damping=0.0,
    ...               sensor="displacement")
    >>> bb(1.0)
    (100.0, 0.01)
    """

    frequency_hz: float
    damping_ratio: float
    cubic_stiffness: float
    damping_amplitude: float
    quadratic_damping: float
    sensor: str
    quadratic_stiffness: float = 0.0

    def _k3(self, w0: float) -> float:
        """``k3``, plus the second-order softening ``-10/9 k2**2 / omega0**2`` of the quadratic spring."""
        if not self.quadratic_stiffness:
            return self.cubic_stiffness
        return self.cubic_stiffness - 10 / 9 * self.quadratic_stiffness**2 / w0**2

    def displacement_amplitude(self, amplitude):
        """The displacement amplitude ``a`` whose sensor amplitude ``a omega(a)**k`` is ``amplitude``."""
        A = np.asarray(amplitude, dtype=float)
        k = _POWER[self.sensor]
        w0 = 2 * np.pi * self.frequency_hz
        a = A / w0**k
        k3 = self._k3(w0)
        for _ in range(60 if k else 0):  # Newton on a omega(a)**k = A (monotone where it is used)
            w2 = w0**2 + 0.75 * k3 * a**2
            with np.errstate(invalid="ignore"):
                w = np.sqrt(w2)
                g = a * w**k - A
                dg = w**k + k * a * w ** (k - 2) * 0.75 * k3 * a
                step = g / dg
            a = a - step
            if np.all(~np.isfinite(step) | (np.abs(step) <= 1e-15 * np.abs(a))):
                break
        return a

    def __call__(self, amplitude):
        """Undamped instantaneous natural frequency (Hz) and damping ratio at ``amplitude``."""
        a = self.displacement_amplitude(amplitude)
        w0 = 2 * np.pi * self.frequency_hz
        with np.errstate(invalid="ignore"):
            w = np.sqrt(w0**2 + 0.75 * self._k3(w0) * a**2)
            c_eq = (
                2 * self.damping_ratio * w0
                + self.damping_amplitude * a**2 / 4
                + 8 / (3 * np.pi) * self.quadratic_damping * np.abs(a) * w
            )
            zeta = c_eq / (2 * w)
        f = w / (2 * np.pi)
        if np.ndim(f) == 0:
            return float(f), float(zeta)
        return f, zeta

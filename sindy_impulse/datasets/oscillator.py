"""Ring-down generators for the paper's oscillators and a noise model.

The reference system of Stender, Oberst & Hoffmann (2019), section 2.6, is the 1-DOF viscously damped
oscillator ``x1' = x2, x2' = -k x1 - c x2 - k_nl x1**3`` with ``k = 64``, ``c = 3.2`` (natural frequency
8 rad/s, damping ratio 0.2), unit initial deflection, 4 s at ``dt = 0.01``.
"""

from __future__ import annotations

from numbers import Real

import numpy as np
from scipy.integrate import solve_ivp

from .._utils.validation import check_signal

__all__ = ["damped_oscillator", "add_noise", "RingDown", "MAX_SAMPLES"]

#: Most samples :func:`damped_oscillator` generates (a tiny ``dt`` would otherwise exhaust memory).
MAX_SAMPLES = 10**7


def _check_real(value, name: str) -> None:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, Real):
        raise TypeError(f"{name} must be a real number, got {value!r}")
    if not np.isfinite(value):
        raise ValueError(f"{name} must be finite, got {value!r}")


class RingDown:
    """A simulated ring-down: time ``t``, states ``x`` (n, 2) and exact derivatives ``x_dot``."""

    def __init__(self, t: np.ndarray, x: np.ndarray, x_dot: np.ndarray, params: dict):
        self.t = t
        self.x = x
        self.x_dot = x_dot
        self.params = params

    def __iter__(self):  # allows ``t, x, x_dot = damped_oscillator()``
        return iter((self.t, self.x, self.x_dot))

    def __repr__(self) -> str:
        return f"RingDown(n_samples={self.t.size}, params={self.params})"


def damped_oscillator(
    k: float = 64.0,
    c: float = 3.2,
    k_nl: float = 0.0,
    x0=(1.0, 0.0),
    t_end: float = 4.0,
    dt: float = 0.01,
    snr_db: float | None = None,
    random_state=None,
) -> RingDown:
    """Impulse response of the (optionally Duffing) damped oscillator of the paper.

    ``x1' = x2``, ``x2' = -k x1 - c x2 - k_nl x1**3``, integrated with ``solve_ivp`` (DOP853,
    rtol = atol = 1e-12) and sampled at ``t = 0, dt, ..., t_end``.

    Parameters
    ----------
    k, c, k_nl : float
        Stiffness, viscous damping and cubic stiffness per unit mass.
    x0 : sequence of 2 floats
        Initial deflection and velocity.
    t_end, dt : float
        Duration and sampling step.
    snr_db : float or None
        If given, add white Gaussian noise to ``x`` at this signal-to-noise ratio per state
        (see :func:`add_noise`); ``x_dot`` stays exact.
    random_state : int, numpy Generator or None
        Seed for the noise.

    Returns
    -------
    RingDown
        With attributes ``t`` (n,), ``x`` (n, 2), ``x_dot`` (n, 2) and ``params``; unpacks as
        ``t, x, x_dot``.

    Examples
    --------
    >>> t, x, x_dot = damped_oscillator()
    >>> x.shape, round(float(t[-1]), 2)
    ((401, 2), 4.0)
    """
    for name, val in (("k", k), ("c", c), ("k_nl", k_nl), ("t_end", t_end), ("dt", dt)):
        _check_real(val, name)
    if dt <= 0 or t_end <= 0:
        raise ValueError(f"dt and t_end must be positive, got dt={dt!r}, t_end={t_end!r}")
    n = int(round(t_end / dt)) + 1
    if n > MAX_SAMPLES:
        raise ValueError(f"t_end / dt = {t_end / dt:.3g} samples; at most {MAX_SAMPLES:.0e} are generated")
    x0 = check_signal(x0, "x0", ndim=(1,), as_2d=False)
    if x0.shape != (2,):
        raise ValueError(f"x0 must have 2 entries (deflection, velocity), got shape {x0.shape}")
    t = np.arange(n) * dt

    def rhs(_t, y):
        return [y[1], -k * y[0] - c * y[1] - k_nl * y[0] ** 3]

    sol = solve_ivp(rhs, (0.0, t[-1]), x0, t_eval=t, method="DOP853", rtol=1e-12, atol=1e-12)
    x = sol.y.T.copy()
    x_dot = np.column_stack([x[:, 1], -k * x[:, 0] - c * x[:, 1] - k_nl * x[:, 0] ** 3])
    if snr_db is not None:
        x = add_noise(x, snr_db, random_state=random_state)
    params = {"k": k, "c": c, "k_nl": k_nl, "x0": tuple(x0), "dt": dt, "snr_db": snr_db}
    return RingDown(t, x, x_dot, params)


def add_noise(x, snr_db: float, random_state=None) -> np.ndarray:
    """Add white Gaussian noise at a signal-to-noise ratio, per column.

    The noise standard deviation of each column is ``std(x) / 10**(snr_db / 20)``.

    Examples
    --------
    >>> x = np.sin(np.linspace(0, 10, 1000))
    >>> noisy = add_noise(x, 40, random_state=0)
    >>> bool(abs(np.std(noisy - x) / np.std(x) - 0.01) < 0.002)
    True
    """
    arr = check_signal(x, "x", as_2d=False)
    _check_real(snr_db, "snr_db")
    rng = np.random.default_rng(random_state)
    sigma = np.std(arr, axis=0) / 10 ** (snr_db / 20)
    return arr + rng.standard_normal(arr.shape) * sigma

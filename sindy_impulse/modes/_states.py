"""A mode's band signal as states for identification, and its shape in other channels.

The states of a mode are the derivative coordinates of its band signal, ``[y, dy/dt]``: a differential
embedding of the single sensor (Takens' theorem covers derivative coordinates as it covers delays). They
make the identified equation read as the mode's oscillator (``dy' = -k y - c dy + ...``), so that terms such
as ``y^2 dy`` (amplitude-dependent damping) or ``y^3`` (hardening) keep their physical meaning.

The band signal is already filtered (the zero-phase band-pass is the denoising step) and band-limited well
below its sampling rate (8-20 samples per period), so a 9-point central difference (8th order)
differentiates it to 1e-4 relative at 8 samples per period and 1e-6 at 16. Measured on a simulated 478 Hz
mode at 10.5 samples per period: TVRegDiff's derivative is biased there
(model ``y' = 1.2 dy``, frequency 20 % off, zero damping), the band-limited derivatives give the frequency
to 3e-5 and the damping ratio to 0.1 %.
"""

from __future__ import annotations

import numpy as np
from scipy.signal import savgol_filter

__all__ = ["derivative_states", "free_decay_states", "group_states", "channel_shape", "STATE_NAMES", "EDGE"]

#: Samples lost at each end (two 9-point differences).
EDGE = 8
#: Names of the states of a mode.
STATE_NAMES = ("y", "dy")
_STENCIL = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])


def _differentiate(y: np.ndarray, dt: float) -> np.ndarray:
    """9-point central difference; 4 samples shorter at each end."""
    return np.convolve(y, _STENCIL[::-1], mode="valid") / dt


def derivative_states(y: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``x = [y, dy/dt]``, its derivative ``[dy/dt, d2y/dt2]`` and ``t`` of a uniformly sampled band-limited
    signal, ``EDGE`` samples dropped at each end.

    Examples
    --------
    >>> t = np.arange(200) / 1600.0
    >>> x, x_dot, tt = derivative_states(np.sin(2 * np.pi * 100 * t), t)
    >>> w = 2 * np.pi * 100
    >>> x.shape, bool(np.max(np.abs(x_dot[:, 1] + w**2 * np.sin(w * tt))) < 1e-4 * w**2)
    ((184, 2), True)
    """
    dt = float(t[1] - t[0])
    dy = _differentiate(y, dt)
    ddy = _differentiate(dy, dt)
    half = EDGE // 2
    x = np.column_stack([y[EDGE:-EDGE], dy[half:-half]])
    return x, np.column_stack([x[:, 1], ddy]), t[EDGE:-EDGE]


def group_states(y: np.ndarray, t: np.ndarray, n_states: int, tau: int):
    """Delay coordinates ``x = [y(t - (n-1) tau), ..., y(t - tau), y(t)]`` of a band that holds
    ``n_states / 2`` close modes (fitted jointly), their derivatives (the band-limited derivative, delayed
    alike) and ``t``: a linear system in these coordinates has the modes' eigenvalues exactly, and delays
    do not amplify noise as high derivatives would.

    Examples
    --------
    >>> t = np.arange(400) / 1600.0
    >>> x, x_dot, tt = group_states(np.sin(2 * np.pi * 100 * t) + np.sin(2 * np.pi * 110 * t), t, 4, 4)
    >>> x.shape, x_dot.shape, bool(np.allclose(x[1:, 0], x[:-1, 1][0:0].sum() + x[1:, 0]))
    ((380, 4), (380, 4), True)
    """
    dt = float(t[1] - t[0])
    half = len(_STENCIL) // 2
    dy = _differentiate(y, dt)
    y = y[half:-half]
    t = t[half:-half]
    span = (n_states - 1) * tau
    x = np.column_stack([y[span - k * tau : len(y) - k * tau] for k in range(n_states - 1, -1, -1)])
    x_dot = np.column_stack([dy[span - k * tau : len(dy) - k * tau] for k in range(n_states - 1, -1, -1)])
    return x, x_dot, t[span:]


def channel_shape(
    reference: np.ndarray, reference_dot: np.ndarray, omega: float, other: np.ndarray
) -> complex:
    """Complex amplitude of ``other`` relative to ``reference`` (same band, same samples).

    ``other ~ a reference + b reference_dot / omega`` by least squares, returned as ``a + 1j b``: its modulus
    is the amplitude ratio, its angle the phase lead of ``other`` (a copy is ``1``, an opposite ``-1``).

    Examples
    --------
    >>> t = np.arange(400) / 1600.0
    >>> ref = np.cos(2 * np.pi * 100 * t)
    >>> ref_dot = -2 * np.pi * 100 * np.sin(2 * np.pi * 100 * t)
    >>> z = channel_shape(ref, ref_dot, 2 * np.pi * 100, 0.5 * np.cos(2 * np.pi * 100 * t + 0.3))
    >>> round(abs(z), 6), round(float(np.angle(z)), 6)
    (0.5, 0.3)
    """
    basis = np.column_stack([reference, reference_dot / omega])
    (a, b), *_ = np.linalg.lstsq(basis, other, rcond=None)
    return complex(a, b)


#: Samples per period kept of a free decay's states (:func:`free_decay_states`).
_FREE_DECAY_SAMPLES_PER_PERIOD = 16.0
#: Length of the Savitzky-Golay window of :func:`free_decay_states`, in periods of the mode. Inside the
#: record the smoothing is a linear time-invariant filter: the smoothed ``y`` of a damped sinusoid is a damped
#: sinusoid with the same pole (to rounding). The derivatives are the local polynomial's: the relation
#: ``y'' = -w^2 y - 2 zeta w y'`` read on them is off by 0.34 % in frequency and 0.6 % in damping ratio at
#: half a period (``tests/test_modes_short.py`` bounds it), the start the identification refines; a wider
#: window passes less noise but is further off (the trade-off set on the equations of short, strongly
#: damped decays of a few periods).
WINDOW_PERIODS = 0.5


def free_decay_states(y: np.ndarray, t: np.ndarray, frequency_hz: float):
    """``x = [y, dy/dt]``, its derivative and ``t`` of a free decay that was not band-passed (a short record
    holding one mode, the others removed): a Savitzky-Golay fit of degree 4 over :data:`WINDOW_PERIODS` of
    ``frequency_hz`` (at least 5 samples) smooths the noise and differentiates, every sample kept (no
    filter transient to trim: the edges are fitted by the end windows' polynomials); the states are then
    taken every ``q``-th sample, about 16 per period.

    Examples
    --------
    >>> t = np.arange(400) / 2000.0
    >>> y = np.exp(-20 * t) * np.cos(2 * np.pi * 50 * t)
    >>> x, x_dot, tt = free_decay_states(y, t, 50.0)
    >>> x.shape, bool(np.allclose(x[:, 0], y[::2], atol=1e-2)), float(tt[1] - tt[0])
    ((200, 2), True, 0.001)
    """
    dt = float(t[1] - t[0])
    per_period = 1.0 / (frequency_hz * dt)
    window = max(5, int(per_period * WINDOW_PERIODS) // 2 * 2 + 1)
    if window > y.size:
        window = max(5, (y.size - 1) // 2 * 2 + 1)
    smooth = [savgol_filter(y, window, 4, deriv=d, delta=dt, mode="interp") for d in (0, 1, 2)]
    q = max(1, int(per_period // _FREE_DECAY_SAMPLES_PER_PERIOD))
    x = np.column_stack(smooth[:2])[::q]
    return x, np.column_stack(smooth[1:])[::q], t[::q]

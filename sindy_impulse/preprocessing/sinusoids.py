"""A sum of exponentially damped sinusoids fitted to a ring-down by nonlinear least squares.

The model of a free decay from its first sample (``t = 0``) is

    ``y(t) = c + sum_k exp(-sigma_k t) (a_k cos(omega_k t) + b_k sin(omega_k t))``

with decay rates ``sigma_k >= 0`` and damped angular frequencies ``omega_k``. Started from estimates of
the frequencies and decay rates (spectral peaks and their half-power widths), all parameters are refined
together by Levenberg-Marquardt steps on the normal equations (analytic Jacobian; a step leaving the
bounds is clipped to them), each frequency kept within a given distance of its start. Fitting all
components at once accounts for the leak of every mode into its neighbours' peaks, which shifts the peaks
of strongly damped modes; the residual is the noise (and whatever the model misses), free of the skirts
of lightly damped modes.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._utils.powers import complex_powers
from .._utils.threads import one_thread
from .._utils.validation import check_array
from ._record import check_fs, check_signal_1d

__all__ = ["DampedSinusoids", "fit_damped_sinusoids", "fit_amplitudes"]

#: Levenberg-Marquardt iterations at most, and the fall of the cost that ends them: at most this many times
#: its reduced value (the residual's variance per degree of freedom, the noise's where the model holds);
#: such a step moves the parameters by a few hundredths of their standard deviations.
_MAX_ITERATIONS, _ATOL = 60, 1e-3
#: Largest damping ratio of a component: a faster decay is a transient, not a vibration.
_MAX_DAMPING = 0.3
#: Decay exponent past which a component is zero (no subnormal numbers: they are slow).
_NEGLIGIBLE = 300.0


@dataclass(frozen=True)
class DampedSinusoids:
    """Components ``exp(-sigma t) (a cos + b sin)(omega t)`` fitted to a ring-down (see the module).

    Attributes
    ----------
    frequency_hz, decay_rate : ndarray (n_components,)
        Damped frequency ``omega / 2 pi`` (Hz) and decay rate ``sigma`` (1/s) of each component.
    amplitude, phase : ndarray (n_components,)
        ``a cos + b sin = amplitude cos(omega t + phase)`` at ``t = 0``.
    constant : float
        The constant ``c``.
    residual : ndarray (n,)
        The ring-down minus the fitted model.
    """

    frequency_hz: np.ndarray
    decay_rate: np.ndarray
    amplitude: np.ndarray
    phase: np.ndarray
    constant: float
    residual: np.ndarray = field(repr=False)

    @property
    def damping_ratio(self) -> np.ndarray:
        """``sigma / sqrt(sigma**2 + omega**2)``."""
        omega = 2.0 * np.pi * self.frequency_hz
        return self.decay_rate / np.hypot(self.decay_rate, omega)

    def component(self, k: int, n: int, fs: float) -> np.ndarray:
        """Samples of component ``k`` over ``n`` samples at ``fs``."""
        t = np.arange(n) / fs
        omega = 2.0 * np.pi * self.frequency_hz[k]
        return self.amplitude[k] * np.exp(-self.decay_rate[k] * t) * np.cos(omega * t + self.phase[k])


def _powers(tau: np.ndarray, sigma: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """``exp((-sigma + i omega) tau)`` for every component, shape (n, k) (``tau`` a uniform grid from 0;
    zero past ``exp(-_NEGLIGIBLE)``)."""
    step = tau[1] - tau[0] if tau.size > 1 else 0.0
    return complex_powers((-sigma + 1j * omega) * step, tau.size, negligible=_NEGLIGIBLE)


def _basis(tau: np.ndarray, sigma: np.ndarray, omega: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``exp(-sigma tau) cos(omega tau)`` and ``... sin`` for every component, shape (n, k)."""
    powers = _powers(tau, sigma, omega)
    return powers.real, powers.imag


def _split(p: np.ndarray, k: int):
    return p[:k], p[k : 2 * k], p[2 * k : 3 * k], p[3 * k : 4 * k], p[4 * k]


def _linear_amplitudes(y, tau, sigma, omega, keep=None) -> np.ndarray:
    """Least-squares ``a``, ``b`` and ``c`` for fixed decay rates and frequencies (on the samples
    ``keep``)."""
    cos, sin = _basis(tau, sigma, omega)
    design = np.column_stack([cos, sin, np.ones_like(tau)])
    if keep is not None:
        design, y = design[keep], y[keep]
    coef = np.linalg.lstsq(design, y, rcond=None)[0]
    k = sigma.size
    return np.concatenate([sigma, omega, coef[:k], coef[k : 2 * k], coef[2 * k :]])


def _residual(p: np.ndarray, y: np.ndarray, tau: np.ndarray, k: int):
    """Model minus data, and the components' powers and weighted powers (what its Jacobian needs) for
    ``p = (sigma, omega, a, b, c)``."""
    sigma, omega, a, b, c = _split(p, k)
    powers = _powers(tau, sigma, omega)
    weighted = powers * (a - 1j * b)  # real part: the model's components, imaginary: their quadrature
    return weighted.real.sum(axis=1) + c - y, (powers, weighted)


def _jacobian(parts, tau: np.ndarray, k: int) -> np.ndarray:
    """The residual's Jacobian with respect to ``p`` from :func:`_residual`'s parts."""
    powers, weighted = parts
    jac = np.empty((tau.size, 4 * k + 1))
    np.multiply(weighted.real, -tau[:, None], out=jac[:, :k])
    np.multiply(weighted.imag, -tau[:, None], out=jac[:, k : 2 * k])
    jac[:, 2 * k : 3 * k], jac[:, 3 * k : 4 * k], jac[:, 4 * k] = powers.real, powers.imag, 1.0
    return jac


def _normal_equations(jac: np.ndarray, res: np.ndarray) -> tuple:
    """``J^T J``, its diagonal scale and ``J^T r`` at an accepted point (the trials from it reuse them)."""
    normal = jac.T @ jac
    return normal, np.maximum(np.diag(normal), np.finfo(float).tiny), jac.T @ res


def _step(normal_equations: tuple, damping: float, free: np.ndarray) -> np.ndarray:
    """The damped Gauss-Newton step of the ``free`` parameters (the others stay)."""
    normal, scale, gradient = normal_equations
    step = np.zeros(gradient.size)
    try:
        step[free] = -np.linalg.solve(normal[np.ix_(free, free)] + damping * np.diag(scale[free]),
                                      gradient[free])
    except np.linalg.LinAlgError:
        pass
    return step


def _free(p: np.ndarray, gradient: np.ndarray, bounds: tuple) -> np.ndarray:
    """The parameters a step may move: all but those at a bound that the descent pushes beyond it (a
    clipped step of the whole set would move the others the wrong way)."""
    lower, upper = bounds
    return ~(((p <= lower) & (gradient > 0)) | ((p >= upper) & (gradient < 0)))


def _levenberg_marquardt(p, y, tau, k, bounds, keep=None) -> tuple[np.ndarray, np.ndarray]:
    """Bounded Levenberg-Marquardt from ``p`` (on the samples ``keep``): the parameters and the residual
    (model minus data). A step moves the parameters not held at a bound and is clipped to the bounds; the
    Jacobian and the normal equations are built only at accepted points (about half the trials are not);
    the iterations stop when the cost falls by at most :data:`_ATOL` times its reduced value."""
    rows = slice(None) if keep is None else keep

    def evaluate(q):
        res, parts = _residual(q, y, tau, k)
        return res[rows], parts, float(res[rows] @ res[rows])

    res, parts, cost = evaluate(p)
    dof = max(res.size - p.size, 1)
    normal = _normal_equations(_jacobian(parts, tau, k)[rows], res)
    damping = 1e-3
    for _ in range(_MAX_ITERATIONS):
        trial = np.clip(p + _step(normal, damping, _free(p, normal[2], bounds)), *bounds)
        out = evaluate(trial)
        if out[2] < cost:
            done = cost - out[2] <= _ATOL * out[2] / dof
            p, (res, parts, cost), damping = trial, out, max(damping / 3.0, 1e-9)
            normal = _normal_equations(_jacobian(parts, tau, k)[rows], res)
            if done:
                break
        else:
            damping *= 4.0
            if damping > 1e8:
                break
    return p, res


def _check_starts(frequency_hz, decay_rate, frequency_tol_hz):
    """Start frequencies (positive), decay rates (clipped at 0) and tolerances (positive), one each."""
    f0 = check_array(frequency_hz, "frequency_hz", ndim=(1,))
    sigma0 = np.maximum(check_array(decay_rate, "decay_rate", ndim=(1,)), 0.0)
    if sigma0.shape != f0.shape:
        raise ValueError(f"decay_rate has {sigma0.size} value(s), frequency_hz {f0.size}: one per component")
    if np.any(f0 <= 0):
        raise ValueError("frequency_hz must be positive")
    tol = check_array(frequency_tol_hz, "frequency_tol_hz", ndim=(0, 1))
    if (tol.ndim and tol.shape != f0.shape) or np.any(tol <= 0):
        raise ValueError("frequency_tol_hz must be positive: one value, or one per component")
    return f0, sigma0, np.broadcast_to(tol, f0.shape)


def fit_damped_sinusoids(y, fs: float, frequency_hz, decay_rate, *, frequency_tol_hz,
                         keep=None) -> DampedSinusoids:
    """Refine damped sinusoids started at ``frequency_hz`` and ``decay_rate`` (see the module).

    Parameters
    ----------
    y : ndarray (n,)
        The ring-down from its first sample.
    fs : float
        Sampling rate (Hz).
    frequency_hz, decay_rate : array-like (k,)
        Start values: damped frequencies (Hz) and decay rates (1/s, clipped at 0).
    frequency_tol_hz : float or array-like (k,)
        Each frequency stays within this distance (Hz) of its start.
    keep : array-like of bool (n,), optional
        The samples to fit (default: all); e.g. those a saturated sensor did not clip. The residual
        covers every sample.

    Returns
    -------
    DampedSinusoids

    Examples
    --------
    >>> t = np.arange(4000) / 2000
    >>> y = 0.3 + np.exp(-1.5 * t) * np.cos(2 * np.pi * 50.2 * t + 0.4) + 0.1 * np.sin(2 * np.pi * 80 * t)
    >>> fit = fit_damped_sinusoids(y, 2000.0, [50.0, 80.5], [1.0, 0.5], frequency_tol_hz=1.0)
    >>> fit.frequency_hz.round(4).tolist(), fit.decay_rate.round(4).tolist(), round(fit.constant, 4)
    ([50.2, 80.0], [1.5, 0.0], 0.3)
    """
    arr, fs = check_signal_1d(y, "y"), check_fs(fs)
    f0, sigma0, tol = _check_starts(frequency_hz, decay_rate, frequency_tol_hz)
    duration = arr.size / fs
    tau = np.arange(arr.size) / arr.size  # time over the record's duration: a well-scaled problem
    omega0 = 2.0 * np.pi * f0 * duration
    sigma0 = sigma0 * duration
    k = omega0.size
    tol = 2.0 * np.pi * tol * duration
    if keep is not None:
        keep = np.asarray(keep, bool)
        if keep.shape != arr.shape or keep.sum() < 4 * k + 1:
            raise ValueError(f"keep must be {arr.size} booleans selecting at least {4 * k + 1} samples")
    p0 = _linear_amplitudes(arr, tau, sigma0, omega0, keep)
    lower = np.concatenate([np.zeros(k), omega0 - tol, np.full(2 * k + 1, -np.inf)])
    sigma_max = _MAX_DAMPING / np.sqrt(1.0 - _MAX_DAMPING**2) * (omega0 + tol)
    upper = np.concatenate([sigma_max, omega0 + tol, np.full(2 * k + 1, np.inf)])
    with one_thread("blas"):  # small products: threads only contend
        p, res = _levenberg_marquardt(np.clip(p0, lower, upper), arr, tau, k, (lower, upper), keep)
    if keep is not None:
        res = _residual(p, arr, tau, k)[0]
    sigma, omega, a, b, c = _split(p, k)
    return DampedSinusoids(
        frequency_hz=omega / (2.0 * np.pi * duration),
        decay_rate=sigma / duration,
        amplitude=np.hypot(a, b),
        phase=np.arctan2(-b, a),
        constant=float(c),
        residual=-res,
    )


def fit_amplitudes(y, fs: float, frequency_hz, decay_rate, *, keep=None) -> DampedSinusoids:
    """Amplitudes, phases and the constant of damped sinusoids with given frequencies and decay rates: the
    linear least-squares part of :func:`fit_damped_sinusoids`, the poles held fixed.

    Parameters
    ----------
    y : array-like (n,)
        The ring-down from its first sample.
    fs : float
        Sampling rate (Hz).
    frequency_hz, decay_rate : array-like (k,)
        Damped frequencies (Hz) and decay rates (1/s, clipped at 0) of the components.
    keep : array-like of bool (n,), optional
        The samples to fit (default: all); the residual covers every sample.

    Returns
    -------
    DampedSinusoids

    Examples
    --------
    >>> t = np.arange(2000) / 1000
    >>> y = 2 * np.exp(-3 * t) * np.cos(2 * np.pi * 40 * t + 0.5) + 0.2 * np.sin(2 * np.pi * 90 * t)
    >>> fit = fit_amplitudes(y, 1000.0, [40.0, 90.0], [3.0, 0.0])
    >>> fit.amplitude.round(6).tolist(), fit.phase.round(6).tolist()
    ([2.0, 0.2], [0.5, -1.570796])
    """
    arr, fs = check_signal_1d(y, "y"), check_fs(fs)
    f0, sigma, _ = _check_starts(frequency_hz, decay_rate, 1.0)
    omega = 2.0 * np.pi * f0
    tau = np.arange(arr.size) / fs
    if keep is not None:
        keep = np.asarray(keep, bool)
        if keep.shape != arr.shape:
            raise ValueError(f"keep must be {arr.size} booleans, one per sample")
    _, _, a, b, c = _split(_linear_amplitudes(arr, tau, sigma, omega, keep), f0.size)
    cos, sin = _basis(tau, sigma, omega)
    return DampedSinusoids(
        frequency_hz=f0,
        decay_rate=sigma,
        amplitude=np.hypot(a, b),
        phase=np.arctan2(-b, a),
        constant=float(c),
        residual=arr - c - cos @ a - sin @ b,
    )

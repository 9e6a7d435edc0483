"""Poles refined by the maximum-likelihood fit of a free decay's spectrum: the linear modes' values and ±.

A free decay sampled every ``dt`` from its first sample, ``y[n] = sum_k (c_k z_k**n + conj(c_k z_k**n))``
with ``z_k = exp((-sigma_k + i omega_k) dt)``, has an exact discrete Fourier transform over its ``N``
samples at the bins ``q_m = exp(-2 pi i m / N)``::

    Y[m] = sum_k  g_k / (1 - z_k q_m)  +  conj(g_k) / (1 - conj(z_k) q_m),     g_k = c_k (1 - z_k**N)

a sum of partial fractions whose residues ``g_k`` absorb the record's truncation. No window, no filter and
no transient: the model holds exactly at every bin, and white (or smoothly coloured) noise in time is
independent noise of one variance per bin. Least squares over the bins near the modes, each bin weighted
by the noise floor there, is then the maximum-likelihood fit of the modes' decay rates, damped frequencies
and complex amplitudes (for white noise, the same estimate as a fit of the whole record in time: the
transform is unitary, and the bins left out -- more than :data:`REACH` half-power half-widths from every
mode -- carry a share of the information that falls as the cube of the distance). Its Fisher information
gives each mode's standard deviations, calibrated against the noise the fit leaves near that mode; the same
residual says where the linear model does not hold (:attr:`DecayFit.lack_of_fit`: a mode whose frequency or
damping moves with amplitude leaves more than noise) and where a mode is missing
(:func:`missing_peaks`).

Started from poles that are already close (the stable poles of the stabilisation diagram, or spectral
peaks), a few Gauss-Newton iterations converge; the cost is that of the bins near the modes, not of the
record's length (one FFT).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from scipy.special import gammaincc

from .._utils.scaled import scaled_covariance, scaled_normal
from .._utils.threads import one_thread
from .._utils.validation import check_signal
from ..preprocessing.noise_floor import noise_floor

__all__ = ["DecayFit", "fit_decay", "missing_peaks", "REACH"]

#: Bins within this many half-power half-widths (``sigma / 2 pi`` Hz) of a mode are fitted ...
REACH = 8.0
#: ... and at least this many bins on each side of it (a resolution-limited mode's leakage), at most
#: :data:`MAX_BINS` (a strongly damped mode on a long record: the far bins add little).
MIN_BINS, MAX_BINS = 8, 256
#: Largest damping ratio of a fitted mode: a faster decay is a transient, not a vibration.
MAX_DAMPING = 0.3
#: A mode whose lack of fit is this improbable from noise alone leaves a residual that is not noise within
#: this many half-power half-widths, or this share of its frequency, of it (a chirp, a changing decay).
MISFIT_P, MISFIT_REACH, MISFIT_SHARE = 1e-6, 20.0, 0.04
#: Bins within this many half-power half-widths of a mode (at least :data:`CORE_BINS`) hold its lack of fit.
CORE = 3.0
CORE_BINS = 2
#: Share of the distance to the nearest other mode that a mode's frequency may move in the fit.
_MOVE = 0.45


@dataclass(frozen=True)
class DecayFit:
    """Modes fitted to a free decay's spectrum (see the module). Arrays are per mode, sorted by frequency.

    Attributes
    ----------
    frequency_hz, damping_ratio : ndarray
        Undamped natural frequency ``|s| / 2 pi`` and damping ratio ``sigma / |s|``.
    frequency_std_hz, damping_ratio_std : ndarray
        Their standard deviations (the fit's Fisher information, scaled up by the reduced chi-square of
        the bins near the mode where it exceeds one).
    decay_rate, decay_rate_std : ndarray
        ``sigma`` (1/s) and its standard deviation.
    amplitude : ndarray (n_modes, n_channels) of complex
        ``2 c_k``: the mode's complex amplitude at the first sample, per channel
        (``y_k(t) = Re(amplitude exp((-sigma + i omega) t))``).
    height_db : ndarray
        The mode's spectral peak over the noise floor at its frequency.
    lack_of_fit : ndarray
        Mean power of the residual in the mode's core bins (:data:`CORE` half-widths) over the noise
        floor: about 1 where the linear mode explains the data, more where it does not.
    lack_of_fit_p : ndarray
        Probability of a lack of fit at least that large from noise alone.
    noise_std : ndarray
        Standard deviation of the noise in time (the floor at the mode's frequency).
    residual_power, noise_power : ndarray (n // 2 + 1,)
        The periodogram (``|transform|^2``) of what the fit leaves, and its noise floor (the noise's variance
        per bin): for the search for missed modes and a later fit of the same decay.
    fs : float
        Sampling rate (Hz).
    n_samples : int
        Length of the free decay fitted.
    """

    frequency_hz: np.ndarray
    damping_ratio: np.ndarray
    frequency_std_hz: np.ndarray
    damping_ratio_std: np.ndarray
    decay_rate: np.ndarray
    decay_rate_std: np.ndarray
    amplitude: np.ndarray = field(repr=False)
    height_db: np.ndarray = field(repr=False)
    lack_of_fit: np.ndarray = field(repr=False)
    lack_of_fit_p: np.ndarray = field(repr=False)
    noise_std: np.ndarray = field(repr=False)
    fs: float = 1.0
    n_samples: int = 0
    residual_power: np.ndarray = field(default=None, repr=False)
    noise_power: np.ndarray = field(default=None, repr=False)

    def __len__(self) -> int:
        return int(self.frequency_hz.size)

    @property
    def noise_rms(self) -> float:
        """Standard deviation in time of the noise floor :attr:`noise_power` (of the first channel): what
        the fitted modes leave, integrated over frequency (Parseval)."""
        if self.noise_power is None or self.n_samples < 2:
            return float("nan")
        return float(np.sqrt(2.0 * np.sum(self.noise_power[1:]) / self.n_samples**2))

    @property
    def damped_frequency_hz(self) -> np.ndarray:
        """``frequency_hz * sqrt(1 - damping_ratio**2)``."""
        return self.frequency_hz * np.sqrt(np.maximum(1.0 - self.damping_ratio**2, 0.0))

    def component(self, k: int, n: int | None = None, channel: int = 0) -> np.ndarray:
        """Samples of mode ``k`` in ``channel`` over ``n`` samples from the first (default: the fit's)."""
        n = self.n_samples if n is None else n
        s = -self.decay_rate[k] + 2j * np.pi * self.damped_frequency_hz[k]
        t = np.arange(n) / self.fs
        return np.real(self.amplitude[k, channel] * np.exp(s * t))


def _bins(f_hz, sigma, n, fs, reach, least) -> np.ndarray:
    """Bin indices (1 .. n//2 - 1) within ``reach`` half-power half-widths (at least ``least`` bins) of
    any of the frequencies."""
    df = fs / n
    top = (n - 1) // 2
    keep = np.zeros(top + 1, bool)
    for f, s in zip(f_hz, sigma):
        half = min(max(reach * s / (2 * np.pi) / df, least), max(MAX_BINS, least))
        centre = f / df
        keep[int(max(1, np.floor(centre - half))): int(min(top, np.ceil(centre + half))) + 1] = True
    keep[0] = False
    return np.flatnonzero(keep)


def _design(log_z, q) -> tuple[np.ndarray, np.ndarray]:
    """``1 / (1 - z q)`` and ``1 / (1 - conj(z) q)``, shape (n_bins, n_modes)."""
    z = np.exp(log_z)
    return 1.0 / (1.0 - q[:, None] * z[None, :]), 1.0 / (1.0 - q[:, None] * np.conj(z)[None, :])


def _amplitudes(Y, a, b, w) -> np.ndarray:
    """Least-squares residues ``g`` (n_modes,) or (n_modes, n_channels) for fixed poles (weights ``w`` per
    bin): the model ``a g + b conj(g)`` is linear in the real and imaginary parts of ``g``."""
    k = a.shape[1]
    design = np.concatenate([a + b, 1j * (a - b)], axis=1) * w[:, None]
    stacked = np.concatenate([design.real, design.imag])
    rhs = Y * (w[:, None] if Y.ndim == 2 else w)
    coef = np.linalg.lstsq(stacked, np.concatenate([rhs.real, rhs.imag]), rcond=None)[0]
    return coef[:k] + 1j * coef[k:]


def _unpack(p, k):
    return p[:k], p[k: 2 * k], p[2 * k: 3 * k] + 1j * p[3 * k:]


class _Problem:
    """The weighted residual of the modes' spectrum at chosen bins, and its Jacobian (real parameters:
    decay rates, damped angular frequencies, then the residues' real and imaginary parts)."""

    def __init__(self, Y, bins, n, fs, weight):
        self.Y, self.dt, self.w = Y, 1.0 / fs, weight
        self.q = np.exp(-2j * np.pi * bins / n)
        self._last = None  # the parameters last evaluated and their parts

    def parts(self, p, k):
        """Residues and design matrices at ``p``; those of the point last evaluated are kept (the
        Levenberg-Marquardt iteration takes the Jacobian where it last evaluated the residual)."""
        key = (k, np.asarray(p, float).tobytes())
        if self._last is None or self._last[0] != key:
            sigma, omega, g = _unpack(p, k)
            a, b = _design((-sigma + 1j * omega) * self.dt, self.q)
            self._last = key, (g, a, b)
        return self._last[1]

    def residual(self, p, k) -> np.ndarray:
        g, a, b = self.parts(p, k)
        r = (self.Y - a @ g - b @ np.conj(g)) * self.w
        return np.concatenate([r.real, r.imag])

    def jacobian(self, p, k) -> np.ndarray:
        g, a, b = self.parts(p, k)
        # d a / d log z = z q / (1 - z q)^2 = (a - 1) a; log z = (-sigma + i omega) dt
        da, db = (a - 1.0) * a * self.dt * g, (b - 1.0) * b * self.dt * np.conj(g)
        w = self.w[:, None]
        model_d = [-(da + db), 1j * (da - db), a + b, 1j * (a - b)]  # d model / d (sigma, omega, Re g, Im g)
        jac = -np.concatenate(model_d, axis=1) * w  # of the residual (data - model)
        return np.concatenate([jac.real, jac.imag])


#: Decrease of the cost (a chi-square: the residual's real and imaginary parts have unit variance), in units
#: of its reduced value where that exceeds 1 (a misfit widens the standard deviations alike), below which the
#: iterations stop: a step that lowers it by less moves the parameters by a few hundredths of their
#: standard deviations.
_ATOL = 1e-3


def _levenberg_marquardt(problem, x, lower, upper, k: int, max_nfev: int) -> np.ndarray:
    """Levenberg-Marquardt steps on the normal equations (scaled by their diagonal), each step clipped to
    the bounds; stops when the cost no longer falls by :data:`_ATOL` (times the reduced chi-square where it
    exceeds 1) or after ``max_nfev`` evaluations of the residual."""
    r = problem.residual(x, k)
    cost, damping, evaluations = float(r @ r), 1e-3, 1
    while evaluations < max_nfev:
        jac = problem.jacobian(x, k)
        normal, gradient = jac.T @ jac, jac.T @ r
        scale = np.sqrt(np.diag(normal))
        scale[scale == 0] = 1.0
        normal, gradient = normal / np.outer(scale, scale), gradient / scale
        improved = False
        while evaluations < max_nfev and damping < 1e12:
            try:
                step = -np.linalg.solve(normal + damping * np.eye(normal.shape[0]), gradient) / scale
            except np.linalg.LinAlgError:
                damping *= 10.0
                continue
            trial = np.clip(x + step, lower, upper)
            r_trial = problem.residual(trial, k)
            evaluations += 1
            new = float(r_trial @ r_trial)
            if np.isfinite(new) and new < cost:
                improved, x, r, drop, cost = True, trial, r_trial, cost - new, new
                damping = max(damping / 10.0, 1e-12)
                break
            damping *= 10.0
        if not improved or drop <= _ATOL * max(1.0, cost / max(r.size - x.size, 1)):
            break
    return x


#: The noise floor stands at least this far under the periodogram's peak (200 dB: a noise-free record's
#: rounding errors are no modes; a recorder's dynamic range is under 150 dB).
PRECISION = 1e-20


def _noise_power(P, fs, n, f_hz, sigma, misfit=None) -> np.ndarray:
    """Noise variance per bin: the floor of the periodogram ``P`` with the modes' core bins left out (and
    the bins within :data:`MISFIT_REACH` half-widths or :data:`MISFIT_SHARE` of the frequency of the modes
    ``misfit`` marks: what a linear decay leaves of them spreads there and is no noise)."""
    core = np.zeros(P.size, bool)
    core[_bins(f_hz, sigma, n, fs, CORE, CORE_BINS)] = True
    spread = core.copy()
    for f, s in zip(np.asarray(f_hz)[misfit], np.asarray(sigma)[misfit]) if misfit is not None else ():
        reach = max(MISFIT_REACH * s / (2 * np.pi), MISFIT_SHARE * f) * n / fs
        spread[int(max(f * n / fs - reach, 0)): int(f * n / fs + reach) + 1] = True
    if spread.mean() <= 0.5:  # the floor needs bins to stand on: broad misfits leave the core alone
        core = spread
    if P.size < 16:
        return np.full(P.size, max(float(np.median(P)), np.finfo(float).tiny))
    return np.maximum(noise_floor(P, exclude=core), np.finfo(float).tiny)


def _bounds(omega, sigma, fs, n, move=_MOVE):
    """Each damped frequency within ``move`` of the distance to its neighbours (and at most its half-power
    band plus two bins from its start); decay rates non-negative."""
    df = 2 * np.pi * fs / n
    tol = np.maximum(2 * df, np.abs(sigma) + 2 * df)
    if omega.size > 1:
        order = np.argsort(omega)
        gap = np.diff(omega[order])
        near = np.full(omega.size, np.inf)
        near[order[:-1]] = np.minimum(near[order[:-1]], gap)
        near[order[1:]] = np.minimum(near[order[1:]], gap)
        tol = np.minimum(tol, move * near)
    tol = np.minimum(tol, 0.5 * omega)
    return omega - tol, omega + tol


def fit_decay(y, fs: float, damped_frequency_hz, decay_rate, *, noise=None, reach: float = REACH,
              max_nfev: int = 50, refloor: bool = True) -> DecayFit:
    """Fit modes to a free decay's spectrum, started from poles close to them (see the module).

    Parameters
    ----------
    y : array-like (n,) or (n, n_channels)
        The free decay from its first sample, offset removed. With several channels the modes' poles come
        from the first (the reference) and each channel gets its own amplitudes.
    fs : float
        Sampling rate (Hz).
    damped_frequency_hz, decay_rate : array-like (n_modes,)
        Starting poles: damped frequency (Hz) and decay rate ``sigma`` (1/s).
    noise : float or ndarray, optional
        The noise: its variance per sample of the reference channel (e.g. from the pre-trigger), or the
        ``noise_power`` of an earlier fit of the same free decay (its variance per bin of the transform).
        Default: the floor of the free decay's own spectrum without the modes' core bins, then of what a
        first fit leaves (two passes).
    reach : float
        Half-power half-widths around each mode whose bins are fitted.
    max_nfev : int
        Most evaluations of the residual.
    refloor : bool
        Where ``noise`` is a floor per bin (an earlier fit's ``noise_power``), report the floor of what this
        fit leaves as its ``noise_power`` (as where the noise is estimated); False keeps the given floor (a
        trial fit whose statistics alone are read: a floor costs a running quantile of the spectrum).

    Returns
    -------
    DecayFit

    Examples
    --------
    >>> fs = 1000.0
    >>> t = np.arange(4000) / fs
    >>> rng = np.random.default_rng(0)
    >>> y = np.exp(-1.2 * t) * np.cos(2 * np.pi * 50.0 * t + 0.3) + 0.4 * np.exp(-3.0 * t) * np.sin(
    ...     2 * np.pi * 121.0 * t) + 1e-3 * rng.standard_normal(t.size)
    >>> fit = fit_decay(y, fs, [50.1, 120.8], [1.0, 3.5])
    >>> fit.damped_frequency_hz.round(3).tolist(), fit.decay_rate.round(2).tolist()
    ([50.0, 121.0], [1.2, 3.0])
    >>> fit.frequency_std_hz.round(4).tolist(), bool(np.all(fit.lack_of_fit < 2))  # std (Hz), no misfit
    ([0.0, 0.0003], True)
    """
    Y2 = check_signal(y, "y", min_samples=8)
    n, c = Y2.shape
    f0 = np.atleast_1d(np.asarray(damped_frequency_hz, float))
    s0 = np.clip(np.atleast_1d(np.asarray(decay_rate, float)), 0.0, None)
    if f0.size != s0.size:
        raise ValueError(f"damped_frequency_hz and decay_rate differ in length ({f0.size}, {s0.size})")
    if np.any(~np.isfinite(f0)) or np.any(f0 <= 0) or np.any(f0 >= fs / 2):
        raise ValueError(f"damped_frequency_hz must lie in (0, fs/2 = {fs / 2:g}) Hz, got {f0.tolist()}")
    order = np.argsort(f0)
    fastest = 0.99 * MAX_DAMPING / np.sqrt(1 - MAX_DAMPING**2) * 2 * np.pi * f0[order]
    f0, s0 = f0[order], np.minimum(s0[order], fastest)
    with one_thread("blas"):
        spectrum = np.fft.rfft(Y2, axis=0)
        P = np.abs(spectrum[:, 0]) ** 2
        if noise is None:
            power, passes = _noise_power(P, fs, n, f0, s0), 2
        elif np.ndim(noise) == 0:
            power, passes = np.full(P.size, float(noise) * n), 1
        else:
            power, passes = np.asarray(noise, float), 1
            if power.shape != P.shape:
                raise ValueError(f"noise holds {power.size} bins, the transform of y {P.size}")
        estimate = noise is None or (np.ndim(noise) != 0 and refloor)
        least = PRECISION * float(np.max(P))
        out = _fit(spectrum, P, np.maximum(power, least), fs, n, f0, s0, reach, max_nfev, passes, estimate)
    return _floored(out, least)


def _floored(fit: DecayFit, least: float) -> DecayFit:
    """The fit with its noise floor at least ``least`` (:data:`PRECISION`) and its heights over that."""
    if np.all(fit.noise_power >= least):
        return fit
    noise = np.maximum(fit.noise_power, least)
    grid = np.arange(noise.size) * fit.fs / fit.n_samples
    ratio = np.interp(fit.damped_frequency_hz, grid, noise / fit.noise_power)
    return replace(fit, noise_power=noise, height_db=fit.height_db - 10 * np.log10(ratio),
                   noise_std=fit.noise_std * np.sqrt(ratio))


def _clusters(ranges: list) -> list:
    """Groups of modes whose bins overlap (transitively), by index."""
    order = sorted(range(len(ranges)), key=lambda k: ranges[k][0])
    groups, top = [], -1
    for k in order:
        if ranges[k][0] > top:
            groups.append([])
        groups[-1].append(k)
        top = max(top, ranges[k][-1])
    return groups


#: Sweeps over the clusters of overlapping modes, each fitted with the others held (their leak into its
#: bins falls as the distance: a second sweep settles what the first moved).
SWEEPS = 2


def _fit(spectrum, P, noise, fs, n, f0, s0, reach, max_nfev, passes, estimate) -> DecayFit:
    """``passes`` fits, each from the last with the noise floor of what the last one left (``estimate``:
    else the noise stays as given); the first with ``noise`` (the floor of the record's spectrum, which
    the modes' skirts may raise, or a known level). Modes whose bins overlap are fitted together, each
    cluster with the other clusters' modes held fixed (:data:`SWEEPS`): the cost of a fit grows with the
    modes' bins, not with the square of their number."""
    k = f0.size
    ranges = [_bins([f], [s], n, fs, reach, MIN_BINS) for f, s in zip(f0, s0)]
    clusters = _clusters(ranges)
    scale = float(np.sqrt(np.mean(P[np.concatenate(ranges)]))) + np.finfo(float).tiny  # parameters near 1
    omega0 = 2 * np.pi * f0
    lo, hi = _bounds(omega0, s0, fs, n)
    fastest = MAX_DAMPING / np.sqrt(1 - MAX_DAMPING**2) * hi
    bounds = (np.concatenate([np.zeros(k), lo]), np.concatenate([fastest, hi]))
    sigma, omega = np.maximum(s0, 1e-9 * omega0), omega0.copy()
    # every mode's amplitude at its seed first, all together: a cluster fitted before a strong neighbour's
    # amplitude is known would otherwise take that neighbour's skirt for itself
    bins = np.unique(np.concatenate(ranges))
    seeded = _design((-sigma + 1j * omega) / fs, np.exp(-2j * np.pi * bins / n))
    g = _amplitudes(spectrum[bins, 0] / scale, *seeded, np.sqrt(2.0 / (noise[bins] / scale**2)))
    first = True
    Y = spectrum[:, 0] / scale  # the reference's transform in units of the scale, once
    for done in range(1, passes + 1):
        scaled_noise = noise / scale**2
        for _sweep in range(SWEEPS if len(clusters) > 1 else 1):
            for c in clusters:
                sigma[c], omega[c], g[c] = _fit_cluster(Y, scaled_noise, ranges, c, (sigma, omega, g), bounds,
                                                        fs, n, max_nfev, first)
            first = False
        full = _all_bins_residual(spectrum[:, 0], sigma, omega, g * scale, fs, n)
        if estimate and done < passes:
            noise = _residual_noise(full, noise, sigma, omega, fs, n)
    cov = np.zeros((2 * k, 2 * k))
    scaled_noise = noise / scale**2
    for c in clusters:
        cov[np.ix_(c + [k + i for i in c], c + [k + i for i in c])] = _cluster_covariance(
            Y, scaled_noise, ranges, c, (sigma, omega, g), fs, n)
    g_all = g[:, None] * scale
    if spectrum.shape[1] > 1:  # the other channels: their own amplitudes at the reference's poles
        bins = np.unique(np.concatenate(ranges))
        a, b = _design((-sigma + 1j * omega) / fs, np.exp(-2j * np.pi * bins / n))
        g_all = np.column_stack([g_all[:, 0], _amplitudes(spectrum[bins, 1:], a, b, np.ones(bins.size))])
    return _result(sigma, omega, g_all, cov, noise, full, fs, n, estimate)


def _cluster_problem(Y, noise, ranges, c, params, fs, n):
    """The weighted problem of cluster ``c``: its modes' bins, the other modes' spectrum subtracted."""
    sigma, omega, g = params
    bins = np.unique(np.concatenate([ranges[i] for i in c]))
    q = np.exp(-2j * np.pi * bins / n)
    rest = [i for i in range(sigma.size) if i not in c]
    target = Y[bins]
    if rest:
        a, b = _design((-sigma[rest] + 1j * omega[rest]) / fs, q)
        target = target - a @ g[rest] - b @ np.conj(g[rest])
    return _Problem(target, bins, n, fs, np.sqrt(2.0 / noise[bins])), q


def _fit_cluster(Y, noise, ranges, c, params, bounds, fs, n, max_nfev, first):
    """Levenberg-Marquardt on cluster ``c``'s modes (amplitudes from least squares the first time)."""
    sigma, omega, g = params
    k, m = len(c), sigma.size
    problem, q = _cluster_problem(Y, noise, ranges, c, params, fs, n)
    if first:
        g0 = _amplitudes(problem.Y, *_design((-sigma[c] + 1j * omega[c]) / fs, q), problem.w)
    else:
        g0 = g[c]
    idx = np.array(c)
    lower = np.concatenate([bounds[0][idx], bounds[0][m + idx], np.full(2 * k, -np.inf)])
    upper = np.concatenate([bounds[1][idx], bounds[1][m + idx], np.full(2 * k, np.inf)])
    x = np.clip(np.concatenate([sigma[idx], omega[idx], g0.real, g0.imag]), lower, upper)
    x = _levenberg_marquardt(problem, x, lower, upper, k, max_nfev)
    return _unpack(x, k)


def _cluster_covariance(Y, noise, ranges, c, params, fs, n) -> np.ndarray:
    """Covariance of cluster ``c``'s decay rates and damped angular frequencies (unit-variance weights:
    the inverse of the Fisher information), in the order (sigma of ``c``, omega of ``c``).

    The information is inverted scaled (:mod:`~sindy_impulse._utils.scaled`): a weak component's pole
    columns are small beside a strong neighbour's amplitudes', and unscaled, the pseudo-inverse drops that
    direction as round-off and reports it as known exactly."""
    sigma, omega, g = params
    problem, _ = _cluster_problem(Y, noise, ranges, c, params, fs, n)
    idx = np.array(c)
    x = np.concatenate([sigma[idx], omega[idx], g[idx].real, g[idx].imag])
    jac = problem.jacobian(x, len(c))
    try:
        return scaled_covariance(*scaled_normal(jac))[: 2 * len(c), : 2 * len(c)]
    except np.linalg.LinAlgError:
        return np.full((2 * len(c), 2 * len(c)), np.nan)


def _all_bins_residual(spectrum, sigma, omega, g, fs, n) -> np.ndarray:
    """The spectrum minus the modes at every bin (for the noise floor and the search for missed modes)."""
    m = np.arange(spectrum.shape[0])
    q = np.exp(-2j * np.pi * m / n)
    out = spectrum.astype(complex).copy()
    for start in range(0, m.size, 8192):
        part = slice(start, start + 8192)
        a, b = _design((-sigma + 1j * omega) / fs, q[part])
        out[part] -= a @ g + b @ np.conj(g)
    out[0] = 0.0
    return out


def _core_statistics(u, bins, sigma, omega, fs, n) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per mode: the mean residual power over the noise in its core bins (lack of fit), the probability of
    at least that from noise alone (a mean of ``m`` unit exponentials: a gamma law), and the reduced
    chi-square of the bins within its reach (at least 1: the factor its covariance is scaled by)."""
    k = sigma.size
    lof, lof_p, chi = np.full(k, np.nan), np.full(k, np.nan), np.ones(k)
    for i in range(k):
        f = [omega[i] / (2 * np.pi)]
        core = np.isin(bins, _bins(f, [sigma[i]], n, fs, CORE, CORE_BINS))
        if core.any():
            m = int(core.sum())
            lof[i] = float(np.mean(u[core]))
            lof_p[i] = float(gammaincc(m, m * lof[i]))
        around = np.isin(bins, _bins(f, [sigma[i]], n, fs, REACH, MIN_BINS))
        dof = max(2 * int(around.sum()) - 4, 1)
        chi[i] = max(1.0, 2.0 * float(np.sum(u[around])) / dof)
    return lof, lof_p, chi


def _natural(sigma, omega, cov, chi) -> tuple[np.ndarray, ...]:
    """Natural angular frequency, damping ratio and their standard deviations, and the decay rate's, from
    the covariance of ``(sigma, omega)`` (delta method), each mode's scaled by its ``chi``."""
    k = sigma.size
    var_s, var_o, cov_so = (np.diag(cov)[:k] * chi, np.diag(cov)[k:] * chi, np.diag(cov[:k, k:]) * chi)
    wn = np.hypot(sigma, omega)
    # d wn = (sigma d sigma + omega d omega) / wn; d zeta = (omega^2 d sigma - sigma omega d omega) / wn^3
    var_wn = (sigma**2 * var_s + omega**2 * var_o + 2 * sigma * omega * cov_so) / wn**2
    gs, go = omega**2 / wn**3, -sigma * omega / wn**3
    var_z = gs**2 * var_s + go**2 * var_o + 2 * gs * go * cov_so
    root = np.sqrt
    return wn, sigma / wn, root(np.maximum(var_wn, 0)), root(np.maximum(var_z, 0)), root(np.maximum(var_s, 0))


def _residual_noise(full, noise, sigma, omega, fs, n, statistics=None) -> np.ndarray:
    """The noise floor of what the fit leaves (``full``), without the reach of the modes whose lack of fit
    (against ``noise``; ``statistics``: their ``(lof, lof_p)`` when known) the linear decay does not explain
    (:data:`MISFIT_P`)."""
    if statistics is None:
        bins = np.unique(_bins(omega / (2 * np.pi), sigma, n, fs, REACH, MIN_BINS))
        statistics = _core_statistics(np.abs(full[bins]) ** 2 / noise[bins], bins, sigma, omega, fs, n)[:2]
    lof, lof_p = statistics
    damping = sigma / np.maximum(np.hypot(sigma, omega), np.finfo(float).tiny)
    misfit = (lof_p < MISFIT_P) & (lof > 1.5) & (damping < MAX_DAMPING)
    return _noise_power(np.abs(full) ** 2, fs, n, omega / (2 * np.pi), sigma, misfit)


def _result(sigma, omega, g, cov, noise, full, fs, n, estimate) -> DecayFit:
    """The fit's values; the reported noise floor re-estimated (``estimate``) without what the modes the
    linear decay does not explain leave near them."""
    bins = np.unique(_bins(omega / (2 * np.pi), sigma, n, fs, REACH, MIN_BINS))
    lof, lof_p, chi = _core_statistics(np.abs(full[bins]) ** 2 / noise[bins], bins, sigma, omega, fs, n)
    noise_out = _residual_noise(full, noise, sigma, omega, fs, n, (lof, lof_p)) if estimate else noise
    wn, zeta, wn_std, zeta_std, sigma_std = _natural(sigma, omega, cov, chi)
    c = g / (1.0 - np.exp((-sigma + 1j * omega) / fs) ** n)[:, None]
    height = _heights(c[:, 0], sigma, omega, fs, n, noise)
    noise_std = np.sqrt(np.interp(omega / (2 * np.pi), np.arange(noise.size) * fs / n, noise) / n)
    o = np.argsort(wn)
    hz = 2 * np.pi
    return DecayFit(wn[o] / hz, zeta[o], wn_std[o] / hz, zeta_std[o], sigma[o], sigma_std[o], 2 * c[o],
                    height[o], lof[o], lof_p[o], noise_std[o], float(fs), int(n), np.abs(full) ** 2,
                    noise_out)


def _heights(c, sigma, omega, fs, n, noise) -> np.ndarray:
    """Each mode's spectral peak (its transform at its own damped frequency) over the noise floor (dB)."""
    z = np.exp((-sigma + 1j * omega) / fs)
    at = np.exp(-1j * omega / fs)
    peak = np.abs(c * (1.0 - (z * at) ** n) / (1.0 - z * at)) ** 2
    floor = np.interp(omega / (2 * np.pi), np.arange(noise.size) * fs / n, noise)
    return 10.0 * np.log10(np.maximum(peak, np.finfo(float).tiny) / floor)


def missing_peaks(fit: DecayFit, threshold_db: float, lo_hz: float = 0.0, hi_hz: float | None = None,
                  away_bins: float = 2.0) -> tuple[np.ndarray, np.ndarray]:
    """Peaks of what the fit leaves (its residual's power over the noise floor) above ``threshold_db``,
    away from every fitted mode by ``away_bins`` bins: ``(damped frequencies (Hz), decay rates to start
    from)``, strongest first.

    Examples
    --------
    >>> fs = 1000.0
    >>> t = np.arange(4000) / fs
    >>> y = np.exp(-1.0 * t) * np.cos(2 * np.pi * 50.0 * t) + 0.01 * np.exp(-2.0 * t) * np.cos(
    ...     2 * np.pi * 80.0 * t) + 1e-4 * np.random.default_rng(1).standard_normal(t.size)
    >>> f, _ = missing_peaks(fit_decay(y, fs, [50.0], [1.0]), 15.0)
    >>> f.round(1).tolist()
    [80.0]
    """
    if fit.residual_power is None:
        return np.empty(0), np.empty(0)
    df = fit.fs / fit.n_samples
    ratio = fit.residual_power / fit.noise_power
    ratio[0] = 0.0
    level = 10.0 * np.log10(np.maximum(ratio, np.finfo(float).tiny))
    f = np.arange(ratio.size) * df
    hi = fit.fs * 0.45 if hi_hz is None else hi_hz
    inner = (level[1:-1] > level[:-2]) & (level[1:-1] >= level[2:]) & (level[1:-1] >= threshold_db)
    idx = np.flatnonzero(inner) + 1
    idx = idx[(f[idx] >= lo_hz) & (f[idx] <= hi)]
    if len(fit):
        away = np.min(np.abs(f[idx][:, None] - fit.damped_frequency_hz[None, :]), axis=1) > away_bins * df
        idx = idx[away]
    idx = _apart(idx[np.argsort(-level[idx])][:_MOST_PEAKS], level)
    # start between bins (a parabola through the log power) and from the measured half-power width
    a, b, cc = (np.log(np.maximum(ratio[np.clip(idx + d, 0, ratio.size - 1)], 1e-300)) for d in (-1, 0, 1))
    curv = a - 2 * b + cc
    shift = np.where(curv < 0, 0.5 * (a - cc) / np.where(curv < 0, curv, -1.0), 0.0)
    width = np.array([_half_width(level, i) for i in idx])
    return f[idx] + np.clip(shift, -0.5, 0.5) * df, 2 * np.pi * df * np.maximum(width - 0.5, 0.1)


#: Highest local maxima of the residual examined (the search adds a few modes a round).
_MOST_PEAKS = 64
#: A weaker peak counts only where it stands this much (dB) over the skirt of a stronger one.
_SKIRT_MARGIN_DB = 6.0


def _half_width(level: np.ndarray, i: int) -> float:
    """Bins from peak ``i`` to where ``level`` (dB) falls 3 dB below it (the nearer side; at most 64)."""
    sides = []
    for step in (-1, 1):
        j = i
        while 0 < j + step < level.size and abs(j - i) < 64 and level[j + step] > level[i] - 3.0:
            j += step
        sides.append(abs(j - i) + 0.5)
    return float(min(sides))


def _apart(idx: np.ndarray, level: np.ndarray) -> np.ndarray:
    """Peaks (strongest first) that stand over the skirts of the stronger ones kept before them: a
    Lorentzian skirt falls 20 dB per decade of distance in half-power half-widths."""
    kept, widths = [], []
    for i in idx:
        ok = all(level[i] > level[j] - 20.0 * np.log10(max(abs(i - j) / w, 1.0)) + _SKIRT_MARGIN_DB
                 for j, w in zip(kept, widths))
        if ok:
            kept.append(int(i))
            widths.append(_half_width(level, int(i)))
    return np.array(kept, dtype=int)



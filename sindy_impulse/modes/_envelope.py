"""The decay envelope of one mode: how its frequency and decay rate change with its amplitude.

- :func:`decay_dependence`, the cheap evidence the survey classifies candidates on: the mode's free decay
  (other modes removed, no band-pass) read against the averaged (first-order) equations of a weakly
  nonlinear oscillator, ``d ln A / dt = -(sigma_0 + sigma_2 A^2)`` and ``d phi / dt = omega_0 + omega_2
  A^2`` (a cubic spring moves the frequency, an ``x^2 x'`` damper the decay rate, both with the squared
  amplitude), fitted from the linear decay's values by Gauss-Newton; the changes of the frequency and of
  the decay rate over the amplitudes seen, with their standard errors, say whether the mode is nonlinear
  enough to matter (:data:`FREQUENCY_CHANGE`, :data:`DECAY_CHANGE`; with ``neighbours``, the squared
  amplitudes of other modes move them too, each with its own slope, ``+ sum_j (omega_2j, sigma_2j)
  A_j^2``, as a nonlinear element shared by several modes moves each one's frequency with the others'
  amplitudes, and the values at zero amplitude are those with every amplitude gone), and the fitted
  equations are the mode's equation where the paper's fit misses that dependence
  (:func:`~.linear.envelope_mode`). Where
  something else is in the free decay (a hit's tail, a neighbour's misfit: the fit's residual stands out
  of the noise), :func:`amplitude_dependence` reads the same equations off the mode's analytic signal in
  its band, the filter's transients trimmed: integrated, both are straight lines in ``t`` and ``I(t) =
  int A^2 dt``, fitted by weighted least squares (weights ``A^2``).
- :func:`_missing_damping`: the small-amplitude damping ratio of a nonlinear mode whose equation lacks the
  amplitude-dependent damping its decay shows (the threshold sweep may drop that term: the segment-wise
  error measure of a long band hardly sees a slow change of the decay rate, and the linear damping then
  absorbs an average over the decay). The decay rate measured over windows of a few periods
  (:func:`envelope_decay`) is regressed on the squared amplitude; where the data's change over the decay is
  significant and the model reproduces less than half of it, the regression's intercept (the rate at zero
  amplitude over the model's natural frequency) is the damping ratio.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._utils.scaled import scaled_covariance, scaled_normal
from ..feature_library.terms import term_table

__all__ = ["AmplitudeDependence", "decay_dependence", "amplitude_dependence", "joint_dependence",
           "envelope_decay", "FREQUENCY_CHANGE", "DECAY_CHANGE"]

#: A mode is nonlinear for the survey when its frequency changes by more than ``FREQUENCY_CHANGE``
#: (relative) over the amplitudes of its decay (a modal table's frequencies are read to about 0.1 %) or its
#: decay rate by more than ``DECAY_CHANGE`` of its small-amplitude value (damping ratios are read to about
#: 10 %), either change standing ``CHANGE_SIGMAS`` standard errors from zero, over at least ``MIN_PERIODS``
#: periods of the mode, from an envelope whose residual about the averaged equations is at most
#: ``ENVELOPE_MISFIT`` times the noise's.
FREQUENCY_CHANGE, DECAY_CHANGE, CHANGE_SIGMAS, MIN_PERIODS, ENVELOPE_MISFIT = 1e-3, 0.1, 3.0, 10.0, 3.0
#: A change beyond its threshold at this many standard errors is doubtful: the mode's equation decides.
DOUBT_SIGMAS = 2.0
#: A decay rate's change beyond :data:`DECAY_CHANGE` at this many standard errors makes a mode nonlinear
#: even where its linear decay explains the record (there the decay rate's change counts only this far
#: out: on linear records it strays beyond :data:`CHANGE_SIGMAS`; measured over about 1,000 modes of linear
#: records, the largest was 4.1 standard errors, and 7.2 on a 15 ms record of modes damped 2-24 %).
DECAY_SIGMAS = 8.0


@dataclass(frozen=True)
class AmplitudeDependence:
    """How a mode's frequency and decay rate change over the amplitudes of its decay
    (:func:`decay_dependence`): relative changes from its smallest amplitude analysed to its largest
    (with neighbours, their amplitudes' share of the change over the same stretch included),
    with their standard errors, the amplitudes, the averaged equations' ``(omega_0, omega_2, sigma_0,
    sigma_2)`` (damped angular frequency and decay rate at zero amplitude and their slopes in ``A^2``)
    with their standard errors, and ``misfit``: the RMS residual of ``A ln A`` and ``A phi`` about them over
    the noise (about 1 where they describe the envelope)."""

    frequency_change: float
    frequency_change_std: float
    decay_change: float
    decay_change_std: float
    amplitude: tuple
    coefficients: tuple = ()
    coefficients_std: tuple = ()
    misfit: float = 1.0
    #: ``(c, a2, rate)`` of a free-decay fit (:func:`decay_dependence`): its complex amplitude at the decay's
    #: start, and the squared amplitude and decay rate of the linear decay its amplitude integral is built
    #: on; None for a band's envelope (:func:`amplitude_dependence`), whose signal it does not describe, and
    #: where neighbours' amplitudes move the mode (its free decay needs theirs).
    start: tuple | None = None
    #: The other modes whose squared amplitudes move it (indices of :func:`joint_dependence`'s drivers).
    drivers: tuple = ()
    #: How far its values with every amplitude gone lie beyond the stretch read (:func:`joint_dependence`):
    #: the frequency's shift still left at its end, over its change within it (0 where its own amplitude
    #: alone moves it: its decay shows it gone).
    beyond: float = 0.0

    def free_decay(self, n: int, fs: float) -> np.ndarray | None:
        """The averaged equations' free decay over ``n`` samples at ``fs`` from the decay's start (the signal
        the free-decay fit describes), or None for a band's envelope.

        Examples
        --------
        >>> e = AmplitudeDependence(0.0, 0.0, 0.0, 0.0, (1.0, 0.5), (2 * np.pi * 10, 0.0, 1.0, 0.0),
        ...                         start=(1.0 + 0j, 1.0, 1.0))
        >>> e.free_decay(3, 100.0).round(3).tolist()  # a linear decay: 1.0 exp(-t) cos(2 pi 10 t)
        [1.0, 0.801, 0.303]
        """
        if self.start is None:
            return None
        c, a2, rate = self.start
        omega0, omega2, sigma0, sigma2 = self.coefficients
        t = np.arange(n) / fs
        integral = _linear_integral(a2, rate, t)
        with np.errstate(over="ignore", invalid="ignore"):  # equations that grow: inf, for the caller to see
            return np.real(c * np.exp((-sigma0 + 1j * omega0) * t + (-sigma2 + 1j * omega2) * integral))

    @property
    def nonlinear(self) -> bool:
        """Whether either change exceeds its threshold (:data:`FREQUENCY_CHANGE`, :data:`DECAY_CHANGE`)
        and :data:`CHANGE_SIGMAS` standard errors, read off an envelope the averaged equations describe
        (``misfit`` at most :data:`ENVELOPE_MISFIT`: not a beating with an unresolved neighbour, nor a
        decay that is not a function of the amplitude)."""
        return self._exceeds(CHANGE_SIGMAS)

    @property
    def decays_nonlinearly(self) -> bool:
        """Whether the decay rate's change exceeds :data:`DECAY_CHANGE` and :data:`DECAY_SIGMAS` standard
        errors, read off an envelope the averaged equations describe."""
        return self._exceeds(DECAY_SIGMAS, frequency=False)

    @property
    def doubtful(self) -> bool:
        """Whether the frequency's change exceeds its threshold and :data:`DOUBT_SIGMAS` standard errors (not
        yet :attr:`nonlinear`): a linear decay's frequency, an average over the amplitudes, may be biased by
        it, so the survey fits the mode's equation, which then decides. (Not the decay rate's: read from the
        logarithm of a noisy envelope, its change strays beyond 2 standard errors on weak linear modes
        more often than the normal law says.)"""
        return self._exceeds(DOUBT_SIGMAS, decay=False)

    def changes(self, sigmas: float, decay: bool = True, frequency: bool = True) -> bool:
        """Whether the frequency's (with ``frequency``) or the decay rate's (with ``decay``) change exceeds
        its threshold and ``sigmas`` standard errors, whatever the envelope's misfit."""
        changes = [(self.frequency_change, self.frequency_change_std, FREQUENCY_CHANGE)] if frequency else []
        if decay:
            changes.append((self.decay_change, self.decay_change_std, DECAY_CHANGE))
        return any(abs(c) > max(limit, sigmas * std) for c, std, limit in changes)

    def _exceeds(self, sigmas: float, decay: bool = True, frequency: bool = True) -> bool:
        return self.misfit <= ENVELOPE_MISFIT and self.changes(sigmas, decay, frequency)


def amplitude_dependence(z: np.ndarray, fs: float, bandwidth_hz: float, noise_rms: float,
                         min_snr_db: float = 10.0, frequency_hz: float | None = None, neighbours=()
                         ) -> AmplitudeDependence | None:
    """The changes of a mode's frequency and decay rate with its amplitude (see the module), from its
    analytic signal ``z`` (transients trimmed) of band ``bandwidth_hz`` wide, used down to ``min_snr_db``
    over the band's noise ``noise_rms``; ``neighbours``: ``(squared amplitude, decay rate)`` of the linear
    decays of other modes whose squared amplitudes move this one's frequency and decay rate too (see the
    module; one that does not decay takes no term). None when fewer than 8 independent samples, or (given
    the mode's
    ``frequency_hz``) fewer than :data:`MIN_PERIODS` of its periods remain: too short a decay to tell an
    amplitude dependence from a start that is not yet free.

    Examples
    --------
    A cubic spring (frequency up 1 % at the largest amplitude) and a linear mode:

    >>> fs, t = 1000.0, np.arange(6000) / 1000.0
    >>> a = np.exp(-0.8 * t)
    >>> hard = a * np.exp(1j * 2 * np.pi * 50 * (t + 0.01 * (1 - a**2) / 1.6))
    >>> e = amplitude_dependence(hard, fs, 10.0, 1e-6)
    >>> round(e.frequency_change, 4), e.nonlinear
    (0.01, True)
    >>> amplitude_dependence(a * np.exp(1j * 2 * np.pi * 50 * t), fs, 10.0, 1e-6).nonlinear
    False
    """
    neighbours = [(b2, rate) for b2, rate in neighbours if rate > 0]
    amplitude = np.abs(z)
    keep = np.flatnonzero(amplitude >= 10 ** (min_snr_db / 20) * noise_rms)
    if keep.size == 0:
        return None
    keep = np.arange(keep[0], keep[-1] + 1)
    n_eff = keep.size / fs * bandwidth_hz
    if n_eff < 8 or (frequency_hz is not None and keep.size / fs * frequency_hz < MIN_PERIODS):
        return None
    unwrapped = np.unwrap(np.angle(z[keep]))
    step = max(1, int(fs / (4.0 * bandwidth_hz)))  # four samples per independent one suffice
    keep, phase = keep[::step], unwrapped[::step]
    a = amplitude[keep]
    t = keep / fs
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (a[1:] ** 2 + a[:-1] ** 2) * np.diff(t))])
    around = [_linear_integral(b2, rate, t) for b2, rate in neighbours]
    design = np.column_stack([np.ones_like(t), t - t[0], integral, *around])
    weights = a**2 / np.max(a**2)
    coef, cov, misfit = [], [], []
    for target in (np.log(a), phase):
        c, v = _weighted_line(design, target, weights, keep.size / n_eff)
        coef.append(c)
        cov.append(v)
        misfit.append(float(np.sqrt(np.mean(((target - design @ c) * a) ** 2))) / max(noise_rms, 1e-300))
    # the changes over the decay: of the squared amplitudes (its own and each neighbour's) times their slopes
    spans = np.array([a.max() ** 2 - a.min() ** 2]  # (a neighbour's: 2 rate times its integral's rise)
                     + [2 * rate * (i[-1] - i[0]) for i, (_, rate) in zip(around, neighbours)])
    sigma0, sigma2 = -coef[0][1], -coef[0][2]
    omega0, omega2 = coef[1][1], coef[1][2]
    frequency_change, frequency_std = _change(coef[1][2:], cov[1][2:, 2:], spans, omega0)
    decay_change, decay_std = _change(-coef[0][2:], cov[0][2:, 2:], spans, sigma0) if sigma0 > 0 else (
        np.inf, np.inf)
    std = lambda c: float(np.sqrt(max(c, 0.0)))  # noqa: E731
    return AmplitudeDependence(float(frequency_change), float(frequency_std), float(decay_change),
                               float(decay_std), (float(a.max()), float(a.min())),
                               (float(omega0), float(omega2), float(sigma0), float(sigma2)),
                               (std(cov[1][1, 1]), std(cov[1][2, 2]), std(cov[0][1, 1]), std(cov[0][2, 2])),
                               max(misfit))


def _weighted_line(design: np.ndarray, target: np.ndarray, weights: np.ndarray, correlation: float):
    """Weighted least squares and the coefficients' covariance, the residual variance scaled by
    ``correlation`` (samples per independent one)."""
    w = np.sqrt(weights)
    # scaled (:mod:`~sindy_impulse._utils.scaled`): the amplitude integrals carry the record's units squared
    normal, scale, columns = scaled_normal(design * w[:, None], scaled=True)
    coef = np.linalg.lstsq(columns, target * w, rcond=None)[0] / scale
    residual = (target - design @ coef) * w
    dof = max(target.size - design.shape[1], 1)
    cov = scaled_covariance(normal, scale) * float(residual @ residual) / dof
    return coef, cov * correlation

#: Periods per window of the decay-rate measurement (half-overlapping windows).
WINDOW_PERIODS = 4.0
#: Smallest change of the damping ratio over the decay (relative to its small-amplitude value) acted on.
MIN_CHANGE = 0.05
#: The data's change must exceed this many standard errors.
MIN_SIGNIFICANCE = 1.5
#: The model reproduces less than this share of the data's change: its amplitude-dependent damping is missing.
MODEL_SHARE = 0.5
#: Smallest number of windows, and largest smallest-to-largest squared amplitude, of a usable regression.
MIN_WINDOWS, MAX_RANGE = 8, 0.5


def _demodulated(y: np.ndarray, dy: np.ndarray, dt: float, omega: float) -> np.ndarray:
    """The envelope of a mode's states ``[y, dy]`` with its harmonics removed: ``y - i dy / omega`` turns
    the mode into ``A exp(i theta)`` and each harmonic ``n`` into terms rotating ``n - 1`` and ``-(n + 1)``
    times as fast; brought to rest at ``omega`` and averaged over one period, only the mode's own term
    stays. (``sqrt(y^2 + (dy / omega)^2)`` itself ripples once per period with a harmonic in the states,
    by three times its relative amplitude for the second, and a window's slope picks up that ripple's
    phase, which drifts as the mode's frequency moves with its amplitude.)"""
    period = max(1, int(round(2 * np.pi / omega / dt)))
    z = (y - 1j * dy / omega) * np.exp(-1j * omega * dt * np.arange(y.size))
    if z.size < period:
        return np.abs(z)
    total = np.concatenate([[0.0], np.cumsum(z)])  # the running mean in O(n), whatever the period
    return np.abs(total[period:] - total[:-period]) / period


def envelope_decay(y: np.ndarray, dy: np.ndarray, dt: float, omega: float):
    """The decay rate against the squared amplitude of a free decay of one mode: windows of
    :data:`WINDOW_PERIODS` periods of its envelope (:func:`_demodulated`, its harmonics removed); a
    straight line of the rate (1/s) on the squared amplitude relative to its largest, weighted by the
    amplitude.

    Returns ``(intercept, slope, intercept_se, slope_se, smallest, largest_amplitude)`` or None when the
    decay is too short or covers too little amplitude (:data:`MIN_WINDOWS`, :data:`MAX_RANGE`).

    Examples
    --------
    >>> t = np.arange(20000) / 2000.0  # a decay rate 0.5 + 2 a^2 (1/s), from a = 1:
    >>> a = np.sqrt(0.5 / ((0.5 + 2.0) * np.exp(2 * 0.5 * t) - 2.0))
    >>> y, dy = a * np.cos(2 * np.pi * 50 * t), -a * 2 * np.pi * 50 * np.sin(2 * np.pi * 50 * t)
    >>> fit = envelope_decay(y, dy, 1 / 2000.0, 2 * np.pi * 50)
    >>> round(fit[0], 1)  # the rate at zero amplitude
    0.5
    """
    amplitude = _demodulated(np.asarray(y, float), np.asarray(dy, float), dt, omega)
    n = max(4, int(round(WINDOW_PERIODS * 2 * np.pi / omega / dt)))
    starts = np.arange(0, amplitude.size - n, max(1, n // 2))
    if starts.size < MIN_WINDOWS or not np.all(amplitude > 0):
        return None
    tt = np.arange(n) * dt
    logs = np.log(amplitude[starts[:, None] + np.arange(n)])
    rate = -np.polyfit(tt, logs.T, 1)[0]
    a2 = np.mean(np.exp(2 * logs), axis=1)
    x = a2 / a2.max()
    if x.min() > MAX_RANGE:
        return None
    w = np.sqrt(x)
    design = np.column_stack([np.ones_like(x), x]) * w[:, None]
    coef, *_ = np.linalg.lstsq(design, rate * w, rcond=None)
    resid = rate * w - design @ coef
    dof = max(1, x.size - 2)
    cov = np.linalg.pinv(design.T @ design) * float(resid @ resid) / dof
    # windows overlap by half: about half as many independent ones
    se = np.sqrt(np.maximum(np.diag(cov), 0) * 2)
    top = float(np.sqrt(a2.max()))
    return float(coef[0]), float(coef[1]), float(se[0]), float(se[1]), float(x.min()), top


def _model_rate_change(model, omega: float, amplitude: float) -> float | None:
    """Change of the decay rate (1/s) the model's nonlinear terms of its ``dy'`` equation give between zero
    amplitude and ``amplitude`` (power balance over one period of ``y = a cos``); None if unknown."""
    try:
        coef = np.asarray(model.coefficients(), float)
        library = getattr(model, "feature_library_", None) or model.feature_library
        terms = term_table(library, coef.shape[0])
    except (AttributeError, TypeError, ValueError):
        return None
    if coef.shape[0] != 2 or terms.powers.shape[1] != 2:
        return None
    theta = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    x, v = amplitude * np.cos(theta), -amplitude * omega * np.sin(theta)
    force = sum(c * x**p * v**q for c, (p, q), lin in zip(coef[1], terms.powers, terms.linear) if not lin)
    return float(-np.mean(force * v) / (2 * np.mean(v**2))) if np.ndim(force) else 0.0


def _missing_damping(mode):
    """``(damping ratio at zero amplitude, its std, data's relative change, model's)`` when the mode's
    ``[y, dy]`` states show a significant change of the decay rate over the decay that its model reproduces
    less than :data:`MODEL_SHARE` of; else None."""
    states = np.asarray(mode.states)
    if states.ndim != 2 or states.shape[1] != 2 or mode.coordinate_ != 0 or len(mode.t) < 3:
        return None
    omega = 2 * np.pi * mode.frequency_hz
    fit = envelope_decay(states[:, 0], states[:, 1], float(np.median(np.diff(mode.t))), omega)
    if fit is None:
        return None
    s0, s1, se0, se1, smallest, top = fit
    change = s1 * (1 - smallest)
    model_change = _model_rate_change(mode.model, omega, top)
    if (s0 <= 0 or model_change is None or abs(change) < MIN_SIGNIFICANCE * se1 * (1 - smallest)
            or abs(change) < MIN_CHANGE * s0 or abs(model_change) >= MODEL_SHARE * abs(change)):
        return None
    return s0 / omega, se0 / omega, change / s0, model_change / s0


#: Gauss-Newton iterations of :func:`decay_dependence` at most (it starts at the decay fit's values).
_ITERATIONS = 6
#: ... stopping when a step lowers the squared residual by less than this share, or when after a step the
#: residual is still this many times the noise (something else is in the decay: its misfit says so).
_TOLERANCE, _HOPELESS = 1e-6, 10 * ENVELOPE_MISFIT
#: ... on every m-th sample of the free decay: at least this many per period, and about this many in all.
_PER_PERIOD, _SAMPLES = 4, 2048
#: The residual's variance that the standard errors use is its power near the mode: within this many
#: half-power half-widths of the mode's frequency, and at least this many bins either side.
_NEAR_WIDTHS, _NEAR_BINS = 5.0, 20


def decay_dependence(y: np.ndarray, fs: float, amplitude: complex, decay_rate: float, frequency_hz: float,
                     noise_std: float, neighbours=()) -> AmplitudeDependence | None:
    """The changes of a mode's frequency and decay rate with its amplitude from its free decay ``y`` itself
    (no band-pass: a filter's transient hides the start of the decay, where the amplitude is largest),
    other modes removed, starting at its linear decay's complex ``amplitude``, ``decay_rate`` (1/s) and
    damped ``frequency_hz``; ``neighbours``: ``(squared amplitude at the start, decay rate)`` of the linear
    decays of other modes whose squared amplitudes move this one's frequency and decay rate too (one that
    does not decay, ``decay rate <= 0``, would move it by a constant: its linear values, no term of its own).

    The averaged equations of the module, to first order in ``omega_2`` and ``sigma_2``: ``y(t) = Re[c
    exp(-sigma_0 t - sigma_2 I(t) + i (omega_0 t + omega_2 I(t)))]`` with ``I(t) = |a|^2 (1 - exp(-2
    sigma t)) / (2 sigma)`` the integral of the linear decay's squared amplitude, fitted by Gauss-Newton
    from the linear decay; the standard errors from the Jacobian and the residual's variance (white
    noise). Returns an :class:`AmplitudeDependence` (``misfit`` the residual's RMS over ``noise_std``),
    or None when fewer than :data:`MIN_PERIODS` periods remain, the linear decay's start gives no finite
    signal or the iteration does not converge.

    Examples
    --------
    A cubic spring (frequency up 0.3 % at the largest amplitude) in noise at 40 dB:

    >>> fs, t = 2000.0, np.arange(4000) / 2000.0
    >>> a, s, w = 1.0, 2.0, 2 * np.pi * 50
    >>> integral = a**2 * (1 - np.exp(-2 * s * t)) / (2 * s)
    >>> y = np.real(a * np.exp(-s * t + 1j * (w * t + 0.003 * w * integral)))
    >>> y = y + 0.01 * np.random.default_rng(0).standard_normal(t.size)
    >>> e = decay_dependence(y, fs, a, s, 50.0, 0.01)
    >>> round(e.frequency_change, 3), e.nonlinear, bool(e.frequency_change_std < 2e-4)
    (0.003, True, True)
    """
    y = np.asarray(y, float)
    short = y.size / fs * frequency_hz < MIN_PERIODS
    if short or not (decay_rate > 0 and frequency_hz > 0 and abs(amplitude) > 0):
        return None
    neighbours = [(b2, rate) for b2, rate in neighbours if rate > 0]
    # every m-th sample, at least _PER_PERIOD per period, at most about _SAMPLES of them: a parametric fit
    # in time needs no band limit (its start is within a fraction of the alias spacing), and the standard
    # errors say what the samples left out cost
    stride = max(1, min(int(fs / (_PER_PERIOD * frequency_hz)), -(-y.size // _SAMPLES)))
    t_end = (y.size - 1) / fs
    y = y[::stride]
    t = np.arange(y.size) * stride / fs
    a2 = abs(amplitude) ** 2
    integrals = np.array([_linear_integral(a2, decay_rate, t)]
                         + [_linear_integral(b2, rate, t) for b2, rate in neighbours])
    x = np.concatenate([[amplitude.real, amplitude.imag, decay_rate, 2 * np.pi * frequency_hz],
                        np.zeros(2 * len(integrals))])
    best = _gauss_newton(y, t, x, integrals, noise_std)
    if best is None:  # (the start itself gave no finite signal)
        return None
    x, residual, normal, scale = best
    if not (x[2] > 0 and x[3] > 0):
        return None
    variance = _variance_near(residual, fs / stride, frequency_hz, decay_rate, x.size)
    cov = scaled_covariance(normal, scale) * variance
    sigma0, omega0, omega2, sigma2 = x[2], x[3], x[4], x[5]
    largest, smallest = abs(amplitude), abs(amplitude) * np.exp(-decay_rate * t_end)
    # the changes over the decay: of the squared amplitudes (its own and each neighbour's) times their slopes
    spans = np.array([a2] + [b2 for b2, _ in neighbours]) * -np.expm1(
        -2 * np.array([decay_rate] + [rate for _, rate in neighbours]) * t_end)
    std = lambda i: float(np.sqrt(max(cov[i, i], 0.0)))  # noqa: E731
    misfit = float(np.sqrt(np.mean(residual**2))) / max(noise_std, 1e-300)
    start = None if neighbours else (complex(x[0], x[1]), float(a2), float(decay_rate))
    return AmplitudeDependence(*_change(x[4::2], cov[4::2, 4::2], spans, omega0),
                               *_change(x[5::2], cov[5::2, 5::2], spans, sigma0),
                               (float(largest), float(smallest)),
                               (float(omega0), float(omega2), float(sigma0), float(sigma2)),
                               (std(3), std(4), std(2), std(5)), misfit, start)


def _gauss_newton(y: np.ndarray, t: np.ndarray, x: np.ndarray, integrals: np.ndarray, noise_std: float):
    """:func:`decay_dependence`'s Gauss-Newton fit from ``x``: ``(x, residual, normal matrix, its scales)``
    at the last point that lowered the squared residual, or None (the start gave no finite signal; a
    singular normal matrix). A step that raises the residual (too long for the first order's reach: a
    chirp of several per cent) is halved from that point, :data:`_HALVINGS` times at most."""
    cost, best, step, halvings, iteration = np.inf, None, None, 0, 0
    while iteration < _ITERATIONS:
        slopes = x[4::2] * 1j - x[5::2]  # i omega_2 - sigma_2: of its own amplitude, then the neighbours'
        with np.errstate(over="ignore", invalid="ignore"):  # (a step too long: not finite, not taken)
            e = np.exp((-x[2] + 1j * x[3]) * t + slopes @ integrals)
            ce = (x[0] + 1j * x[1]) * e
            residual = y - ce.real
            new_cost = float(residual @ residual)
        if not np.isfinite(new_cost) or new_cost > cost * (1 - _TOLERANCE):
            if step is None or halvings >= _HALVINGS or new_cost <= cost:
                break  # (neither the last step nor its halves lowered the misfit: keep its start)
            # a step too long for the first order's reach (a chirp of several per cent): half of it
            step, halvings = step / 2, halvings + 1
            x = best[0] + step
            continue
        # the Jacobian of an accepted point only (a rejected step's is never read)
        jac = np.column_stack([e.real, -e.imag, -t * ce.real, -t * ce.imag]
                              + [c for i in integrals for c in (-i * ce.imag, -i * ce.real)])
        normal, scale, scaled = scaled_normal(jac, scaled=True)
        cost, best = new_cost, (x, residual, normal, scale)
        if iteration > 0 and np.sqrt(cost / y.size) > _HOPELESS * noise_std:
            break  # something else is in the decay: the misfit says so without converging
        iteration += 1
        try:
            step = np.linalg.solve(normal, scaled.T @ residual) / scale
        except np.linalg.LinAlgError:
            return None
        x, halvings = x + step, 0
    return best


def _variance_near(residual: np.ndarray, fs: float, frequency_hz: float, decay_rate: float,
                   n_parameters: int) -> float:
    """The residual's variance as the standard errors of a fit of one mode need it: its power near the
    mode's frequency (:data:`_NEAR_WIDTHS` half-power half-widths, at least :data:`_NEAR_BINS` bins either
    side), where the fit's Jacobian has its energy. For white noise it is the residual's variance; what the
    averaged equations leave of a decay they do not describe lies near the mode, where it moves the
    parameters as much as noise of its power would (its total variance averaged over every frequency would
    understate it)."""
    n = residual.size
    white = float(residual @ residual) / max(n - n_parameters, 1)
    power = np.abs(np.fft.rfft(residual)) ** 2 / n
    width = max(_NEAR_WIDTHS * decay_rate / (2 * np.pi), _NEAR_BINS * fs / n)
    near = np.abs(np.fft.rfftfreq(n, 1 / fs) - frequency_hz) <= width
    near[0] = near[-1] = False  # the ends left out (zero, and the Nyquist bin of an even length: real)
    if near.sum() < _NEAR_BINS:
        return white
    return float(np.mean(power[near])) * n / max(n - n_parameters, 1)


def _change(slopes: np.ndarray, cov: np.ndarray, spans: np.ndarray, value: float) -> tuple[float, float]:
    """The relative change of a frequency or decay rate ``value`` over a decay and its standard error: its
    ``slopes`` in the squared amplitudes (covariance ``cov``) times their changes ``spans``."""
    return float(slopes @ spans / value), float(np.sqrt(max(spans @ cov @ spans, 0.0))) / abs(value)


def _linear_integral(a2: float, rate: float, t: np.ndarray) -> np.ndarray:
    """``I(t)``, the integral from 0 to ``t`` of a linear decay's squared amplitude ``a2 exp(-2 rate t)``: the
    first-order amplitude term of the averaged equations (:func:`decay_dependence`); ``a2 t`` for a decay rate
    of zero (the limit).

    Examples
    --------
    >>> _linear_integral(2.0, 0.0, np.array([0.0, 1.5])).tolist()
    [0.0, 3.0]
    >>> bool(np.allclose(_linear_integral(2.0, 1e-9, np.array([1.5])), 3.0))
    True
    """
    if rate == 0:
        return a2 * np.asarray(t, float)
    return a2 * -np.expm1(-2 * rate * t) / (2 * rate)


#: A term of :func:`joint_dependence` (one mode's frequency and decay rate moved by one mode's squared
#: amplitude) is added where it lowers the squared residual by this many times the residual's variance:
#: the chi-square of its two slopes at about one chance in a million under white noise (a free decay of a
#: few modes offers tens of such terms).
JOINT_SCORE = 27.6
#: Gauss-Newton iterations of :func:`joint_dependence` per term added, at most, and halvings of a step
#: that does not lower the residual; it stops where a step lowers the squared residual by less than this
#: share of the residual's variance (its decisions are in units of that variance: :data:`JOINT_SCORE`).
_JOINT_ITERATIONS, _HALVINGS, _JOINT_TOLERANCE = 20, 4, 0.1
#: ... and per trial of a term (from the fit without it: enough to measure what the term lowers).
_TRIAL_ITERATIONS = 5


def joint_dependence(y: np.ndarray, fs: float, components: list, noise_std: float, stops: list,
                     drivers: list | None = None) -> list:
    """The averaged equations of several modes read together off their joint free decay ``y`` (every other
    component removed): each mode's frequency and decay rate moved by the squared amplitudes of the modes
    that the data show move it, its own included (a nonlinear element shared by several modes moves each
    one's frequency with the others' amplitudes as well as its own).

    ``components``: ``(complex amplitude, decay rate, damped frequency_hz)`` of each one's linear decay,
    where the fit starts; ``stops``: samples over which each is read (its decay's audible stretch);
    ``drivers``: ``(squared amplitude, decay rate, component or None)`` of the linear decays of the modes
    whose squared amplitudes may move them (a mode already removed from ``y`` may move those in it), by
    default the components'. The model is
    :func:`decay_dependence`'s,
    summed: ``y(t) = sum_k Re[c_k exp(-sigma_k t + i omega_k t + sum_j (i omega_kj - sigma_kj) I_j(t))]``
    with ``I_j`` the integral of mode ``j``'s linear decay's squared amplitude. The terms ``(k, j)`` enter
    one at a time, each the one whose slopes lower the residual most (their score: the chi-square of the
    step onto them, the fitted terms projected out), while the fit with it lowers the squared residual by
    :data:`JOINT_SCORE` times the residual's variance (the fit tried with the mode it moves refitted alone,
    the others held), the chosen terms then fitted together; every mode starts linear. Returns one
    :class:`AmplitudeDependence` per component (None for one not decaying): its changes
    over its stretch from every term that moves it, ``coefficients`` with its own slopes (zero where its
    own amplitude does not move it), ``drivers`` the other drivers that move it, ``misfit`` the joint
    residual's RMS over ``noise_std``. Returns ``[]`` where the fit fails.

    Examples
    --------
    Two modes, the second's frequency moved by the first's amplitude (0.5 % at the start) alone:

    >>> fs, t = 2000.0, np.arange(8000) / 2000.0
    >>> i1 = (1 - np.exp(-2 * 1.0 * t)) / 2.0
    >>> y = np.real(np.exp(-1.0 * t + 2j * np.pi * 40 * t)
    ...             + 0.5 * np.exp(-3.0 * t + 2j * np.pi * 90 * t * 1.0 + 1j * 0.005 * 2 * np.pi * 90 * i1))
    >>> y = y + 0.001 * np.random.default_rng(0).standard_normal(t.size)
    >>> first, second = joint_dependence(y, fs, [(1.0, 1.0, 40.0), (0.5, 3.0, 90.45)], 0.001, [8000, 8000])
    >>> second.drivers, round(second.coefficients[0] / (2 * np.pi), 2)
    ((0,), 90.0)
    """
    y = np.asarray(y, float)
    if y.ndim != 1 or not components or len(stops) != len(components):
        raise ValueError(f"joint_dependence needs a 1-D free decay and one stop per component; got y of "
                         f"shape {y.shape}, {len(components)} component(s) and {len(stops)} stop(s)")
    stride = _joint_stride(fs, components, y.size)
    if drivers is None:
        drivers = [(abs(components[j][0]) ** 2, components[j][1], j) for j in range(len(components))]
    drivers = [d for d in drivers if d[1] > 0]
    decay = _JointDecay(y[::stride], fs / stride, components, drivers)
    terms: list = []  # (k, j): mode k's frequency and decay rate moved by driver j's squared amplitude
    cost, best = decay.fit(decay.start, terms)
    if best is None:
        return []
    while True:  # the terms one at a time, while one lowers the residual by JOINT_SCORE variances
        variance = cost / max(decay.y.size - best[0].size, 1)
        untried = [(k, j) for k in range(len(components)) for j in range(len(drivers)) if (k, j) not in terms]
        if not untried:
            break
        scores = decay.scores(best, untried, variance)
        k, j = untried[int(np.argmax(scores))]
        if max(scores) < JOINT_SCORE:
            break
        longer = np.concatenate([best[0], [0.0, 0.0]])
        trial_terms = terms + [(k, j)]
        trial_cost, trial = decay.fit(longer, trial_terms, _TRIAL_ITERATIONS, free=k)
        own = next((i for i, d in enumerate(drivers) if d[2] == k), None)
        if own is not None and own != j and (k, own) not in terms:
            # another mode's amplitude whose decay its own follows closely: where the data cannot tell
            # them apart, its own amplitude is the simpler explanation of its chirp
            own_cost, own_fit = decay.fit(longer, terms + [(k, own)], _TRIAL_ITERATIONS, free=k)
            if own_fit is not None and own_cost <= trial_cost + JOINT_SCORE * variance:
                trial_terms, trial_cost, trial = terms + [(k, own)], own_cost, own_fit
        if trial is None or (cost - trial_cost) < JOINT_SCORE * variance:
            break
        terms, cost, best = trial_terms, trial_cost, trial
    if terms:  # the terms chosen, fitted to convergence
        cost, polished = decay.fit(best[0], terms)
        best = polished or best
    x, residual, normal, scale = best[:4]
    cov = scaled_covariance(normal, scale)
    misfit = float(np.sqrt(np.mean(residual**2))) / max(noise_std, 1e-300)
    return [_joint_reading(k, x, cov, residual, decay.fs, terms, drivers, stops[k] / fs, misfit)
            for k in range(len(components))]


#: A stride of :func:`joint_dependence` keeps the folded frequencies of its components (and their images at
#: zero and the folded Nyquist frequency) this many times their half-power half-widths, plus two bins, apart
#: (or as far apart as they are).
_ALIAS_GAP = 10.0


def _joint_stride(fs: float, components: list, n: int) -> int:
    """Every m-th sample for :func:`joint_dependence`: about :data:`_SAMPLES` per component in all, the
    largest stride at which folding brings no two components (nor one and its own image) closer (a
    parametric fit in time needs no band limit, only frequencies the samples tell apart)."""
    frequencies = np.array([f for _, _, f in components], float)
    widths = np.array([rate for _, rate, _ in components], float) / (2 * np.pi)
    for stride in range(max(1, -(-n // (_SAMPLES * len(components)))), 1, -1):
        rate = fs / stride
        folded = np.abs((frequencies + rate / 2) % rate - rate / 2)
        gap = _ALIAS_GAP * np.abs(widths) + 2 * rate / (n / stride)
        distance = np.abs(folded[:, None] - folded[None, :])
        true = np.abs(frequencies[:, None] - frequencies[None, :])
        apart = (distance >= gap[:, None] + gap[None, :]) | (distance >= true * (1 - 1e-9))
        images = np.minimum(folded, rate / 2 - folded) >= np.minimum(gap, frequencies * (1 - 1e-9))
        if apart.all() and images.all():
            return stride
    return 1


class _JointDecay:
    """The free decay of :func:`joint_dependence`'s model: ``x`` holds per component ``(Re c, Im c, sigma,
    omega)``, then per term ``(omega_kj, sigma_kj)``."""

    def __init__(self, y, fs, components, drivers):
        self.y, self.fs, self.n = y, fs, len(components)
        self.t = np.arange(y.size) / fs
        self.integrals = [_linear_integral(a2, rate, self.t) for a2, rate, _ in drivers]
        self.start = np.concatenate([[complex(a).real, complex(a).imag, rate, 2 * np.pi * f]
                                     for a, rate, f in components])

    def signals(self, x, terms, held: np.ndarray | None = None, free: int | None = None) -> np.ndarray:
        """Each component's complex signal ``c_k exp(...)``; with ``held`` (these signals at parameters that
        differ from ``x`` in component ``free``'s and its terms' alone) only that component's is computed,
        the others taken from ``held`` (the same numbers: each row depends on its own parameters only)."""
        rows = range(self.n) if held is None else [free]
        exponents = np.outer(-x[2:4 * self.n:4][rows] + 1j * x[3:4 * self.n:4][rows], self.t)
        for i, (k, j) in enumerate(terms):
            if k in rows:
                slope = x[4 * self.n + 2 * i]
                exponents[rows.index(k)] += (-x[4 * self.n + 2 * i + 1] + 1j * slope) * self.integrals[j]
        with np.errstate(over="ignore", invalid="ignore"):
            ce = (x[0:4 * self.n:4][rows] + 1j * x[1:4 * self.n:4][rows])[:, None] * np.exp(exponents)
        if held is None:
            return ce
        out = held.copy()
        out[free] = ce[0]
        return out

    def fit(self, x, terms, iterations: int = _JOINT_ITERATIONS, free: int | None = None) -> tuple:
        """Gauss-Newton from ``x``: ``iterations`` steps at most (the halvings of a step that does not lower
        the residual not counted), of every parameter or, with ``free``, of that component's and its terms'
        alone (the others held: components apart in frequency barely share their residual's directions):
        ``(squared residual, (x, residual, normal matrix, its scales, scaled Jacobian, signals))``, the
        normal matrix and Jacobian of every parameter; or ``(inf, None)``."""
        index = None if free is None else self.parameters_of(free, terms)
        cost, best, step, steps, held = np.inf, None, None, 0, None
        for _ in range(iterations * _HALVINGS):
            ce = self.signals(x, terms, held, free)
            if index is not None:  # (the held components' signals stay: only the free one's is computed)
                held = ce
            with np.errstate(over="ignore", invalid="ignore"):  # (a step too long: not finite, halved)
                residual = self.y - ce.real.sum(axis=0)
                new_cost = float(residual @ residual)
            if not np.isfinite(new_cost) or new_cost > cost * (1 - _TOLERANCE):
                if step is None or np.max(np.abs(step)) < 1e-12 * np.max(np.abs(best[0])):
                    break
                step = step / 2  # (a step too long for the exponent: halved from the last point)
                x = best[0] + step
                continue
            normal, scale, scaled = scaled_normal(self.jacobian(x, ce, terms, index), scaled=True)
            settled = cost - new_cost < _JOINT_TOLERANCE * new_cost / self.y.size
            cost, best = new_cost, (x, residual, normal, scale, scaled, ce)
            if settled or steps == iterations:  # (settled: a step worth less than a tenth of one
                break                           # sample's residual decides nothing)
            steps += 1
            try:
                solved = np.linalg.solve(normal, scaled.T @ residual) / scale
            except np.linalg.LinAlgError:
                break
            step = np.zeros(x.size)  # (the held parameters do not move)
            step[slice(None) if index is None else index] = solved
            x = x + step
        if best is not None and index is not None:  # every parameter's normal matrix at the point reached
            x, residual, ce = best[0], best[1], best[5]
            best = (x, residual, *scaled_normal(self.jacobian(x, ce, terms), scaled=True), ce)
        return cost, best

    def parameters_of(self, k: int, terms) -> np.ndarray:
        """The indices in ``x`` of component ``k``'s parameters and of its terms' slopes."""
        own = [4 * self.n + 2 * i + d for i, (m, _) in enumerate(terms) if m == k for d in (0, 1)]
        return np.array([4 * k, 4 * k + 1, 4 * k + 2, 4 * k + 3] + own)

    def jacobian(self, x, ce, terms, index=None) -> np.ndarray:
        """The Jacobian's columns of every parameter, or of those at ``index`` (:meth:`parameters_of`)."""
        amplitudes = x[0:4 * self.n:4] + 1j * x[1:4 * self.n:4]
        z = ce / np.where(amplitudes == 0, 1, amplitudes)[:, None]
        wanted = None if index is None else set(index.tolist())
        columns = []
        for k in range(self.n):
            if wanted is None or 4 * k in wanted:
                columns += [z[k].real, -z[k].imag, -self.t * ce[k].real, -self.t * ce[k].imag]
        for i, (k, j) in enumerate(terms):
            if wanted is None or 4 * self.n + 2 * i in wanted:
                columns += self.term_columns(ce, k, j)
        return np.column_stack(columns)

    def term_columns(self, ce, k: int, j: int) -> list:
        return [-self.integrals[j] * ce[k].imag, -self.integrals[j] * ce[k].real]

    def scores(self, best, untried, variance) -> list:
        """Each untried term's chi-square: the squared residual a Gauss-Newton step onto its slopes alone
        removes, the fitted parameters' directions projected out, over the residual's variance."""
        residual, normal, scaled, ce = best[1], best[2], best[4], best[5]
        inverse = np.linalg.pinv(normal)  # (the projection onto the fitted columns through their normal
        scores = []                       # matrix: two columns at a time, not a factorisation of all)
        for k, j in untried:
            new = np.column_stack(self.term_columns(ce, k, j))
            new = new - scaled @ (inverse @ (scaled.T @ new))
            g = new.T @ residual
            scores.append(float(g @ np.linalg.pinv(new.T @ new) @ g) / variance)
        return scores


def _joint_reading(k: int, x, cov, residual, fs: float, terms: list, drivers: list, t_end: float,
                   misfit: float) -> AmplitudeDependence | None:
    """Component ``k``'s :class:`AmplitudeDependence` from :func:`joint_dependence`'s fit (``cov`` its
    unscaled covariance, times the residual's power near the mode), read over its stretch of ``t_end``
    seconds; None where it does not decay."""
    n = (x.size - 2 * len(terms)) // 4
    sigma0, omega0 = x[4 * k + 2], x[4 * k + 3]
    if not (sigma0 > 0 and omega0 > 0):
        return None
    cov = cov * _variance_near(residual, fs, omega0 / (2 * np.pi), sigma0, x.size)
    std = lambda i: float(np.sqrt(max(cov[i, i], 0.0)))  # noqa: E731
    mine = [i for i, (m, _) in enumerate(terms) if m == k]
    own = [i for i in mine if drivers[terms[i][1]][2] == k]
    w_idx, s_idx = [4 * n + 2 * i for i in mine], [4 * n + 2 * i + 1 for i in mine]
    a2 = np.array([drivers[terms[i][1]][0] for i in mine])
    fall = np.exp(-2 * np.array([drivers[terms[i][1]][1] for i in mine]) * t_end)
    spans = a2 * (1 - fall)  # each squared amplitude's change over the stretch; a2 * fall: left at its end
    frequency, decay, beyond = (0.0, 0.0), (0.0, 0.0), 0.0
    if mine:
        frequency = _change(x[w_idx], cov[np.ix_(w_idx, w_idx)], spans, omega0)
        decay = _change(x[s_idx], cov[np.ix_(s_idx, s_idx)], spans, sigma0)
        beyond = abs(float(x[w_idx] @ (a2 * fall))) / max(abs(frequency[0] * omega0), 1e-300)
    slopes = (x[w_idx[mine.index(own[0])]], x[s_idx[mine.index(own[0])]]) if own else (0.0, 0.0)
    slopes_std = (std(w_idx[mine.index(own[0])]), std(s_idx[mine.index(own[0])])) if own else (0.0, 0.0)
    largest = float(np.hypot(x[4 * k], x[4 * k + 1]))
    return AmplitudeDependence(*frequency, *decay, (largest, largest * float(np.exp(-sigma0 * t_end))),
                               (float(omega0), float(slopes[0]), float(sigma0), float(slopes[1])),
                               (std(4 * k + 3), slopes_std[0], std(4 * k + 2), slopes_std[1]), misfit,
                               drivers=tuple(terms[i][1] for i in mine if i not in own), beyond=float(beyond))

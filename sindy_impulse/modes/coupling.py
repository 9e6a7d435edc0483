"""The modes of a record read together where one nonlinear element couples them (the survey's ``coupling``
stage).

One cubic spring or amplitude-dependent damper at one place of a structure moves every mode through every
mode's amplitude. Averaged over a period, it moves mode ``k``'s squared frequency by ``C_km a_m^2`` and its
decay rate by ``D_km a_m^2`` (``a_m``: mode ``m``'s measured amplitude, wherever the sensor is), with

    ``C_km = (2 - delta_km) G_k E_m``,   ``D_km = (2 - delta_km) H_k E_m``:

the element's share of mode ``k`` (``G_k`` for its stiffness, ``H_k`` for its damping) times its share of
mode ``m`` (``E_m``, one for both), the other modes' amplitudes weighing twice their own. A mode's own
reading (its band, its equation) sees only its own amplitude: where a strongly damped mode rings beside
lightly damped ones, their amplitudes hardly change while it dies, and move its frequency or decay rate by
a constant offset that its own decay cannot tell from its linear values. Read together under this
structure, ``3 n`` parameters beyond the linear ones, the offset follows from what the record shows over
long stretches: each mode's own chirp, its neighbours', and their transients as the short-lived mode dies.

:func:`one_element_reading` fits that model to a free decay; :func:`read_coupling` is the stage: in a
record with a nonlinear candidate, or one that moves with its amplitude however little
(:func:`~.classify.moves_with_amplitude`), among 2 to :data:`~.classify.MAX_TOGETHER` decaying ones, it
reads them together and, where the reading describes the decay (its residual at most
:data:`~._envelope.ENVELOPE_MISFIT` times the noise, every mode decaying) and leaves nothing but noise in
any mode's band (:func:`band_consistency`, at :data:`NOISE_LEVEL` for the bands together), it reports a
mode's small-amplitude frequency and damping ratio from it where they differ from the mode's own beyond
:data:`COUPLING_SIGMAS` of the reading's standard deviations or are known better than the mode's own
(:func:`takes_reading`; ``source`` ``"coupling"``), unless the reading couples it the other way than
one element can (:func:`_against_element`). Where the reading describes the decay but is not taken, each
mode keeps its own values and its ± takes in the difference from the reading (:func:`_doubted`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.integrate import cumulative_trapezoid
from scipy.special import gammaincc

from .._utils.scaled import scaled_covariance, scaled_normal
from .._utils.validation import check_signal
from ..preprocessing._record import check_fs
from ._envelope import ENVELOPE_MISFIT, _joint_stride, _linear_integral
from .classify import MAX_TOGETHER, _audible, moves_with_amplitude
from .kinds import Kind
from .signals import deflated

__all__ = ["COUPLING_SIGMAS", "CouplingReading", "NOISE_LEVEL", "band_consistency", "one_element_reading",
           "read_coupling", "takes_reading"]

#: A mode's frequency or damping ratio is taken from the coupling reading where the reading moves it by
#: more than this many of its standard deviations from the mode's own value.
COUPLING_SIGMAS = 3.0
#: The reading is believed where the residual in every mode's band is noise: the chance that noise leaves
#: as much power in at least one of the bands is at least this (each band tested at this level over the
#: number of bands).
NOISE_LEVEL = 0.01
#: Rounds of :func:`one_element_reading` at most: each fits the model with the amplitudes it integrates held,
#: then takes them from that fit (the model's own decays, which an amplitude-dependent damper or a strong
#: coupling bends away from the components' linear ones); it stops where a round lowers the squared
#: residual by less than a tenth of one sample's share of it.
ROUNDS = 6
#: Gauss-Newton steps of :func:`one_element_reading` at most (a step that does not lower the residual is
#: halved, up to 4 times each); it stops where a step lowers the squared residual by less than a tenth of
#: one sample's share of it.
ITERATIONS = 40
#: The band of a mode in :func:`band_consistency`: this many half-power half-widths either side of its
#: frequency, at least this many bins.
BAND_WIDTHS, BAND_BINS = 3.0, 3


@dataclass(frozen=True)
class CouplingReading:
    """What :func:`one_element_reading` reads: per component its small-amplitude ``frequency_hz`` and
    ``damping_ratio`` (arrays) with their standard deviations, the shares ``stiffness`` (``G``),
    ``damping`` (``H``) and ``element`` (``E``), the ``residual`` at the sampling rate ``fs`` it was read
    at, and its RMS."""

    frequency_hz: np.ndarray
    damping_ratio: np.ndarray
    frequency_std_hz: np.ndarray
    damping_ratio_std: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    element: np.ndarray
    residual: np.ndarray
    fs: float
    stiffness_std: np.ndarray | None = None
    element_std: np.ndarray | None = None

    @property
    def rms(self) -> float:
        """The residual's RMS."""
        return float(np.sqrt(np.mean(self.residual**2)))


def _model(x: np.ndarray, t: np.ndarray, integrals: np.ndarray, n: int) -> np.ndarray:
    """Each component's complex signal: ``c_k exp(-sigma_k t + i omega_k t + sum_m (2 - delta_km)
    (i G_k - H_k) E_m I_m(t))``."""
    amplitudes = x[0:4 * n:4] + 1j * x[1:4 * n:4]
    pull, drive = 1j * x[4 * n:5 * n] - x[5 * n:6 * n], x[6 * n:]
    coupling = ((2.0 - np.eye(n)) * pull[:, None] * drive) @ integrals
    exponents = np.outer(-x[2:4 * n:4] + 1j * x[3:4 * n:4], t) + coupling
    with np.errstate(over="ignore", invalid="ignore"):  # (a step too long: not finite, halved)
        return amplitudes[:, None] * np.exp(exponents)


def _jacobian(x: np.ndarray, ce: np.ndarray, t: np.ndarray, integrals: np.ndarray, n: int) -> np.ndarray:
    """The derivatives of the summed real signal by ``x``: per component ``(Re c, Im c, sigma, omega)``,
    then ``G``, ``H`` and ``E``."""
    amplitudes = x[0:4 * n:4] + 1j * x[1:4 * n:4]
    z = ce / np.where(amplitudes == 0, 1, amplitudes)[:, None]
    weight = 2.0 - np.eye(n)
    pull, drive = 1j * x[4 * n:5 * n] - x[5 * n:6 * n], x[6 * n:]
    moved = (weight * drive) @ integrals  # d exponent_k / d pull_k
    columns = []
    for k in range(n):
        columns += [z[k].real, -z[k].imag, -t * ce[k].real, -t * ce[k].imag]
    columns += [(1j * moved[k] * ce[k]).real for k in range(n)]
    columns += [(-moved[k] * ce[k]).real for k in range(n)]
    by_element = (weight * pull[:, None]).T  # [m, k]: d exponent_k / d E_m over I_m
    columns += [(by_element[m] @ ce * integrals[m]).real for m in range(n)]
    return np.column_stack(columns)


def _gauss_newton(x: np.ndarray, y: np.ndarray, t: np.ndarray, integrals: np.ndarray, n: int):
    """``(x, squared residual, residual, components' complex signals)`` of the Gauss-Newton fit of
    :func:`_model` to ``y`` from ``x`` with the ``integrals`` held (:data:`ITERATIONS` steps at most; a step
    that does not lower the residual is halved); the cost is infinite where ``x`` gives no finite signal."""
    cost, best, step = np.inf, (x, None, None), None
    for _ in range(4 * ITERATIONS):
        ce = _model(x, t, integrals, n)
        with np.errstate(over="ignore", invalid="ignore"):
            residual = y - ce.real.sum(axis=0)
            new = float(residual @ residual)
        if not np.isfinite(new) or new > cost:
            if step is None:
                break
            step = step / 2
            x = best[0] + step
            continue
        settled = cost - new < 0.1 * new / y.size
        cost, best = new, (x, residual, ce)
        if settled:
            break
        normal, scale, scaled = scaled_normal(_jacobian(x, ce, t, integrals, n), scaled=True)
        step = np.linalg.lstsq(normal, scaled.T @ residual, rcond=1e-10)[0] / scale  # (G E: one scale free)
        x = x + step
    return best[0], cost, best[1], best[2]


def _own_integrals(ce: np.ndarray, fs: float) -> np.ndarray:
    """Per component, the running integral (trapezoids at ``fs``) of its squared amplitude ``|ce|^2``."""
    return cumulative_trapezoid(np.abs(ce) ** 2, dx=1 / fs, axis=1, initial=0)


def one_element_reading(y: np.ndarray, fs: float, components: list) -> CouplingReading:
    """The small-amplitude values of the modes of a free decay ``y`` coupled through one nonlinear element.

    Fits ``y(t) = sum_k Re[c_k exp(-sigma_k t + i omega_k t + sum_m (2 - delta_km) (i G_k - H_k) E_m
    I_m(t))]`` (``I_m``: the integral of mode ``m``'s squared amplitude) by Gauss-Newton from the
    components' linear decays (``G = H = 0``, ``E = 1``, ``I_m`` theirs), on every ``m``-th sample where
    folding keeps the components apart (:func:`~._envelope._joint_stride`). The amplitudes integrated are
    then the fit's own, and it is fitted again, for up to :data:`ROUNDS` rounds: an amplitude-dependent
    damper, or a coupling that holds a mode's decay back while another rings, bends the amplitudes away
    from the linear decays, and a model integrating the linear ones misreads the lightly damped modes'
    small-amplitude frequencies by tens of their standard deviations to make up for it. ``components``:
    ``(complex amplitude, decay rate, damped frequency_hz)`` of each one's linear decay. The standard
    deviations are the fit's (residual's variance times the pseudo-inverse of the normal matrix, the
    amplitudes integrated held: ``G E`` keeps one scale free).

    Examples
    --------
    Two modes, a cubic element moving the second's frequency by the first's amplitude twice as much as by
    its own:

    >>> fs, t = 2000.0, np.arange(8000) / 2000.0
    >>> i1, i2 = (1 - np.exp(-2 * 1.0 * t)) / 2.0, 0.25 * (1 - np.exp(-2 * 6.0 * t)) / 12.0
    >>> w1, w2 = 2 * np.pi * 40, 2 * np.pi * 90
    >>> g, e = np.array([0.02, 0.03]), np.array([1.0, 1.0])  # d omega_k = g_k (e_k I_k + 2 e_m I_m)
    >>> y = np.real(np.exp(-1.0 * t + 1j * w1 * t + 1j * w1 * g[0] * (i1 + 2 * i2))
    ...             + 0.5 * np.exp(-6.0 * t + 1j * w2 * t + 1j * w2 * g[1] * (2 * i1 + i2)))
    >>> y = y + 0.001 * np.random.default_rng(0).standard_normal(t.size)
    >>> reading = one_element_reading(y, fs, [(1.0, 1.0, 40.3), (0.5, 6.0, 91.0)])
    >>> np.round(reading.frequency_hz, 1)
    array([40., 90.])
    """
    y, fs = check_signal(y, "y", ndim=(1,), as_2d=False), check_fs(fs)
    if len(components) < 1:
        raise ValueError("one_element_reading needs at least one component, got none")
    stride = _joint_stride(fs, components, y.size)
    y, fs = y[::stride], fs / stride
    t = np.arange(y.size) / fs
    n = len(components)
    integrals = np.array([_linear_integral(abs(complex(c)) ** 2, rate, t) for c, rate, _ in components])
    x = np.concatenate([np.concatenate([[complex(c).real, complex(c).imag, rate, 2 * np.pi * f]
                                        for c, rate, f in components]), np.zeros(2 * n), np.ones(n)])
    best = None
    for _ in range(ROUNDS):  # the amplitudes the coupling integrates: the model's own, until they settle
        fit = (*_gauss_newton(x, y, t, integrals, n), integrals)
        if not np.isfinite(fit[1]) or (best is not None and fit[1] > best[1]):
            break
        settled = best is not None and best[1] - fit[1] < 0.1 * fit[1] / y.size
        best = fit
        if settled:
            break
        x, integrals = fit[0], _own_integrals(fit[3], fs)
    if best is None:
        raise ValueError("one_element_reading: the components' linear decays give no finite signal")
    x, cost, residual, ce, integrals = best
    normal, scale = scaled_normal(_jacobian(x, ce, t, integrals, n))
    cov = scaled_covariance(normal, scale) * (cost / max(y.size - x.size, 1))
    sd = np.sqrt(np.abs(np.diag(cov)))
    sigma, omega = x[2:4 * n:4], x[3:4 * n:4]
    wn = np.hypot(omega, sigma)
    return CouplingReading(wn / (2 * np.pi), sigma / wn, sd[3:4 * n:4] / (2 * np.pi), sd[2:4 * n:4] / wn,
                           x[4 * n:5 * n], x[5 * n:6 * n], x[6 * n:], residual, float(fs), sd[4 * n:5 * n],
                           sd[6 * n:])


def band_consistency(residual: np.ndarray, fs: float, components: list) -> np.ndarray:
    """Per component, the chance that white noise leaves as much power in its band of ``residual`` (sampled
    at ``fs``): the band :data:`BAND_WIDTHS` half-power half-widths either side of its frequency folded into
    the residual's range, at least :data:`BAND_BINS` bins; the noise's power per bin the median bin's over
    ``ln 2`` (a periodogram's bins of white noise are exponential; the bands are a small part of them). The
    band's summed power is then a Gamma variable of as many degrees as bins.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> t = np.arange(4000) / 1000.0
    >>> noise = rng.standard_normal(4000)
    >>> left = noise + 0.5 * np.cos(2 * np.pi * 120 * t)  # a component the reading did not describe
    >>> [bool(p > 0.01) for p in band_consistency(noise, 1000.0, [(1, 2.0, 120.0)])]
    [True]
    >>> [bool(p > 0.01) for p in band_consistency(left, 1000.0, [(1, 2.0, 120.0)])]
    [False]
    """
    bins, power = band_power(residual, fs, components)
    return np.array([float(gammaincc(b, p)) for b, p in zip(bins, power)])  # Gamma(bins, 1) beyond the sum


def band_power(residual: np.ndarray, fs: float, components: list,
               noise: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Per component, the number of bins of its band of ``residual`` (see :func:`band_consistency`) and the
    power there in units of the noise's power per bin: ``noise`` where given, else the median bin's over
    ``ln 2``."""
    residual = check_signal(residual, "residual", ndim=(1,), min_samples=2 * BAND_BINS, as_2d=False)
    fs = check_fs(fs)
    if noise is not None and not (np.isfinite(noise) and noise > 0):
        raise ValueError(f"band_power: noise must be a positive power per bin, got {noise}")
    power = np.abs(np.fft.rfft(residual)) ** 2
    power = power / (np.median(power) / np.log(2) if noise is None else noise)
    frequencies = np.fft.rfftfreq(residual.size, 1 / fs)
    bins, out = [], []
    for _, rate, f in components:
        folded = abs((f + fs / 2) % fs - fs / 2)
        half = max(BAND_WIDTHS * rate / (2 * np.pi), BAND_BINS * fs / residual.size)
        band = np.abs(frequencies - folded) <= half
        bins.append(int(band.sum()))
        out.append(float(power[band].sum()))
    return np.array(bins), np.array(out)


def read_coupling(state) -> None:
    """The modes' values read together where one nonlinear element couples them.

    In a record with a nonlinear candidate, or one whose frequency moves with its amplitude beyond doubt but
    under a modal table's reading (:func:`~.classify.moves_with_amplitude`: the element that moves it a
    little may move a mode it shares more with a lot), among 2 to :data:`~.classify.MAX_TOGETHER` decaying
    ones (linear or nonlinear), their joint free decay (every other component removed, up to where the
    longest-lived falls into the noise) is read by :func:`one_element_reading`. A mode takes the reading's
    small-amplitude frequency and damping ratio, with their standard deviations (``source``
    ``"coupling"``), where either differs from its own by more than :data:`COUPLING_SIGMAS` of the
    reading's standard deviations or the reading knows both better (:func:`takes_reading`), provided the
    reading describes the decay: its residual's RMS at most :data:`~._envelope.ENVELOPE_MISFIT` times the
    candidates' noise, every mode decaying within its band (:func:`_lost_mode`: a reading that lets a mode
    grow, or sends it elsewhere, has traded the record's physics for its noise), and no mode's band
    holding more than noise (:func:`band_consistency` at :data:`NOISE_LEVEL` for the bands together).
    Otherwise the modes' own values stand, their ± widened by the reading where it describes the
    decay (:func:`_doubted`); the trace says which.
    """
    cands = state.candidates
    read = [k for k, c in enumerate(cands) if c.kind in (Kind.NONLINEAR, Kind.LINEAR) and c.decay_rate > 0]
    if not any(cands[k].kind is Kind.NONLINEAR or moves_with_amplitude(cands[k]) for k in read):
        state.decide("no candidate moves with its amplitude: nothing to read together")
        return
    if not 2 <= len(read) <= MAX_TOGETHER:
        state.decide(f"{len(read)} decaying candidate(s), not 2-{MAX_TOGETHER}: the modes' own values stand")
        return
    components = [(complex(cands[k].amplitude[0]), cands[k].decay_rate, cands[k].damped_frequency_hz)
                  for k in read]
    try:  # a refinement: where it fails, the modes' own readings are the survey's answer
        n = state.pre.y.size - state.start
        stop = max(min(_audible(cands[k], state.pre.fs) or n, n) for k in read)
        y = deflated(state, read[0], keep=read[1:])[state.start:][:stop]
        reading = one_element_reading(y, state.pre.fs, components)
    except Exception as err:  # noqa: BLE001 - the modes' own values stand; the trace says why
        state.decide(f"the coupling reading failed ({type(err).__name__}: {err}): the modes' own values "
                     "stand")
        return
    misfit = reading.rms / min(cands[k].noise_std for k in read)
    if not misfit <= ENVELOPE_MISFIT:
        state.decide(f"the coupling reading does not describe the decay (residual {misfit:.3g} times the "
                     "noise): the modes' own values stand")
        return
    lost = _lost_mode(cands, read, reading)
    if lost:
        state.decide(f"the coupling reading {lost}: the modes' own values stand")
        return
    against = _against_element(reading)
    chance = band_consistency(reading.residual, reading.fs, components)
    failing = chance < NOISE_LEVEL / len(read)
    where = cands[read[int(np.argmin(chance))]].frequency_hz
    modes = sum(k in state.origin for k in read)
    if failing.any() and modes < 2:  # a mode and what is not one (a harmonic its backbone named): no coupling
        doubted = _doubted(state, read, reading, against, clean_bands=False)
        state.decide(f"the coupling reading leaves more than noise in the band at {where:.5g} Hz (chance "
                     f"{chance.min():.2g}), and reads {modes} mode(s) only: the modes' own values "
                     f"stand{doubted}")
        return
    if failing.any():
        explained = _explains(y, state.pre.fs, components, reading, failing)
        taken = _take(state, read, reading, against, widened=True, only=None if explained else ~failing)
        doubted = _doubted(state, read, reading, against, clean_bands=False)
        why = (f"but at most {EXPLAINED_SHARE:.0%} of what the modes' linear decays leave there" if explained
               else "where its own band is noise")
        state.decide(f"the coupling reading leaves more than noise in the band at {where:.5g} Hz (chance "
                     f"{chance.min():.2g}); values taken from the reading {why}, their ± widened by the "
                     f"modes' own: {', '.join(taken) if taken else 'none'}{doubted}")
        return
    taken = _take(state, read, reading, against)
    doubted = _doubted(state, read, reading, against, clean_bands=True)
    state.decide(f"{len(read)} modes read together (residual {misfit:.2g} times the noise); values taken "
                 f"from the reading: {', '.join(taken) if taken else 'none'}{doubted}")


#: Where the coupling reading leaves more than noise in a band, it is still the record's better reading
#: where it leaves at most this share of what the components' linear decays leave there.
EXPLAINED_SHARE = 0.1


def _explains(y: np.ndarray, fs: float, components: list, reading: CouplingReading, failing) -> bool:
    """Whether the ``reading`` of the free decay ``y`` (at ``fs``), where it leaves more than noise in the
    bands ``failing`` (a mask over ``components``), leaves there at most :data:`EXPLAINED_SHARE` of the
    power (over the noise's) that the components' own linear decays leave: of two readings of one decay
    that both miss something, the one that misses an order of magnitude less is the one to report."""
    stride = max(1, int(round(fs / reading.fs)))  # the reading's samples
    y = y[::stride][: reading.residual.size]
    t = np.arange(y.size) / reading.fs
    linear = y - sum((complex(c) * np.exp((-rate + 2j * np.pi * f) * t)).real for c, rate, f in components)
    _, left = band_power(reading.residual, reading.fs, components)
    noise = np.median(np.abs(np.fft.rfft(reading.residual)) ** 2) / np.log(2)
    _, own = band_power(linear, reading.fs, components, noise=noise)
    failing = np.asarray(failing, bool)
    return bool(np.all(left[failing] <= EXPLAINED_SHARE * own[failing]))


def _take(state, read: list, reading: CouplingReading, against: set, widened: bool = False,
          only=None) -> list:
    """The modes of the candidates ``read`` (the reading's, in its order; ``only``: a mask over them) that
    take the ``reading``'s values (:func:`takes_reading`), with its standard deviations; ``widened``: where
    the reading leaves more than noise in a band, the difference from the mode's own values added to them
    in quadrature (what the reading misses may move its values as far); never the modes at the positions
    ``against`` (:func:`_against_element`). Returns their frequencies' words for the trace."""
    taken = []
    for i, (j, mode, (f, z, f_std, z_std)) in _modes_read(state, read, reading, positions=True):
        if (only is not None and not only[i]) or i in against or not takes_reading(mode, f, z, f_std, z_std):
            continue
        if widened:
            f_std = float(np.hypot(f_std, f - mode.frequency_hz))
            z_std = float(np.hypot(z_std, z - mode.damping_ratio))
        note = (f"its frequency and damping ratio are read with the other modes' coupling through one "
                f"nonlinear element (its own reading, from its {mode.source}: {mode.frequency_hz:.6g} Hz, "
                f"{mode.damping_ratio:.4g}; its equation is that reading's)")
        note = f"{mode.uncertainty_note}; {note}" if mode.uncertainty_note else note
        state.modes[j] = replace(mode, frequency_hz=f, damping_ratio=z, frequency_std_hz=f_std,
                                 damping_ratio_std=z_std, source="coupling", uncertainty_note=note)
        taken.append(f"{f:.5g} Hz")
    return taken


def _against_element(reading: CouplingReading) -> set:
    """Positions (in the reading's order) of the modes that the ``reading`` couples the other way than one
    element can: both their stiffness share ``G`` and their share of the element ``E`` of the other sign
    than the shares it knows most surely (:func:`_other_sign`). One element moves mode ``k`` by mode
    ``m``'s amplitude as ``C_km = (2 - delta_km) G_k E_m``, every term of one sign; with both shares
    flipped, mode ``k`` is moved by every other mode, and moves them, the other way (a strongly damped
    476.3 Hz mode beside a softening spring, ``G`` 115 beside -22 and -20, ``E`` -0.53 beside 1.11 and
    0.74, read 470.95 +- 1.6 Hz, 1.1 % below its own and the true value). One share of the other sign alone
    is not enough: a strongly damped mode's ``E`` (its own amplitude, soon gone) is free to take up what the
    model misses while its reading is right, and a damper's stiffness shares are small and of either sign.

    Examples
    --------
    >>> from types import SimpleNamespace as Reading
    >>> reading = Reading(stiffness=np.array([-21.8, -20.0, 115.3]), stiffness_std=np.array([0.5, 0.8, 20.0]),
    ...                   element=np.array([1.11, 0.74, -0.53]), element_std=np.array([0.01, 0.02, 0.1]))
    >>> _against_element(reading)
    {2}
    >>> reading.element = np.array([1.11, 0.74, 0.53])  # its share of the element has their sign
    >>> _against_element(reading)
    set()
    """
    return _other_sign(reading.stiffness, reading.stiffness_std) & _other_sign(reading.element,
                                                                                reading.element_std)


def _other_sign(share, share_std) -> set:
    """Positions of the shares of the other sign than the one known most surely (each beyond
    :data:`COUPLING_SIGMAS` of its standard deviation; none where the standard deviations are None)."""
    if share_std is None:
        return set()
    share, share_std = np.asarray(share, float), np.asarray(share_std, float)
    sure = np.isfinite(share) & np.isfinite(share_std) & (np.abs(share) > COUPLING_SIGMAS * share_std)
    if not sure.any():
        return set()
    surest = np.flatnonzero(sure)[np.argmax(np.abs(share[sure]) / np.maximum(share_std[sure], 1e-300))]
    return {int(i) for i in np.flatnonzero(sure & (share * share[surest] < 0))}


def _lost_mode(cands, read: list, reading: CouplingReading) -> str | None:
    """Why the ``reading`` has lost one of the modes of ``read`` (the reading's, in its order), or ``None``:
    a damping ratio at or below zero (a reading that lets a mode grow has traded the record's physics for
    its noise), or a damped frequency out of the candidate's band (:func:`_astray`)."""
    growing = [f for f, z in zip(reading.frequency_hz, reading.damping_ratio) if not z > 0]
    if growing:
        return f"gives the mode at {growing[0]:.5g} Hz no free decay (a damping ratio at or below zero)"
    astray = _astray(cands, read, reading)
    if astray:
        k, f = astray[0]
        return f"moves the mode at {cands[k].frequency_hz:.5g} Hz out of its band (to {f:.5g} Hz)"
    return None


def _astray(cands, read: list, reading: CouplingReading) -> list:
    """``(candidate, damped frequency_hz)`` of each candidate of ``read`` (the reading's, in its order) whose
    damped frequency the reading puts outside its band (a reading refines a mode where the record shows it;
    one that sends a component elsewhere, or damps it away, has dropped it from the model: its samples are
    every ``m``-th, so a component may also drift to an alias)."""
    out = []
    for i, k in enumerate(read):
        band = cands[k].band_hz
        z = float(reading.damping_ratio[i])
        damped = float(reading.frequency_hz[i]) * np.sqrt(max(1 - z * z, 0.0))
        if band is not None and not band[0] <= damped <= band[1]:
            out.append((k, damped))
    return out


def takes_reading(mode, frequency_hz: float, damping_ratio: float, frequency_std_hz: float,
                  damping_ratio_std: float) -> bool:
    """Whether a ``mode`` takes the coupling reading's values (given with their standard deviations) in
    place of its own, the reading having described the decay: where they differ from its own by more than
    :data:`COUPLING_SIGMAS` of the reading's standard deviations (its own reading, which sees only its own
    amplitude, is offset by the others'), or where the reading knows both better than its own reading does
    (the two agree, and the reading is the more precise of two readings of one record).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> own = SimpleNamespace(frequency_hz=100.0, damping_ratio=0.02, frequency_std_hz=0.5,
    ...                       damping_ratio_std=0.002)
    >>> takes_reading(own, 100.9, 0.021, 0.2, 0.001)  # 4.5 of its standard deviations off
    True
    >>> takes_reading(own, 100.1, 0.021, 0.2, 0.001)  # agrees, and knows both better
    True
    >>> takes_reading(own, 100.1, 0.021, 0.2, 0.004)  # agrees, and knows the damping ratio worse
    False
    """
    off = (abs(frequency_hz - mode.frequency_hz) > COUPLING_SIGMAS * frequency_std_hz
           or abs(damping_ratio - mode.damping_ratio) > COUPLING_SIGMAS * damping_ratio_std)
    better = frequency_std_hz < mode.frequency_std_hz and damping_ratio_std < mode.damping_ratio_std
    return bool(off or better)


def _modes_read(state, read: list, reading: CouplingReading, positions: bool = False):
    """``(index in state.modes, mode, (frequency, damping ratio, their standard deviations by the
    reading))`` for each candidate of ``read`` (the reading's, in its order) that has a mode; with
    ``positions``, ``(its position in read, that)``."""
    columns = (reading.frequency_hz, reading.damping_ratio,
               reading.frequency_std_hz, reading.damping_ratio_std)
    for i, k in enumerate(read):
        if k in state.origin:
            j = state.origin.index(k)
            row = (j, state.modes[j], tuple(float(v[i]) for v in columns))
            yield (i, row) if positions else row


#: A mode's ± is widened (and a note says so) where the coupling reading widens it by more than this share.
DOUBT_SHARE = 0.1


def _doubted(state, read: list, reading: CouplingReading, against: set, clean_bands: bool) -> str:
    """The ± of the modes of the candidates ``read`` (the reading's, in its order) whose own values stand
    beside the coupling ``reading``, widened by what that reading says of them. Called only where the
    reading describes the decay (its residual within :data:`~._envelope.ENVELOPE_MISFIT` times the noise;
    a reading that does not describe it says nothing of the modes): the record then does not decide between
    a mode's own reading, which sees only its own amplitude, and one that lets the other modes' amplitudes
    move it. A reading that leaves more than noise in a band is not taken, but that band may hold a
    component the reading does not model while its values for the other modes are right (three strongly
    damped modes of coupled records, 0.4-0.5 % off by their own readings, within 0.06 % by such readings).
    The difference between the two is added to the mode's standard deviations (in quadrature) and, where
    the reading also passed the band test (``clean_bands``), the reading's own standard deviations are the
    least they can be (its offset from the other modes' amplitudes is known no better). Not where the
    reading gives a mode no free decay, or one it does not resolve (a damping ratio within
    :data:`COUPLING_SIGMAS` of its standard deviations of zero: a strongly damped mode 12 dB over the noise,
    its own 109.5 Hz and 2.05 %, read at 102.9 +- 5.0 Hz and 0.27 +- 3.7 %, says nothing of it). Returns the
    words for the trace ("" if nothing was widened); nor at the positions ``against``, where it couples the
    mode the other way than one element can (:func:`_against_element`)."""
    widened = []
    for i, (j, mode, (f, z, f_read_std, z_read_std)) in _modes_read(state, read, reading, positions=True):
        if mode.source == "coupling" or i in against:  # (the reading's own values, with its ±; or not one
            continue                                   # element's reading of it)
        if not (np.isfinite(f) and np.isfinite(z) and z > COUPLING_SIGMAS * z_read_std):
            continue
        f_std = float(np.hypot(mode.frequency_std_hz, f - mode.frequency_hz))
        z_std = float(np.hypot(mode.damping_ratio_std, z - mode.damping_ratio))
        if clean_bands:
            f_std, z_std = max(f_std, f_read_std), max(z_std, z_read_std)
        if not (f_std > (1 + DOUBT_SHARE) * mode.frequency_std_hz
                or z_std > (1 + DOUBT_SHARE) * mode.damping_ratio_std):
            continue
        note = (f"its ± includes what the modes' coupling through one nonlinear element may move it by (the "
                f"reading of the modes together gives {f:.6g} Hz, {z:.4g}): the record does not decide "
                "between the two")
        note = f"{mode.uncertainty_note}; {note}" if mode.uncertainty_note else note
        state.modes[j] = replace(mode, frequency_std_hz=f_std, damping_ratio_std=z_std, uncertainty_note=note)
        widened.append(f"{mode.frequency_hz:.5g} Hz")
    return f"; their ± widened by it: {', '.join(widened)}" if widened else ""

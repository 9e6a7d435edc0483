"""The first stages of the survey: the record prepared, its poles, and the modes of its free decay.

- ``read`` (:func:`read_record`): the reference channel's hit, clipped samples and offset
  (:func:`~sindy_impulse.preprocessing.pipeline.prepare_record`), the ring-down's spectrum and its
  significant peaks (no fit), the data's quality and what the clipping did.
- ``poles`` (:func:`stable_poles`): the stabilisation diagram of the free decay
  (:func:`~sindy_impulse.poles.stabilisation`), once: its persistent stable poles are the first candidates.
- ``candidates`` (:func:`fit_candidates`): the stable poles and the spectral peaks no pole explains,
  refined together by the decay fit (:func:`~sindy_impulse.poles.decay_fit.fit_decay`: each mode's
  frequency, damping ratio, their standard deviations, its amplitude in every channel, and the lack of fit
  that says whether the linear decay explains it). What the fit leaves is searched for modes it misses
  (:func:`~sindy_impulse.poles.decay_fit.missing_peaks`), away from modes it does not explain (there the
  residual is that mode's own amplitude dependence, not another mode), and a component under the detection
  threshold is dropped: a mode is a candidate when it stands out of the noise, as a spectral peak must. A
  persistent stable pole that no component accounts for is fitted beside them: where the linear decay
  explains every component, it is a candidate when it stands over the lower threshold of the few places the
  poles name (:func:`_confirmed_by_poles`), else a hidden component removed from its neighbours' signals. A
  component the linear decay does not explain is refitted as the two or more stable poles in its
  half-power band, or, where the diagram did not resolve them, as itself and the peak of what it leaves
  beside it (:func:`_split_unexplained`): two modes whose half-power bands touch.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from numbers import Integral
from typing import NamedTuple

import numpy as np

from .._utils.params import Interval, check_param
from ..poles.decay_fit import MAX_DAMPING, MISFIT_REACH, MISFIT_SHARE, fit_decay, missing_peaks
from ..poles.esprit import MAX_ROWS
from ..preprocessing._record import check_signal_1d
from ..preprocessing.partition import HARMONIC_NEAR, at_harmonic_place, peak_bands, resolved
from ..preprocessing.peaks import SpectralPeaks, spectral_peaks
from ..preprocessing.pipeline import prepare_record
from ..preprocessing.quality import check_quality, ringdown_snr_db
from ..preprocessing.spectrum import detection_threshold_db, search_range
from ._clipped import clipping_report
from .kinds import Kind
from .result import pole_table

__all__ = ["Candidate", "ConfirmingPole", "read_record", "stable_poles", "fit_candidates", "PERSISTENCE",
           "NONLINEAR_P"]

#: A stable mode of the diagram is a candidate when found at this share of its orders or more (noise poles
#: that pass the stability rule by chance recur at a few orders).
PERSISTENCE = 0.5
#: The survey's diagram: every other order of the classical one (10, 14, ..., 58), a pole stable when it
#: recurs at 3 of them (the classical 5 of 26 in proportion), on at most this many samples of the free
#: decay. Its poles only seed the decay fit, which refines them on the whole record.
SEED_ORDERS, SEED_MIN_ORDERS, SEED_SAMPLES = tuple(range(10, 61, 4)), 3, 8192
#: ... and a stable mode found at this share of its orders or more seeds the decay fit (which keeps it only
#: if it stands out of the noise): a strongly damped mode beside a lightly damped one stabilises late.
SEED_PERSISTENCE = 0.25
#: A component whose damping ratio reaches this share of the decay fit's largest is a transient (the hit's
#: tail, a trend the offset left), not a mode.
TRANSIENT = 0.95
#: Highest damped frequency of a candidate over the sampling rate (the decay fit holds up to the Nyquist
#: frequency; a spectral peak is searched up to 0.45 fs, a stable pole may lie above).
TOP = 0.49
#: A component damped more than this is a mode only where a stable pole confirms it (a broad component
#: that the diagram does not see follows the hit's tail or a misfit, not a vibration).
MODE_DAMPING = 0.2
#: A component the linear decay does not explain is tried as a pair with the strongest peak of what the fit
#: leaves within this many of its half-power half-widths (:func:`_split_seeds`).
PAIR_REACH = 3.0
#: ... and within this many frequency resolutions of the survey's diagram (``fs / SEED_SAMPLES``): the
#: diagram's poles resolve pairs farther apart.
PAIR_RESOLUTIONS = 4.0
#: Most evaluations of the residual in the cheap test of a split (two components on the free decay without the
#: others, :func:`_split_unexplained`): the test asks whether the seeds come out separate modes, not their
#: last digits, and a split of a chirp creeps along its misfit for every evaluation it is given.
TRIAL_EVALUATIONS = 20
#: Rounds of the search for modes the fit misses, and new modes per round at most.
ROUNDS, NEW_PER_ROUND = 4, 8
#: A mode whose lack of fit is this improbable from noise alone is not explained by a linear decay.
NONLINEAR_P = 1e-6
#: ... and its residual at least this many times the noise (a small, significant misfit of a strong mode
#: is rounding of the record, not physics).
NONLINEAR_RATIO = 1.5


class ConfirmingPole(NamedTuple):
    """The stable mode of the survey's diagram that confirms a candidate, and the stretch the diagram read.

    Attributes
    ----------
    frequency_hz, damping_ratio : float
        The stable mode's median natural frequency and damping ratio over its orders.
    frequency_spread_hz, damping_ratio_spread : float
        How far its orders' poles scatter about them
        (:attr:`~sindy_impulse.poles.stabilisation.StableMode.frequency_spread_hz`).
    span_s : float
        The span of one column of the diagram's Hankel matrix, seconds: ``L = min(MAX_ROWS, n // 3)``
        samples of the ``n`` it read (the free decay's first :data:`SEED_SAMPLES` at most).
    """

    frequency_hz: float
    damping_ratio: float
    frequency_spread_hz: float
    damping_ratio_spread: float
    span_s: float


@dataclass
class Candidate:
    """One mode of the free decay as the decay fit sees it, and what the survey makes of it.

    Attributes
    ----------
    frequency_hz, damping_ratio, frequency_std_hz, damping_ratio_std : float
        The decay fit's natural frequency and damping ratio with their standard deviations.
    decay_rate, decay_rate_std : float
        ``sigma`` (1/s) and its standard deviation.
    amplitude : ndarray of complex (n_channels,)
        Complex amplitude at the free decay's first sample, per channel (reference first).
    height_db : float
        Its spectral peak over the noise floor.
    lack_of_fit, lack_of_fit_p : float
        Residual power over the noise near the mode, and how probable that is from noise alone.
    pole : ConfirmingPole or None
        The stable mode of the diagram (found at :data:`SEED_PERSISTENCE` of its orders) within its
        half-power band that confirms it (the one nearest to it), or None.
    kind : Kind
        What it is (stage ``classify``).
    parent : int or None
        For a harmonic or a merged piece, the index of the mode it belongs to.
    evidence : dict
        The numbers the kind rests on.
    band_hz : (float, float) or None
        Its band (stage ``identify``).
    noise_std : float
        The noise's standard deviation in time at its frequency (the decay fit's floor).
    """

    frequency_hz: float
    damping_ratio: float
    frequency_std_hz: float
    damping_ratio_std: float
    decay_rate: float
    decay_rate_std: float
    amplitude: np.ndarray = field(repr=False)
    height_db: float
    lack_of_fit: float
    lack_of_fit_p: float
    kind: Kind = Kind.LINEAR
    parent: int | None = None
    evidence: dict = field(default_factory=dict, repr=False)
    band_hz: tuple | None = None
    noise_std: float = 0.0
    pole: ConfirmingPole | None = None

    @property
    def stable(self) -> bool:
        """Whether a stable mode of the diagram confirms it (:attr:`pole`)."""
        return self.pole is not None

    @property
    def damped_frequency_hz(self) -> float:
        return float(self.frequency_hz * np.sqrt(max(1.0 - self.damping_ratio**2, 0.0)))

    @property
    def explained(self) -> bool:
        """Whether the linear decay explains the data near the mode (see :data:`NONLINEAR_P`)."""
        return not _misfit(self.lack_of_fit, self.lack_of_fit_p)


def _misfit(lack_of_fit, lack_of_fit_p):
    """Whether (elementwise) a component's lack of fit is too improbable from noise and large enough to be
    physics (:data:`NONLINEAR_P`, :data:`NONLINEAR_RATIO`)."""
    return (np.asarray(lack_of_fit_p) < NONLINEAR_P) & (np.asarray(lack_of_fit) > NONLINEAR_RATIO)


def _reference_channel(record: np.ndarray, channel) -> int:
    if channel is not None:
        check_param("channel", channel, [Interval(Integral, 0, record.shape[1] - 1)], "identify_modes")
        return int(channel)
    centred = record - np.median(record, axis=0)
    return int(np.argmax(np.sqrt(np.mean(centred**2, axis=0))))


def read_record(state) -> None:
    """The record prepared: the hit, clipped samples, the offset."""
    opts = state.options
    state.channel = _reference_channel(state.record, opts.channel)
    pre, raw = prepare_record(state.record[:, state.channel], state.t, fs=state.fs, force=state.force,
                              onset=opts.onset, offset=opts.offset)
    # (refused in the free decay's words: the record itself may be long enough)
    hit = pre.impact.ringdown_index
    ring = check_signal_1d(pre.y[hit:], f"the free decay after the hit (sample {hit} of {pre.y.size})")
    peaks = spectral_peaks(ring, pre.fs, bands=opts.bands, refine=False)
    quality = check_quality(raw, pre.fs, onset_index=pre.impact.onset_index, peaks=peaks)
    state.pre, state.raw = replace(pre, peaks=peaks, quality=quality), raw
    state.start = decay_start(state.pre)
    clipped, products = clipping_report(state.pre, state.index)
    # the offset is removed here, the clipping's note says what was done with it, and the SNR is judged
    # where the noise is known (fit_candidates: the modes' residual, where no pre-trigger measured it)
    held = {"offset", "snr"} | ({"clipping"} if clipped else set())
    for check, problem in quality.problems.items():
        if check not in held:
            state.note(problem)
    state.notes += clipped
    state.rejected += products
    if pre.impact.double_hit:
        state.note(f"double hit at {', '.join(f'{h[0]:.4g} s' for h in pre.impact.hits)}")
    state.decide(f"channel {state.channel}; the free decay starts at {pre.impact.ringdown_time:.6g} s "
                 f"({ring.size} samples at {pre.fs:.6g} Hz); offset {pre.offset.value:.4g} removed "
                 f"({pre.offset.method}); {len(peaks)} spectral peak(s)")


#: Share of the free decay in which a record without a pre-trigger has its decay fit start at the envelope's
#: peak.
_EARLY = 0.1


def decay_start(pre) -> int:
    """The first sample of the free decay that the decay fit reads: the end of the hit's contact; but when
    the record shows no pre-trigger to find the hit by, the peak of the response over the first tenth of
    the ring-down and at least two periods of its strongest spectral peak (before it the response may be
    quiet or still rising, which a free decay does not do).

    Examples
    --------
    >>> from sindy_impulse.preprocessing.pipeline import prepare_record
    >>> y = np.r_[np.zeros(12), np.exp(-np.arange(400) / 80) * np.sin(np.arange(400) / 3)]
    >>> pre, _ = prepare_record(y, fs=1000.0)
    >>> pre.impact.source, decay_start(pre) > 12  # the envelope's peak, past the quiet start
    ('no pre-trigger', True)
    """
    start = pre.impact.ringdown_index
    if pre.impact.source != "no pre-trigger":
        return start
    span = _EARLY * (pre.y.size - start)
    if len(pre.peaks):
        span = max(span, 2 * pre.fs / pre.peaks.frequency_hz[int(np.argmax(pre.peaks.height_db))])
    early = np.abs(pre.y[start: start + max(int(span), 1)])
    return start + int(np.argmax(early))


def stable_poles(state) -> None:
    """The stabilisation diagram of the free decay: stable poles, computed once."""
    state.poles = pole_table(state.pre, max_samples=SEED_SAMPLES, start=state.start, orders=SEED_ORDERS,
                             min_orders=SEED_MIN_ORDERS)
    stable = persistent_modes(state.poles)
    state.decide(f"{len(stable)} stable mode(s) at {PERSISTENCE:.0%} of {len(state.poles.orders)} orders"
                 + (": " + ", ".join(f"{m.frequency_hz:.5g}" for m in stable) + " Hz" if stable else ""))


def persistent_modes(table) -> list:
    """The stable modes of a diagram found at :data:`PERSISTENCE` of its orders or more, below
    :data:`~sindy_impulse.poles.decay_fit.MAX_DAMPING`.

    Examples
    --------
    >>> from sindy_impulse import impact_record
    >>> from sindy_impulse.poles import stabilisation
    >>> rec = impact_record([50.0], [0.1], fs=1000.0, duration=0.3, snr_db=50, pre_trigger=0, random_state=0)
    >>> [round(m.frequency_hz) for m in persistent_modes(stabilisation(rec.y[5:], fs=rec.fs))]
    [50]
    """
    return [m for m in table.modes()
            if m.n_orders >= PERSISTENCE * len(table.orders) and m.damping_ratio < MAX_DAMPING]


def _seed_poles(table) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The stable modes found at :data:`SEED_PERSISTENCE` of the orders or more, below
    :data:`MAX_DAMPING`: damped frequencies (Hz), decay rates (1/s) and numbers of orders."""
    found = [m for m in table.modes() if m.n_orders >= SEED_PERSISTENCE * len(table.orders)
             and m.damping_ratio < MAX_DAMPING]
    fd = np.array([m.frequency_hz * np.sqrt(1 - m.damping_ratio**2) for m in found])
    sigma = np.array([2 * np.pi * m.frequency_hz * m.damping_ratio for m in found])
    return fd, sigma, np.array([m.n_orders for m in found], dtype=int)


def _pole_seeds(table) -> tuple[list, list]:
    """The seed poles (:func:`_seed_poles`), strongest first, one per half-power band (a mode's poles may
    make two clusters): damped frequencies and decay rates."""
    found_f, found_s, orders = _seed_poles(table)
    f, s = [], []
    for k in np.argsort(-orders, kind="stable"):
        fd, sigma = float(found_f[k]), float(found_s[k])
        if all(abs(fd - g) > (sigma + t) / (2 * np.pi) for g, t in zip(f, s)):
            f.append(fd)
            s.append(sigma)
    return f, s


def _seeds(state) -> tuple[np.ndarray, np.ndarray]:
    """Starting poles: the stable modes (:func:`_pole_seeds`), then the spectral peaks no pole explains
    (farther from every pole than their joint half-power band and two bins); with given bands, the poles
    inside each band, else its peak."""
    pre, fs = state.pre, state.pre.fs
    f, s = _pole_seeds(state.poles)
    resolution = fs / max(pre.y.size - pre.impact.ringdown_index, 1)
    peaks = pre.peaks
    if state.options.bands is not None:
        inside = [[i for i, g in enumerate(f) if lo <= g <= hi] for lo, hi in peaks.band_hz]
        keep = sorted({i for group in inside for i in group})
        f, s = [f[i] for i in keep], [s[i] for i in keep]
        empty = [k for k, group in enumerate(inside) if not group]
    else:
        empty = range(len(peaks))
    for k in empty:
        g, width = peaks.frequency_hz[k], peaks.half_power_width_hz[k]
        if not any(abs(g - h) <= (width + t / np.pi) / 2 + 2 * resolution for h, t in zip(f, s)):
            f.append(float(g))
            s.append(float(np.pi * max(width - 1.28 * resolution, 0.1 * resolution)))
    f, s = np.asarray(f, float), np.asarray(s, float)
    ok = (f > 0) & (f < 0.499 * fs)
    return f[ok], s[ok]


def _ring(state) -> np.ndarray:
    """The free decay of every channel, the reference first (its offset removed; the other channels'
    offsets fall on the transform's zero bin, which the fit leaves out)."""
    pre, start = state.pre, state.start
    others = [c for c in range(state.record.shape[1]) if c != state.channel]
    columns = [pre.y[start:]] + [state.record[start:, c] - np.mean(state.record[start:, c]) for c in others]
    return np.column_stack(columns)




def _away_from_misfits(fit, frequency_hz: np.ndarray) -> np.ndarray:
    """Which of ``frequency_hz`` lie beyond the reach of every component the fit does not explain
    (:data:`MISFIT_REACH` half-power half-widths, :data:`MISFIT_SHARE` of its frequency, 8 bins): there
    what the fit leaves is that mode's own amplitude dependence, not another mode."""
    away = np.ones(len(frequency_hz), bool)
    for k in np.flatnonzero(np.asarray(fit.lack_of_fit_p) < NONLINEAR_P):
        fk = fit.damped_frequency_hz[k]
        width = fit.decay_rate[k] / (2 * np.pi)
        reach = max(MISFIT_REACH * width, MISFIT_SHARE * fk, 8 * fit.fs / fit.n_samples)
        away &= np.abs(np.asarray(frequency_hz) - fk) > reach
    return away


def _searched(fit, lo: float, hi: float, threshold_db: float) -> tuple[np.ndarray, np.ndarray]:
    """Peaks of what the fit leaves, away from the modes it does not explain (:func:`_away_from_misfits`)."""
    f, s = missing_peaks(fit, threshold_db, lo, hi)
    away = _away_from_misfits(fit, f)
    return f[away][:NEW_PER_ROUND], s[away][:NEW_PER_ROUND]


def _within_range(frequency_hz, lo: float, hi: float, seeds: tuple) -> np.ndarray:
    """Which of ``frequency_hz`` the survey reads: up to ``hi``, and from ``lo`` (the spectral search's
    lowest frequency, 3 periods over the free decay: below it a peak is not told from the offset's
    leakage) or inside the half-power band of a seed pole (``seeds``, :func:`_pole_seeds`'s: a pole that
    recurs over the diagram's orders is its own evidence, whatever the periods the record holds of it)."""
    f = np.asarray(frequency_hz, float)
    named = np.zeros(f.size, bool)
    for g, sigma in zip(*seeds):
        named |= np.abs(f - g) <= sigma / (2 * np.pi)
    return ((f >= lo) | named) & (f <= hi)


def fit_candidates(state) -> None:
    """The modes of the free decay: poles and spectral peaks refined by the decay fit."""
    pre, fs, given = state.pre, state.pre.fs, state.options.bands is not None
    ring = _ring(state)
    lo = search_range(pre.peaks.spectrum)[0] if len(pre.peaks.spectrum.psd) > 2 else 0.0
    hi = TOP * fs
    f0, s0 = _seeds(state)
    seeds = _pole_seeds(state.poles)
    inside = _within_range(f0, lo, hi, seeds)
    f0, s0 = f0[inside], s0[inside]
    threshold = detection_threshold_db(max(ring.shape[0] // 2, 1))
    fit, rounds, noise = None, 0, None
    while f0.size:
        rounds += 1
        fit = fit_decay(ring, fs, f0, s0, noise=noise)
        # the floor only falls from round to round: what a poor round leaves unexplained lifts its floor
        noise = fit.noise_power if noise is None else np.minimum(noise, fit.noise_power)
        f = fit.damped_frequency_hz
        keep = np.ones(len(fit), bool) if given else (fit.height_db >= threshold) & (
            fit.damping_ratio < TRANSIENT * MAX_DAMPING)
        keep &= _within_range(f, lo, hi, seeds)
        last = rounds >= ROUNDS
        new_f, new_s = (np.empty(0), np.empty(0)) if given or last else _searched(fit, lo, hi, threshold)
        if keep.all() and not new_f.size:
            break
        f0 = np.concatenate([fit.damped_frequency_hz[keep], new_f])
        s0 = np.concatenate([fit.decay_rate[keep], new_s])
        fit = None
    hidden = np.zeros(0 if fit is None else len(fit), bool)
    if fit is not None and not given:
        fit = _split_unexplained(fit, ring, fs, state.poles, noise, threshold)
        fit, hidden, places = _with_hidden(fit, ring, fs, state.poles, noise, threshold)
        confirmed = hidden & _confirmed_by_poles(fit, places)
        hidden &= ~confirmed
        if confirmed.any():
            at = detection_threshold_db(places)
            state.decide(f"{int(confirmed.sum())} stable pole(s) under the detection threshold stand over "
                         f"the {at:.1f} dB of {places} place(s) the poles name, none at a nonlinear mode's "
                         "harmonic or intermodulation place: candidate(s) at "
                         + ", ".join(f"{f:.5g} Hz" for f in fit.frequency_hz[confirmed]))
    state.fit = fit
    found = [] if fit is None else _candidates(fit, state.poles)
    state.hidden = [c for c, h in zip(found, hidden) if h]
    state.candidates = [c for c, h in zip(found, hidden) if not h]
    state.candidates = [c for c in state.candidates if c.stable or c.damping_ratio <= MODE_DAMPING or given]
    if state.options.n_modes is not None:
        strongest = sorted(range(len(state.candidates)), key=lambda k: -state.candidates[k].height_db)
        state.candidates = [state.candidates[k] for k in sorted(strongest[: state.options.n_modes])]
    spectrum = pre.peaks.spectrum if fit is None else _floored(pre.peaks.spectrum, fit)
    peaks = replace(pre.peaks, spectrum=spectrum)
    state.pre = replace(pre, peaks=_as_peaks(state.candidates, peaks, threshold, fs, given))
    _signal_to_noise(state)
    state.decide(f"{len(state.candidates)} candidate(s) over {threshold:.1f} dB after {rounds} round(s): "
                 + ", ".join(f"{c.frequency_hz:.5g} Hz ({c.height_db:.0f} dB)" for c in state.candidates))
    if state.hidden:
        hidden = ", ".join(f"{c.frequency_hz:.5g} Hz ({c.height_db:.0f} dB)" for c in state.hidden)
        state.decide(f"{len(state.hidden)} stable pole(s) of no candidate fitted as hidden component(s), "
                     f"removed from the modes' signals: {hidden}")


def _signal_to_noise(state) -> None:
    """The record's SNR note: where no pre-trigger measured the noise, the SNR is measured again against
    the noise the decay fit leaves (the upper bounds read off a short ring-down of strong modes stand on
    the modes themselves: a clean record would read as one with no signal above the noise)."""
    quality, fit = state.pre.quality, state.fit
    if not quality.noise_measured and fit is not None and np.isfinite(fit.noise_rms) and fit.noise_rms > 0:
        ring = state.pre.y[state.pre.impact.ringdown_index:]
        quality = quality.with_snr(ringdown_snr_db(ring, state.pre.fs, noise_rms=fit.noise_rms))
        state.pre = replace(state.pre, quality=quality)
    if "snr" in quality.problems:
        state.note(quality.problems["snr"])


def _with_hidden(fit, ring: np.ndarray, fs: float, table, noise, threshold_db: float):
    """The decay fit refitted with the persistent stable poles (:func:`persistent_modes`) that none of its
    components accounts for, as hidden components: ``(fit, hidden, places)``, ``hidden`` a mask of its
    components, ``places`` the number of poles tried.

    Such a pole belongs to no candidate (the rounds dropped its component under the detection threshold:
    it does not stand out of the noise as a spectral peak must), but it is in the record: left out of the
    fit, its signal stays in its neighbours' residual and own signals, where its beat reads as an amplitude
    dependence or a misfit of theirs. Each pole outside every component's half-power band is fitted with
    the components; a hidden component stands when it stays under the detection threshold (over it, it is
    a piece the fit left out on purpose: a nonlinear mode's poles spread along its chirp), the linear decay
    explains it, it is damped less than :data:`TRANSIENT` of the largest damping, and no component the
    linear decay leaves unexplained has it within its misfit's reach (:data:`MISFIT_REACH`: there the poles
    may follow that mode's own amplitude dependence, which a sum of linear decays does not explain).
    """
    f, zeta = np.asarray(fit.frequency_hz, float), np.asarray(fit.damping_ratio, float)
    resolution = fs / ring.shape[0]
    added = [m for m in persistent_modes(table)
             if np.all(np.abs(f - m.frequency_hz) > np.maximum(zeta * f, 1.5 * resolution))
             and 0 < m.frequency_hz < TOP * fs]
    places = len(added)
    for _ in range(2):  # the poles, then those of them that stand
        if not added:
            return fit, np.zeros(len(fit), bool), places
        fa = np.array([m.frequency_hz * np.sqrt(1 - m.damping_ratio**2) for m in added])
        seeds = np.concatenate([fit.damped_frequency_hz, fa])
        sa = [2 * np.pi * m.frequency_hz * m.damping_ratio for m in added]
        rates = np.concatenate([fit.decay_rate, sa])
        trial = fit_decay(ring, fs, seeds, rates, noise=noise)
        where = np.sort(seeds).searchsorted(fa)  # one component per seed, sorted by frequency
        stands = _standing(trial, where, threshold_db)
        if stands.all():
            mask = np.zeros(len(trial), bool)
            mask[where] = True
            return trial, mask, places
        added = [m for m, ok in zip(added, stands) if ok]
    return fit, np.zeros(len(fit), bool), places


def _confirmed_by_poles(fit, places: int) -> np.ndarray:
    """Which components stand out of the noise at a place the stable poles name: a mode, though under the
    detection threshold.

    The detection threshold guards a search of the whole spectrum (:func:`detection_threshold_db` of its
    bins); a stable pole names its place before the fit looks there, so its component is tested against
    the threshold of the ``places`` poles tried. A component the linear decay does not explain is a
    nonlinear mode, whose harmonics and intermodulation tones stand where no mode is: beside one, a pole
    names a mode only away from those places (:func:`_at_product_place`; its chirp's own poles are beyond
    the hidden components' reach, :func:`_standing`), or where it decays faster than a product of the
    others can (:func:`_faster_than_products`).
    """
    if places < 1:
        return np.zeros(len(fit), bool)
    over = np.asarray(fit.height_db) >= detection_threshold_db(places)
    misfit = _misfit(fit.lack_of_fit, fit.lack_of_fit_p)
    if not misfit.any():
        return over
    f, rate = np.asarray(fit.damped_frequency_hz, float), np.asarray(fit.decay_rate, float)
    products = np.array([_at_product_place(fk, np.delete(f, k), f[misfit]) for k, fk in enumerate(f)], bool)
    return over & ~misfit & ~(products & ~_faster_than_products(rate))


#: A product of order 2 or 3 of components (a harmonic, an intermodulation tone) has an amplitude that goes
#: as theirs to that power: it decays at most 3 times as fast as the fastest of them, and twice that where
#: the damping grows with amplitude (the parent's decay at the hit faster than its linear fit's: an
#: ``x^2 x'`` damper's third harmonics decayed 4.2 and 5.7 times as fast as their parents' fitted rates).
PRODUCT_DECAY = 6.0


def _faster_than_products(rate: np.ndarray) -> np.ndarray:
    """Which components decay more than :data:`PRODUCT_DECAY` times as fast as the fastest other one: no
    product of the others (a strongly damped mode near ``2 f_a + f_b`` of two lightly damped ones).

    Examples
    --------
    >>> _faster_than_products(np.array([0.43, 0.31, 13.8])).tolist()
    [False, False, True]
    """
    rate = np.asarray(rate, float)
    if rate.size < 2:
        return np.zeros(rate.size, bool)
    others = np.array([np.delete(rate, k).max() for k in range(rate.size)])
    return rate > PRODUCT_DECAY * others


def _at_product_place(frequency_hz: float, components, nonlinear) -> bool:
    """Whether ``frequency_hz`` lies within :data:`HARMONIC_NEAR` of a product of order 2 or 3 of a
    ``nonlinear`` frequency: 2 or 3 times it, or it plus or minus one or two times any of ``components``
    (the other components of the fit), or twice it plus or minus one of them.

    Examples
    --------
    >>> _at_product_place(1310.0, [100.0, 1000.0], [310.0]), _at_product_place(1500.0, [1000.0], [310.0])
    (True, False)
    """
    a = np.asarray(nonlinear, float)[:, None]
    b = np.asarray(components, float)[None, :]
    places = [2 * a, 3 * a, a + b, a - b, 2 * a + b, 2 * a - b, a + 2 * b, a - 2 * b]
    places = np.abs(np.concatenate([np.ravel(p) for p in places]))
    places = places[places > 0]
    return bool(np.any(np.abs(frequency_hz / places - 1) <= HARMONIC_NEAR))


def _standing(fit, hidden: np.ndarray, threshold_db: float) -> np.ndarray:
    """Which of the components ``hidden`` (indices) stand as hidden components (:func:`_with_hidden`)."""
    ok = ~_misfit(fit.lack_of_fit, fit.lack_of_fit_p) & (fit.damping_ratio < TRANSIENT * MAX_DAMPING)
    ok &= (np.asarray(fit.height_db) < threshold_db) & _away_from_misfits(fit, fit.damped_frequency_hz)
    return ok[hidden]


def _split_unexplained(fit, ring: np.ndarray, fs: float, table, noise, threshold_db: float, tried=None):
    """The decay fit with each component it does not explain replaced by two or more modes, where that
    explains them.

    Two modes whose half-power bands touch give two stable poles, but seed the fit once (the seeds keep
    one pole per half-power band, as a single mode's poles may make two clusters), and the one component
    then leaves a misfit. Where the poles resolve the pair, they seed the split; where the survey's
    diagram is too short to (a pair closer than a few of its frequency resolutions gives one pole), the
    peak of what the one component leaves does (:func:`_split_seeds`). The split is kept when every seed
    comes out a separate component that the linear decay explains and that stands over the detection
    threshold, and, seeded without poles, is resolved from the others
    (:func:`~sindy_impulse.preprocessing.partition.resolved`: else the survey would merge them again as
    pieces of one mode) and damped at most :data:`MODE_DAMPING` (as a candidate without a stable pole must
    be). A nonlinear mode's chirp, whose poles also spread, stays unexplained by linear components and
    keeps its one. A split seeded without poles is tested first on the free decay without
    the other components (two components fitted instead of all: what a record of many modes can afford
    for each one the linear decay leaves unexplained), and each component is tried once.
    """
    unexplained = np.flatnonzero(_misfit(fit.lack_of_fit, fit.lack_of_fit_p))
    if not unexplained.size:
        return fit
    tried = [] if tried is None else tried  # components already tried (a split refits the others)
    left = {}
    poles = _seed_poles(table)[:2]
    resolution = fs / ring.shape[0]
    unresolved = PAIR_RESOLUTIONS * fs / min(ring.shape[0], SEED_SAMPLES)  # closer pairs: one pole
    for k in unexplained:
        fk = float(fit.damped_frequency_hz[k])
        if any(abs(fk - g) <= resolution for g in tried):
            continue
        tried.append(fk)
        others = np.arange(len(fit)) != k
        alone = None
        for fi, si, by_poles in _split_seeds(fit, k, poles, resolution, threshold_db, unresolved):
            if np.any(fi <= 0) or np.any(fi >= fs / 2):  # a broad component's mirror seed beyond the band
                continue
            if not by_poles:  # first alone, on the record without the other components: a cheap test
                alone = _alone(fit, ring, k, left) if alone is None else alone
                if not _split_holds(fit_decay(alone, fs, fi, si, noise=noise, refloor=False,
                                              max_nfev=TRIAL_EVALUATIONS), fi, resolution,
                                    threshold_db, by_poles):
                    continue
            trial = fit_decay(ring, fs, np.concatenate([fit.damped_frequency_hz[others], fi]),
                              np.concatenate([fit.decay_rate[others], si]), noise=noise)
            if len(trial) == len(fit) + fi.size - 1 and _split_holds(trial, fi, resolution, threshold_db,
                                                                     by_poles):
                return _split_unexplained(trial, ring, fs, table, noise, threshold_db, tried)
    return fit


def _alone(fit, ring: np.ndarray, k: int, left: dict) -> np.ndarray:
    """The free decay without the fit's components other than ``k``, every channel (``left`` keeps what the
    whole fit leaves, computed once per fit)."""
    n, channels = ring.shape[0], range(ring.shape[1])
    if "y" not in left:
        left["y"] = ring - np.column_stack([sum((fit.component(j, n, c) for j in range(len(fit))),
                                                np.zeros(n)) for c in channels])
    return left["y"] + np.column_stack([fit.component(k, n, c) for c in channels])


def _split_holds(trial, seeds, resolution: float, threshold_db: float, by_poles: bool) -> bool:
    """Whether the components of ``trial`` nearest the ``seeds`` are the separate modes a split needs
    (see :func:`_split_unexplained`)."""
    tf = np.asarray(trial.damped_frequency_hz)
    new = np.unique([int(np.argmin(np.abs(tf - g))) for g in seeds])  # the seeds' components
    if new.size != len(seeds) or np.min(np.diff(np.sort(tf[new]))) <= 2 * resolution:
        return False
    if not by_poles:  # ... and resolved: pieces of one mode would be merged again
        order = new[np.argsort(tf[new])]
        if not all(resolved((trial.frequency_hz[a], trial.frequency_hz[b]),
                            (trial.damping_ratio[a], trial.damping_ratio[b]))
                   for a, b in zip(order[:-1], order[1:])):
            return False
        if np.any(trial.damping_ratio[new] > MODE_DAMPING):  # no pole: a mode by its damping
            return False
    explained = not _misfit(trial.lack_of_fit, trial.lack_of_fit_p)[new].any()
    return bool(explained and np.all(trial.height_db[new] >= threshold_db))


def _split_seeds(fit, k: int, poles, resolution: float, threshold_db: float, unresolved: float) -> list:
    """Seeds ``(damped frequencies, decay rates, by_poles)`` to try for component ``k`` of the fit as several
    modes.

    The stable poles whose half-power bands overlap its own, where two or more stand apart (a pole of a
    strongly damped mode beside a lightly damped one lies outside the one component's band, while its own
    band reaches it); at a harmonic's place of a stronger component the linear decay does not explain
    (:func:`_may_be_harmonic`), the poles inside its own band only (a chirping harmonic's poles spread
    along its sweep, beside the one component fitted to it). Else the strongest peak
    of what the fit leaves within :data:`PAIR_REACH` half-power half-widths of the component and within
    ``unresolved`` Hz (:data:`PAIR_RESOLUTIONS` frequency resolutions of the survey's diagram, which
    resolves pairs farther apart): the other mode of a pair whose half-power bands touch and which the
    poles did not resolve (the one component fitted to such a pair is about as broad as the pair). The
    one component then sits between the two modes, nearer the stronger, longer-ringing one: it is tried
    with that peak as it is, and as that peak's mirror image about the component beside the peak. A
    residual peak farther out is no such pair (a mode the rounds search for, or the component's own
    misfit).
    """
    f, sigma = poles
    fk, width = fit.damped_frequency_hz[k], fit.decay_rate[k] / (2 * np.pi)
    harmonic = _may_be_harmonic(fit, k)
    # at a harmonic's place only the poles inside its band: a chirping harmonic's poles spread beside it
    reach = width if harmonic else width + sigma / (2 * np.pi)
    inside = np.flatnonzero(np.abs(f - fk) <= np.maximum(reach, resolution))
    if inside.size >= 2 and np.min(np.diff(np.sort(f[inside]))) > 2 * resolution:
        return [(f[inside], sigma[inside], True)]
    if harmonic:
        return []
    reach = max(min(PAIR_REACH * width, unresolved), 4 * resolution)
    rf, rs = missing_peaks(fit, threshold_db, fk - reach, fk + reach)
    if not rf.size:
        return []
    rate = fit.decay_rate[k]
    return [(np.array([fk, rf[0]]), np.array([rate, rs[0]]), False),
            (np.array([2 * fk - rf[0], rf[0]]), np.array([rate, rs[0]]), False)]


def _may_be_harmonic(fit, k: int) -> bool:
    """Whether component ``k`` lies at a harmonic's place
    (:func:`~sindy_impulse.preprocessing.partition.at_harmonic_place`) of a stronger component that the
    linear decay does not explain: a nonlinear mode's harmonic chirps with it, and what its one component
    leaves is that chirp, not a second mode."""
    f = np.asarray(fit.damped_frequency_hz, float)
    stronger = (np.asarray(fit.height_db) > fit.height_db[k]) & _misfit(fit.lack_of_fit, fit.lack_of_fit_p)
    return at_harmonic_place(f[k], f[stronger])


def _candidates(fit, table) -> list:
    stable = [m for m in table.modes() if m.n_orders >= SEED_PERSISTENCE * len(table.orders)]
    # the diagram reads the decay's first SEED_SAMPLES: where a mode's frequency moves with its amplitude,
    # its pole lies where the mode was then, within that stretch's resolution of the whole decay's component
    read = min(fit.n_samples, SEED_SAMPLES)
    resolution = fit.fs / read
    span = max(min(MAX_ROWS, read // 3), 3) / fit.fs  # the diagram's Hankel rows (:class:`SignalSpace`)
    # a pole confirms the component nearest to it only (a broad component's half-power band holds its
    # neighbours' poles too)
    f_all = np.asarray(fit.frequency_hz, float)
    nearest = [(int(np.argmin(np.abs(f_all - m.frequency_hz))), m) for m in stable] if f_all.size else []
    out = []
    for k in range(len(fit)):
        f, zeta = float(fit.frequency_hz[k]), float(fit.damping_ratio[k])
        reach = max(zeta * f, 1.5 * resolution)
        near = [m for j, m in nearest if j == k and abs(m.frequency_hz - f) <= reach]
        pole = min(near, key=lambda m: abs(m.frequency_hz - f), default=None)
        out.append(Candidate(f, zeta, float(fit.frequency_std_hz[k]), float(fit.damping_ratio_std[k]),
                             float(fit.decay_rate[k]), float(fit.decay_rate_std[k]), fit.amplitude[k],
                             float(fit.height_db[k]), float(fit.lack_of_fit[k]), float(fit.lack_of_fit_p[k]),
                             noise_std=float(fit.noise_std[k]),
                             pole=None if pole is None else ConfirmingPole(
                                 pole.frequency_hz, pole.damping_ratio, pole.frequency_spread_hz,
                                 pole.damping_ratio_spread, span)))
    return out


def _floored(spectrum, fit):
    """The ring-down's spectrum with the noise floor of what the decay fit leaves (a one-sided density: the
    spectrum's own floor is raised under the skirts of lightly damped modes)."""
    f = np.arange(fit.noise_power.size) * fit.fs / fit.n_samples
    density = 2.0 * fit.noise_power / (fit.n_samples * fit.fs)
    return replace(spectrum, floor=np.interp(spectrum.frequency_hz, f, density))


def _as_peaks(candidates: list, spectrum_peaks: SpectralPeaks, threshold: float, fs: float, given: bool):
    """The candidates as the record's spectral peaks (their bands cut by
    :func:`~sindy_impulse.preprocessing.partition.peak_bands`; given bands kept)."""
    f = np.array([c.damped_frequency_hz for c in candidates])
    width = np.array([c.decay_rate / np.pi for c in candidates])
    if given:
        bands = [next((b for b in spectrum_peaks.band_hz if b[0] <= g <= b[1]), None) for g in f]
    else:
        bands = peak_bands(f, width, fs) if f.size else []
    for c, band in zip(candidates, bands):
        c.band_hz = None if band is None else tuple(float(b) for b in band)
    return SpectralPeaks(f, np.array([c.height_db for c in candidates]), width,
                         [c.band_hz for c in candidates], float(threshold), spectrum_peaks.spectrum,
                         np.array([c.damping_ratio for c in candidates]))

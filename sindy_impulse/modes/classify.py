"""What each candidate of the free decay needs, decided on cheap evidence before anything is fitted.

The decay fit (:mod:`sindy_impulse.poles.decay_fit`) already holds the evidence; the record holds the rest:

- **tone** (:attr:`Kind.TONE`): a sinusoid that stands as strong before the hit as after it, or, where the
  record has no pre-trigger long enough to tell, that the decay fit explains and that does not decay
  measurably (its decay rate within three standard deviations of zero, and at most three e-folds over the
  record at its upper bound; a slow component of a chirp leaves a misfit a tone does not): hum, a rotating
  machine (or a mode too lightly damped for the record to measure its decay: the row says which it may
  be). A pre-trigger where it is absent shows that it began with the hit: a mode, however slowly it
  decays. It is named, not reported as a mode
  with a damping ratio it does not have.
- **harmonic** (:attr:`Kind.HARMONIC`): a component near 2 or 3 times a lower one that is phase-locked to it
  and whose amplitude goes as a whole power of the lower one's (:func:`~._harmonics.harmonic_evidence`): a
  product of the lower mode's nonlinearity, which is then nonlinear too.
- **product** (:attr:`Kind.PRODUCT`): in a record with a mode that moves with its amplitude, a component
  near a sum or difference ``m f_a + n f_b`` (``|m| + |n|`` 2 or 3) of two stronger candidates that is
  phase-locked to that combination of their phases and whose amplitude goes as ``a_a^|m| a_b^|n|``
  (:func:`~._harmonics.product_evidence`): the intermodulation of a nonlinear element both modes drive.
- **clipping** (:attr:`Kind.CLIPPING`): in a record whose clipped samples could be neither repaired nor
  left behind (the impact's ``clipping`` is ``"kept"``), a component on a harmonic of a stronger one or on a
  combination of two (within its half-power half-width or three standard deviations, folded about the
  Nyquist frequency, and no stronger than clipping makes that product: :func:`~._clipped.clipping_product`):
  the sensor's clipping makes harmonics and intermodulation products of what it clips, not modes.
- **nonlinear** (:attr:`Kind.NONLINEAR`): a component whose frequency or decay rate changes with its
  amplitude by more than a modal table reads, read where the averaged equations of a weakly nonlinear
  oscillator describe its decay (:func:`~._envelope.decay_dependence` on its own free decay; where
  something else is in it, :func:`~._envelope.amplitude_dependence` on its band's analytic signal): beyond
  3 standard errors where the linear decay does not explain it (its residual stands out of the noise:
  :attr:`~.candidates.Candidate.explained`), the frequency beyond 2 where it does; where something else
  is in its free decay, read again with the nonlinear candidates removed by their own averaged equations
  and their squared amplitudes moving it too (a nonlinear mode's chirp, left by its linear decay, hides
  how a weak mode coupled to it moves: :func:`_beside_nonlinear`);
  or a strong chirp that neither reading describes, the averaged equations far closer than the linear
  decay and putting its small-amplitude frequency outside its half-power band (:func:`_undescribed`);
  or that makes a harmonic; or, in a record with a nonlinear mode, a linear candidate that changes
  when read together with the nonlinear ones, each moved by the amplitudes of those that move it
  (:func:`_read_jointly`: a mode moved by a longer-lived one's amplitude shows no change of its own). The
  paper's sweep and refinement identify its equation (and where they miss
  the dependence its free decay shows, the averaged equations fitted there stand:
  :func:`~.linear.envelope_mode`). (A significant misfit alone is common on real records at 60-70 dB: a
  structure is never exactly a sum of damped sinusoids.) Components closer than the wider one's
  half-power half-width (:func:`~sindy_impulse.preprocessing.partition.resolved`) are pieces of one such
  mode (no record tells such modes apart; a sum of close damped sinusoids is how a linear fit follows a
  chirp or a decay rate that changes): the strongest stands for them, the others are
  :attr:`Kind.MERGED` into it.
- **unsupported** (:attr:`Kind.UNSUPPORTED`): a component whose decay the record does not measure (its
  decay rate within three standard deviations of zero), that is no tone (the linear decay does not explain
  it, or the record is too short to show it steady) and that no stable pole of the diagram confirms:
  nothing says it is a mode's free decay (what a short, strongly damped record's decay fit leaves in the
  noise after its modes have died out; a slow wander of a few periods). It is named, not reported as a
  mode with a damping ratio the record does not give, from poles it does not have.
- **linear** (:attr:`Kind.LINEAR`): everything else; its equation comes from its poles.
"""

from __future__ import annotations

import itertools
from dataclasses import replace

import numpy as np
from scipy.fft import next_fast_len

from ..preprocessing.filters import transient_samples
from ..preprocessing.partition import _TOP, peak_bands, resolved
from ._clipped import clipping_product
from ._envelope import (
    CHANGE_SIGMAS,
    ENVELOPE_MISFIT,
    amplitude_dependence,
    decay_dependence,
    joint_dependence,
)
from ._harmonics import NEAR, ORDERS, RATIO_TOL, _evidence, product_evidence
from .candidates import MISFIT_REACH, MISFIT_SHARE
from .kinds import Kind
from .signals import _members, analytic, component, deflated

__all__ = ["classify_candidates", "TONE_SIGMAS", "TONE_SHARE"]

#: A joint reading whose values with every amplitude gone lie further beyond its stretch than twice the
#: change it shows within it (:attr:`~._envelope.AmplitudeDependence.beyond`) is an extrapolation the record
#: does not support: the amplitudes that move the mode have not fallen by a third while it is heard.
MAX_BEYOND = 2.0
#: At most this many candidates are read together (:func:`_read_jointly`): the joint fit's work grows as
#: the cube of their number, and a record with more to read (a real structure's many modes at 60-80 dB,
#: none exactly a damped sinusoid) keeps each one's own reading.
MAX_TOGETHER = 6
#: A component whose decay rate is within this many standard deviations of zero does not decay.
TONE_SIGMAS = 3.0
#: ... and which at most decays this many e-folds over the record at that many standard deviations above its
#: rate (a broad component whose decay the record cannot pin down is no tone).
TONE_DECAY = 3.0
#: ... or whose amplitude before the hit is at least this share of its amplitude after it.
TONE_SHARE = 0.5
#: Largest share of its linear decay's misfit (the square root of its lack of fit: both over the noise)
#: that the averaged equations of a chirp leave (:func:`_undescribed`).
CHIRP_MISFIT = 0.5
#: Fewest periods of a component in the pre-trigger for its amplitude there to be read.
_PRE_PERIODS = 4.0


def classify_candidates(state) -> None:
    """What each candidate needs, from cheap evidence (kind and reasons)."""
    cands = state.candidates
    for c in cands:
        c.kind, c.parent, c.evidence = Kind.LINEAR, None, {}
    _tones(state)
    _pieces(cands)
    _clipping_products(state)
    _amplitude_dependent(state)
    _unconfirmed(state)
    _harmonics(state)  # of whole modes: a chirp's pieces are one parent
    _products(state)
    _read_jointly(state)
    _unsupported(cands)
    counts = {k: sum(c.kind is k for c in cands) for k in Kind}
    again = [f"{c.frequency_hz:.5g} Hz" for c in cands if c.evidence.get("beside_nonlinear")]
    joint = [f"{c.frequency_hz:.5g} Hz" for c in cands if c.evidence.get("joint")]
    state.decide(", ".join(f"{n} {k.value}" for k, n in counts.items() if n) or "no candidate")
    if again:
        state.decide(f"read again with the nonlinear candidates' own equations removed: {', '.join(again)}")
    if joint:
        state.decide(f"read together, each moved by the others' amplitudes: {', '.join(joint)}")


def _unsupported(cands: list) -> None:
    """Linear candidates without a stable pole that do not decay measurably (decay rate within
    :data:`TONE_SIGMAS` standard deviations of zero) and that are not tones: unsupported."""
    for c in cands:
        if c.kind is Kind.LINEAR and not c.stable and not _decays(c):
            c.kind = Kind.UNSUPPORTED


def _decays(c) -> bool:
    """Whether a candidate's decay rate stands :data:`TONE_SIGMAS` standard deviations over zero."""
    return bool(c.decay_rate > TONE_SIGMAS * c.decay_rate_std)


def _pre_trigger_amplitude(state, frequency_hz: float) -> float | None:
    """Amplitude of a sinusoid at ``frequency_hz`` in the pre-trigger (None when it holds too few periods)."""
    pre = state.pre
    n = pre.impact.onset_index
    if n < 16 or n * frequency_hz / pre.fs < _PRE_PERIODS:
        return None
    y = pre.y[:n]
    phase = np.exp(-2j * np.pi * frequency_hz * np.arange(n) / pre.fs)
    return float(2 * abs(np.dot(y - np.mean(y), phase)) / n)


def _tones(state) -> None:
    duration = (state.pre.y.size - state.start) / state.pre.fs
    for c in state.candidates:
        upper = (c.decay_rate + TONE_SIGMAS * c.decay_rate_std) * duration
        still = not _decays(c) and upper < TONE_DECAY and c.explained
        before = _pre_trigger_amplitude(state, c.damped_frequency_hz)
        at_start = float(np.abs(c.amplitude[0]))
        there = before is not None and before >= TONE_SHARE * at_start
        if there or (still and before is None):  # a pre-trigger without it: it began with the hit
            c.kind = Kind.TONE
            c.evidence.update(decay_rate=(c.decay_rate, c.decay_rate_std), pre_trigger_amplitude=before,
                              amplitude=at_start)


def _clipping_products(state) -> None:
    """In a record that stays clipped, linear candidates on a product of clipping one stronger candidate, or
    two, that are no such products themselves (see the module): :attr:`Kind.CLIPPING`, the stronger one as
    parent, the combination as evidence."""
    if state.pre.impact.clipping != "kept":
        return
    cands = state.candidates
    loudest = sorted(range(len(cands)), key=lambda k: -cands[k].height_db)
    for n, j in enumerate(loudest):
        c = cands[j]
        if c.kind is not Kind.LINEAR:
            continue
        reach = max(c.decay_rate / (2 * np.pi), 3 * c.frequency_std_hz)  # its half-power half-width
        stronger = [i for i in loudest[:n] if cands[i].kind in (Kind.LINEAR, Kind.TONE)]
        for group in [*([i] for i in stronger), *itertools.combinations(stronger, 2)]:
            parents = [(cands[i].damped_frequency_hz, cands[i].frequency_std_hz,
                        float(np.abs(cands[i].amplitude[0]))) for i in group]
            found = clipping_product(c.damped_frequency_hz, reach, float(np.abs(c.amplitude[0])), parents,
                                     state.pre.fs)
            if found is not None:
                c.kind, c.parent = Kind.CLIPPING, group[0]
                c.evidence.update(clipping_product=True, frequency_hz=c.frequency_hz, combination=found[0],
                                  combination_offset=found[1] / c.damped_frequency_hz)
                break


#: A component's band for the harmonic test reaches this many half-power half-widths beyond its frequencies.
_REACH = 6.0


def _pair_bands(state, i: int, j: int, order: int) -> tuple:
    """Bands of parent ``i`` and candidate harmonic ``j`` of ``order`` for the harmonic test, one width for
    both: each spans its frequencies (its merged pieces: a nonlinear mode's frequency moves) and
    :data:`_REACH` half-widths beyond them; the harmonic's at least ``order`` times the parent's (it moves
    ``order`` times as far); the parent's as wide as the harmonic's, so that its filter's transient is no
    longer than the harmonic's (which decays ``order`` times as fast). Neither reaches the other's side of
    their midpoint (the other components are removed from both signals: :func:`deflated`)."""
    cands, fs = state.candidates, state.pre.fs

    def span(k: int) -> tuple[float, float]:
        f = [cands[m].damped_frequency_hz for m in _members(state, k)]
        reach = _REACH * cands[k].decay_rate / (2 * np.pi)
        return min(f) - reach, max(f) + reach

    (lo1, hi1), (lo2, hi2) = span(i), span(j)
    half = 0.5 * max(hi2 - lo2, order * (hi1 - lo1))
    f1, f2 = cands[i].damped_frequency_hz, cands[j].damped_frequency_hz
    middle = 0.5 * (f1 + f2)
    return ((max(f1 - half, 0.05 * f1), min(f1 + half, middle)),
            (max(f2 - half, middle), min(f2 + half, _TOP * fs)))


def _heard(cand, noise: float, fs: float, bands) -> int | None:
    """Samples of the free decay the harmonic test needs: until the candidate's fitted envelope falls to its
    band's noise, and both filters' transients after that (the test reads nothing under the noise); None
    (all of it) without a decay to go by."""
    amplitude = float(np.abs(cand.amplitude[0]))
    if not (cand.decay_rate > 0 and amplitude > noise > 0):
        return None
    seconds = np.log(amplitude / noise) / cand.decay_rate
    return next_fast_len(int(seconds * fs) + 2 * max(transient_samples(fs, b) for b in bands) + 16)


def _own(state, k: int, band, keep=()) -> tuple:
    """Candidate ``k``'s own signal from the decay's start (the other components but ``keep`` removed) and
    its noise in ``band``."""
    cand, fs = state.candidates[k], state.pre.fs
    noise = cand.noise_std * np.sqrt(2 * (band[1] - band[0]) / fs)
    return deflated(state, k, keep)[state.start:], noise


def _siblings(state, i: int, order: int) -> list:
    """The candidates named harmonic ``order`` of candidate ``i`` so far."""
    return [k for k, c in enumerate(state.candidates) if c.kind is Kind.HARMONIC and c.parent == i
            and c.evidence["harmonic"]["order"] == order]


def _harmonic_order(cand, parent) -> int | None:
    """The order of :data:`~._harmonics.ORDERS` whose multiple of ``parent``'s frequency ``cand`` lies
    within a harmonic's reach of, or None. A broad component's frequency is known to its half-width (its
    damping ratio is added); a parent the linear decay explains keeps its frequency, and its harmonic lies
    at n times it (within the phase test's tolerance, :data:`~._harmonics.RATIO_TOL`), while a nonlinear
    parent's moves (:data:`~._harmonics.NEAR`)."""
    steady = parent.kind is Kind.LINEAR and parent.explained
    near = (RATIO_TOL if steady else NEAR) + cand.damping_ratio
    ratio = cand.damped_frequency_hz / parent.damped_frequency_hz
    return next((n for n in ORDERS if abs(ratio / n - 1) <= near), None)


def _harmonics(state) -> None:
    """Candidates phase-locked at 2 or 3 times a lower one, its amplitude a whole power of the lower one's."""
    live = sorted((k for k, c in enumerate(state.candidates) if c.kind in (Kind.LINEAR, Kind.NONLINEAR)),
                  key=lambda k: state.candidates[k].frequency_hz)
    if len(live) < 2:
        return
    cands = state.candidates
    for b, j in enumerate(live):
        cand = cands[j]
        for i in live[:b]:
            parent = cands[i]
            if parent.kind is Kind.HARMONIC:
                continue
            order = _harmonic_order(cand, parent)
            if order is None or _energy(cand) > order**4 * _energy(parent):  # stronger than a harmonic can be
                continue
            band1, band2 = _pair_bands(state, i, j, order)
            # a piece of a harmonic named already is tested with it: a chirping harmonic is fitted as a run
            # of pieces, and a piece's envelope and phase alone, its neighbours removed, are not the chirp's
            siblings = _siblings(state, i, order)
            (y1, noise1), (y2, noise2) = _own(state, i, band1), _own(state, j, band2, siblings)
            stop = _heard(cand, noise2, state.pre.fs, (band1, band2))
            y1, y2 = y1[:stop], y2[:stop]
            try:
                e = _evidence(state.pre, None, None, i, parent, band2, noise2, order, cand,
                              nonlinear=_moves(parent), own=(y1, y2, band1, noise1))
            except (ValueError, ArithmeticError, np.linalg.LinAlgError):
                continue
            cand.evidence.setdefault("harmonic_tests", []).append(e)
            if (e["undecided"] and e["resolved"] and parent.kind is Kind.LINEAR
                    and moves_with_amplitude(parent)):
                # a resolved ratio that the parent's movement may explain is left to the parent's backbone:
                # a parent whose free decay shows its frequency move needs its equation (where it has no
                # nonlinear terms, its poles' values stand and the candidate stays a mode; an unresolved
                # test says too little to fit for, and a decay the averaged equations do not describe, as
                # a real structure's often, shows no movement to follow)
                parent.kind = Kind.NONLINEAR
                parent.evidence["harmonic_undecided"] = True
            if e["harmonic"]:
                cand.kind, cand.parent = Kind.HARMONIC, i  # (its merged pieces stay merged into it)
                cand.evidence["harmonic"] = e
                parent.evidence["makes_harmonic"] = order
                if parent.kind is Kind.LINEAR:
                    parent.kind = Kind.NONLINEAR
                _sweep_pieces(state, i, j, order)
                break


#: Intermodulation products tested: ``m f_a + n f_b`` with ``m, n`` non-zero and ``|m| + |n|`` of these
#: (a quadratic element's sums and differences, a cubic one's ``2 f_a +- f_b``).
PRODUCT_ORDERS = (2, 3)


def _combinations(cand, a, b) -> list:
    """``(m, n)`` of :data:`PRODUCT_ORDERS` whose ``m f_a + n f_b`` lies within the phase test's tolerance
    (:data:`~._harmonics.RATIO_TOL`) of ``cand``'s frequency, nearest first: a product's linear decay
    averages the combination of the two modes' averaged frequencies. (Not the harmonic window: on a real
    beam record a mode 0.34 % off the sum of two others, whose filtered phases carried their neighbours'
    leakage, read as locked to it.)"""
    near = RATIO_TOL
    f, fa, fb = cand.damped_frequency_hz, a.damped_frequency_hz, b.damped_frequency_hz
    found = []
    for m, n in itertools.product(range(-2, 3), repeat=2):
        value = m * fa + n * fb
        if m and n and abs(m) + abs(n) in PRODUCT_ORDERS and value > 0 and abs(f / value - 1) <= near:
            found.append((abs(f / value - 1), (m, n)))
    return [counts for _, counts in sorted(found)]


def _product_band(state, k: int, reach: float = 0.0) -> tuple[float, float]:
    """Candidate ``k``'s band for the product test: its frequencies (its merged pieces') and
    :data:`_REACH` half-power half-widths beyond them, at least ``reach`` either side of its frequency; up
    to the midpoints to the nearest other components (the other components are removed from its signal by
    their linear decays, which leave a nonlinear mode's chirp behind)."""
    cands, fs = state.candidates, state.pre.fs
    members = _members(state, k)
    f = [cands[m].damped_frequency_hz for m in members]
    half = _REACH * cands[k].decay_rate / (2 * np.pi)
    centre = cands[k].damped_frequency_hz
    lo, hi = min(min(f) - half, centre - reach), max(max(f) + half, centre + reach)
    others = np.array([c.damped_frequency_hz for q, c in enumerate(cands) if q not in members])
    below, above = others[others < min(f)], others[others > max(f)]
    if below.size:
        lo = max(lo, 0.5 * (below.max() + min(f)))
    if above.size:
        hi = min(hi, 0.5 * (above.min() + max(f)))
    return max(lo, 0.05 * centre), min(hi, _TOP * fs)


def _products(state) -> None:
    """Candidates phase-locked to a sum or difference of two stronger modes' phases, their amplitude going
    as the product of those modes' (:func:`~._harmonics.product_evidence`): intermodulation products of a
    nonlinear element both modes drive, not modes. Tested where one of the two moves with its amplitude
    (the element shows itself there), on the combinations near the candidate's frequency
    (:func:`_combinations`); the first product found names it (:attr:`Kind.PRODUCT`, the stronger mode as
    parent, the evidence kept)."""
    cands = state.candidates
    live = [k for k, c in enumerate(cands) if c.kind in (Kind.LINEAR, Kind.NONLINEAR)]
    movers = {k for k in live if cands[k].kind is Kind.NONLINEAR or moves_with_amplitude(cands[k])}
    if not movers or len(live) < 3:
        return
    for j in live:
        cand = cands[j]
        if cand.evidence.get("makes_harmonic"):
            continue
        stronger = [k for k in live if k != j and _energy(cands[k]) > _energy(cand)]
        for i, k in itertools.combinations(stronger, 2):
            if i not in movers and k not in movers:
                continue
            for m, n in _combinations(cand, cands[i], cands[k]):
                e = _product_test(state, i, k, j, (m, n))
                if e is None:
                    continue
                cand.evidence.setdefault("product_tests", []).append(e)
                if e["product"]:
                    parent = max((i, k), key=lambda q: _energy(cands[q]))
                    cand.kind, cand.parent = Kind.PRODUCT, parent
                    cand.evidence["product"] = dict(e, modes=(cands[i].frequency_hz, cands[k].frequency_hz))
                    break
            if cand.kind is Kind.PRODUCT:
                break


def _product_test(state, i: int, k: int, j: int, counts) -> dict | None:
    """:func:`~._harmonics.product_evidence` of candidate ``j`` as the product ``counts`` of candidates
    ``i`` and ``k``, on their own signals (the other components removed) until ``j`` falls into its band's
    noise; None where the signals give no test."""
    m, n = counts
    band_a, band_b = _product_band(state, i), _product_band(state, k)
    reach = abs(m) * 0.5 * (band_a[1] - band_a[0]) + abs(n) * 0.5 * (band_b[1] - band_b[0])
    band_c = _product_band(state, j, reach)
    # the modes' bands as wide as the product's, so that their filters' transients are no longer than its
    # (a product decays as fast as its modes together)
    half = 0.5 * (band_c[1] - band_c[0])
    bands = (*(_product_band(state, q, half) for q in (i, k)), band_c)
    (ya, na), (yb, nb), (yc, nc) = (_own(state, q, band) for q, band in zip((i, k, j), bands))
    stop = _heard(state.candidates[j], nc, state.pre.fs, bands)
    try:
        return product_evidence((ya[:stop], yb[:stop], yc[:stop]), state.pre.fs, bands, counts, (na, nb, nc))
    except (ValueError, ArithmeticError, np.linalg.LinAlgError):
        return None


def _moves(parent) -> bool:
    """Whether a would-be parent's frequency or decay rate may move along its decay, for the harmonic test:
    its linear decay does not explain it, or the classification has found it nonlinear (pieces of its
    chirp merged into it, or its amplitude dependence). Only a parent that neither says moves keeps a
    constant decay rate, whose harmonic decays exactly a whole number of times as fast
    (:func:`~._harmonics._evidence`)."""
    return not parent.explained or parent.kind is Kind.NONLINEAR


def _sweep_pieces(state, i: int, j: int, order: int) -> None:
    """The other pieces of harmonic ``j`` of mode ``i``: the candidates within ``order`` times the
    frequencies the mode's pieces span (and ``order`` half-power half-widths beyond them), merged into it (a
    hardening mode's third harmonic sweeps three times the mode's span and is fitted as a run of pieces the
    overlap rule may cut in two; each piece a linear decay explains, some confirmed by a pole of the
    diagram). Of a mode in one piece (its frequency steady), only the unconfirmed ones."""
    cands = state.candidates
    members = _members(state, i)
    f = [cands[m].damped_frequency_hz for m in members]
    reach = order * cands[i].decay_rate / (2 * np.pi)
    lo, hi = order * min(f) - reach, order * max(f) + reach
    for m, c in enumerate(cands):
        piece_like = len(members) > 1 or not c.stable
        if m != j and c.kind in (Kind.LINEAR, Kind.NONLINEAR) and piece_like and lo <= c.frequency_hz <= hi:
            for piece in [m, *(k for k, d in enumerate(cands) if d.kind is Kind.MERGED and d.parent == m)]:
                cands[piece].kind, cands[piece].parent = Kind.MERGED, j


#: The amplitude dependence is read on a free decay until its envelope falls this far (dB) under its start
#: (its squared amplitude, which the dependence goes with, to 1e-3 of its start).
_DEPENDENCE_DB = 30.0


def _audible(cand, fs: float) -> int | None:
    """Samples of a candidate's free decay until its linear envelope falls :data:`_DEPENDENCE_DB` under its
    start or to the noise in a band of :data:`_REACH` half-power half-widths either side of it (a fit to
    the whole signal reads it that far); None (all of it) without a decay to go by."""
    noise = cand.noise_std * np.sqrt(2 * 2 * _REACH * cand.decay_rate / (2 * np.pi) / fs)
    amplitude = float(np.abs(cand.amplitude[0]))
    if not (cand.decay_rate > 0 and amplitude > noise > 0):
        return None
    fall = min(np.log(amplitude / noise), _DEPENDENCE_DB / 20 * np.log(10))
    return int(fall / cand.decay_rate * fs) + 1


def _band_dependence(state, k: int, modes: list, neighbours=()):
    """:func:`~._envelope.amplitude_dependence` of candidate ``k`` on its analytic signal in its band (cut
    among the candidates ``modes``; its frequency and decay rate also moved by the squared amplitudes of the
    candidates ``neighbours``), or None."""
    cands, fs = state.candidates, state.pre.fs
    others = [j for j in modes if j != k]
    f = np.array([cands[j].damped_frequency_hz for j in [k, *others]])
    band = peak_bands(f, np.array([cands[j].decay_rate / np.pi for j in [k, *others]]), fs)[0]
    try:
        z, _ = analytic(state, k, band)
    except ValueError:
        return None
    if not z.size:
        return None
    noise = cands[k].noise_std * np.sqrt(2 * (band[1] - band[0]) / fs)
    return amplitude_dependence(z, fs, band[1] - band[0], noise, frequency_hz=cands[k].frequency_hz,
                                neighbours=_squared_amplitudes(state, neighbours))


def _squared_amplitudes(state, neighbours) -> list:
    """``(squared amplitude at the decay's start, decay rate)`` of each candidate of ``neighbours``: their
    linear decays, whose squared amplitudes move a coupled mode's frequency and decay rate."""
    return [(float(np.abs(state.candidates[j].amplitude[0])) ** 2, state.candidates[j].decay_rate)
            for j in neighbours]


def _amplitude_dependent(state) -> None:
    """Candidates whose frequency or decay rate changes with amplitude beyond what a modal table reads
    (:func:`~._envelope.decay_dependence`; a linear decay within the noise does not exclude it when the
    mode is strongly damped or the noise high): nonlinear, or doubtful (the mode's equation decides)."""
    cands = state.candidates
    linear = [k for k, c in enumerate(cands) if c.kind is Kind.LINEAR]
    for k in linear:
        c = cands[k]
        c.evidence["lack_of_fit"] = (c.lack_of_fit, c.lack_of_fit_p)
        e = _free_decay_dependence(state, k)
        if e is None or not e.misfit <= ENVELOPE_MISFIT:  # something else in it: its band's envelope
            e = _band_dependence(state, k, linear) or e
        c.evidence["amplitude_dependence"] = e
        if _depends(c, e):
            c.kind = Kind.NONLINEAR
    _beside_nonlinear(state, linear)
    for k in linear:  # what the second look left undescribed: the paper's fit decides
        c = cands[k]
        if c.kind is Kind.LINEAR and _undescribed(c, c.evidence.get("amplitude_dependence")):
            c.kind = Kind.NONLINEAR
            c.evidence["undescribed"] = True


def _free_decay_dependence(state, k: int, correction: np.ndarray | None = None, neighbours=()):
    """:func:`~._envelope.decay_dependence` of candidate ``k`` on its own free decay (the other candidates
    removed by their linear decays, plus ``correction`` where given), while it stands out of the noise;
    its frequency and decay rate also moved by the squared amplitudes of the candidates ``neighbours``."""
    c, fs = state.candidates[k], state.pre.fs
    stop = _audible(c, fs)
    y = deflated(state, k)[state.start:][:stop]
    if correction is not None:
        y = y + correction[:stop]
    return decay_dependence(y, fs, complex(c.amplitude[0]), c.decay_rate, c.damped_frequency_hz, c.noise_std,
                            _squared_amplitudes(state, neighbours))


def moves_with_amplitude(cand) -> bool:
    """Whether a candidate's frequency moves with its amplitude beyond doubt, however little: its linear
    decay does not explain it (not :attr:`~.candidates.Candidate.explained`), its averaged equations do
    (misfit at most :data:`~._envelope.ENVELOPE_MISFIT`), and its frequency's change stands
    :data:`~._envelope.CHANGE_SIGMAS` standard errors from zero. A change under a modal table's reading
    (:data:`~._envelope.FREQUENCY_CHANGE`) leaves the mode linear; but a nonlinear element that moves it
    that little moves a mode it shares more with, through this mode's amplitude, by a multiple of it (the
    survey's ``coupling`` stage reads the modes together)."""
    e = cand.evidence.get("amplitude_dependence")
    return bool(e is not None and not cand.explained and e.misfit <= ENVELOPE_MISFIT
                and abs(e.frequency_change) > CHANGE_SIGMAS * e.frequency_change_std)


def _undescribed(cand, e) -> bool:
    """Whether a candidate is a strong oscillator's chirp that neither cheap reading describes: its linear
    decay leaves a misfit (not :attr:`~.candidates.Candidate.explained`), the averaged equations of its decay
    leave one too (over :data:`~._envelope.ENVELOPE_MISFIT`: a frequency that moves by several per cent
    goes beyond their first order) but at most :data:`CHIRP_MISFIT` of the linear decay's (they follow
    the chirp the linear decay averages over), and they put its small-amplitude frequency outside its
    linear decay's half-power band (the linear decay's frequency, an average over the amplitudes, is then
    not the mode's). The paper's fit decides; where its equation has no nonlinear terms the mode is linear
    and its poles stand. (A real structure's mode that no sum of damped sinusoids describes exactly leaves
    both readings about as far off, or puts the small-amplitude frequency within its band.)"""
    if e is None or cand.explained or e.misfit <= ENVELOPE_MISFIT or len(e.coefficients) != 4:
        return False
    w0, _, s0, _ = e.coefficients
    small = np.hypot(w0, s0) / (2 * np.pi)
    outside = abs(small - cand.frequency_hz) > cand.damping_ratio * cand.frequency_hz
    return bool(outside and e.misfit <= CHIRP_MISFIT * np.sqrt(cand.lack_of_fit))


def _depends(cand, e) -> bool:
    """Whether a candidate's amplitude dependence ``e`` makes it nonlinear, or doubtful (its equation then
    decides). Of a candidate the linear decay explains, the frequency's change counts, and the decay rate's
    only far beyond its standard errors (:attr:`~._envelope.AmplitudeDependence.decays_nonlinearly`: it
    strays beyond them where the envelope is noisy); a linear decay averages a decay rate that changes with
    the amplitude, and its damping ratio is then not the small-amplitude one."""
    return e is not None and (e.doubtful or e.decays_nonlinearly or (e.nonlinear and not cand.explained))


def _beside_nonlinear(state, linear: list) -> None:
    """A second look at the linear candidates whose free decay the averaged equations do not describe,
    with the nonlinear candidates removed by their own averaged equations instead of their linear decays.

    A nonlinear mode's linear decay leaves its chirp in every other candidate's free decay, where it reads
    as a misfit; a weak mode coupled to it through the same nonlinear element (its frequency moved by the
    strong mode's amplitude) is then not told from one whose decay has something else in it, and its
    linear decay's frequency, an average over a frequency that moves, is reported. Removed by the
    equations that describe it, the strong mode's decay leaves the weak one's own, and the averaged
    equations read there describe it (misfit at most :data:`~._envelope.ENVELOPE_MISFIT`). Where
    they do not (a shared nonlinear element moves it with the strong modes' amplitudes, not its own), a
    mode confirmed by a stable pole is read again with the squared amplitudes of the nonlinear candidates
    whose frequency moves moving its frequency and decay rate too, on its free decay or else its band's
    envelope. The first equations that describe it are its evidence, read as in the first look."""
    cands, fs = state.candidates, state.pre.fs
    n = state.pre.y.size - state.start
    t = np.arange(n) / fs
    corrections = {}  # each nonlinear candidate's linear decay minus its averaged equations' decay
    # the nonlinear candidates whose frequency moves with their amplitude: through the same element, theirs
    # moves the coupled modes' frequencies (one nonlinear by its decay rate alone is left out)
    moving = []
    for j in (j for j, c in enumerate(cands) if c.kind is Kind.NONLINEAR):
        e = cands[j].evidence.get("amplitude_dependence")
        if e is None:  # nonlinear by another test (its pieces): its own free decay read here
            e = _free_decay_dependence(state, j)
        if e is not None and e.changes(CHANGE_SIGMAS, decay=False):
            moving.append(j)
        own = e.free_decay(n, fs) if e is not None and e.misfit <= ENVELOPE_MISFIT else None
        if own is not None and np.all(np.isfinite(own)):  # (equations that grow beyond their decay: not used)
            corrections[j] = sum(component(cands[m], n, fs, t) for m in _members(state, j)) - own
    correction = sum(corrections.values()) if corrections else None
    for k in linear:
        c = cands[k]
        e = c.evidence.get("amplitude_dependence")
        if c.kind is not Kind.LINEAR or e is None or e.misfit <= ENVELOPE_MISFIT:
            continue
        # the simplest equations that describe its decay: its own amplitude moving it, then (for a mode a
        # stable pole confirms: a weak component's envelope has too little in it to say which other
        # amplitudes move it) the nonlinear candidates' amplitudes too
        second = _second_look(state, k, correction, [], linear)
        if second is None and c.stable:
            second = _second_look(state, k, correction, moving, linear)
        if second is not None:
            c.evidence.update(amplitude_dependence=second, beside_nonlinear=True)
            if _depends(c, second):
                c.kind = Kind.NONLINEAR


def _read_jointly(state) -> None:
    """The nonlinear candidates and the linear ones whose averaged equations do not describe their own free
    decay, read together (:func:`~._envelope.joint_dependence`): each one's frequency and decay rate moved
    by the squared amplitudes of those the data show move it.

    A nonlinear element shared by several modes moves each one's frequency and decay rate with the others'
    amplitudes. Read one at a time, the others removed by their linear decays, each keeps the others'
    chirps in its free decay, and a mode moved by a longer-lived one's amplitude shows a linear decay
    whose frequency and decay rate are averages over the other's amplitudes, not its own small-amplitude
    ones. Where the joint reading describes the decay (misfit at most :data:`~._envelope.ENVELOPE_MISFIT`)
    and its values with every amplitude gone lie within the record's reach (:data:`MAX_BEYOND`), it is the
    evidence of each linear candidate read, and of each nonlinear one that other modes' amplitudes move
    (one moved by its own alone keeps its own reading); a linear candidate whose joint reading changes
    beyond a modal table's reading becomes nonlinear. (A chirp's merged pieces stay in the decay the
    reading fits: its one oscillator's equations follow them.) Where more than :data:`MAX_TOGETHER`
    candidates would be read, none is."""
    cands = state.candidates
    read = [k for k, c in enumerate(cands) if c.kind is Kind.NONLINEAR]
    if not read:
        return
    read += [k for k, c in enumerate(cands) if c.kind is Kind.LINEAR and _undescribed_alone(c)]
    if len(read) > MAX_TOGETHER:
        return
    n = state.pre.y.size - state.start
    stops = [min(_audible(cands[k], state.pre.fs) or n, n) for k in read]
    y = deflated(state, read[0], keep=read[1:])[state.start:][:max(stops)]
    drivers = [k for k in read if cands[k].decay_rate > 0]
    starts = [(complex(cands[k].amplitude[0]), cands[k].decay_rate, cands[k].damped_frequency_hz)
              for k in read]
    squared = [(float(np.abs(cands[j].amplitude[0])) ** 2, cands[j].decay_rate, read.index(j))
               for j in drivers]
    readings = joint_dependence(y, state.pre.fs, starts, min(cands[k].noise_std for k in read), stops,
                                drivers=squared)
    for k, e in zip(read, readings):
        if e is None or not e.misfit <= ENVELOPE_MISFIT or e.beyond > MAX_BEYOND:
            continue
        c = cands[k]
        e = replace(e, drivers=tuple(drivers[j] for j in e.drivers))
        if (c.kind is Kind.NONLINEAR and not e.drivers) or _at_their_harmonic(cands, k, read, e.drivers):
            continue
        c.evidence.update(amplitude_dependence=e, joint=True)
        if c.kind is Kind.LINEAR and _depends(c, e):
            c.kind = Kind.NONLINEAR


def _at_their_harmonic(cands: list, k: int, read: list, movers) -> bool:
    """Whether candidate ``k`` and the other candidates that move it in the joint reading (``movers``)
    are a nonlinear mode and its harmonics (:func:`_harmonic_order`): ``k`` linear, within a harmonic's
    reach of nonlinear candidates of ``read`` that are all its movers, or every mover within a harmonic's
    reach of ``k``. A nonlinear mode's harmonic follows that mode's amplitude (and its own, a power of
    it) as a mode the element moves would, and the mode's own amplitude dependence reads as the
    harmonic's amplitude moving it: the joint reading does not make the harmonic a mode, nor the mode
    one moved by another; the harmonic tests decide."""
    c = cands[k]
    parents = {j for j in read
               if cands[j].kind is Kind.NONLINEAR and _harmonic_order(c, cands[j]) is not None}
    if c.kind is Kind.LINEAR and parents and set(movers) <= parents:
        return True
    return bool(movers) and all(_harmonic_order(cands[j], c) is not None for j in movers)


def _undescribed_alone(cand) -> bool:
    """Whether a candidate's own averaged equations were read and do not describe its free decay (misfit
    over :data:`~._envelope.ENVELOPE_MISFIT`)."""
    e = cand.evidence.get("amplitude_dependence")
    return e is not None and not e.misfit <= ENVELOPE_MISFIT


def _second_look(state, k: int, correction, neighbours: list, linear: list):
    """Candidate ``k``'s amplitude dependence with ``correction`` (or None) added to its free decay and its
    frequency and decay rate moved by the squared amplitudes of the ``neighbours`` too, where the averaged
    equations then describe it (misfit at most :data:`~._envelope.ENVELOPE_MISFIT`; with neighbours, else
    read off its band's envelope), or None."""
    if correction is None and not neighbours:
        return None
    e = _free_decay_dependence(state, k, correction, neighbours)
    if neighbours and (e is None or not e.misfit <= ENVELOPE_MISFIT):  # something else in it: its band's
        e = _band_dependence(state, k, linear, neighbours)
    return e if e is not None and e.misfit <= ENVELOPE_MISFIT else None


#: Neighbours closer than this many times the sum of their half-power half-widths overlap in the spectrum.
CLOSE = 3.0


def _runs(cands: list, kinds: tuple, joined) -> list:
    """Runs (by frequency) of candidates of ``kinds`` each ``joined(previous, next)`` to the next, of two or
    more."""
    live = sorted((k for k, c in enumerate(cands) if c.kind in kinds), key=lambda k: cands[k].frequency_hz)
    runs, run = [], live[:1]
    for a, b in zip(live, live[1:]):
        if joined(cands[a], cands[b]):
            run.append(b)
        else:
            runs.append(run)
            run = [b]
    runs.append(run)
    return [r for r in runs if len(r) > 1]


def _merge(cands: list, run: list, evidence: str) -> None:
    """The strongest of ``run`` stands for it as a nonlinear mode; the others (and what was merged into
    them) are merged into it."""
    head = max(run, key=lambda k: _energy(cands[k]))
    cands[head].kind = Kind.NONLINEAR
    members = [k for k in run if k != head]
    members += [j for j, c in enumerate(cands) if c.kind is Kind.MERGED and c.parent in members]
    cands[head].evidence[evidence] = sorted(set(cands[head].evidence.get(evidence, [])) | set(members))
    for k in members:
        cands[k].kind, cands[k].parent = Kind.MERGED, head


def _energy(c) -> float:
    """A component's energy over its decay, ``|A|^2 / (4 sigma)`` (a broad transient's large start is
    short-lived)."""
    return float(np.abs(c.amplitude[0]) ** 2 / (4 * max(c.decay_rate, 1e-12)))


#: Close neighbours are also within this share of each other's frequency (a chirp's pieces are).
CLOSE_SHARE = 0.05


def _beside(mode, other, gap: float) -> bool:
    """Whether ``other``, unconfirmed by the diagram, lies where nonlinear ``mode``'s misfit spreads (the
    decay fit's residual is not searched there either: :data:`~.candidates.MISFIT_REACH`)."""
    reach = max(MISFIT_REACH * mode.damping_ratio * mode.frequency_hz, MISFIT_SHARE * mode.frequency_hz)
    # (never half way to the lower one's second harmonic: what lies there is tested as a harmonic)
    reach = min(reach, 0.5 * min(mode.frequency_hz, other.frequency_hz))
    return mode.kind is Kind.NONLINEAR and not other.stable and gap < reach


def _unconfirmed(state) -> None:
    """Runs of close neighbours (within :data:`CLOSE` times their half-power half-widths and
    :data:`CLOSE_SHARE` of their frequency) that are not sure to be modes of their own: two the
    stabilisation diagram does not confirm (its poles wander with the model order: a frequency that moves
    along the decay), one unconfirmed beside a nonlinear mode, or two the linear decay does not explain (a
    chirp's start and end, each fitted with the other's misfit) that are not modes of their own
    (:func:`_own_modes`). Beside a nonlinear mode they are pieces of it; a run of linear ones is one
    nonlinear mode to be tested as such (``evidence["unconfirmed"]``: :mod:`.identify` keeps them apart
    when one oscillator does not need nonlinear terms to reproduce them)."""
    cands = state.candidates
    index = {id(c): k for k, c in enumerate(cands)}
    own = {}  # (i, j): whether they are modes of their own (each pair read once)

    def joined(a, b) -> bool:
        width = a.damping_ratio * a.frequency_hz + b.damping_ratio * b.frequency_hz
        gap = b.frequency_hz - a.frequency_hz
        close = gap < CLOSE * width and gap < CLOSE_SHARE * a.frequency_hz
        if close and not (a.stable or b.stable):
            return True
        if close and not (a.explained or b.explained):
            pair = (index[id(a)], index[id(b)])
            if pair not in own:
                own[pair] = _own_modes(state, *pair)
            if not own[pair]:
                return True
        return _beside(a, b, gap) or _beside(b, a, gap)

    # until none is left: a merged run is a nonlinear mode, whose neighbours are then beside it
    runs = _joined_runs(cands, joined)
    while runs:
        for run in runs:
            nonlinear = any(cands[k].kind is Kind.NONLINEAR for k in run)
            _merge(cands, run, "pieces" if nonlinear else "unconfirmed")
        runs = _joined_runs(cands, joined)


def _joined_runs(cands: list, joined) -> list:
    """The runs of linear and nonlinear candidates ``joined`` by frequency (:func:`_runs`), less the
    confirmed modes (stable poles of the diagram) farther than a chirp's pieces lie from the run's
    strongest member (:data:`CLOSE_SHARE` of its frequency) that the run joins to it only through others
    (a broad component overlapping two modes' bands, a piece within reach of both): a mode of its own, not
    a piece of its neighbour's. (A chirp spreads stable poles over the frequencies it sweeps.)"""
    def piece(c, head) -> bool:
        near = abs(c.frequency_hz - head.frequency_hz) < CLOSE_SHARE * head.frequency_hz
        return c is head or not c.stable or near or joined(*sorted((c, head), key=lambda d: d.frequency_hz))

    out = []
    for run in _runs(cands, (Kind.LINEAR, Kind.NONLINEAR), joined):
        head = cands[max(run, key=lambda k: _energy(cands[k]))]
        run = [k for k in run if piece(cands[k], head)]
        if len(run) > 1:
            out.append(run)
    return out


def _own_modes(state, i: int, j: int) -> bool:
    """Whether close candidates ``i`` and ``j``, neither of which its linear decay explains, are modes of
    their own rather than pieces of one chirping signal: each is confirmed by a stable pole and its free
    decay (the others removed) is described by its own averaged equations (misfit at most
    :data:`~._envelope.ENVELOPE_MISFIT`: an oscillator, not a harmonic's piece), and one oscillator's
    averaged equations read on their joint free decay (:func:`_joint_dependence`) describe it no better
    than their two linear decays do (a misfit at least the larger of theirs; without a joint reading,
    nothing keeps them apart). A chirp is one oscillator: its pieces' linear decays leave far more than its
    equations (they follow the frequency the pieces average over). Two modes moved by one nonlinear element
    beat: one oscillator does not follow the beating, their two decays do."""
    a, b = state.candidates[i], state.candidates[j]
    for c in (a, b):
        e = c.evidence.get("amplitude_dependence")
        if not (c.stable and e is not None and e.misfit <= ENVELOPE_MISFIT):
            return False
    joint = _joint_dependence(state, i, j)
    return joint is not None and joint.misfit >= np.sqrt(max(a.lack_of_fit, b.lack_of_fit))


def _joint_dependence(state, i: int, j: int):
    """One oscillator's averaged equations (:func:`~._envelope.decay_dependence`) on the joint free decay of
    candidates ``i`` and ``j`` (the others removed) while either stands out of the noise, started from the
    stronger one's linear decay and from their amplitude-weighted mean; the reading with the smaller misfit,
    or None."""
    cands, fs = state.candidates, state.pre.fs
    a, b = cands[i], cands[j]
    y = deflated(state, i, keep=(j,))[state.start:]
    stops = [_audible(c, fs) for c in (a, b)]
    y = y[:max(stops)] if None not in stops else y
    weights = np.abs([a.amplitude[0], b.amplitude[0]])
    head = max((a, b), key=_energy)
    starts = [(complex(head.amplitude[0]), head.decay_rate, head.damped_frequency_hz),
              (complex(a.amplitude[0] + b.amplitude[0]), float(np.average([a.decay_rate, b.decay_rate],
                                                                           weights=weights)),
               float(np.average([a.damped_frequency_hz, b.damped_frequency_hz], weights=weights)))]
    noise = max(a.noise_std, b.noise_std)
    readings = [e for e in (decay_dependence(y, fs, *start, noise) for start in starts) if e is not None]
    return min(readings, key=lambda e: e.misfit) if readings else None


def _pieces(cands: list) -> None:
    """Runs of unresolved components, or of components whose half-power bands overlap and which the linear
    decay does not explain: one mode, which a linear decay does not describe."""
    def joined(a, b) -> bool:
        f, z = (a.frequency_hz, b.frequency_hz), (a.damping_ratio, b.damping_ratio)
        overlap = abs(f[1] - f[0]) < z[0] * f[0] + z[1] * f[1]
        return not resolved(f, z) or (overlap and not (a.explained and b.explained))

    for run in _joined_runs(cands, joined):
        _merge(cands, run, "pieces")

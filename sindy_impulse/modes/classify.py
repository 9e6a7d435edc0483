"""What each candidate of the free decay needs, decided on cheap evidence before anything is fitted.

The decay fit (:mod:`sindy_impulse.poles.decay_fit`) already holds the evidence; the record holds the rest:

- **tone** (:attr:`Kind.TONE`): a component that does not decay (no evidence of a decay: its decay rate
  within three standard deviations of zero; and evidence of little: less than one e-fold over the record
  at three standard deviations above its rate), or that stands as strong before the hit as after it: hum,
  a rotating machine. It is named, not reported as a mode.
- **harmonic** (:attr:`Kind.HARMONIC`): a component near 2 or 3 times a lower one that is phase-locked to it
  and whose amplitude goes as a whole power of the lower one's (:func:`~._harmonics.harmonic_evidence`): a
  product of the lower mode's nonlinearity, which is then nonlinear too.
- **nonlinear** (:attr:`Kind.NONLINEAR`): a component the linear decay does not explain (its residual stands
  out of the noise: :attr:`~.candidates.Candidate.explained`), or that makes a harmonic. The paper's
  sweep and refinement identify its equation. Components closer than the wider one's half-power half-width
  (:func:`~sindy_impulse.preprocessing.partition.resolved`) are pieces of one such mode: the strongest
  stands for them, the others are :attr:`Kind.MERGED` into it.
- **linear** (:attr:`Kind.LINEAR`): everything else; its equation comes from its poles.
"""

from __future__ import annotations

import numpy as np

from ..preprocessing.band import band_noise_rms
from ..preprocessing.partition import resolved
from ._harmonics import NEAR, ORDERS, _analysis_bands, _evidence
from .kinds import Kind

__all__ = ["classify_candidates", "TONE_SIGMAS", "TONE_SHARE"]

#: A component whose decay rate is within this many standard deviations of zero does not decay.
TONE_SIGMAS = 3.0
#: ... or whose amplitude before the hit is at least this share of its amplitude after it.
TONE_SHARE = 0.5
#: Fewest periods of a component in the pre-trigger for its amplitude there to be read.
_PRE_PERIODS = 8.0


def classify_candidates(state) -> None:
    """What each candidate needs, from cheap evidence (kind and reasons)."""
    cands = state.candidates
    for c in cands:
        c.kind, c.parent, c.evidence = Kind.LINEAR, None, {}
    _tones(state)
    _harmonics(state)
    for c in cands:
        if c.kind is Kind.LINEAR and not c.explained:
            c.kind = Kind.NONLINEAR
            c.evidence["lack_of_fit"] = (c.lack_of_fit, c.lack_of_fit_p)
    _pieces(cands)
    counts = {k: sum(c.kind is k for c in cands) for k in Kind}
    state.decide(", ".join(f"{n} {k.value}" for k, n in counts.items() if n) or "no candidate")


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
        upper = c.decay_rate + TONE_SIGMAS * c.decay_rate_std
        still = not c.decay_rate > TONE_SIGMAS * c.decay_rate_std and upper * duration < 1.0
        before = _pre_trigger_amplitude(state, c.damped_frequency_hz)
        at_start = float(np.abs(c.amplitude[0]))
        there = before is not None and before >= TONE_SHARE * at_start
        if still or there:
            c.kind = Kind.TONE
            c.evidence.update(decay_rate=(c.decay_rate, c.decay_rate_std), pre_trigger_amplitude=before,
                              amplitude=at_start)


def _harmonics(state) -> None:
    """Candidates phase-locked at 2 or 3 times a lower one, its amplitude a whole power of the lower one's."""
    cands = [c for c in state.candidates if c.kind is not Kind.TONE]
    if len(cands) < 2:
        return
    pre = state.pre
    ring = pre.y[pre.impact.ringdown_index:]
    bands = _analysis_bands(pre, cands)
    freqs = np.array([c.damped_frequency_hz for c in cands])
    for j, cand in enumerate(cands):
        for i, parent in enumerate(cands[:j]):
            if parent.kind is Kind.HARMONIC:
                continue
            order = next((n for n in ORDERS if abs(freqs[j] / (n * freqs[i]) - 1) <= NEAR), None)
            if order is None or abs(cand.amplitude[0]) > order**2 * abs(parent.amplitude[0]):
                continue
            try:
                e = _evidence(pre, ring, (bands, freqs), i, parent, bands[j],
                              band_noise_rms(pre.peaks.spectrum, bands[j]), order, cand,
                              nonlinear=not parent.explained)
            except (ValueError, ArithmeticError, np.linalg.LinAlgError):
                continue
            cand.evidence.setdefault("harmonic_tests", []).append(e)
            if e["harmonic"]:
                cand.kind, cand.parent = Kind.HARMONIC, state.candidates.index(parent)
                cand.evidence["harmonic"] = e
                parent.evidence["makes_harmonic"] = order
                if parent.kind is Kind.LINEAR:
                    parent.kind = Kind.NONLINEAR
                break


def _pieces(cands: list) -> None:
    """Runs of unresolved components around a nonlinear one: the strongest stands for them all."""
    live = sorted((k for k, c in enumerate(cands) if c.kind in (Kind.LINEAR, Kind.NONLINEAR)),
                  key=lambda k: cands[k].frequency_hz)
    runs, run = [], live[:1]
    for a, b in zip(live, live[1:]):
        pair = (cands[a], cands[b])
        if not resolved(tuple(c.frequency_hz for c in pair), tuple(c.damping_ratio for c in pair)):
            run.append(b)
        else:
            runs.append(run)
            run = [b]
    runs.append(run)
    for run in (r for r in runs if len(r) > 1):
        if all(cands[k].explained for k in run):
            continue  # a resolved fit of unresolved poles explains the data: leave them (rare)
        head = max(run, key=lambda k: abs(cands[k].amplitude[0]))
        cands[head].kind = Kind.NONLINEAR
        cands[head].evidence["pieces"] = [cands[k].frequency_hz for k in run]
        for k in run:
            if k != head:
                cands[k].kind, cands[k].parent = Kind.MERGED, head

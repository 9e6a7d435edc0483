"""One answer per mode, the candidates that are not modes named, and the notes a user should read.

- Tones, harmonics and unsupported components (:mod:`.classify`) become :class:`~.result.Rejected` rows
  with their code and the evidence (decay rate, phase locking, amplitude exponent).
- A harmonic the record could not decide on its own (its phase locking unresolved: a few dB over the noise,
  or seen only just after the hit; or a piece of a moving parent's harmonic sweep, whose band's test does
  not decide) is decided by its parent's equation once fitted: at ``n`` times a
  frequency the nonlinear parent's backbone passes, it is the parent's harmonic
  (:func:`~._harmonics._on_backbone`), unless its envelope decays faster against the parent's than a
  harmonic of that order can (:func:`_steeper_than_harmonic`); harmonics of a nonlinear mode too weak to
  be candidates are named where a spectral peak stands phase-locked at their place
  (:func:`~._harmonics._unseen_harmonics`).
- A nonlinear mode whose equation misreads how its decay rate changes with amplitude gets its decay's
  damping ratio (``source`` "envelope"): the envelope's at zero amplitude where the decay rate changes and
  the equation lacks that change (:func:`~._envelope._missing_damping`), the free decay's constant rate where
  the decay rate does not change and the equation's damping terms change it (:func:`_steady_rate`).
- A mode the harmonic test left undecided whose numbers fit a harmonic of a lower mode (its frequency ratio
  within :data:`~._harmonics.SIGMAS` standard errors of ``n``, its amplitude going at least as the lower
  mode's to the power :data:`~._harmonics.MIN_EXPONENT`) stays a mode, and a note says it may be that
  harmonic and what would tell (:func:`_maybe_harmonics`): a linear mode at ``n`` times another with the
  same damping ratio reads the same on the few periods the test had.
- Pieces merged into a nonlinear mode are said so in a note.
- A mode a band's fit found outside its candidate's half-power band, nearer another candidate that has its
  own mode, is that neighbour's decay, not a second mode (:func:`_found_elsewhere`): rejected as a poor fit.
- Two modes that no record tells apart (closer than the wider one's half-power half-width) at frequencies
  that agree within their standard deviations are one mode found twice (:func:`_found_twice`): the more
  precise one stands.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..preprocessing.partition import resolved
from ._envelope import DECAY_CHANGE, DOUBT_SIGMAS, ENVELOPE_MISFIT, _missing_damping, _model_rate_change
from ._harmonics import _EXPONENT_MARGIN, MIN_EXPONENT, NEAR, SIGMAS, _on_backbone, _reason, _unseen_harmonics
from ._nonlinear import has_nonlinear_terms
from .candidates import persistent_modes
from .kinds import Kind, Reason
from .result import Rejected
from .signals import _members

__all__ = ["reconcile"]


def reconcile(state) -> None:
    """One answer per mode, named rejections, notes."""
    _named(state)
    _found_elsewhere(state)
    _found_twice(state)
    _decided_by_backbones(state)
    _maybe_harmonics(state)
    _envelope_damping(state)
    pre = state.pre
    ring = pre.y[pre.impact.ringdown_index:]
    poles = [m.frequency_hz for m in persistent_modes(state.poles)] if state.poles is not None else []
    state.rejected, unseen = _unseen_harmonics(pre, ring, state.modes, state.rejected, poles)
    state.notes += unseen
    order = np.argsort([m.frequency_hz for m in state.modes], kind="stable")
    state.modes = [state.modes[i] for i in order]
    state.origin = [state.origin[i] for i in order]
    state.decide(f"{len(state.modes)} mode(s), {len(state.rejected)} rejected row(s)")


def _named(state) -> None:
    """Rows for the tones, the harmonics and the unsupported components; notes for merged pieces."""
    cands = state.candidates
    for c in cands:
        if c.kind is Kind.TONE:
            sigma, std = c.evidence.get("decay_rate", (c.decay_rate, c.decay_rate_std))
            before = c.evidence.get("pre_trigger_amplitude")
            before = "" if before is None else f"; amplitude {before:.3g} before the hit"
            why = (f"a tone at {c.damped_frequency_hz:.5g} Hz that does not decay measurably (decay rate "
                   f"{sigma:.3g} +- {std:.2g} 1/s{before}): hum, a machine, or a mode too lightly damped for "
                   "this record; not reported as a mode")
            state.rejected.append(Rejected(c.band_hz, why, state.index, dict(c.evidence), Reason.TONE))
            state.note(why)
        elif c.kind is Kind.UNSUPPORTED:
            why = (f"a component at {c.damped_frequency_hz:.5g} Hz ({c.height_db:.0f} dB) that does not "
                   f"decay measurably (decay rate {c.decay_rate:.3g} +- {c.decay_rate_std:.2g} 1/s), that no "
                   "stable pole of the diagram confirms and that the record does not show to be a steady "
                   "tone: not a mode's free decay (noise the decay fit absorbed after the modes died out, a "
                   "slow wander); not reported as a mode")
            state.rejected.append(Rejected(c.band_hz, why, state.index, dict(c.evidence), Reason.UNSUPPORTED))
        elif c.kind is Kind.CLIPPING:
            e = c.evidence
            why = (f"a peak at {c.damped_frequency_hz:.5g} Hz ({c.height_db:.0f} dB) on {e['combination']} "
                   f"({e['combination_offset']:.2%} off) in a record that stays clipped: a product of the "
                   "clipping, not a mode")
            state.rejected.append(Rejected(c.band_hz, why, state.index, dict(e), Reason.CLIPPING_PRODUCT))
        elif c.kind is Kind.PRODUCT:
            e = c.evidence["product"]
            (m, n), (fa, fb) = e["counts"], e["modes"]
            combination = f"{m} x {fa:.5g} Hz {'+' if n > 0 else '-'} {abs(n)} x {fb:.5g} Hz"
            why = (f"intermodulation product {combination} of two modes, not a mode: phase-locked to their "
                   f"combination (offset {e['offset']:+.1e} +- {e['offset_sigma']:.1g}) and its amplitude "
                   f"goes as theirs (exponent {e['exponent']:.2f}, 1 for a product)")
            state.rejected.append(Rejected(c.band_hz, why, state.index, dict(e), Reason.INTERMODULATION))
            state.note(f"the peak at {c.frequency_hz:.4g} Hz is an {why}")
        elif c.kind is Kind.HARMONIC:
            e = c.evidence["harmonic"]
            parent = next((m for k, m in zip(state.origin, state.modes) if k == c.parent), cands[c.parent])
            why = _reason(parent, e)
            state.rejected.append(Rejected(c.band_hz, why, state.index, e, Reason.HARMONIC))
            state.note(f"the peak at {c.frequency_hz:.4g} Hz is the {why}")
    for c in cands:
        merged = [*c.evidence.get("pieces", []), *c.evidence.get("unconfirmed", [])]  # (kept together)
        pieces = [c.frequency_hz] + [cands[j].frequency_hz for j in merged]
        if len(pieces) > 1 and c.kind is Kind.NONLINEAR:
            listed = ", ".join(f"{f:.5g}" for f in sorted(pieces))
            state.note(f"the components at {listed} Hz are pieces of one nonlinear mode (too close to "
                       f"be modes of their own, which their decays do not show: its frequency or damping "
                       f"changes with amplitude)")


def _found_elsewhere(state) -> None:
    """Modes that a band's fit found at another candidate's place, not at its own: the mode's frequency lies
    outside the half-power bands of its candidate and of the pieces merged into it, and nearer the
    frequency of another candidate that has a mode of its own (a wide band around a weak, strongly damped
    candidate also holds a strong neighbour, whose decay the fit then follows). The neighbour's mode
    stands; this one is a poor fit of its candidate, not a second mode."""
    cands = state.candidates
    reported = set(state.origin)
    drop = set()
    for i, (k, mode) in enumerate(zip(state.origin, state.modes)):
        if mode.source == "poles":
            continue
        own = [cands[m] for m in _members(state, k)]
        if any(abs(mode.frequency_hz - c.frequency_hz) <= c.damping_ratio * c.frequency_hz for c in own):
            continue
        near = min(abs(mode.frequency_hz - c.frequency_hz) for c in own)
        other = min((j for j in reported if j != k),
                    key=lambda j: abs(mode.frequency_hz - cands[j].frequency_hz), default=None)
        if other is None or not abs(mode.frequency_hz - cands[other].frequency_hz) < near:
            continue
        f = cands[k].damped_frequency_hz
        why = (f"the fit of the band of the component at {f:.5g} Hz found a mode at "
               f"{mode.frequency_hz:.5g} Hz, outside that component's half-power band and nearer the mode at "
               f"{cands[other].frequency_hz:.5g} Hz: its neighbour's decay, not a mode of its own")
        evidence = {"frequency_hz": float(mode.frequency_hz), "component_hz": float(f),
                    "neighbour_hz": float(cands[other].frequency_hz)}
        state.rejected.append(Rejected(mode.band_hz, why, state.index, evidence, Reason.POOR_FIT))
        drop.add(i)
    _drop(state, drop)


def _found_twice(state) -> None:
    """One mode found from the bands of two candidates (a broad component beside a nonlinear mode's chirp
    makes a band of its own, whose fit follows that mode): two modes closer than the wider one's
    half-power half-width (:func:`~sindy_impulse.preprocessing.partition.resolved`) whose frequencies
    agree within :data:`~._envelope.DOUBT_SIGMAS` of their combined standard deviations. The more precise
    one stands; the other is a row saying so."""
    drop = set()
    order = sorted(range(len(state.modes)), key=lambda i: state.modes[i].frequency_hz)
    for i, j in zip(order, order[1:]):
        a, b = state.modes[i], state.modes[j]
        if i in drop or j in drop:
            continue
        if resolved((a.frequency_hz, b.frequency_hz), (a.damping_ratio, b.damping_ratio)):
            continue
        spread = np.hypot(a.frequency_std_hz, b.frequency_std_hz)
        if not abs(a.frequency_hz - b.frequency_hz) <= DOUBT_SIGMAS * spread:
            continue
        keep, other = (i, j) if a.frequency_std_hz <= b.frequency_std_hz else (j, i)
        kept, twice = state.modes[keep], state.modes[other]
        why = (f"a mode at {twice.frequency_hz:.6g} +- {twice.frequency_std_hz:.2g} Hz from the band "
               f"{twice.band_hz[0]:.5g}-{twice.band_hz[1]:.5g} Hz is the mode at {kept.frequency_hz:.6g} +- "
               f"{kept.frequency_std_hz:.2g} Hz found again (closer than its half-power half-width, within "
               f"their standard deviations)")
        evidence = {"frequency_hz": float(twice.frequency_hz), "mode_hz": float(kept.frequency_hz),
                    "frequency_std_hz": float(twice.frequency_std_hz)}
        state.rejected.append(Rejected(twice.band_hz, why, state.index, evidence, Reason.DUPLICATE))
        drop.add(other)
    _drop(state, drop)


def _drop(state, drop: set) -> None:
    """The modes (and their candidates in ``state.origin``) at the indices ``drop`` taken out."""
    state.modes = [m for i, m in enumerate(state.modes) if i not in drop]
    state.origin = [k for i, k in enumerate(state.origin) if i not in drop]


def _described(cand):
    """The candidate's amplitude dependence where the averaged equations describe its free decay (misfit
    at most :data:`~._envelope.ENVELOPE_MISFIT`), else None."""
    e = cand.evidence.get("amplitude_dependence")
    return e if e is not None and e.misfit <= ENVELOPE_MISFIT else None


def _steady_decay(cand) -> bool:
    """Whether the candidate's free decay, described by the averaged equations, shows no change of its
    decay rate."""
    e = _described(cand)
    return e is not None and not e.changes(DOUBT_SIGMAS, frequency=False)


def _decided_by_backbones(state) -> None:
    """Modes left undecided by the harmonic test that lie on a nonlinear parent's backbone times ``n``.

    A candidate whose own frequency stays steady while its parent's sweeps is no harmonic
    (:func:`_steady_frequency`), unless another piece of the same harmonic (same parent, same order) is
    named: a harmonic that sweeps is fitted as a run of pieces, and each piece, read with the others
    removed, holds its own stretch of the sweep only."""
    by_candidate = dict(zip(state.origin, state.modes))
    drop, named = set(), set()
    for sweep_known in (False, True):
        for i, (k, mode) in enumerate(zip(state.origin, state.modes)):
            if i in drop:
                continue
            for e in state.candidates[k].evidence.get("harmonic_tests", []):
                if not e.get("undecided"):
                    continue
                f = e["parent_frequency_hz"]
                parent_k = next(
                    (j for j, c in enumerate(state.candidates) if abs(c.frequency_hz - f) <= 1e-9 * f), None)
                parent = by_candidate.get(parent_k)
                if parent is None or not has_nonlinear_terms(parent.model):
                    continue
                if sweep_known != ((parent_k, e["order"]) in named):
                    continue
                if not sweep_known and (_steady_frequency(state.candidates[k], e)
                                        or _steeper_than_harmonic(mode, e)):
                    continue
                if _beyond_its_decay(state.candidates[parent_k], mode, e["order"]):
                    continue
                if _on_backbone(parent, mode, e["order"], e.get("decay_exponent")):
                    e = dict(e, harmonic=True, by_backbone=True, frequency_hz=mode.frequency_hz)
                    why = _reason(parent, e)
                    state.rejected.append(Rejected(mode.band_hz, why, state.index, e, Reason.HARMONIC))
                    state.note(f"the peak at {mode.frequency_hz:.4g} Hz is the {why}")
                    drop.add(i)
                    named.add((parent_k, e["order"]))
                    break
    _drop(state, drop)


def _beyond_its_decay(parent, mode, order: int) -> bool:
    """Whether ``mode`` lies beyond ``order`` times every frequency its would-be parent's own free decay
    passes: farther from it, relatively, than the parent's measured frequency change over its decay (its
    averaged equations, where they describe it and no other mode's amplitude moves it) and
    :data:`~._harmonics.SIGMAS` of its standard errors, widened by the mode's half-power half-width (a
    strongly damped harmonic's decay reads its frequency that far off). A backbone extrapolated to the
    hit's amplitude may pass frequencies the decay never shows."""
    d = _described(parent)
    if d is None or d.drivers:
        return False
    offset = abs(mode.frequency_hz / (order * parent.frequency_hz) - 1)
    reach = abs(d.frequency_change) + SIGMAS * d.frequency_change_std + mode.damping_ratio
    return bool(offset > reach)


def _maybe_harmonics(state) -> None:
    """A note on each mode whose undecided harmonic test fits a harmonic of a lower mode (see the module)."""
    for k, mode in zip(state.origin, state.modes):
        for e in state.candidates[k].evidence.get("harmonic_tests", []):
            ratio, sigma, n = e["frequency_ratio"], e["ratio_sigma"], e["order"]
            if not (e.get("undecided") and not e["resolved"] and np.isfinite(sigma)
                    and abs(ratio - n) <= SIGMAS * sigma and e["exponent"] >= MIN_EXPONENT):
                continue
            state.note(f"the mode at {mode.frequency_hz:.5g} Hz may be harmonic {n} of the mode at "
                       f"{e['parent_frequency_hz']:.5g} Hz: {ratio:.4f} +- {sigma:.1g} times it, its "
                       f"amplitude going as that mode's to the power {e['exponent']:.2f}, over too few "
                       f"periods ({e['periods']:.0f}) to prove the phase locking; a hit at another amplitude "
                       "tells (a harmonic's share of its mode changes with the amplitude, a mode's does not)")
            break


def _steeper_than_harmonic(mode, e: dict) -> bool:
    """Whether the candidate's envelope decays faster against its would-be parent's than a harmonic of
    order ``n`` can: a term of power at most ``n`` makes harmonic ``n``, whose amplitude goes as the
    parent's to that power, so an exponent beyond ``n`` + :data:`~._harmonics._EXPONENT_MARGIN` by
    :data:`~._harmonics.SIGMAS` standard errors is a mode that decays faster of its own. Only where the
    candidate's band holds the whole sweep a harmonic would make over the test's stretch (``n`` times the
    parent's, ``e["parent_sweep"]``): a piece of a sweeping harmonic has the piece's envelope, which rises
    and falls as the sweep passes, not the harmonic's.

    Examples
    --------
    >>> from types import SimpleNamespace as Mode
    >>> e = dict(order=2, exponent=4.69, exponent_sigma=0.40, parent_sweep=0.013, parent_frequency_hz=42.6)
    >>> wide, piece = Mode(band_hz=(60.3, 120.5)), Mode(band_hz=(85.0, 86.0))
    >>> _steeper_than_harmonic(wide, e), _steeper_than_harmonic(piece, e)
    (True, False)
    """
    order, p, p_sigma = e["order"], e.get("exponent", np.nan), e.get("exponent_sigma", np.nan)
    sweep = e.get("parent_sweep", np.nan)
    if not (np.isfinite(p) and np.isfinite(p_sigma) and np.isfinite(sweep)):
        return False
    centre = order * e["parent_frequency_hz"]
    lo, hi = mode.band_hz
    holds = lo <= centre * (1 - sweep) and centre * (1 + sweep) <= hi
    return bool(holds and p - SIGMAS * p_sigma > order + _EXPONENT_MARGIN)


def _steady_frequency(cand, e: dict) -> bool:
    """Whether the candidate's own free decay shows its frequency steady where a harmonic's could not be: a
    harmonic's frequency is ``n`` times its mode's at every instant, so over the stretch of the harmonic test
    it sweeps as the mode does (``e["parent_sweep"]``, relative). Steady: the averaged equations describe the
    candidate's decay (misfit at most :data:`~._envelope.ENVELOPE_MISFIT`) and its frequency's relative
    change over its amplitudes, at :data:`~._harmonics.SIGMAS` standard errors, stays under half that
    sweep. The backbone then does not name it (its phase locking unresolved over few independent samples,
    a mode of its own 2.02 times as high as a softening mode that swept 2.2 % read as on its backbone). A
    sweep beyond :data:`~._harmonics.NEAR` is no measure of the parent's frequency (its harmonic would
    have left the window the test looks in: the pieces' phase slopes read noise) and shows nothing."""
    d, sweep = _described(cand), e.get("parent_sweep", np.nan)
    if d is None or not np.isfinite(sweep) or sweep > NEAR:
        return False
    return bool(abs(d.frequency_change) + SIGMAS * d.frequency_change_std < 0.5 * sweep)


def _envelope_damping(state) -> None:
    """The damping ratio of the decay itself for a nonlinear mode whose equation misreads how its decay rate
    changes with amplitude; two readings of one decay rate, where the equation's damping terms disagree
    with the decay they were fitted to, the decay's stands:

    - the decay rate changes (its free decay, read against the averaged equations that describe it, beyond
      :data:`~._envelope.DOUBT_SIGMAS` standard errors and :data:`~._envelope.DECAY_CHANGE`) and the
      equation lacks that change (:func:`~._envelope._missing_damping`): the envelope's damping ratio at
      zero amplitude;
    - the decay rate does not change, and the equation's damping terms change it over the same amplitudes
      by more than :data:`~._envelope.DECAY_CHANGE` beyond the decay's own change (:func:`_steady_rate`: a
      large linear damping and a nonlinear one of opposite sign that average to the decay's rate over the
      decay, but not at its small-amplitude end): the free decay's constant rate.
    """
    for i, (k, mode) in enumerate(zip(state.origin, state.modes)):
        cand = state.candidates[k]
        if cand.kind is not Kind.NONLINEAR or mode.source != "equation":
            continue
        steady = _steady_decay(cand)
        found = _steady_rate(cand, mode) if steady else _missing_damping(mode)
        if found is None:
            continue
        zeta, zeta_std, change, model_change = found
        where = f"mode at {mode.frequency_hz:.6g} Hz"
        linear = f"the model's linear part: {mode.damping_ratio:.4g}"
        if steady:
            state.note(f"{where}: its free decay's rate does not change with its amplitude "
                       f"({change:+.0%}), its model's damping terms change it by {model_change:+.0%} over "
                       f"the same amplitudes; the damping ratio {zeta:.4g} is the free decay's ({linear})")
        else:
            state.note(f"{where}: its decay rate changes by {change:+.0%} over the decay, its model's "
                       f"terms give {model_change:+.0%}; the damping ratio {zeta:.4g} is the decay "
                       f"envelope's at zero amplitude ({linear})")
        state.modes[i] = replace(mode, damping_ratio=zeta, damping_ratio_std=zeta_std, source="envelope")


def _steady_rate(cand, mode):
    """``(damping ratio, its std, the decay's relative change, the model's)`` of a candidate whose steady free
    decay (:func:`_steady_decay`) its mode's equation contradicts: the equation's damping terms change the
    decay rate between the largest and the smallest amplitude the averaged equations read by more than
    :data:`~._envelope.DECAY_CHANGE` plus :data:`~._envelope.DOUBT_SIGMAS` standard errors beyond the
    decay's change (the model's relative to the free decay's constant rate, the decay's to the averaged
    equations' rate at zero amplitude: the same rate within the change the test allows); the damping ratio
    and its std are the constant rate's, the linear decay fit's (the candidate's own). Else None (also where
    the model's change cannot be computed)."""
    e = _described(cand)
    if e is None or not cand.decay_rate > 0:
        return None
    omega = 2 * np.pi * mode.frequency_hz
    rates = [_model_rate_change(mode.model, omega, a) for a in (max(e.amplitude), min(e.amplitude))]
    if None in rates:
        return None
    model_change = (rates[0] - rates[1]) / cand.decay_rate
    if abs(model_change - e.decay_change) <= DECAY_CHANGE + DOUBT_SIGMAS * e.decay_change_std:
        return None
    return cand.damping_ratio, cand.damping_ratio_std, e.decay_change, model_change

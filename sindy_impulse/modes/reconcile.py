"""One answer per mode, the candidates that are not modes named, and the notes a user should read.

- Tones, harmonics and unsupported components (:mod:`.classify`) become :class:`~.result.Rejected` rows
  with their code and the evidence (decay rate, phase locking, amplitude exponent).
- A harmonic the record could not decide on its own (its phase locking unresolved: a few dB over the noise,
  or seen only just after the hit) is decided by its parent's equation once fitted: at ``n`` times a
  frequency the nonlinear parent's backbone passes, it is the parent's harmonic
  (:func:`~._harmonics._on_backbone`); harmonics of a nonlinear mode too weak to be candidates are named
  where a spectral peak stands phase-locked at their place (:func:`~._harmonics._unseen_harmonics`).
- A nonlinear mode whose equation lacks the amplitude-dependent damping its decay envelope shows gets the
  envelope's damping ratio at zero amplitude (:func:`~._envelope._missing_damping`; ``source`` "envelope").
- Pieces merged into a nonlinear mode are said so in a note.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ._envelope import DOUBT_SIGMAS, ENVELOPE_MISFIT, _missing_damping
from ._harmonics import SIGMAS, _on_backbone, _reason, _unseen_harmonics
from ._nonlinear import has_nonlinear_terms
from .candidates import persistent_modes
from .kinds import Kind, Reason
from .result import Rejected

__all__ = ["reconcile"]


def reconcile(state) -> None:
    """One answer per mode, named rejections, notes."""
    _named(state)
    _decided_by_backbones(state)
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
            state.note(f"the components at {listed} Hz, closer than their "
                       f"half-power bandwidth, are one nonlinear mode (its frequency or damping changes with "
                       f"amplitude)")


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
    """Modes left undecided by the harmonic test that lie on a nonlinear parent's backbone times ``n``."""
    by_candidate = dict(zip(state.origin, state.modes))
    drop = set()
    for i, (k, mode) in enumerate(zip(state.origin, state.modes)):
        for e in state.candidates[k].evidence.get("harmonic_tests", []):
            if not e.get("undecided"):
                continue
            f = e["parent_frequency_hz"]
            parent_k = next(
                (j for j, c in enumerate(state.candidates) if abs(c.frequency_hz - f) <= 1e-9 * f), None)
            parent = by_candidate.get(parent_k)
            if parent is None or not has_nonlinear_terms(parent.model) or _steady_frequency(
                    state.candidates[k], e):
                continue
            if _on_backbone(parent, mode, e["order"]):
                e = dict(e, harmonic=True, by_backbone=True, frequency_hz=mode.frequency_hz)
                why = _reason(parent, e)
                state.rejected.append(Rejected(mode.band_hz, why, state.index, e, Reason.HARMONIC))
                state.note(f"the peak at {mode.frequency_hz:.4g} Hz is the {why}")
                drop.add(i)
                break
    state.modes = [m for i, m in enumerate(state.modes) if i not in drop]
    state.origin = [k for i, k in enumerate(state.origin) if i not in drop]


def _steady_frequency(cand, e: dict) -> bool:
    """Whether the candidate's own free decay shows its frequency steady where a harmonic's could not be: a
    harmonic's frequency is ``n`` times its mode's at every instant, so over the stretch of the harmonic test
    it sweeps as the mode does (``e["parent_sweep"]``, relative). Steady: the averaged equations describe the
    candidate's decay (misfit at most :data:`~._envelope.ENVELOPE_MISFIT`) and its frequency's relative
    change over its amplitudes, at :data:`~._harmonics.SIGMAS` standard errors, stays under half that
    sweep. The backbone then does not name it (its phase locking unresolved over few independent samples,
    a mode of its own 2.02 times as high as a softening mode that swept 2.2 % read as on its backbone)."""
    d, sweep = _described(cand), e.get("parent_sweep", np.nan)
    if d is None or not np.isfinite(sweep):
        return False
    return bool(abs(d.frequency_change) + SIGMAS * d.frequency_change_std < 0.5 * sweep)


def _envelope_damping(state) -> None:
    """The envelope's damping ratio at zero amplitude for a nonlinear mode whose equation lacks the change
    of the decay rate its band's envelope shows (:func:`~._envelope._missing_damping`), unless its free
    decay, read against the averaged equations that describe it, showed a decay rate that does not change
    (within :data:`~._envelope.DOUBT_SIGMAS` standard errors or :data:`~._envelope.DECAY_CHANGE`): two
    readings of one decay rate, the one of the whole free decay the sharper."""
    for i, (k, mode) in enumerate(zip(state.origin, state.modes)):
        cand = state.candidates[k]
        if cand.kind is not Kind.NONLINEAR or mode.source != "equation" or _steady_decay(cand):
            continue
        found = _missing_damping(mode)
        if found is None:
            continue
        zeta, zeta_std, change, model_change = found
        state.note(f"mode at {mode.frequency_hz:.6g} Hz: its decay rate changes by {change:+.0%} over the "
                   f"decay, its model's terms give {model_change:+.0%}; the damping ratio {zeta:.4g} is the "
                   f"decay envelope's at zero amplitude (the model's linear part: {mode.damping_ratio:.4g})")
        state.modes[i] = replace(mode, damping_ratio=zeta, damping_ratio_std=zeta_std, source="envelope")

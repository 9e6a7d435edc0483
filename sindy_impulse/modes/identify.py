"""One equation per mode: from its poles where the mode is linear, the paper's fit where it is not.

Each candidate's route follows from its kind (:mod:`.classify`):

- :attr:`~.kinds.Kind.LINEAR`: :func:`.linear.linear_mode`, the oscillator of its poles (no sweep); where
  it was read together with the modes a nonlinear element moves (:func:`~.classify._read_jointly`), the
  oscillator of that reading (its linear decay fitted with their chirps described, not left in its own);
- :attr:`~.kinds.Kind.NONLINEAR`: the paper's machinery on its band signal (:func:`.band_fit.fit_band`:
  derivative states, the threshold sweep scored on the simulation error, the bounded refinement), its band
  spanning the pieces merged into it, the other components removed (:mod:`.signals`); where the band cut
  among the nonlinear modes keeps too few periods, its own band regardless of its neighbours (removed).
  When that gives no mode (its model does not reproduce the band, or its mode is not damped) the decay
  fit's values stand, with a note: an average over the decay's amplitudes, not the small-amplitude limit.
  Where other modes' amplitudes move it (the joint reading's ``drivers``), the averaged equations give its
  values with every amplitude gone: an equation of its band alone holds its own amplitude only;
- a mode carried by the decay fit's values alone is rejected where nothing else supports it: no stable
  pole, a linear decay that does not explain it and does not reproduce its band (:func:`_supported`; the
  paper's fit on such a band gives no better: a damping ratio of tens of per cent, or a mode elsewhere);
- tones, harmonics and merged pieces get no mode of their own (:mod:`.reconcile` names them).

The candidates are independent: with ``n_jobs`` they run in parallel (joblib), each with one BLAS thread,
and the result equals the serial run's.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import replace

import numpy as np

from .._utils.threads import one_thread
from ..preprocessing.partition import peak_bands
from ._envelope import DOUBT_SIGMAS
from ._states import free_decay_states
from .band_fit import MAX_FIT_ERROR, fit_band, fit_states, mode_of_states, with_uncertainty
from .classify import TONE_SIGMAS
from .kinds import Kind, Reason
from .linear import (
    envelope_mode,
    impulse_of,
    linear_amplitude,
    linear_mode,
    residue_of,
    shape_of,
    with_values_of,
)
from .result import Mode, Rejected
from .signals import _members, _noise_spectrum, band_signal, deflated, free_decay, mode_bands

__all__ = ["identify_candidates"]

#: An equation's nonlinear terms stand out of the noise where noise alone gives them as large with a chance
#: under this (:attr:`~.result.Mode.nonlinear_chance`): one term's at :data:`~._envelope.DOUBT_SIGMAS`.
NONLINEAR_LEVEL = math.erfc(DOUBT_SIGMAS / math.sqrt(2))


def identify_candidates(state) -> None:
    """One equation per mode: from its poles where linear, the paper's fit where not."""
    mode_bands(state)
    todo = [k for k, c in enumerate(state.candidates) if c.kind in (Kind.LINEAR, Kind.NONLINEAR)]
    if todo:  # what every candidate reads, once, before any worker copies the state
        deflated(state, todo[0])
        _noise_spectrum(state)
    results = _map(state, todo, state.options.n_jobs)
    for outs in results:
        for j, out in outs:
            if isinstance(out, Mode):
                state.modes.append(out)
                state.origin.append(j)
            else:
                state.rejected.append(out)
    routes = [state.candidates[k].kind.value for k in todo]
    state.decide(f"{routes.count('linear')} from their poles, {routes.count('nonlinear')} by the paper's "
                 f"fit; {len(state.modes)} mode(s)")


def _map(state, todo: list, n_jobs) -> list:
    if n_jobs in (None, 1) or len(todo) < 2:
        return [_one(state, k) for k in todo]
    from joblib import Parallel, delayed

    chunks = [todo[i::abs(n_jobs) if n_jobs > 0 else 2] for i in range(min(len(todo), abs(n_jobs) or 2))]
    done = Parallel(n_jobs=n_jobs)(delayed(_chunk)(state, chunk) for chunk in chunks)
    found = {k: out for chunk, outs in zip(chunks, done) for k, out in zip(chunk, outs)}
    return [found[k] for k in todo]


def _chunk(state, chunk: list) -> list:
    return [_one(state, k) for k in chunk]


def _one(state, k: int) -> list:
    """``[(candidate, mode or rejection)]`` of candidate ``k`` (and of the neighbours it was tested with);
    a failure stays the candidate's."""
    cand = state.candidates[k]
    try:
        with one_thread(), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if cand.kind is Kind.LINEAR:
                outs = [(k, _jointly_read(state, k) or linear_mode(state, k) or nonlinear_mode(state, k))]
            else:
                outs = [(j, _measured(state, j, out))
                        for j, out in _kept(state, k, nonlinear_mode(state, k, uncertainty=False))]
            return [(j, _supported(state, j, out)) for j, out in outs]
    except Exception as err:  # noqa: BLE001 - one candidate's failure must not abort the survey
        return [(k, Rejected(cand.band_hz, f"the identification failed ({type(err).__name__}: {err})",
                             state.index, {"error": type(err).__name__, "message": str(err)},
                             Reason.FIT_FAILED))]


def _unsupported(state, k: int, out) -> bool:
    """Whether nothing supports candidate ``k`` as a mode: the mode ``out`` carries the decay fit's values
    (no equation reproduced it) from a model whose fit error exceeds :data:`~.band_fit.MAX_FIT_ERROR`, and
    either no stable pole of the diagram confirms it and its linear decay does not explain it (what a
    linear decay fit leaves beside a nonlinear mode's chirp or a slow drift: a broad component that changes
    from fit to fit), or its damping ratio lies within :data:`~.classify.TONE_SIGMAS` of its standard
    deviations of zero (the record does not measure its decay: what a short record of strongly damped modes
    leaves in the noise after they died out, 15 dB over it, read 0.35 +- 0.51 % damped with a fit error of
    0.70, beside a pole found at 3 of the diagram's 12 orders)."""
    cand = state.candidates[k]
    if not (isinstance(out, Mode) and out.source == "poles" and out.fit_error > MAX_FIT_ERROR):
        return False
    unconfirmed = not cand.stable and not cand.explained
    return unconfirmed or _unmeasured(out)


def _supported(state, k: int, out):
    """``out``, or its rejection where nothing supports candidate ``k`` as a mode (:func:`_unsupported`)."""
    if not _unsupported(state, k, out):
        return out
    cand = state.candidates[k]
    if not cand.stable and not cand.explained:
        first = (f"no stable pole confirms the component at {cand.damped_frequency_hz:.5g} Hz, its linear "
                 f"decay does not explain it (lack of fit {cand.lack_of_fit:.3g} x the noise)")
    else:
        first = (f"the record does not measure the decay of the component at {cand.damped_frequency_hz:.5g} "
                 f"Hz (damping ratio {out.damping_ratio:.3g} +- {out.damping_ratio_std:.2g})")
    why = (f"{first} and that decay does not reproduce its band (fit error {out.fit_error:.3g} > "
           f"{MAX_FIT_ERROR}): not reported as a mode")
    evidence = {"fit_error": float(out.fit_error), "lack_of_fit": float(cand.lack_of_fit),
                "frequency_hz": float(out.frequency_hz), "damping_ratio": float(out.damping_ratio)}
    return Rejected(cand.band_hz, why, state.index, evidence, Reason.POOR_FIT)


def _kept(state, k: int, out) -> list:
    """What nonlinear candidate ``k``'s paper's fit ``out`` gives: its unconfirmed neighbours apart where it
    has no nonlinear equation (:func:`_apart`), else ``out``, the averaged equations' mode
    (:func:`_envelope_instead`) or, where both readings call it linear, its poles' mode
    (:func:`_sent_on_doubt`, :func:`_agreeing_poles`). The fit's standard deviations are computed for a
    mode that is kept only (:func:`~.band_fit.with_uncertainty`); where that fails, the fit failed (as if
    inside it: the decay fit's values instead, :func:`_linear_instead`)."""
    if "unconfirmed" in state.candidates[k].evidence and not _nonlinear_equation(out):
        return _apart(state, k)
    kept = _envelope_instead(state, k, out)
    if kept is out:
        if _sent_on_doubt(state, k, out) and not _nonlinear_equation(out):
            return [(k, linear_mode(state, k) or out)]  # both readings call it linear
        done = with_uncertainty(out, state.index)
        if done is not out:  # the standard deviations failed: the fit failed
            return _kept(state, k, _linear_instead(state, k, f"the paper's fit gave no mode ({done.reason})"))
        if _sent_on_doubt(state, k, out) and not _nonlinear_equation(out, significant=True):
            linear = linear_mode(state, k)  # its nonlinear terms stand out of nothing ...
            if linear is not None and not _needs_its_terms(linear, out):  # ... and nothing needs them
                return [(k, linear)]
        return [(k, _agreeing_poles(state, k, out) or out)]
    return [(k, kept)]


#: An equation's nonlinear terms are needed where its poles' linear oscillator reproduces the band with a
#: fit error more than this many times the equation's (the poles are the best linear decay of the band:
#: extra terms fitted to a linear mode's noise lower its fit error a little, not by this factor).
NEEDED_GAIN = 2.0


def _needs_its_terms(linear, out) -> bool:
    """Whether the equation ``out`` needs its nonlinear terms: the candidate's poles' mode ``linear``
    reproduces its band with a fit error over :data:`NEEDED_GAIN` times the equation's. The chance that
    noise alone gives the terms as large (:attr:`~.result.Mode.nonlinear_chance`) reads the coefficients
    against their standard deviations; the simulation error reads what they do: a cubic spring that moves a
    lightly damped mode 2.5 % over its decay, its terms' chance 0.10, left the linear oscillator a fit
    error of 0.22 beside the equation's 0.004, and its average frequency 2.7 % above the small-amplitude
    one.

    Examples
    --------
    >>> from types import SimpleNamespace as Mode
    >>> _needs_its_terms(Mode(fit_error=0.22), Mode(fit_error=0.004))
    True
    >>> _needs_its_terms(Mode(fit_error=0.012), Mode(fit_error=0.010))
    False
    """
    return bool(linear.fit_error > NEEDED_GAIN * out.fit_error)


def _measured(state, k: int, out):
    """``out``, or candidate ``k``'s poles' mode (:func:`.linear.linear_mode`) where ``out``, its equation
    or averaged equations without nonlinear terms, does not measure its damping (a damping ratio within
    :data:`~.classify.TONE_SIGMAS` of its standard deviations of zero) and the linear decay, confirmed by a
    stable pole, does: of two linear readings, the one that measures it. A weak, strongly damped mode whose
    frequency other modes' amplitudes move leaves its own reading little to go on: a 1.18 %-damped mode
    34 dB under its neighbours read 0.29 +- 0.22 %, while its stable pole read 1.13 %. An equation with
    nonlinear terms of its own amplitude keeps its values whatever its damping's standard deviation: its
    frequency and damping are the small-amplitude ones, which a linear decay's average over its chirp is
    not (a softening mode read 7.5 % under its equation's). Terms that carry the amplitudes of the modes
    that move it (the joint reading's ``drivers``) do not: while a strongly damped mode dies out, the
    lightly damped modes that move it hardly decay, and its linear decay reads its damping at one shift.
    """
    from ._nonlinear import has_nonlinear_terms

    cand = state.candidates[k]
    if not (isinstance(out, Mode) and out.source in ("equation", "envelope") and _unmeasured(out)
            and cand.stable and not _unmeasured(cand)):
        return out
    e = cand.evidence.get("amplitude_dependence")
    moved_by_others = out.source == "envelope" and e is not None and bool(e.drivers)
    if has_nonlinear_terms(out.model) and not moved_by_others:
        return out
    linear = linear_mode(state, k)
    if linear is None:
        return out
    note = (f"its own reading ({out.frequency_hz:.6g} Hz, {100 * out.damping_ratio:.3g} +- "
            f"{100 * out.damping_ratio_std:.2g} %) does not measure its damping: its linear decay's values "
            "are reported, an average over the decay's amplitudes")
    return replace(linear, uncertainty_note="; ".join(filter(None, [note, linear.uncertainty_note])))


def _unmeasured(values) -> bool:
    """Whether a damping ratio lies within :data:`~.classify.TONE_SIGMAS` of its standard deviations of
    zero: the record does not measure the decay.

    Examples
    --------
    >>> from types import SimpleNamespace as M
    >>> _unmeasured(M(damping_ratio=0.0029, damping_ratio_std=0.0022))
    True
    >>> _unmeasured(M(damping_ratio=0.0113, damping_ratio_std=0.0005))
    False
    """
    return not values.damping_ratio > TONE_SIGMAS * values.damping_ratio_std


def _single_equation(state, k: int, out) -> bool:
    """Whether ``out`` is an equation of the paper's fit of candidate ``k`` alone (no pieces merged)."""
    return isinstance(out, Mode) and out.source == "equation" and len(_members(state, k)) == 1


def _doubtful(state, k: int, out) -> bool:
    """Whether ``out`` is the paper's fit of a single component that the linear decay explains (a candidate
    sent to it because its frequency's change with amplitude was doubtful)."""
    return _single_equation(state, k, out) and state.candidates[k].explained


def _sent_on_doubt(state, k: int, out) -> bool:
    """Whether ``out`` is the paper's fit of a single component sent to it on doubt: a doubtful change of
    its frequency (:func:`_doubtful`), neither its linear decay nor its averaged equations describing it
    (:func:`~.classify._undescribed`), or a higher candidate's harmonic test left to its backbone
    (``harmonic_undecided``: its decay moves, and the test could not tell its harmonic). Where its
    equation has no nonlinear terms, both readings call the mode linear, and its poles' values, the sharper
    reading with their calibrated standard deviations, are its answer, as for any linear mode."""
    cand = state.candidates[k]
    return _single_equation(state, k, out) and (cand.explained or bool(cand.evidence.get("undescribed"))
                                                or bool(cand.evidence.get("harmonic_undecided")))


def _agreeing_poles(state, k: int, out) -> Mode | None:
    """Its poles' mode where a doubtful candidate's (:func:`_doubtful`) free decay did not show the change
    beyond doubt (not :attr:`~._envelope.AmplitudeDependence.nonlinear`) and its equation's small-amplitude
    frequency and damping ratio agree with its poles' within :data:`~._envelope.DOUBT_SIGMAS` of their
    combined standard deviations: the nonlinear terms a weak band's sweep keeps then move nothing that the
    linear decay does not say within what the fit can tell, and both readings call the mode linear, as
    where the equation has no such terms. Else None."""
    cand = state.candidates[k]
    e = cand.evidence.get("amplitude_dependence")
    if not _doubtful(state, k, out) or e is None or e.nonlinear:
        return None
    # the poles' values are the candidate's (:func:`~.linear.linear_mode`): its mode is built only if kept
    pairs = ((out.frequency_hz, out.frequency_std_hz, cand.frequency_hz, cand.frequency_std_hz),
             (out.damping_ratio, out.damping_ratio_std, cand.damping_ratio, cand.damping_ratio_std))
    agree = all(abs(a - b) <= DOUBT_SIGMAS * np.hypot(sa, sb) for a, sa, b, sb in pairs)
    return linear_mode(state, k) if agree else None


def _envelope_instead(state, k: int, out):
    """The averaged equations' mode (:func:`.linear.envelope_mode`) where the candidate's free decay shows
    an amplitude dependence (:attr:`~._envelope.AmplitudeDependence.nonlinear`) that the paper's fit did
    not give (a linear equation, or none), or where other modes' amplitudes move it (the joint reading's
    ``drivers``: an equation of its band alone holds its own amplitude only, and cannot say what the mode
    is with theirs gone)."""
    cand = state.candidates[k]
    e = cand.evidence.get("amplitude_dependence")
    # its free decay's fit had its pieces removed as linear decays (not the joint reading's)
    pieces = len(_members(state, k)) > 1 and not cand.evidence.get("joint")
    if e is None or pieces or not e.nonlinear or (_nonlinear_equation(out) and not e.drivers):
        return out
    return envelope_mode(state, k, e) or out


def _jointly_read(state, k: int):
    """A linear candidate's mode from the averaged equations of the joint free decay it was read in
    (:func:`~.classify._read_jointly`), or None: beside modes whose amplitudes move their frequencies, its
    linear decay is fitted there with their chirps described, not left in its free decay."""
    e = state.candidates[k].evidence.get("amplitude_dependence")
    return envelope_mode(state, k, e) if state.candidates[k].evidence.get("joint") else None


def _nonlinear_equation(out, significant: bool = False) -> bool:
    """Whether ``out`` is an equation with nonlinear terms; with ``significant``, terms that noise alone
    gives as large with a chance under :data:`NONLINEAR_LEVEL` (:attr:`~.result.Mode.nonlinear_chance`,
    all of them together; where it was not computed, any term counts)."""
    from ._nonlinear import has_nonlinear_terms

    if not (isinstance(out, Mode) and out.source == "equation" and has_nonlinear_terms(out.model)):
        return False
    return not (significant and out.nonlinear_chance >= NONLINEAR_LEVEL)


def _apart(state, k: int) -> list:
    """Unconfirmed neighbours that one nonlinear oscillator does not reproduce: linear modes each."""
    members = [k, *state.candidates[k].evidence["unconfirmed"]]
    for j in members:
        state.candidates[j].kind, state.candidates[j].parent = Kind.LINEAR, None
    mode_bands(state)
    return [(j, linear_mode(state, j) or nonlinear_mode(state, j)) for j in members]


def nonlinear_mode(state, k: int, uncertainty: bool = True):
    """The paper's fit on candidate ``k``'s band (see the module); ``uncertainty=False``: the standard
    deviations of a mode of the band's fit left to :func:`~.band_fit.with_uncertainty`."""
    try:
        band = band_signal(state, k, state.options.max_periods)
    except ValueError:
        cand = state.candidates[k]
        own = peak_bands([cand.damped_frequency_hz], [cand.decay_rate / np.pi], state.pre.fs)[0]
        cand.band_hz = tuple(float(b) for b in own)
        try:
            band = band_signal(state, k, state.options.max_periods)
        except ValueError:
            return _free_decay_fit(state, k)
    pre = state.pre
    out = fit_band(band, state.options.template, onset_time=pre.impact.onset_time, record=state.record,
                   channel=state.channel, impulse=impulse_of(state), sensor=state.options.sensor,
                   index=state.index, uncertainty=uncertainty)
    if isinstance(out, Rejected):
        return _linear_instead(state, k, f"the paper's fit gave no mode ({out.reason})")
    return out


def _free_decay_fit(state, k: int):
    """The paper's fit on candidate ``k``'s free decay without band-pass (its band keeps too few periods:
    a short or strongly damped decay), the other components removed (:func:`~.signals.free_decay`)."""
    cand = state.candidates[k]
    y, t = free_decay(state, k)
    states, states_dot, t = free_decay_states(y, t, cand.frequency_hz)
    found = fit_states(states, states_dot, t, cand.band_hz, state.options.template, index=state.index)
    if isinstance(found, Rejected):
        return _linear_instead(state, k, f"the paper's fit on its free decay gave no mode ({found.reason})")
    model, frequency, zeta, fit_error = found
    amplitude = linear_amplitude(state, cand)
    return mode_of_states(model, states, t, cand.band_hz, state.index, frequency_hz=frequency,
                          damping_ratio=zeta, fit_error=fit_error, amplitude=amplitude,
                          shape=shape_of(state, cand), residue=residue_of(state, cand, amplitude))


def _linear_instead(state, k: int, why: str):
    """The decay fit's mode for a nonlinear candidate whose paper's fit failed, saying so."""
    mode = linear_mode(state, k)
    cand = state.candidates[k]
    if mode is None:
        return Rejected(cand.band_hz, why, state.index, {}, Reason.POOR_FIT)
    note = (f"{why}: the decay fit's values are reported, a linear average over the decay (lack of fit "
            f"{cand.lack_of_fit:.3g} x the noise)")
    return with_values_of(mode, cand, note)


"""A mode from fixed oscillator coefficients: its equation, states, values and their standard deviations.

A mode the linear decay explains (:mod:`.classify`) needs no sweep: the decay fit
(:mod:`sindy_impulse.poles.decay_fit`) is the output-error fit of its oscillator ``y'' + c y' + k y = 0``,
whose free response is the damped sinusoid fitted there, so ``k = omega_n^2`` and ``c = 2 sigma`` with their
standard deviations by the delta method (:func:`linear_mode`). A mode whose free decay shows an amplitude
dependence the paper's fit missed gets the averaged equations fitted to that decay instead
(:func:`envelope_mode`). The mode's model is the survey's estimator carrying these
coefficients (:class:`~sindy_impulse.optimizers.fixed.FixedCoefficients`), fitted on the mode's own states:
its band signal and its derivative (:func:`~._states.derivative_states`), or, where the band-pass would keep
too few periods of a strongly damped mode, the free decay with every other component of the decay fit
removed (:func:`~._states.free_decay_states`); both from :mod:`.signals`. Simulation, backbones,
diagnostics and every analysis work on it as on any other mode.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..feature_library.terms import term_table
from ..identification.estimator import fit_deferred
from ..optimizers import fresh_copy
from ..optimizers.fixed import FixedCoefficients
from ._envelope import CHANGE_SIGMAS
from ._states import EDGE, STATE_NAMES, derivative_states, free_decay_states
from .band_fit import SENSOR_POWER, fit_error_of
from .result import Mode
from .signals import band_signal, free_decay

__all__ = ["linear_mode", "pole_instead", "POLE_SIGMAS", "LACK_P", "LACK_SHARE", "envelope_mode",
           "linear_amplitude", "oscillator_model", "shape_of", "residue_of", "impulse_of", "with_values_of"]

def _states(state, k: int):
    """``(states, states_dot, t, band or None)`` of candidate ``k``: its band signal's, else its free
    decay's."""
    cand = state.candidates[k]
    try:
        band = band_signal(state, k, state.options.max_periods)
        if band.y.size > 2 * EDGE + 8:
            return (*derivative_states(band.y, band.t), band)
    except ValueError:
        pass
    y, t = free_decay(state, k)
    return (*free_decay_states(y, t, cand.frequency_hz), None)


def _coefficients(library, n_features: int, terms: dict) -> tuple[np.ndarray, np.ndarray] | None:
    """The oscillator ``y' = dy``, ``dy' = -sum c_pq y^p dy^q`` in the library's columns and its standard
    deviations (NaN for the terms it does not have), from ``terms``: ``{(p, q): (c_pq, std)}``; None when
    the library lacks one of them."""
    try:
        powers = term_table(library, 2).powers
    except (TypeError, AttributeError):
        return None
    column = {tuple(int(v) for v in p): i for i, p in enumerate(powers)}
    if any(key not in column for key in [(0, 1), *terms]) or powers.shape[0] != n_features:
        return None
    coef, std = np.zeros((2, n_features)), np.full((2, n_features), np.nan)
    coef[0, column[(0, 1)]], std[0, column[(0, 1)]] = 1.0, 0.0  # the kinematic y' = dy is exact
    for key, (value, value_std) in terms.items():
        coef[1, column[key]], std[1, column[key]] = -value, value_std
    return coef, std


def oscillator_model(template, states, states_dot, t, terms: dict):
    """The survey's estimator carrying the oscillator ``dy' = -sum c_pq y^p dy^q`` of ``terms`` (``{(p, q):
    (c_pq, std)}``), fitted on ``states``, and its coefficients' standard deviations; ``(None, None)`` when
    its library cannot hold it (the mode then takes the paper's fit)."""
    model = fresh_copy(template)
    library = fresh_copy(model.feature_library) if model.feature_library is not None else None
    if library is None:
        return None, None
    library.fit(states)
    found = _coefficients(library, len(library.get_feature_names()), terms)
    if found is None:
        return None, None
    coef, std = found
    model.set_params(optimizer=FixedCoefficients(coef), sweep=False, refine=False, output_error=False)
    x_dot = states_dot if getattr(model, "differentiation_method", None) is None else None
    fit_deferred(model, states, t=t, x_dot=x_dot, feature_names=list(STATE_NAMES))
    return model, std


def _fixed_mode(state, k: int, terms: dict, source: str, **values) -> Mode | None:
    """Candidate ``k``'s :class:`Mode` carrying the oscillator of ``terms`` (:func:`oscillator_model`) on
    its states, with ``values`` (frequency, damping ratio and their standard deviations, a note); None when
    the survey's estimator cannot carry it."""
    cand = state.candidates[k]
    states, states_dot, t, band = _states(state, k)
    model, coefficients_std = oscillator_model(state.options.template, states, states_dot, t, terms)
    if model is None:
        return None
    amplitude = linear_amplitude(state, cand)
    return Mode(band_hz=cand.band_hz, amplitude=amplitude, fit_error=fit_error_of(model), model=model,
                states=states, t=t, snr_db=float(band.snr_db) if band is not None else float(cand.height_db),
                shape=shape_of(state, cand), residue=residue_of(state, cand, amplitude), record=state.index,
                coefficients_std=coefficients_std, source=source, **values)


#: A candidate's decay fit and its stable pole disagree where they lie more than this many standard
#: deviations of their difference apart, in frequency or damping ratio (:func:`pole_instead`) ...
POLE_SIGMAS = 3.0
#: ... and the decay fit's model lacks something near the mode where what it leaves there is this
#: improbable from noise alone (:attr:`~.candidates.Candidate.lack_of_fit_p`) ...
LACK_P = 0.01
#: ... and something small: what it leaves beyond the noise is under this share of the mode's own power
#: (its amplitude at the decay's start over the noise, squared); a larger share is no damped sinusoid
#: beside a small extra.
LACK_SHARE = 0.1


def pole_instead(cand) -> bool:
    """Whether candidate ``cand`` reports its stable pole's values instead of its decay fit's.

    The decay fit's components are the candidates only. Where its model lacks something small the record
    holds near a mode (what it leaves there is improbable from noise alone, :data:`LACK_P`, and a small
    share of the mode's power, :data:`LACK_SHARE`), a strongly damped mode, whose information lies in its
    first samples, absorbs it (the hit's tail, a component under the threshold), where the diagram's
    higher orders give it poles of their own. (Where the fit leaves a large share, the mode is no damped
    sinusoid, and its pole is no sharper a reading of it: a flutter rig's 2.74 Hz mode, its residual a
    third of its power, has poles 50 % more damped than the classical diagram's.) Where such a mode also dies
    out within one column of the diagram's Hankel matrix (its amplitude at the decay's start falls to the
    noise within its rows), every column holds its whole decay, the pole is about as sharp as the fit
    (its standard deviation taken as the fit's or its orders' scatter, whichever is larger), and a
    difference beyond :data:`POLE_SIGMAS` of theirs is the fit's bias: the pole's values are reported. A
    mode that outlives the rows keeps the decay fit's values (the pole reads it through windows shorter
    than it: a lightly damped mode's pole lies several of the fit's standard deviations off, and moves
    from one hit of a structure to the next), as does one the fit explains.

    Examples
    --------
    >>> from types import SimpleNamespace as C
    >>> from sindy_impulse.modes.candidates import ConfirmingPole
    >>> short = ConfirmingPole(1096.5, 0.1227, 0.4, 5e-4, span_s=0.017)  # a 12 % mode dies in 7 ms
    >>> cand = C(frequency_hz=1089.9, frequency_std_hz=0.54, damping_ratio=0.1225, damping_ratio_std=6e-4,
    ...          decay_rate=840.0, amplitude=[2.3], noise_std=1e-3, lack_of_fit=1.6, lack_of_fit_p=3e-4,
    ...          pole=short)
    >>> pole_instead(cand)
    True
    >>> pole_instead(C(**{**vars(cand), "pole": short._replace(frequency_hz=1090.5)}))  # they agree
    False
    >>> pole_instead(C(**{**vars(cand), "pole": short._replace(span_s=0.005)}))  # it outlives the rows
    False
    >>> pole_instead(C(**{**vars(cand), "lack_of_fit_p": 0.5}))  # the fit explains it
    False
    >>> pole_instead(C(**{**vars(cand), "lack_of_fit": 1e6}))  # it is no damped sinusoid
    False
    """
    pole = cand.pole
    if pole is None or not cand.noise_std > 0 or not cand.decay_rate > 0 or not cand.lack_of_fit_p < LACK_P:
        return False
    level = abs(cand.amplitude[0]) / cand.noise_std
    if level > 1 and cand.decay_rate * pole.span_s < math.log(level):
        return False
    if not cand.lack_of_fit - 1.0 < LACK_SHARE * level**2:
        return False
    # the pole's standard deviation: the fit's (the same samples' noise), at least its orders' scatter
    f_std = math.hypot(cand.frequency_std_hz, max(cand.frequency_std_hz, pole.frequency_spread_hz))
    z_std = math.hypot(cand.damping_ratio_std, max(cand.damping_ratio_std, pole.damping_ratio_spread))
    return bool(abs(pole.frequency_hz - cand.frequency_hz) > POLE_SIGMAS * f_std
                or abs(pole.damping_ratio - cand.damping_ratio) > POLE_SIGMAS * z_std)


def linear_mode(state, k: int) -> Mode | None:
    """The :class:`Mode` of linear candidate ``k`` (see the module): the oscillator of its poles, ``k =
    omega_n^2`` (its std ``2 omega_n`` times the frequency's), ``c = 2 sigma``; None when the survey's
    estimator cannot carry an oscillator (its library lacks ``y`` or ``dy``). Its values are the decay
    fit's, or its stable pole's where :func:`pole_instead` says so (with the decay fit's standard
    deviations and a note)."""
    cand = state.candidates[k]
    frequency, zeta, rate, note = cand.frequency_hz, cand.damping_ratio, cand.decay_rate, ""
    if pole_instead(cand):
        frequency, zeta = cand.pole.frequency_hz, cand.pole.damping_ratio
        rate = 2 * np.pi * frequency * zeta
        note = (f"the decay fit ({cand.frequency_hz:.6g} Hz, {100 * cand.damping_ratio:.4g} %) leaves "
                "something near the mode unexplained and disagrees with its stable pole beyond "
                f"{POLE_SIGMAS:g} standard deviations of their difference; the mode dies out within the "
                "diagram's Hankel rows: the stable pole's values are reported")
    omega = 2 * np.pi * frequency
    terms = {(1, 0): (omega**2, 2 * omega * 2 * np.pi * cand.frequency_std_hz),
             (0, 1): (2 * rate, 2 * cand.decay_rate_std)}
    return _fixed_mode(state, k, terms, "poles", frequency_hz=frequency, damping_ratio=zeta,
                       frequency_std_hz=cand.frequency_std_hz, damping_ratio_std=cand.damping_ratio_std,
                       uncertainty_note=note)


def envelope_mode(state, k: int, e) -> Mode | None:
    """The :class:`Mode` of candidate ``k`` from the averaged equations its free decay was fitted with
    (:func:`~._envelope.decay_dependence`, ``e``): ``omega(A) = omega_0 + omega_2 A^2`` and ``sigma(A) =
    sigma_0 + sigma_2 A^2`` are the free decay of ``y'' + 2 sigma_0 y' + (omega_0^2 + sigma_0^2) y + k_3
    y^3 + c_3 y^2 y' = 0`` with ``k_3 = 8 omega_0 omega_2 / 3`` and ``c_3 = 8 sigma_2`` (first order in
    the nonlinear terms), each nonlinear term where its change stands out (:meth:`~._envelope.
    AmplitudeDependence.changes`); its frequency and damping ratio are the small-amplitude ones. None when
    the estimator's library lacks those terms, or when the equations do not decay at small amplitude
    (``sigma_0 <= 0``: a growing oscillation is no mode of a free decay, as the paper's fit refuses an
    undamped one, and the caller keeps what it had)."""
    (w0, w2, s0, s2), (w0_std, w2_std, s0_std, s2_std) = e.coefficients, e.coefficients_std
    if not s0 > 0:
        return None
    wn, wn_std = math.hypot(w0, s0), math.hypot(w0 * w0_std, s0 * s0_std) / math.hypot(w0, s0)
    terms = {(1, 0): (wn**2, 2 * wn * wn_std), (0, 1): (2 * s0, 2 * s0_std)}
    if e.changes(CHANGE_SIGMAS, decay=False):
        terms[3, 0] = 8 * w0 * w2 / 3, 8 * math.hypot(w0 * w2_std, w2 * w0_std) / 3
    if e.changes(CHANGE_SIGMAS, frequency=False):
        terms[2, 1] = 8 * s2, 8 * s2_std
    if state.candidates[k].evidence.get("joint"):
        moved = ", ".join(f"{state.candidates[j].frequency_hz:.5g}" for j in e.drivers)
        note = ("the averaged equations of the free decay of the modes read together, every amplitude gone"
                + (f" (moved by the amplitudes of the modes at {moved} Hz)" if moved else ""))
    else:
        note = ("the averaged equations of its free decay (the paper's fit did not give the amplitude "
                "dependence its envelope shows)")
    return _fixed_mode(state, k, terms, "envelope", frequency_hz=wn / (2 * np.pi), damping_ratio=s0 / wn,
                       frequency_std_hz=wn_std / (2 * np.pi), damping_ratio_std=s0_std / wn,
                       uncertainty_note=note)


def linear_amplitude(state, cand) -> float:
    """A candidate's amplitude at the hit: its decay fit's at the decay's start, extrapolated back with its
    decay rate."""
    pre = state.pre
    since_hit = (state.start - pre.impact.onset_index) / pre.fs
    return float(np.abs(cand.amplitude[0]) * math.exp(cand.decay_rate * since_hit))


def shape_of(state, cand) -> np.ndarray | None:
    """The mode's complex amplitude in every channel relative to the reference channel (None with one)."""
    n = state.record.shape[1]
    if n == 1:
        return None
    others = [c for c in range(n) if c != state.channel]
    shape = np.empty(n, dtype=complex)
    shape[state.channel] = 1.0
    ref = cand.amplitude[0]
    for j, c in enumerate(others, start=1):
        shape[c] = cand.amplitude[j] / ref if ref != 0 else np.nan
    return shape


def residue_of(state, cand, amplitude: float) -> float | None:
    """The driving-point residue from the amplitude at the hit and the impulse (force and sensor given)."""
    impulse, sensor = impulse_of(state), state.options.sensor
    if impulse is None or sensor is None or not impulse > 0:
        return None
    omega = 2 * np.pi * cand.frequency_hz
    omega_d = omega * math.sqrt(max(1 - cand.damping_ratio**2, 0.0))
    return amplitude * omega_d / (omega ** SENSOR_POWER[sensor] * impulse)


def impulse_of(state) -> float | None:
    """Impulse of the hammer (N s): the force integrated over the hit's pulses."""
    pre = state.pre
    if state.force is None or not pre.impact.hits:
        return None
    force = np.asarray(state.force, float).reshape(-1)
    lo, hi = pre.impact.onset_index, pre.impact.ringdown_index
    return float(np.sum(force[lo: hi + 1]) / pre.fs)


def with_values_of(mode: Mode, cand, note: str) -> Mode:
    """``mode`` reporting a candidate's decay-fit values instead of its model's, with a note saying why."""
    return replace(mode, frequency_hz=cand.frequency_hz, damping_ratio=cand.damping_ratio,
                   frequency_std_hz=cand.frequency_std_hz, damping_ratio_std=cand.damping_ratio_std,
                   uncertainty_note=note, source="poles")

"""A linear mode from its poles: the equation, its states, its values and their standard deviations.

A mode the linear decay explains (:mod:`.classify`) needs no sweep: the decay fit
(:mod:`sindy_impulse.poles.decay_fit`) is the output-error fit of its oscillator ``y'' + c y' + k y = 0``,
whose free response is the damped sinusoid fitted there, so ``k = omega_n^2`` and ``c = 2 sigma`` with their
standard deviations by the delta method. The mode's model is the survey's estimator carrying these
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
from ._states import EDGE, STATE_NAMES, derivative_states, free_decay_states
from .band_fit import SENSOR_POWER, fit_error_of
from .result import Mode
from .signals import band_signal, free_decay

__all__ = ["linear_mode", "linear_amplitude", "pole_model", "shape_of", "residue_of", "impulse_of",
           "with_values_of"]

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


def _coefficients(library, n_features: int, k: float, c: float) -> np.ndarray | None:
    """The oscillator ``y' = dy``, ``dy' = -k y - c dy`` in the library's columns (None when the library
    lacks the linear terms of ``[y, dy]``)."""
    try:
        powers = term_table(library, 2).powers
    except (TypeError, AttributeError):
        return None
    column = {tuple(int(v) for v in p): i for i, p in enumerate(powers) if p.sum() == 1}
    if (1, 0) not in column or (0, 1) not in column or powers.shape[0] != n_features:
        return None
    coef = np.zeros((2, n_features))
    coef[0, column[(0, 1)]] = 1.0
    coef[1, column[(1, 0)]], coef[1, column[(0, 1)]] = -k, -c
    return coef


def _coefficients_std(coef: np.ndarray, cand) -> np.ndarray:
    """Standard deviations of the oscillator's coefficients: ``k = omega_n^2`` (``2 omega_n`` times its
    std), ``c = 2 sigma``; the kinematic ``y' = dy`` is exact; NaN for the terms the model does not have."""
    std = np.full(coef.shape, np.nan)
    omega = 2 * np.pi * cand.frequency_hz
    std[0, coef[0] != 0] = 0.0
    y_col = int(np.flatnonzero(coef[1] == coef[1].min())[0]) if coef[1].min() < 0 else None
    std[1, coef[1] != 0] = 2 * cand.decay_rate_std
    if y_col is not None:
        std[1, y_col] = 2 * omega * 2 * np.pi * cand.frequency_std_hz
    return std


def pole_model(template, states, states_dot, t, cand):
    """The survey's estimator carrying the oscillator of a candidate's poles, fitted on ``states`` (None
    when its library cannot hold it: the mode then takes the paper's fit)."""
    omega = 2 * np.pi * cand.frequency_hz
    model = fresh_copy(template)
    library = fresh_copy(model.feature_library) if model.feature_library is not None else None
    if library is None:
        return None, None
    library.fit(states)
    n_features = len(library.get_feature_names())
    coef = _coefficients(library, n_features, omega**2, 2 * cand.decay_rate)
    if coef is None:
        return None, None
    model.set_params(optimizer=FixedCoefficients(coef), sweep=False, refine=False, output_error=False)
    x_dot = states_dot if getattr(model, "differentiation_method", None) is None else None
    fit_deferred(model, states, t=t, x_dot=x_dot, feature_names=list(STATE_NAMES))
    return model, _coefficients_std(coef, cand)


def linear_mode(state, k: int) -> Mode | None:
    """The :class:`Mode` of linear candidate ``k`` (see the module); None when the survey's estimator cannot
    carry an oscillator (its library lacks ``y`` or ``dy``)."""
    cand = state.candidates[k]
    states, states_dot, t, band = _states(state, k)
    model, coefficients_std = pole_model(state.options.template, states, states_dot, t, cand)
    if model is None:
        return None
    amplitude = linear_amplitude(state, cand)
    return Mode(frequency_hz=cand.frequency_hz, damping_ratio=cand.damping_ratio, band_hz=cand.band_hz,
                amplitude=amplitude, fit_error=fit_error_of(model), model=model, states=states, t=t,
                snr_db=float(band.snr_db) if band is not None else float(cand.height_db),
                shape=shape_of(state, cand), residue=residue_of(state, cand, amplitude), record=state.index,
                frequency_std_hz=cand.frequency_std_hz, damping_ratio_std=cand.damping_ratio_std,
                coefficients_std=coefficients_std, source="poles")


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

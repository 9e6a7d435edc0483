"""One band of a record to one mode: states, the paper's identification, the mode's values and checks."""

from __future__ import annotations

import functools
import math

import numpy as np
import pysindy as ps

from ..identification.estimator import fit_deferred
from ..optimizers import fresh_copy
from ..poles.modal import modal_parameters
from ..preprocessing import bandpass
from ..preprocessing.band import resample_band
from ..simulation.scoring import AUTO_PERIODS, Auto, Segmented
from ._states import EDGE, STATE_NAMES, channel_shape, derivative_states
from .result import Mode, Rejected
from .uncertainty import mode_uncertainty

__all__ = ["default_estimator", "fit_band", "fit_states", "mode_of_states", "fit_error_of", "MAX_FIT_ERROR",
           "SENSOR_POWER", "PENDING", "with_uncertainty"]

#: Largest fit error (mean absolute deviation relative to the local amplitude) of a model reported as a
#: mode; a peak whose best model does worse is rejected.
MAX_FIT_ERROR = 0.25
#: A mode's model is selected and refined on bands longer than 30 periods by segments normalised by their
#: own amplitude down to this share of the largest, by absolute errors below it (the estimator's default
#: floor is 0.01): the quiet end of a band, near the noise, then does not magnify its noise. Measured on
#: simulated single modes with an x^2 x' damper (SNR 30-60 dB, 40-80 periods; mode backbones within the
#: marks): 0.01 -> 36/50 (the split between linear and amplitude-dependent damping followed the
#: noise of the last segments), 0.1 -> 40/50, 0.3 -> 41/50; but at 0.3 two of 24 records rounded to 8
#: digits moved a coefficient of two correlated terms (y^3, y dy^2) by 27 % and 259 % (another local
#: minimum), at 0.1 none by more than 3.9e-4
#: (``python -m benchmarks model_backbone --rounding 12 [--floor F]``).
SEGMENT_FLOOR = 0.1
#: Longest band, in periods, whose mode is selected and refined by the paper's Gamma (first-sample
#: simulation; ``"auto"``'s threshold), and the segments' length of the measure of longer bands: the
#: estimator's defaults. Longer segments or Gamma up to 150 periods lift the damper backbones
#: (``python -m benchmarks model_backbone --segment-periods 24 | --gamma-periods 150``, 20 records: 16 -> 17
#: | 18 of 20) but move a coefficient of a record rounded to 8 digits by 12 % | 33 % (``--rounding 12``): on
#: those longer simulations the refinement stops early or the work budget runs out before it, in
#: another place for the rounded record.
GAMMA_PERIODS = AUTO_PERIODS
SEGMENT_PERIODS = Segmented().segment_periods
#: Longest band, in periods, whose refined model is fitted once more with its initial state by output error
#: (the default estimator's ``output_error``,
#: :func:`~sindy_impulse.identification.output_error.fit_output_error`). Gamma and
#: the segments start every simulation from the filtered measured state, whose noise the coefficients then
#: absorb: a fit of the generating equation's own structure with its initial state fixed there passes
#: 29/50 damper backbones, with the initial state fitted 46/50 (simulated single modes with an x^2 x'
#: damper, 40-105 periods); the modes' backbones went from 40/50 to 45/50. A fit of a whole
#: free decay is local: on bands of hundreds of periods the segment-wise measure's model stays.
OUTPUT_ERROR_PERIODS = 150
#: Power of omega between a displacement and what each sensor measures.
SENSOR_POWER = {"displacement": 0, "velocity": 1, "acceleration": 2}


def isolated(bands_of):
    """A fit whose failure stays its band's: any exception (not ``BaseException``: an interrupt still stops
    the survey) becomes a :class:`Rejected` of the band it was fitting, or one per band of a group
    (``bands_of(args)`` names them from the fit's positional arguments), with the error as its reason and
    evidence, so the rest of the survey stands.

    Examples
    --------
    >>> @isolated(lambda args: args[0])
    ... def fit(band_hz, *, index=0):
    ...     raise FloatingPointError("overflow")
    >>> fit((90.0, 110.0), index=1).evidence
    {'error': 'FloatingPointError', 'message': 'overflow'}
    """

    def decorate(fit):
        @functools.wraps(fit)
        def run(*args, index: int = 0, **kwargs):
            try:
                return fit(*args, index=index, **kwargs)
            except Exception as err:  # noqa: BLE001 - one band's failure must not abort the survey
                reason = f"the identification failed ({type(err).__name__}: {err})"
                evidence = {"error": type(err).__name__, "message": str(err)}
                bands = bands_of(args)
                if isinstance(bands, list):
                    return [Rejected(tuple(b), reason, index, evidence) for b in bands]
                return Rejected(tuple(float(b) for b in bands), reason, index, evidence)

        return run

    return decorate


def default_estimator():
    """The identification of one mode: ImpulseSINDy with a cubic polynomial library on ``[y, dy]``.

    The linear oscillator's terms (``dy`` in ``y'``; ``y`` and ``dy`` in ``dy'``) are protected from the
    threshold sweep: a mode always keeps a stiffness and a damping (a very lightly damped mode's damping
    term explains a tiny share of ``dy'``, which the sweep would otherwise remove first), and the sweep
    searches only the nonlinear terms. Bands of at most :data:`OUTPUT_ERROR_PERIODS` periods get the
    output-error fit after the refinement.
    """
    from ..identification.estimator import ImpulseSINDy
    from ..optimizers import ThresholdSweep

    library = ps.PolynomialLibrary(degree=3, include_bias=False)  # y, dy, y^2, y dy, dy^2, y^3, ...
    protected = np.zeros((2, 9), dtype=bool)
    protected[0, 1] = protected[1, 0] = protected[1, 1] = True
    measure = Auto(long=Segmented(SEGMENT_PERIODS, SEGMENT_FLOOR), periods=GAMMA_PERIODS)
    return ImpulseSINDy(optimizer=ThresholdSweep(protected=protected), feature_library=library,
                        error_measure=measure, output_error=OUTPUT_ERROR_PERIODS)


def fit_error_of(model) -> float:
    """A mode's fit error: the model's simulation error per compared value, measured as ``"auto"`` does
    with its defaults (Gamma on a band of at most 30 periods, else segments each normalised by their own
    amplitude down to 1 % of the largest), whatever measure selected the model: :data:`MAX_FIT_ERROR` and the
    survey's comparisons of modes are set on that scale (under a floor of 0.3 a model of a band that is
    mostly noise scores low: the broad peak of a damper's third harmonic gave a "mode" at 151 Hz, 1.8x the
    fundamental, with 0.22; tests/test_modes_nonlinear.py)."""
    x = model.x_filtered_
    return float(Auto().resolve([x]).bind([x], [model.t_])(model.model_)[0]) / np.size(x)


def _linear_mode(model, band_hz):
    """The model's oscillatory linear mode inside the band: (frequency_hz, damping_ratio) or a reason."""
    frequencies, damping = modal_parameters(model)
    return _closest_mode(frequencies, damping, band_hz)


def _closest_mode(frequencies, damping, band_hz):
    """The mode of ``frequencies`` inside the band nearest its centre, if damped; or a reason."""
    inside = (frequencies >= band_hz[0]) & (frequencies <= band_hz[1])
    if not inside.any():
        found = ", ".join(f"{f:.4g}" for f in frequencies) or "none"
        return None, f"no oscillatory mode of the model inside the band (model modes: {found} Hz)"
    i = int(
        np.flatnonzero(inside)[np.argmin(np.abs(np.log(frequencies[inside] / np.sqrt(np.prod(band_hz)))))]
    )
    if not damping[i] > 0:
        return None, f"the identified mode is not damped (damping ratio {damping[i]:.3g}): an unstable model"
    return (float(frequencies[i]), float(damping[i])), None


#: Largest decay (in e-folds) of a mode during the band-pass transient trimmed before its band signal, and
#: largest share of the band its half-power width may take: beyond either the band signal is mostly the
#: filter's own response, not the mode's.
MAX_TRIM_DECAY, MAX_WIDTH_SHARE = 3.0, 0.5


def _too_narrow(band, frequency: float, zeta: float) -> str | None:
    """Why the band cannot represent a mode this damped (None when it can)."""
    decay = zeta * 2 * np.pi * frequency * band.trimmed_start / band.record_fs
    width = 2 * zeta * frequency / (band.band_hz[1] - band.band_hz[0])
    if decay > MAX_TRIM_DECAY or width > MAX_WIDTH_SHARE:
        return (
            f"the band is too narrow for a mode this damped (damping ratio {zeta:.3g}: it decays by "
            f"{decay:.1f} e-folds during the band-pass transient and fills {width:.0%} of the band)"
        )
    return None


def _poor_fit(band_hz, fit_error: float, index: int) -> Rejected:
    return Rejected(
        tuple(band_hz),
        f"the model does not reproduce the signal (fit error {fit_error:.3g} > {MAX_FIT_ERROR})",
        index,
    )


def _shape(record, band, states, omega, channel) -> np.ndarray:
    """Complex amplitude of the mode in every channel relative to the reference channel."""
    out = np.empty(record.shape[1], dtype=complex)
    span = (band.start_index, band.stop_index)
    for c in range(record.shape[1]):
        if c == channel:
            out[c] = 1.0
            continue
        if band.upsampling > 1:  # the other channel resampled as the band signal was
            z = bandpass(record[:, c], band.record_fs, band.band_hz, analytic=True)
            centre = float(np.sqrt(band.band_hz[0] * band.band_hz[1]))
            other = resample_band(z, *span, band.record_fs, centre, band.upsampling)[0]
        else:
            other = bandpass(record[:, c], band.record_fs, band.band_hz)[span[0] : span[1] : band.decimation]
        other = other[EDGE : EDGE + len(states)]
        out[c] = channel_shape(states[: len(other), 0], states[: len(other), 1], omega, other)
    return out


@isolated(lambda args: args[0].band_hz)  # the band signal's band
def fit_band(
    band,
    template,
    *,
    onset_time: float,
    record=None,
    channel: int = 0,
    impulse=None,
    sensor=None,
    index: int = 0,
    uncertainty: bool = True,
):
    """Identify the mode of one band (a :class:`~sindy_impulse.preprocessing.BandSignal`).

    Returns a :class:`Mode`, or a :class:`Rejected` saying why no stable, well-fitting model explains the
    band. ``uncertainty=False`` leaves the mode's standard deviations to :func:`with_uncertainty` (its
    ``uncertainty_note`` is :data:`PENDING` until then): for a caller that may not keep the mode.
    """
    states, states_dot, t = derivative_states(band.y, band.t)
    found = fit_states(states, states_dot, t, band.band_hz, template, index=index)
    if isinstance(found, Rejected):
        return found
    model, frequency, zeta, fit_error = found
    narrow = _too_narrow(band, frequency, zeta)
    if narrow:
        return Rejected(tuple(band.band_hz), narrow, index)
    omega = 2 * np.pi * frequency
    omega_d = omega * math.sqrt(max(1 - zeta**2, 0.0))
    amplitude = float(band.envelope[EDGE] * np.exp(zeta * omega * (t[0] - onset_time)))
    residue = None
    if impulse is not None and sensor is not None and impulse > 0:
        residue = amplitude * omega_d / (omega ** SENSOR_POWER[sensor] * impulse)
    shape = None if record is None or record.shape[1] == 1 else _shape(record, band, states, omega, channel)
    return _mode(
        band,
        model,
        states,
        t,
        index,
        uncertainty=uncertainty,
        frequency_hz=frequency,
        damping_ratio=zeta,
        fit_error=fit_error,
        amplitude=amplitude,
        shape=shape,
        residue=residue,
    )


def fit_states(states, states_dot, t, band_hz, template, *, index: int = 0):
    """The survey's estimator fitted on a mode's states ``[y, dy]`` (the paper's sweep and refinement):
    ``(model, frequency_hz, damping_ratio, fit_error)`` of its linear mode inside ``band_hz``, or a
    :class:`Rejected` when it has none there, it is not damped, or the model does not reproduce the states
    (:data:`MAX_FIT_ERROR`)."""
    model = fresh_copy(template)
    # states from a filtered signal: their derivatives given, unless the template asks for its own method
    x_dot = states_dot if getattr(model, "differentiation_method", None) is None else None
    fit_deferred(model, states, t=t, x_dot=x_dot, feature_names=list(STATE_NAMES))
    found, reason = _linear_mode(model, band_hz)
    if found is None:
        return Rejected(tuple(band_hz), reason, index)
    fit_error = fit_error_of(model)
    if not fit_error <= MAX_FIT_ERROR:
        return _poor_fit(band_hz, fit_error, index)
    return model, found[0], found[1], fit_error


def mode_of_states(model, states, t, band_hz, index: int, **values) -> Mode:
    """The :class:`Mode` of a ``model`` fitted on ``[y, dy]`` states, its standard deviations from the fit
    (:mod:`.uncertainty`); ``values``: frequency, damping ratio, fit error, amplitude, shape, residue."""
    values.update(_uncertainty(model, states, t, band_hz, values["frequency_hz"]))
    band_hz = tuple(float(b) for b in band_hz)
    return Mode(band_hz=band_hz, model=model, states=states, t=t, record=index, **values)


def _uncertainty(model, states, t, band_hz, frequency: float, **kws) -> dict:
    """The mode's standard deviations from its fit (:func:`.uncertainty.mode_uncertainty`) as
    :class:`Mode` fields."""
    u = mode_uncertainty(model, states, t, band_hz, frequency, **kws)
    return dict(frequency_std_hz=u.frequency_std_hz, damping_ratio_std=u.damping_ratio_std,
                coefficients_std=u.coefficients_std, uncertainty_note=u.reason,
                nonlinear_chance=u.nonlinear_chance)


def _mode(band, model, states, t, index, lags=None, uncertainty: bool = True, **values) -> Mode:
    """The :class:`Mode` of a band's ``model`` fitted on ``states`` (delay coordinates of the band
    signal with ``lags``, else ``[y, dy]``); ``values`` are the mode's own (frequency, damping ratio, fit
    error; amplitude, shape, residue where known). ``uncertainty=False``: its standard deviations are left
    :data:`PENDING` (``[y, dy]`` states only)."""
    values.setdefault("amplitude", math.nan)  # a mode of a joint group's model: no amplitude of its own
    band_hz = tuple(float(b) for b in band.band_hz)
    snr_db = float(band.snr_db)
    if uncertainty or lags is not None:
        values.update(_uncertainty(model, states, t, band_hz, values["frequency_hz"], lags=lags))
    else:
        values.update(uncertainty_note=PENDING)
    return Mode(band_hz=band_hz, model=model, states=states, t=t, snr_db=snr_db, record=index, **values)


#: ``uncertainty_note`` of a mode of :func:`fit_band` whose standard deviations are not computed yet.
PENDING = "standard deviations not computed yet"


def with_uncertainty(mode: Mode, index: int = 0) -> Mode | Rejected:
    """A mode of :func:`fit_band` (``uncertainty=False``) with its standard deviations from its fit, as
    ``fit_band`` computes them (in place); the :class:`Rejected` ``fit_band`` gives where that computation
    fails. Any other mode is returned as it is.

    Examples
    --------
    >>> from sindy_impulse.preprocessing import extract_band
    >>> t = np.arange(8000) / 4000.0
    >>> y = np.exp(-2.0 * t) * np.cos(2 * np.pi * 100.0 * t)
    >>> band = extract_band(y + 1e-6 * np.sin(2 * np.pi * 1000 * t), 4000.0, (80.0, 120.0))
    >>> mode = fit_band(band, default_estimator(), onset_time=0.0, uncertainty=False)
    >>> mode.uncertainty_note == PENDING, math.isnan(mode.frequency_std_hz)
    (True, True)
    >>> done = with_uncertainty(mode)
    >>> done is mode, done.uncertainty_note == PENDING, bool(done.frequency_std_hz >= 0)
    (True, False, True)
    """
    if not isinstance(mode, Mode) or mode.uncertainty_note != PENDING:
        return mode
    try:
        values = _uncertainty(mode.model, mode.states, mode.t, mode.band_hz, mode.frequency_hz)
    except Exception as err:  # noqa: BLE001 - as fit_band (isolated) reports a failure of its band
        return Rejected(mode.band_hz, f"the identification failed ({type(err).__name__}: {err})", index,
                        {"error": type(err).__name__, "message": str(err)})
    for name, value in values.items():
        setattr(mode, name, value)
    return mode

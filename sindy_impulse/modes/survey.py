"""A raw hammer-test record in, a modal table out: :func:`identify_modes`, one declared pipeline.

Each record (one hit; several synchronous sensors allowed) runs through :data:`SURVEY`, an ordered list of
stages over one :class:`~.pipeline.SurveyState` (``print(SURVEY)`` shows it):

1. ``read`` (:func:`~.candidates.read_record`): the hit, clipped samples repaired, the offset removed;
2. ``poles`` (:func:`~.candidates.stable_poles`): the stabilisation diagram of the free decay, once;
3. ``candidates`` (:func:`~.candidates.fit_candidates`): its stable poles and the spectral peaks no pole
   explains, refined together by the decay fit (:mod:`sindy_impulse.poles.decay_fit`): each mode's
   frequency, damping ratio, their standard deviations, its amplitude per channel, and whether the linear
   decay explains it;
4. ``classify`` (:func:`~.classify.classify_candidates`): tones, harmonics, nonlinear modes (and the pieces
   of one), linear modes, from that evidence and the record;
5. ``identify`` (:func:`~.identify.identify_candidates`): a linear mode's equation from its poles, a
   nonlinear mode's by the paper's sweep and refinement on its band (candidates in parallel with
   ``n_jobs``);
6. ``reconcile`` (:func:`~.reconcile.reconcile`): one answer per mode, the other candidates named;
7. ``coupling`` (:func:`~.coupling.read_coupling`): where a nonlinear element couples the modes, their
   values read together under its first-order structure, taken where they move beyond the reading's
   standard deviations (or it knows them better) and the reading leaves nothing but noise in every mode's
   band.

``survey.trace`` holds, per record and stage, the time it took and what it decided. Repeated hits of one
structure are matched by frequency and combined by the paper's consensus (section 3.3.2).
"""

from __future__ import annotations

import warnings
from numbers import Integral, Real

import numpy as np

from .._utils.params import HasMethods, Interval, Options, check_param
from .._utils.threads import one_thread
from .._utils.validation import check_signal
from ..exceptions import DataWarning, NoDynamicsWarning
from ._hits import merge_hits
from .band_fit import default_estimator
from .candidates import fit_candidates, read_record, stable_poles
from .classify import classify_candidates
from .coupling import read_coupling
from .identify import identify_candidates
from .kinds import Reason
from .pipeline import Pipeline, Stage, SurveyOptions, SurveyState, SurveyTrace
from .reconcile import reconcile
from .result import ModalSurvey, Rejected

__all__ = ["check_options", "identify_modes", "SURVEY"]

_SENSORS = Options({"displacement", "velocity", "acceleration"})

#: The survey of one record: its stages in order (see the module).
SURVEY = Pipeline([
    Stage("read", read_record),
    Stage("poles", stable_poles),
    Stage("candidates", fit_candidates),
    Stage("classify", classify_candidates),
    Stage("identify", identify_candidates),
    Stage("reconcile", reconcile),
    Stage("coupling", read_coupling),
])


def _records(y, force) -> tuple[list[np.ndarray], list]:
    """One (n_samples, n_channels) array per hit, and the force of each (or None)."""
    many = isinstance(y, (list, tuple)) and len(y) > 0 and all(hasattr(r, "shape") for r in y)
    ys = list(y) if many else [y]
    arrays = [check_signal(r, "y" if not many else f"y[{i}]", ndim=(1, 2)) for i, r in enumerate(ys)]
    if force is None:
        return arrays, [None] * len(arrays)
    forces = list(force) if many else [force]
    if len(forces) != len(arrays):
        raise ValueError(f"force has {len(forces)} records but y has {len(arrays)}")
    checked = []
    for i, (f, r) in enumerate(zip(forces, arrays)):
        f = check_signal(f, "force" if not many else f"force[{i}]", ndim=(1, 2), as_2d=False).reshape(-1)
        if f.size != r.shape[0]:
            raise ValueError(f"force has {f.size} samples but y has {r.shape[0]}")
        checked.append(f)
    return arrays, checked


def _times(t, n_records: int):
    if isinstance(t, (list, tuple)) and len(t) == n_records and n_records > 1 and np.ndim(t[0]) == 1:
        return list(t)
    return [t] * n_records


def _survey_record(state: SurveyState) -> SurveyState:
    """One record through :data:`SURVEY`. A problem of the input (the ``read`` stage refuses it) raises its
    clear error; a failure after that becomes one :class:`Rejected` row of the record, with the error as
    its evidence, so the other records of a survey stand. BLAS runs on one thread: a survey's products are
    small (a band's few thousand samples by a handful of columns), where threads only contend."""
    with one_thread("blas"):
        Pipeline(SURVEY[:1])(state)
        try:
            Pipeline(SURVEY[1:])(state)
        except Exception as err:  # noqa: BLE001 - one record's failure must not abort the survey
            evidence = {"error": type(err).__name__, "message": str(err)}
            reason = f"the identification of record {state.index} failed ({type(err).__name__}: {err})"
            state.modes, state.origin = [], []
            state.rejected.append(Rejected(None, reason, state.index, evidence, Reason.FIT_FAILED))
    return state


def check_options(sensor=None, estimator=None, max_periods=200.0, n_jobs=None) -> None:
    """The checks of :func:`identify_modes`' options that concern no record (a batch runs them once,
    before any record: :func:`~sindy_impulse.modes.batch.survey_many`).

    Examples
    --------
    >>> check_options(sensor="acceleration")
    >>> try:
    ...     check_options(sensor="laser")
    ... except ValueError as err:
    ...     print(str(err)[:40])
    identify_modes: sensor must be None or o
    """
    check_param("sensor", sensor, [None, _SENSORS], "identify_modes")
    check_param("estimator", estimator, [None, HasMethods("fit", "an ImpulseSINDy")], "identify_modes")
    check_param("max_periods", max_periods, [None, Interval(Real, 10, None)], "identify_modes")
    check_param("n_jobs", n_jobs, [None, Interval(Integral, None, None)], "identify_modes")
    if n_jobs == 0:
        raise ValueError("identify_modes: n_jobs must be None, a positive number of workers or negative "
                         "(-1: every core), got 0")


def identify_modes(
    y,
    t=None,
    *,
    fs: float | None = None,
    force=None,
    n_modes: int | None = None,
    bands=None,
    sensor: str | None = None,
    estimator=None,
    channel: int | None = None,
    onset="auto",
    offset="auto",
    samples_per_period: float = 16.0,
    max_periods: float | None = 200.0,
    n_jobs: int | None = None,
) -> ModalSurvey:
    """Identify the modes of a hammer-test record: a modal table with one equation per mode.

    Parameters
    ----------
    y : array-like (n_samples,) or (n_samples, n_channels), or a list of them
        One record (several synchronous sensors allowed), or a list of records (repeated hits of the same
        test, combined by consensus). Raw: pre-trigger, offset and all modes included.
    t : array-like (n_samples,) or float, optional
        Time vector (uniform) or step (a list of vectors for several records); or give ``fs``.
    fs : float, optional
        Sampling rate (Hz).
    force : array-like (n_samples,) or list, optional
        The hammer's force: the onset and the end of contact come from it, double hits are reported, and
        with ``sensor`` the driving-point residues are computed.
    n_modes : int, optional
        Keep the ``n_modes`` strongest spectral peaks.
    bands : sequence of (low_hz, high_hz), optional
        The bands to identify, instead of the detected peaks' bands.
    sensor : {"displacement", "velocity", "acceleration"}, optional
        The kind of sensor (for the residues).
    estimator : ImpulseSINDy, optional
        Template of the per-mode identification (cloned per mode); default: a cubic polynomial library on
        the states ``[y, dy]`` (see :func:`~sindy_impulse.modes.band_fit.default_estimator`).
    channel : int, optional
        Reference channel (peaks and bands are found on it); default: the strongest.
    onset, offset, samples_per_period
        Passed to :func:`~sindy_impulse.preprocessing.preprocess` (every automatic choice can be
        overridden).
    max_periods : float or None, default=200
        Each mode is identified on the first ``max_periods`` periods of its band signal (the strongest
        part of the ring-down; None: all of it). 200 periods resolve the frequency and the damping ratio
        well and bound the cost of long records.
    n_jobs : int, optional
        Identify the modes of a record in parallel (joblib; -1: every core). The result equals the serial
        run's.

    Returns
    -------
    ModalSurvey
        ``.modes`` (sorted by frequency), ``.table()``, ``.plot()``, ``.rejected``, ``.preprocessing``.

    Examples
    --------
    >>> from sindy_impulse import identify_modes, impact_record
    >>> rec = impact_record([120.0, 240.0], [0.005, 0.01], fs=5000, duration=1.0, snr_db=50, random_state=0)
    >>> survey = identify_modes(rec.y, fs=rec.fs)
    >>> [round(m.frequency_hz, 1) for m in survey.modes], [round(m.damping_ratio, 3) for m in survey.modes]
    ([120.0, 240.0], [0.005, 0.01])
    """
    check_options(sensor=sensor, estimator=estimator, max_periods=max_periods, n_jobs=n_jobs)
    records, forces = _records(y, force)
    options = SurveyOptions(n_modes=n_modes, bands=bands, sensor=sensor,
                            template=default_estimator() if estimator is None else estimator, channel=channel,
                            onset=onset, offset=offset, samples_per_period=samples_per_period,
                            max_periods=max_periods, n_jobs=n_jobs)
    check_param("n_modes", n_modes, [None, Interval(Integral, 1, None)], "identify_modes")
    states = [_survey_record(SurveyState(i, record, ti, fs, fi, options))
              for i, (record, ti, fi) in enumerate(zip(records, _times(t, len(records)), forces))]
    return _survey(states)


def _survey(states: list) -> ModalSurvey:
    """The survey of the records' states: repeated hits combined, notes warned once."""
    per_record = [s.modes for s in states]
    modes = merge_hits(per_record) if len(states) > 1 else list(per_record[0])
    modes.sort(key=lambda m: m.frequency_hz)
    rejected = [r for s in states for r in s.rejected]
    notes = [n for s in states for n in s.notes]
    for note in notes:
        warnings.warn(note, DataWarning, stacklevel=3)
    notes += [f"mode at {m.frequency_hz:.6g} Hz: {m.uncertainty_note}" for m in modes if m.uncertainty_note]
    if not modes:
        warnings.warn(
            "no mode found: "
            + ("; ".join(r.reason for r in rejected) or "no ring-down above the noise in the record")
            + " (check the sensor, the sampling rate fs, or give bands=)",
            NoDynamicsWarning,
            stacklevel=3,
        )
    trace = SurveyTrace(t for s in states for t in s.trace)
    survey = ModalSurvey(modes, rejected, [s.pre for s in states], notes, trace)
    survey.__dict__["poles"] = [s.poles for s in states]  # computed once: survey.poles reads them
    return survey

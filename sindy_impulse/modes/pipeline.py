"""The survey as a declared list of stages over one state object, and the trace of what each did.

A :class:`Pipeline` is an ordered tuple of :class:`Stage` (a name and a function that takes the
:class:`SurveyState` of one record and fills in its part); running it records, per stage, the time it took
and the decisions it took (:class:`StageTrace`), which :attr:`ModalSurvey.trace
<sindy_impulse.modes.result.ModalSurvey.trace>` hands to users. Printing a pipeline shows its stages:

>>> from sindy_impulse.modes.survey import SURVEY
>>> print(SURVEY)  # doctest: +NORMALIZE_WHITESPACE
Pipeline of 7 stages:
  1. read        the record prepared: the hit, clipped samples, the offset
  2. poles       the stabilisation diagram of the free decay: stable poles, computed once
  3. candidates  the modes of the free decay: poles and spectral peaks refined by the decay fit
  4. classify    what each candidate needs, from cheap evidence (kind and reasons)
  5. identify    one equation per mode: from its poles where linear, the paper's fit where not
  6. reconcile   one answer per mode, named rejections, notes
  7. coupling    the modes' values read together where one nonlinear element couples them
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Pipeline", "Stage", "StageTrace", "SurveyOptions", "SurveyState", "SurveyTrace"]


@dataclass(frozen=True)
class SurveyOptions:
    """The user's options of :func:`~sindy_impulse.identify_modes`, checked once, shared by every record."""

    n_modes: int | None = None
    bands: list | None = None
    sensor: str | None = None
    template: object = None
    channel: int | None = None
    onset: object = "auto"
    offset: object = "auto"
    samples_per_period: float = 16.0
    max_periods: float | None = 200.0
    n_jobs: int | None = None


@dataclass
class StageTrace:
    """What one stage did to one record: its time (s) and its decisions, in words."""

    stage: str
    record: int
    seconds: float = 0.0
    decisions: list = field(default_factory=list)

    def __str__(self) -> str:
        said = "; ".join(self.decisions) if self.decisions else "-"
        return f"record {self.record}  {self.stage:<11s} {1e3 * self.seconds:8.1f} ms  {said}"


class SurveyTrace(list):
    """The :class:`StageTrace` of every stage of every record, in order; prints as a table.

    Examples
    --------
    >>> trace = SurveyTrace([StageTrace("read", 0, 0.012, ["offset 0.3 removed"])])
    >>> print(trace)
    record 0  read            12.0 ms  offset 0.3 removed
    >>> trace.seconds()
    {'read': 0.012}
    """

    def __str__(self) -> str:
        return "\n".join(str(t) for t in self)

    def seconds(self) -> dict:
        """Total time per stage over the records (s)."""
        out: dict = {}
        for t in self:
            out[t.stage] = out.get(t.stage, 0.0) + t.seconds
        return out


@dataclass
class SurveyState:
    """Everything the stages know about one record, filled in stage by stage.

    Attributes
    ----------
    index : int
        The record's index among the survey's records (repeated hits).
    record : ndarray (n_samples, n_channels)
        The raw record.
    t, fs, force
        Its time (vector or step), sampling rate and the hammer's force (or None), as given.
    options : SurveyOptions
        The user's options.
    channel : int
        The reference channel (stage ``read``).
    pre : Preprocessed
        The prepared record (``read``), its peaks and bands (``candidates``).
    raw : ndarray
        The reference channel as recorded.
    start : int
        The first sample of ``pre.y`` the decay fit reads (``read``: :func:`~.candidates.decay_start`).
    poles : PoleTable
        The stabilisation diagram (``poles``).
    fit : DecayFit
        The candidates' decay fit (``candidates``).
    candidates : list of Candidate
        The modes of the free decay and what they need (``candidates``, ``classify``).
    hidden : list of Candidate
        Components of the decay fit under the detection threshold that a persistent stable pole confirms
        and that are not candidates (``candidates``: :func:`~.candidates._confirmed_by_poles`): not modes
        of the table, but in the record, so removed from every mode's own signal.
    modes, rejected, notes : list
        The result (``identify``, ``reconcile``; ``coupling`` may replace a mode's values).
    origin : list of int
        The candidate each mode comes from.
    trace : list of StageTrace
        What each stage did.
    cache : dict
        What several stages read and one computes once (the decay fit's components).
    """

    index: int
    record: np.ndarray
    t: object
    fs: float | None
    force: object
    options: SurveyOptions
    channel: int = 0
    pre: object = None
    raw: np.ndarray | None = None
    start: int = 0
    poles: object = None
    fit: object = None
    candidates: list = field(default_factory=list)
    hidden: list = field(default_factory=list)
    modes: list = field(default_factory=list)
    origin: list = field(default_factory=list)
    rejected: list = field(default_factory=list)
    notes: list = field(default_factory=list)
    trace: list = field(default_factory=list)
    cache: dict = field(default_factory=dict, repr=False)

    def decide(self, text: str) -> None:
        """Record a decision of the running stage (shown in the trace)."""
        if self.trace:
            self.trace[-1].decisions.append(text)

    def note(self, text: str) -> None:
        """A note for the user (a warning of the survey), prefixed with the record."""
        self.notes.append(f"record {self.index}: {text}")


@dataclass(frozen=True)
class Stage:
    """One named step of a pipeline: ``run(state)`` fills in its part of a :class:`SurveyState`."""

    name: str
    run: Callable

    @property
    def summary(self) -> str:
        """The first line of the stage function's docstring: what it does."""
        doc = (self.run.__doc__ or "").strip()
        line = doc.split("\n")[0].rstrip(".") if doc else self.run.__name__
        return line[:1].lower() + line[1:]


class Pipeline(tuple):
    """An ordered tuple of :class:`Stage`; calling it runs them on a state and traces each."""

    def __new__(cls, stages):
        stages = tuple(stages)
        names = [s.name for s in stages]
        if len(set(names)) != len(names):
            raise ValueError(f"stage names must be unique, got {names}")
        return super().__new__(cls, stages)

    def __call__(self, state: SurveyState) -> SurveyState:
        for stage in self:
            state.trace.append(StageTrace(stage.name, state.index))
            start = time.perf_counter()
            stage.run(state)
            state.trace[-1].seconds = time.perf_counter() - start
        return state

    def __repr__(self) -> str:
        rows = [f"  {i}. {s.name:<11s} {s.summary}" for i, s in enumerate(self, 1)]
        return "\n".join([f"Pipeline of {len(self)} stages:", *rows])

    __str__ = __repr__

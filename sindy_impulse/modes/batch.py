"""Many records, one survey each: :func:`survey_many` (joblib workers, a dask cluster, a progress bar).

:func:`~sindy_impulse.identify_modes` given a list treats it as repeated hits of one structure and makes
one consensus table; a batch is the other case: independent records (many test points, many parts off
a line), each surveyed on its own. Every record runs in a joblib task, with one BLAS thread in the worker
as in the main process, so the surveys are the same to the last digit whatever ``n_jobs`` or backend
(``tests/test_modes_batch.py``). The warnings of a record's survey are caught where it runs (a worker
process would lose them) and re-issued in the caller, in record order, prefixed with the record's name.

A record whose survey raises (an input identify_modes refuses: too short, NaN, no sampling rate)
comes back as a :class:`FailedRecord` in its place, naming the record and the error, with one DataWarning
counting the failures: the other records' surveys stand. A failure *inside* a survey (one band's fit) is
already a :class:`~sindy_impulse.modes.Rejected` row of that record's survey. Options that concern no
record (``sensor``, ``estimator``, ``max_periods``, an unknown keyword, ``n_jobs``) are checked once,
before any work, and raise.
"""

from __future__ import annotations

import inspect
import warnings
from contextlib import nullcontext
from dataclasses import dataclass
from numbers import Integral, Real

from joblib import Parallel, delayed, parallel_config

from .._utils.params import check_param
from .._utils.progress import progress_bar, wants_progress
from .._utils.threads import one_thread
from ..exceptions import DataWarning
from .survey import check_options, identify_modes

__all__ = ["FailedRecord", "run_surveys", "survey_many"]

#: identify_modes' arguments that survey_many sets per record itself.
_PER_RECORD = ("y", "t", "fs", "force")
#: The options survey_many passes on to identify_modes, the same for every record.
_OPTIONS = tuple(p for p in inspect.signature(identify_modes).parameters if p not in _PER_RECORD)


@dataclass(frozen=True)
class FailedRecord:
    """A record of a batch whose survey raised, in its place in :func:`survey_many`'s list.

    It reads like an empty survey (``modes``, ``rejected``, ``notes`` and ``table()`` are empty;
    ``len()`` is 0), so loops over a batch's results need no special case.

    Attributes
    ----------
    index : int
        Position of the record in the batch.
    name : str
        The record's name (``names=``, a Record's ``source``, else ``"record <index>"``).
    error : str
        The exception's type, e.g. ``"ValueError"``.
    message : str
        The exception's message.

    Examples
    --------
    >>> failed = FailedRecord(3, "hit3.uff", "ValueError", "y has 10 samples")
    >>> print(failed)
    hit3.uff: ValueError: y has 10 samples
    >>> len(failed), failed.table()
    (0, [])
    """

    index: int
    name: str
    error: str
    message: str

    @property
    def modes(self) -> list:
        """No mode."""
        return []

    @property
    def rejected(self) -> list:
        """No band (the whole record failed: see :attr:`message`)."""
        return []

    @property
    def notes(self) -> list:
        """No note."""
        return []

    def table(self, nonlinear: bool = False) -> list:
        """An empty modal table."""
        return []

    def __len__(self) -> int:
        return 0

    def __str__(self) -> str:
        return f"{self.name}: {self.error}: {self.message}"


def _survey_one(index, name, y, t, fs, force, options, nonlinearity):
    """One record's survey (or its FailedRecord) and the warnings it raised as ``(category, message)``.

    Module level so that every joblib backend, dask included, can pickle it; one BLAS thread, as in
    every worker, so that the numbers do not depend on where the record ran.
    """
    with warnings.catch_warnings(record=True) as caught, one_thread():
        warnings.simplefilter("always")
        try:
            result = identify_modes(y, t, fs=fs, force=force, **options)
            if nonlinearity:
                for mode in result.modes:
                    mode.nonlinearity  # noqa: B018 - computed here, in the worker, and kept with the mode
        except Exception as err:  # noqa: BLE001 - one record's failure must not abort the batch
            result = FailedRecord(index, name, type(err).__name__, " ".join(str(err).split()))
    seen = dict.fromkeys((w.category, str(w.message)) for w in caught)  # once each, in order
    return result, list(seen)


def _per_record(value, n: int, what: str, scalar_ok: bool) -> list:
    """``value`` for each of ``n`` records: a scalar (``scalar_ok``) repeated, or a sequence of ``n``."""
    if value is None or (scalar_ok and isinstance(value, Real)):
        return [value] * n
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__"):
        raise TypeError(f"{what} must be a sequence with one entry per record, not {type(value).__name__}")
    if len(value) != n:
        raise ValueError(f"{what} has {len(value)} entries but there are {n} records")
    return list(value)


def _check_batch(records, names, options: dict, n_jobs) -> list:
    """The checks that concern no single record; returns the records as a list."""
    if not isinstance(records, (list, tuple)):
        raise TypeError(
            f"records must be a list of records (arrays or sindy_impulse.io.Record), not "
            f"{type(records).__name__}; for one record call identify_modes"
        )
    if not records:
        raise ValueError("records is empty; expected at least one record")
    unknown = sorted(set(options) - set(_OPTIONS))
    if unknown:
        raise TypeError(f"survey_many got unknown keyword(s) {unknown}; identify_modes takes {_OPTIONS}")
    check_options(**{k: options[k] for k in ("sensor", "estimator", "max_periods") if k in options})
    check_param("n_jobs", n_jobs, [None, Integral], "survey_many")
    if names is not None:
        names = _per_record(names, len(records), "names", scalar_ok=False)
        if not all(isinstance(n, str) for n in names):
            raise TypeError("names must be strings")
    return list(records)


def _inputs(records, fs, t, force, names) -> list:
    """Per record: ``(name, y, t, fs, force)``; a :class:`~sindy_impulse.io.Record` brings its own
    response channels, clock and force (``force=`` overrides it)."""
    from ..io import Record

    n = len(records)
    fs_, t_, force_ = (_per_record(fs, n, "fs", True), _per_record(t, n, "t", False),
                       _per_record(force, n, "force", False))
    names = names if names is not None else [None] * n
    out = []
    for i, rec in enumerate(records):
        name = names[i]
        if isinstance(rec, Record):
            y = rec.response[:, 0] if rec.response.shape[1] == 1 else rec.response
            f = force_[i] if force_[i] is not None else rec.force
            out.append((name or rec.source or f"record {i}", y, rec.t, None, f))
        else:
            out.append((name or f"record {i}", rec, t_[i], fs_[i], force_[i]))
    return out


def survey_many(
    records,
    fs=None,
    *,
    t=None,
    force=None,
    names=None,
    nonlinearity: bool = False,
    n_jobs: int | None = None,
    progress: bool | None = None,
    backend=None,
    **identify_modes_kwargs,
) -> list:
    """One modal survey per record, over many independent records, in parallel.

    Parameters
    ----------
    records : list
        The records: arrays (n_samples,) or (n_samples, n_channels), raw as for
        :func:`~sindy_impulse.identify_modes`, or :class:`sindy_impulse.io.Record` (its response channels,
        clock and force are used: ``read_record`` output goes in as it is).
    fs : float or sequence of float, optional
        Sampling rate (Hz) of the array records: one for all, or one per record.
    t : sequence, optional
        One time vector (or step) per array record, instead of ``fs``.
    force : sequence, optional
        One hammer force per record (None entries allowed); overrides a Record's force.
    names : sequence of str, optional
        The records' names, used in warnings and in :class:`FailedRecord` (default: a Record's
        ``source``, else ``"record <i>"``).
    nonlinearity : bool, default=False
        Also run each mode's test for nonlinearity (``mode.nonlinearity``, kept with the mode) in the
        worker.
    n_jobs : int, optional
        Parallel joblib workers (-1: every core); None: 1, or what an enclosing
        ``joblib.parallel_config`` says.
    progress : bool, optional
        A tqdm progress bar over the records; default: when standard error is a terminal.
    backend : str, optional
        A joblib backend for this call (e.g. ``"dask"`` with a ``dask.distributed.Client`` created
        first); default: the enclosing ``joblib.parallel_config``'s, else processes (loky).
    **identify_modes_kwargs
        Any other option of :func:`~sindy_impulse.identify_modes` (``sensor``, ``n_modes``, ``bands``,
        ``max_periods``...), the same for every record.

    Returns
    -------
    list of ModalSurvey or FailedRecord
        One per record, in the records' order; a record whose survey raised is a :class:`FailedRecord`
        (a DataWarning counts them). The surveys equal a serial run's to the last digit.

    Examples
    --------
    >>> from sindy_impulse import impact_record
    >>> recs = [impact_record([120.0, 240.0], [0.005, 0.01], fs=5000, duration=1.0, snr_db=50,
    ...                       random_state=seed).y for seed in (0, 1)]
    >>> surveys = survey_many(recs, fs=5000.0, names=["point 1", "point 2"], n_jobs=1)
    >>> [[round(m.frequency_hz) for m in s.modes] for s in surveys]
    [[120, 240], [120, 240]]
    """
    results = run_surveys(
        records, fs, t=t, force=force, names=names, nonlinearity=nonlinearity, n_jobs=n_jobs,
        progress=progress, backend=backend, **identify_modes_kwargs,
    )
    return _collect(results)


def run_surveys(records, fs=None, **options) -> list:
    """What :func:`survey_many` runs, with each record's warnings handed back instead of re-issued (the
    command line prints them as the record's notes).

    Same parameters as :func:`survey_many` (``options``: its keywords, the rest passed to
    :func:`identify_modes`). Returns one ``(name, survey or FailedRecord, warnings)`` per
    record, ``warnings`` a list of ``(category, message)`` in the order they were raised (each once).

    Examples
    --------
    >>> import numpy as np
    >>> ((name, failed, caught),) = run_surveys([np.zeros(10)], fs=1000.0, names=["short.csv"])
    >>> name, failed.error, caught
    ('short.csv', 'ValueError', [])
    """
    t, force, names, backend, progress = (options.pop(k, None) for k in ("t", "force", "names", "backend",
                                                                          "progress"))
    nonlinearity, n_jobs = options.pop("nonlinearity", False), options.pop("n_jobs", None)
    identify_modes_kwargs = options
    records = _check_batch(records, names, identify_modes_kwargs, n_jobs)
    jobs = _inputs(records, fs, t, force, names)
    tasks = (
        delayed(_survey_one)(i, name, y, ti, fsi, fi, identify_modes_kwargs, nonlinearity)
        for i, (name, y, ti, fsi, fi) in enumerate(jobs)
    )
    config = parallel_config(backend=backend) if backend is not None else nullcontext()
    # thread pools are the process's: held at one thread around the whole batch, so that workers sharing
    # this process (the threading backend) never see one another restore them
    with config, one_thread():
        results = Parallel(n_jobs=n_jobs, return_as="generator")(tasks)
        bar = wants_progress(progress, len(jobs))
        results = list(progress_bar(results, total=len(jobs), desc="records", unit="record", enabled=bar))
    return [(job[0], survey, caught) for job, (survey, caught) in zip(jobs, results)]


def _collect(results: list) -> list:
    """The surveys, after re-issuing each record's warnings (prefixed with its name) and one warning
    counting the failed records."""
    surveys = []
    for name, survey, caught in results:
        for category, message in caught:
            warnings.warn(f"{name}: {message}", category, stacklevel=3)
        surveys.append(survey)
    failed = [s for s in surveys if isinstance(s, FailedRecord)]
    if failed:
        warnings.warn(
            f"{len(failed)} of {len(surveys)} records gave no survey (FailedRecord in their place); "
            f"first: {failed[0]}",
            DataWarning,
            stacklevel=3,
        )
    return surveys

"""The complexity-error plane (paper section 3.2, Figure 10): many models, their Gamma and their size.

Every SINDy model is a point in the plane spanned by its complexity (the number of non-zero
coefficients) and its reconstruction error Gamma. :func:`complexity_error` fits a family of models --
several estimators (e.g. polynomial libraries of degree ``p = 1 .. 5``), several inputs (e.g. signals
mixed from the states, ``s = beta x1 + (1 - beta) x2``), or every combination of both -- and returns a
:class:`ComplexityError` holding one row per model: Gamma, number of terms, labels, coefficients and
the fitted models, plus the Pareto front (models that no other model beats in both size and error).

Single-sensor data are rebuilt into states by an embedding transformer
(:class:`~sindy_impulse.DelayEmbedding`), fitted on each input separately as in the paper.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from numbers import Integral
from typing import Any

import numpy as np
from sklearn.base import clone

from .._utils.validation import check_signal, check_time
from ..simulation.scoring import gamma_from_arrays

__all__ = ["complexity_error", "ComplexityError"]


@dataclass
class ComplexityError:
    """Models on the complexity-error plane: one entry per (estimator, input) pair.

    Entries are ordered estimator-major: model ``k`` is estimator ``k // n_inputs`` fitted on input
    ``k % n_inputs``. Arrays have one value per model.

    Attributes
    ----------
    gamma : ndarray of float
        Gamma of the model simulated from the first input sample against the input states (the
        paper's definition: the embedded trajectories ``q(t)`` for single-signal input). ``inf`` if the
        simulation diverged or the fit failed.
    gamma_filtered : ndarray of float
        The estimator's own ``gamma_``: against the states filtered by its differentiation (NaN if the
        estimator has none or the fit failed).
    gamma_sindy : ndarray of float
        The estimator's ``gamma_sindy_``: the selected sweep candidate before refinement, against the
        filtered states (NaN if unavailable).
    n_terms : ndarray of int
        Number of non-zero coefficients (the complexity); -1 for a failed fit.
    estimator_index, input_index : ndarray of int
        Position of the model's estimator and input.
    estimator_label, input_label : ndarray
        Their labels (numbers stay numeric, e.g. degrees and mixing ratios).
    tau, dimension : ndarray of int
        Embedding delay and dimension used for the input (-1 without embedding or if it failed).
    fit_time : ndarray of float
        Wall time of each fit in seconds (embedding excluded).
    coefficients : list of ndarray or None
        Coefficient matrix (n_states, n_features) of each model; None for a failed fit.
    term_names : list of list of str or None
        Names of the library terms (the columns of ``coefficients``).
    equations : list of list of str or None
        Right-hand sides, one string per state.
    models : list of estimator or None
        The fitted estimators (None for failed fits, or all None with ``keep_models=False``).
    errors : list of str or None
        ``"ExceptionType: message"`` for each failed fit, None for the others.

    Examples
    --------
    >>> import numpy as np, pysindy as ps
    >>> from sindy_impulse import DelayEmbedding, ImpulseSINDy, damped_oscillator
    >>> from sindy_impulse.analysis import complexity_error
    >>> ring_down = damped_oscillator()
    >>> signals = {beta: beta * ring_down.x[:, 0] + (1 - beta) * ring_down.x[:, 1] for beta in (0.5, 1.0)}
    >>> estimators = {p: ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=p)) for p in (1, 2)}
    >>> result = complexity_error(estimators, signals, t=0.01, embedding=DelayEmbedding())
    >>> len(result), result.n_terms.tolist()
    (4, [4, 4, 4, 4])
    >>> bool(np.all(result.gamma < 0.01))
    True
    >>> rec = result.to_records()
    >>> rec.dtype.names[:4]
    ('estimator_label', 'input_label', 'n_terms', 'gamma')
    >>> result.grid("n_terms")
    array([[4, 4],
           [4, 4]])
    """

    gamma: np.ndarray
    gamma_filtered: np.ndarray
    gamma_sindy: np.ndarray
    n_terms: np.ndarray
    estimator_index: np.ndarray
    input_index: np.ndarray
    estimator_label: np.ndarray
    input_label: np.ndarray
    tau: np.ndarray
    dimension: np.ndarray
    fit_time: np.ndarray
    coefficients: list = field(repr=False)
    term_names: list = field(repr=False)
    equations: list = field(repr=False)
    models: list = field(repr=False)
    errors: list = field(repr=False)
    n_estimators: int = 1
    n_inputs: int = 1

    def __len__(self) -> int:
        return int(self.gamma.size)

    @property
    def succeeded(self) -> np.ndarray:
        """Boolean mask of the fits that did not raise."""
        return np.array([e is None for e in self.errors], dtype=bool)

    @property
    def stable(self) -> np.ndarray:
        """Boolean mask of the models whose simulation stayed finite (finite ``gamma``)."""
        return np.isfinite(self.gamma)

    def _metric(self, metric: str) -> np.ndarray:
        if metric not in ("gamma", "gamma_filtered", "gamma_sindy"):
            raise ValueError(f"metric must be 'gamma', 'gamma_filtered' or 'gamma_sindy', got {metric!r}")
        return getattr(self, metric)

    def pareto_front(self, metric: str = "gamma") -> np.ndarray:
        """Indices of the non-dominated models, sparsest first.

        A model is dominated if another has no more terms and no larger error, and is better in one
        of the two. Failed fits and models with non-finite error are never on the front; of exactly
        equal points the first is kept.

        Parameters
        ----------
        metric : {"gamma", "gamma_filtered", "gamma_sindy"}, default="gamma"
            The error axis.

        Returns
        -------
        ndarray of int
            Model indices ordered by increasing number of terms (and decreasing error).
        """
        err = self._metric(metric)
        ok = np.flatnonzero(self.succeeded & np.isfinite(err) & (self.n_terms >= 0))
        order = ok[np.lexsort((ok, err[ok], self.n_terms[ok]))]
        front, best = [], np.inf
        for i in order:
            if err[i] < best:
                front.append(int(i))
                best = err[i]
        return np.asarray(front, dtype=int)

    def best(self, metric: str = "gamma", max_terms: int | None = None) -> int:
        """Index of the model of least error (fewest terms on ties), optionally at most ``max_terms``.

        Raises
        ------
        ValueError
            If no successful model with finite error (and few enough terms) exists.
        """
        err = self._metric(metric)
        ok = self.succeeded & np.isfinite(err) & (self.n_terms >= 0)
        if max_terms is not None:
            ok &= self.n_terms <= max_terms
        idx = np.flatnonzero(ok)
        if idx.size == 0:
            raise ValueError("no successful model with a finite error" + ("" if max_terms is None else
                             f" and at most {max_terms} terms"))
        return int(idx[np.lexsort((idx, self.n_terms[idx], err[idx]))[0]])

    def grid(self, name: str) -> np.ndarray:
        """A per-model array reshaped to (n_estimators, n_inputs), e.g. for a heat map.

        Parameters
        ----------
        name : str
            One of ``gamma``, ``gamma_filtered``, ``gamma_sindy``, ``n_terms``, ``tau``, ``dimension``,
            ``fit_time``.
        """
        allowed = ("gamma", "gamma_filtered", "gamma_sindy", "n_terms", "tau", "dimension", "fit_time")
        if name not in allowed:
            raise ValueError(f"name must be one of {allowed}, got {name!r}")
        return getattr(self, name).reshape(self.n_estimators, self.n_inputs)

    def to_records(self) -> np.recarray:
        """All scalar columns as a NumPy record array (one record per model).

        Fields: ``estimator_label, input_label, n_terms, gamma, gamma_filtered, gamma_sindy,
        estimator_index, input_index, tau, dimension, fit_time, succeeded, stable, pareto``. Pass it to
        ``pandas.DataFrame`` or ``numpy.savetxt``-like writers as is.
        """
        pareto = np.zeros(len(self), dtype=bool)
        pareto[self.pareto_front()] = True
        columns = {
            "estimator_label": self.estimator_label,
            "input_label": self.input_label,
            "n_terms": self.n_terms,
            "gamma": self.gamma,
            "gamma_filtered": self.gamma_filtered,
            "gamma_sindy": self.gamma_sindy,
            "estimator_index": self.estimator_index,
            "input_index": self.input_index,
            "tau": self.tau,
            "dimension": self.dimension,
            "fit_time": self.fit_time,
            "succeeded": self.succeeded,
            "stable": self.stable,
            "pareto": pareto,
        }
        return np.rec.fromarrays(list(columns.values()), names=list(columns))

    def summary(self, metric: str = "gamma") -> str:
        """A text table per estimator: terms (min/median/max), error (min/median/max), failures.

        Examples
        --------
        The first line is the header: ``estimator  n  failed  unstable  terms min/med/max ...``.
        """
        err = self._metric(metric)
        lines = [
            f"{'estimator':>12} {'n':>4} {'failed':>6} {'unstable':>8} {'terms min/med/max':>18} "
            f"{metric + ' min/median/max':>34}"
        ]
        for e in range(self.n_estimators):
            sel = self.estimator_index == e
            ok = sel & self.succeeded
            fin = ok & np.isfinite(err)
            if fin.any():
                k = self.n_terms[fin]
                g = err[fin]
                terms = f"{k.min()}/{np.median(k):g}/{k.max()}"
                gam = f"{g.min():.4g}/{np.median(g):.4g}/{g.max():.4g}"
            else:
                terms, gam = "-", "-"
            label = self.estimator_label[np.flatnonzero(sel)[0]]
            lines.append(
                f"{label!s:>12} {int(sel.sum()):>4} {int((sel & ~self.succeeded).sum()):>6} "
                f"{int((ok & ~np.isfinite(err)).sum()):>8} {terms:>18} {gam:>34}"
            )
        return "\n".join(lines)

_ERRORS = ("record", "raise")


# --------------------------------------------------------------------------------------------------------
# input handling
# --------------------------------------------------------------------------------------------------------
def _as_labelled(obj, name: str, labels, is_item) -> tuple[list, list]:
    """(items, labels) from one item, a sequence of items or a mapping label -> item."""
    if isinstance(obj, Mapping):
        if labels is not None:
            raise ValueError(f"{name} is a mapping (its keys are the labels); do not pass {name[:-1]}_labels")
        items, labs = list(obj.values()), list(obj.keys())
    elif is_item(obj):
        items, labs = [obj], None
    elif isinstance(obj, Sequence) and not isinstance(obj, str):
        items, labs = list(obj), None
    else:
        raise TypeError(f"{name} must be one item, a list of them or a dict label -> item; got {type(obj)}")
    if not items:
        raise ValueError(f"{name} is empty")
    if labs is None:
        if labels is None:
            labs = list(range(len(items)))
        else:
            if isinstance(labels, (str, bytes)) or not hasattr(labels, "__len__"):
                raise TypeError(f"{name[:-1]}_labels must be a sequence, got {labels!r}")
            labs = list(labels)
            if len(labs) != len(items):
                raise ValueError(f"{name[:-1]}_labels has {len(labs)} labels for {len(items)} {name}")
    return items, labs


def _label_array(labels: list) -> np.ndarray:
    """Numeric labels as a numeric array, anything else as strings."""
    if all(isinstance(v, (Integral, float, np.floating)) and not isinstance(v, bool) for v in labels):
        return np.asarray(labels)
    return np.asarray([str(v) for v in labels])


def _is_estimator(obj) -> bool:
    return hasattr(obj, "fit") and hasattr(obj, "get_params")


def _check_estimator(est, i: int) -> None:
    missing = [m for m in ("fit", "get_params", "simulate", "coefficients") if not hasattr(est, m)]
    if missing:
        hint = ""
        if hasattr(est, "steps"):
            hint = (
                "; for a Pipeline(DelayEmbedding(), ImpulseSINDy()) pass the ImpulseSINDy as the estimator "
                "and the DelayEmbedding as embedding="
            )
        raise TypeError(
            f"estimators[{i}] ({type(est).__name__}) is not an ImpulseSINDy-like estimator: it lacks "
            f"{', '.join(missing)}{hint}"
        )


def _is_input(obj) -> bool:
    """One input: an array (or DataFrame/Series), not a list of arrays."""
    return hasattr(obj, "shape") or (
        isinstance(obj, Sequence)
        and not isinstance(obj, str)
        and len(obj) > 0
        and not hasattr(obj[0], "shape")
        and np.ndim(obj[0]) <= 1
    )


def _per_input_times(t, signals: list[np.ndarray], input_keys, inputs_is_mapping: bool) -> list:
    """One validated step (float), vector or None per input."""
    n = len(signals)
    if t is None:
        return [None] * n
    if isinstance(t, Mapping):
        if not inputs_is_mapping or set(t) != set(input_keys):
            raise ValueError("t as a dict must have the same keys as inputs")
        per = [t[k] for k in input_keys]
    elif isinstance(t, (list, tuple)) and len(t) > 0 and all(np.ndim(ti) == 1 for ti in t):
        if len(t) != n:
            raise ValueError(f"t has {len(t)} time vectors for {n} inputs")
        per = list(t)
    else:
        per = [t] * n
    return [
        check_time(ti, s.shape[0], "t" if len(per) == 1 else f"t[{i}]")
        for i, (ti, s) in enumerate(zip(per, signals))
    ]


def _embed(embedding, signal: np.ndarray, t):
    """Fit a clone of ``embedding`` on the signal; return (states, time, fitted embedding)."""
    emb = clone(embedding)
    states = np.asarray(emb.fit_transform(signal), dtype=float)
    if states.ndim == 1:
        states = states[:, None]
    if t is None or np.ndim(t) == 0:
        t_states = t
    elif hasattr(emb, "transform_time"):
        t_states = np.asarray(emb.transform_time(t), dtype=float)
    else:
        raise ValueError(
            f"{type(emb).__name__} has no transform_time(); pass t as a scalar time step with this embedding"
        )
    return states, t_states, emb


# --------------------------------------------------------------------------------------------------------
# one fit
# --------------------------------------------------------------------------------------------------------
@dataclass
class _Fit:
    """One (estimator, input) fit of the study: what becomes one entry of :class:`ComplexityError`.

    A fit that does not exist (yet, or failed) has Gamma inf and no terms (``n_terms`` -1).
    """

    gamma: float = np.inf
    gamma_filtered: float = np.nan
    gamma_sindy: float = np.nan
    n_terms: int = -1
    coefficients: np.ndarray | None = None
    term_names: list | None = None
    equations: list | None = None
    model: Any = None
    error: str | None = None
    fit_time: float = np.nan


@dataclass
class _Input:
    """One input ready to fit: states, their times and names (None when its embedding failed), and the
    embedding's delay and dimension (-1 without)."""

    states: np.ndarray | None
    t: Any = None
    names: list | None = None
    tau: int = -1
    dimension: int = -1
    error: str | None = None


def _fit_one(estimator, data: _Input, keep_model: bool, errors: str) -> _Fit:
    states, t = data.states, data.t
    out = _Fit()
    est = clone(estimator)
    start = time.perf_counter()
    try:
        kwargs = {} if data.names is None else {"feature_names": data.names}
        est.fit(states, t=t, **kwargs)
        out.fit_time = time.perf_counter() - start
        coef = np.asarray(est.coefficients(), dtype=float)
        out.coefficients = coef.copy()
        out.n_terms = int(np.count_nonzero(coef))
        out.gamma_filtered = float(getattr(est, "gamma_", np.nan))
        out.gamma_sindy = float(getattr(est, "gamma_sindy_", np.nan))
        if hasattr(est, "get_feature_names"):
            out.term_names = list(est.get_feature_names())
        if hasattr(est, "equations"):
            out.equations = list(est.equations())
        t_sim = getattr(est, "t_", None)
        if t_sim is None or np.ndim(t_sim) != 1 or len(t_sim) != len(states):
            t_sim = np.arange(len(states)) * (1.0 if t is None or np.ndim(t) else float(t))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # divergence -> NaN rows -> Gamma inf
            sim = np.asarray(est.simulate(states[0], t_sim), dtype=float)
        if sim.shape == states.shape:
            out.gamma = gamma_from_arrays(states, sim)
    except Exception as err:  # noqa: BLE001 - a failing fit is a data point of the study
        if errors == "raise":
            raise
        out.fit_time = time.perf_counter() - start
        out.error = f"{type(err).__name__}: {err}"
        return out
    if keep_model:
        out.model = est
    return out


# --------------------------------------------------------------------------------------------------------
# the study
# --------------------------------------------------------------------------------------------------------
def complexity_error(
    estimators,
    inputs,
    *,
    t=None,
    dt: float | None = None,
    embedding=None,
    estimator_labels: Sequence | None = None,
    input_labels: Sequence | None = None,
    feature_names: Sequence[str] | None = None,
    n_jobs: int | None = None,
    keep_models: bool = True,
    errors: str = "record",
) -> ComplexityError:
    """Fit every estimator on every input and place the models on the complexity-error plane.

    The data of the paper's Figure 10b: for each (estimator, input) pair the number of non-zero
    coefficients and the reconstruction error Gamma, with the Pareto front of the plane.

    Parameters
    ----------
    estimators : estimator, list of estimators or dict label -> estimator
        ImpulseSINDy-like estimators (``fit(x, t=...)``, ``coefficients()``, ``simulate(x0, t)``),
        e.g. ``ImpulseSINDy(feature_library=PolynomialLibrary(degree=p))`` for several ``p``. Each is
        cloned per input; the originals are not modified.
    inputs : array, list of arrays or dict label -> array
        State arrays (n_samples, n_states), or single signals (n_samples,) with ``embedding``.
    t : float, array (n_samples,), list of arrays or dict, optional
        Time step, one time vector shared by all inputs, or one per input (a list, or a dict keyed like
        ``inputs``). Defaults to ``dt``; without either each estimator's own ``dt`` is used.
    dt : float, optional
        Time step (an alternative to ``t``; pass one of them).
    embedding : transformer, optional
        E.g. :class:`~sindy_impulse.DelayEmbedding`: cloned and fitted on each input, whose embedded
        states are then fitted (with time ``embedding.transform_time(t)`` for a time vector). Its feature
        names (``q1 .. qm``) name the states unless ``feature_names`` is given.
    estimator_labels, input_labels : sequence, optional
        Labels of the estimators and the inputs (e.g. degrees and mixing ratios); default 0, 1, ...
        Not allowed when the corresponding argument is a dict (its keys are the labels).
    feature_names : sequence of str, optional
        Names of the states, passed to every fit.
    n_jobs : int, optional
        Fits run in parallel with joblib (processes); None or 1 runs them here, -1 uses every core.
    keep_models : bool, default=True
        Keep the fitted estimators in ``result.models`` (coefficients are always kept).
    errors : {"record", "raise"}, default="record"
        ``"record"``: a fit (or embedding) that raises gives Gamma = inf and ``n_terms = -1``, its
        message is kept in ``result.errors`` and one warning summarizes the failures. ``"raise"``:
        the first failure propagates.

    Returns
    -------
    ComplexityError
        One entry per (estimator, input) pair, estimator-major.

    Raises
    ------
    TypeError
        An estimator that is not ImpulseSINDy-like, an embedding without ``fit_transform``, inputs of
        the wrong type.
    ValueError
        Empty or non-finite inputs, multi-column inputs with an embedding, label counts that do not
        match, both ``t`` and ``dt``, time vectors of the wrong length, an unknown ``errors``.

    Notes
    -----
    ``gamma`` is the paper's error: the model is simulated from the first input sample and compared with
    the input states (for embedded signals the trajectories ``q(t)``). ImpulseSINDy's own ``gamma_`` is
    measured against the states filtered by its differentiation; it is kept as ``gamma_filtered``.

    Examples
    --------
    Table 1 of the paper (one signal, degrees 1 to 3):

    >>> import pysindy as ps
    >>> from sindy_impulse import DelayEmbedding, ImpulseSINDy, damped_oscillator
    >>> x1 = damped_oscillator().x[:, 0]
    >>> result = complexity_error(
    ...     [ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=p)) for p in (1, 2, 3)],
    ...     x1, dt=0.01, embedding=DelayEmbedding(), estimator_labels=[1, 2, 3])
    >>> result.tau.tolist(), result.dimension.tolist(), result.n_terms.tolist()
    ([18, 18, 18], [2, 2, 2], [4, 4, 4])
    >>> result.pareto_front().tolist()
    [0]
    """
    t = _check_study(errors, keep_models, t, dt, n_jobs, embedding)
    ests, est_labels = _as_labelled(estimators, "estimators", estimator_labels, _is_estimator)
    for i, est in enumerate(ests):
        _check_estimator(est, i)
    raw, in_labels = _as_labelled(inputs, "inputs", input_labels, _is_input)
    signals = _signals(raw, embedding is not None)
    if feature_names is not None:
        if isinstance(feature_names, str):
            raise TypeError("feature_names must be a sequence of strings, not one string")
        feature_names = [str(f) for f in feature_names]
    times = _per_input_times(t, signals, in_labels, isinstance(inputs, Mapping))
    prepared = [
        _prepare(embedding, s, ti, feature_names, i, errors) for i, (s, ti) in enumerate(zip(signals, times))
    ]
    tasks = [(e, i) for e in range(len(ests)) for i in range(len(signals))]
    records = _run_fits(ests, prepared, tasks, keep_models, errors, n_jobs)
    failed = [r.error for r in records if r.error is not None]
    if failed:
        warnings.warn(
            f"{len(failed)} of {len(records)} fits failed (recorded with Gamma = inf); first: {failed[0]}",
            RuntimeWarning,
            stacklevel=2,
        )
    return _result(records, tasks, est_labels, in_labels, prepared, len(ests), len(signals))


def _check_study(errors, keep_models, t, dt, n_jobs, embedding):
    """The study's options checked; returns ``t`` (``dt`` folded in)."""
    if errors not in _ERRORS:
        raise ValueError(f"errors must be one of {_ERRORS}, got {errors!r}")
    if not isinstance(keep_models, (bool, np.bool_)):
        raise TypeError(f"keep_models must be True or False, got {keep_models!r}")
    if t is not None and dt is not None:
        raise ValueError("pass either t or dt, not both")
    if n_jobs is not None and (not isinstance(n_jobs, Integral) or isinstance(n_jobs, bool) or n_jobs == 0):
        raise ValueError(f"n_jobs must be None or a non-zero int, got {n_jobs!r}")
    if embedding is not None and not all(hasattr(embedding, a) for a in ("fit_transform", "get_params")):
        raise TypeError(f"embedding must be a scikit-learn transformer, got {type(embedding).__name__}")
    return check_time(dt, 1, "dt") if dt is not None else t


def _signals(raw, embedded: bool) -> list[np.ndarray]:
    """Validated inputs: state arrays, or 1-D signals for an embedding."""
    if not embedded:
        return [check_signal(s, f"inputs[{i}]", min_samples=3) for i, s in enumerate(raw)]
    signals = [check_signal(s, f"inputs[{i}]", min_samples=3, as_2d=False) for i, s in enumerate(raw)]
    for i, s in enumerate(signals):
        if s.ndim == 2 and s.shape[1] != 1:
            raise ValueError(
                f"inputs[{i}] has {s.shape[1]} columns; an embedding needs one signal (n_samples,)"
            )
    return [s.reshape(-1) for s in signals]


def _prepare(embedding, signal, t, feature_names, i: int, errors: str) -> _Input:
    """One input ready to fit: states, time, state names, delay and dimension (or the embedding's error)."""
    if embedding is None:
        return _Input(signal, t, feature_names)
    try:
        states, t_states, emb = _embed(embedding, signal, t)
    except Exception as err:  # noqa: BLE001 - recorded like a failing fit
        if errors == "raise":
            raise
        return _Input(None, error=f"embedding of inputs[{i}] failed: {type(err).__name__}: {err}")
    names = feature_names
    if names is None and hasattr(emb, "get_feature_names_out"):
        names = [str(n) for n in emb.get_feature_names_out()]
    dimension = int(getattr(emb, "dimension_", states.shape[1]))
    return _Input(states, t_states, names, int(getattr(emb, "tau_", -1)), dimension)


def _run_fits(ests, prepared, tasks, keep_models, errors, n_jobs) -> list[_Fit]:
    """Every (estimator, input) fit, serially or with joblib; a record per task."""
    runnable = [(e, i) for e, i in tasks if prepared[i].states is not None]
    if n_jobs is None or n_jobs == 1 or len(runnable) <= 1:
        outputs = [_fit_one(ests[e], prepared[i], keep_models, errors) for e, i in runnable]
    else:
        from joblib import Parallel, delayed

        outputs = Parallel(n_jobs=n_jobs)(
            delayed(_fit_one)(ests[e], prepared[i], keep_models, errors) for e, i in runnable
        )
    by_task = dict(zip(runnable, outputs))
    return [by_task.get(task) or _Fit(error=prepared[task[1]].error) for task in tasks]


def _result(records, tasks, est_labels, in_labels, prepared, n_estimators, n_inputs) -> ComplexityError:
    est_idx = np.array([e for e, _ in tasks], dtype=int)
    in_idx = np.array([i for _, i in tasks], dtype=int)
    est_lab, in_lab = _label_array(est_labels), _label_array(in_labels)

    def column(name, dtype=float):
        return np.array([getattr(r, name) for r in records], dtype=dtype)

    return ComplexityError(
        gamma=column("gamma"),
        gamma_filtered=column("gamma_filtered"),
        gamma_sindy=column("gamma_sindy"),
        n_terms=column("n_terms", int),
        estimator_index=est_idx,
        input_index=in_idx,
        estimator_label=est_lab[est_idx],
        input_label=in_lab[in_idx],
        tau=np.array([p.tau for p in prepared], dtype=int)[in_idx],
        dimension=np.array([p.dimension for p in prepared], dtype=int)[in_idx],
        fit_time=column("fit_time"),
        coefficients=[r.coefficients for r in records],
        term_names=[r.term_names for r in records],
        equations=[r.equations for r in records],
        models=[r.model for r in records],
        errors=[r.error for r in records],
        n_estimators=n_estimators,
        n_inputs=n_inputs,
    )

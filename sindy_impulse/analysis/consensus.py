"""One model from many fits of the same system (paper section 3.3.2, Figure 12).

Repeated hammer impacts excite the same system with different amplitudes; each record gives its own
refined model. :func:`consensus` combines them coefficient by coefficient:

* the support is a majority vote: a coefficient is kept when it is non-zero in at least
  ``min_frequency`` (default half) of the models;
* its value is the most frequent value of its non-zero estimates (``method="mode"``): the peak of a
  histogram with Freedman-Diaconis bins (robust to the outliers a few poor fits produce, at most
  ``max_bins`` bins), refined to the median of the estimates inside the peak bin, so the result does not
  depend on where the bin edges fall; or their median (``method="median"``).

:func:`consensus_fit` is the alternative the paper contrasts this with (Brunton et al.): one fit on all
records together. It returns the same :class:`Consensus` type so both can be compared directly.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
from sklearn.base import clone

from .._utils.validation import check_array, check_signal

__all__ = ["consensus", "consensus_fit", "Consensus", "Histogram", "coefficient_stack"]

_METHODS = ("mode", "median")


class Histogram(NamedTuple):
    """Histogram of one coefficient's non-zero estimates (one panel of Figure 12)."""

    counts: np.ndarray
    edges: np.ndarray
    values: np.ndarray
    peak: int
    """Index of the peak bin."""


@dataclass
class Consensus:
    """Consensus coefficients of several models of one system.

    Attributes
    ----------
    coefficients : ndarray (n_states, n_features)
        The consensus coefficient matrix.
    feature_names : list of str
        Library term names (columns).
    state_names : list of str
        State names (rows).
    method : str
        ``"mode"``, ``"median"`` or ``"stacked"``.
    n_models : int
        Models combined (1 for ``"stacked"``).
    frequency_nonzero : ndarray (n_states, n_features)
        Fraction of the models in which each coefficient is non-zero.
    spread : ndarray (n_states, n_features)
        Interquartile range of each coefficient's non-zero estimates (0 where fewer than 2).
    histograms : dict
        ``{(i, k): Histogram}`` for every coefficient that is non-zero in some model.
    estimates : ndarray (n_models, n_states, n_features)
        The coefficients of every model.
    library : feature library or None
        The (fitted) library of the models, used by :meth:`compiled`.
    model : estimator or None
        The single fitted estimator of :func:`consensus_fit`.
    """

    coefficients: np.ndarray
    feature_names: list[str]
    state_names: list[str]
    method: str
    n_models: int
    frequency_nonzero: np.ndarray
    spread: np.ndarray
    histograms: dict = field(default_factory=dict)
    estimates: np.ndarray | None = None
    library: object = None
    model: object = None

    def names(self) -> dict:
        """``{(i, k): "x1' : x0"}`` for every coefficient."""
        return {
            (i, k): f"{s}' : {f}"
            for i, s in enumerate(self.state_names)
            for k, f in enumerate(self.feature_names)
        }

    def equations(self, precision: int = 3) -> list[str]:
        """Right-hand sides of the consensus model as strings."""
        out = []
        for row in self.coefficients:
            terms = [
                f"{c:.{precision}f} {n}"
                for c, n in zip(row, self.feature_names)
                if np.round(c, precision) != 0
            ]
            out.append(" + ".join(terms) if terms else f"{0:.{precision}f}")
        return out

    def compiled(self, reference=None):
        """The consensus model as a :class:`~sindy_impulse.simulation.CompiledModel` (to simulate it)."""
        if self.library is None:
            raise ValueError("the library is unknown (the consensus was built from bare coefficient arrays)")
        from ..feature_library.terms import term_table
        from ..simulation import CompiledModel

        terms = term_table(self.library, self.coefficients.shape[0])
        return CompiledModel(self.coefficients, terms, reference=reference)

    def __repr__(self) -> str:
        eqs = "; ".join(f"{s}' = {e}" for s, e in zip(self.state_names, self.equations()))
        return f"Consensus(method={self.method!r}, n_models={self.n_models}, {eqs})"


def coefficient_stack(models, feature_names=None):
    """Coefficients of several fitted models as one array, with their names and library.

    Parameters
    ----------
    models : list of fitted estimators, or array (n_models, n_states, n_features)
        Estimators need ``coefficients()``; all must share the library (same term names).
    feature_names : list of str, optional
        Term names for a bare array.

    Returns
    -------
    stack : ndarray (n_models, n_states, n_features)
    feature_names : list of str
    state_names : list of str
    library : fitted library or None
    """
    if isinstance(models, np.ndarray) or (
        isinstance(models, (list, tuple)) and models and isinstance(models[0], (np.ndarray, list))
    ):
        name = "models (coefficients)"
        stack = check_array(models, name)
        if stack.ndim != 3:
            raise ValueError(
                f"{name} must be an array (n_models, n_states, n_features), got shape {stack.shape}"
            )
        n_features = stack.shape[2]
        names = list(feature_names) if feature_names is not None else [f"f{k}" for k in range(n_features)]
        if len(names) != n_features:
            raise ValueError(f"{len(names)} feature names for {n_features} features")
        return stack, names, [f"x{i}" for i in range(stack.shape[1])], None
    if not isinstance(models, (list, tuple)) or len(models) == 0:
        raise ValueError("models must be a non-empty list of fitted models or a coefficient array")
    coefs, names, states, library = [], None, None, None
    for j, m in enumerate(models):
        if not (hasattr(m, "coefficients") and hasattr(m, "get_feature_names")):
            raise TypeError(f"models[{j}] is a {type(m).__name__}, not a fitted SINDy model")
        try:
            c = np.asarray(m.coefficients(), dtype=float)
            n = list(m.get_feature_names())
        except Exception as err:
            raise ValueError(f"models[{j}] is not fitted: {err}") from err
        if names is None:
            names = n
            states = list(getattr(m, "feature_names_", None) or [f"x{i}" for i in range(c.shape[0])])
            library = getattr(m, "feature_library_", None)
        elif n != names or c.shape != coefs[0].shape:
            raise ValueError(
                f"models[{j}] has a different library ({len(n)} terms, {c.shape[0]} states) than models[0] "
                f"({len(names)} terms, {coefs[0].shape[0]} states)"
            )
        coefs.append(c)
    return np.stack(coefs), names, states, library


def _iqr(values: np.ndarray) -> float:
    if values.size < 2:
        return 0.0
    q1, q3 = np.percentile(values, [25, 75])
    return float(q3 - q1)


def _histogram(values: np.ndarray, bins, max_bins: int) -> Histogram:
    """Histogram of ``values`` (Freedman-Diaconis bins by default, capped at ``max_bins``)."""
    if values.size == 1 or np.ptp(values) == 0:
        v = float(values[0])
        half = 0.5 * max(abs(v) * 1e-6, np.finfo(float).tiny)
        return Histogram(np.array([values.size]), np.array([v - half, v + half]), values, 0)
    edges = np.histogram_bin_edges(values, bins=bins)
    if edges.size - 1 > max_bins:
        edges = np.histogram_bin_edges(values, bins=max_bins)
    counts, edges = np.histogram(values, bins=edges)
    top = np.flatnonzero(counts == counts.max())
    if top.size > 1:  # ties: the bin closest to the median of all estimates
        centers = 0.5 * (edges[top] + edges[top + 1])
        top = top[[int(np.argmin(np.abs(centers - np.median(values))))]]
    return Histogram(counts, edges, values, int(top[0]))


def _peak_value(h: Histogram) -> float:
    """Median of the estimates inside the peak bin (the last bin is closed on the right)."""
    lo, hi = h.edges[h.peak], h.edges[h.peak + 1]
    last = h.peak == len(h.counts) - 1
    inside = h.values[(h.values >= lo) & ((h.values <= hi) if last else (h.values < hi))]
    return float(np.median(inside)) if inside.size else float(0.5 * (lo + hi))


def consensus(
    models,
    method: str = "mode",
    *,
    min_frequency: float = 0.5,
    bins="fd",
    max_bins: int = 50,
    feature_names=None,
) -> Consensus:
    """Combine the models of repeated measurements of one system into one coefficient matrix.

    Parameters
    ----------
    models : list of fitted estimators (e.g. ImpulseSINDy), or array (n_models, n_states, n_features)
        All with the same library.
    method : {"mode", "median"}, default="mode"
        Per coefficient: the most frequent value (histogram peak, refined to the median of the estimates
        in the peak bin) or the median of the non-zero estimates.
    min_frequency : float, default=0.5
        A coefficient is kept when non-zero in at least this fraction of the models (majority vote);
        otherwise it is 0 in the consensus.
    bins : str or int, default="fd"
        Histogram bins, as for :func:`numpy.histogram_bin_edges` (Freedman-Diaconis by default).
    max_bins : int, default=50
        Cap on the number of bins (far outliers would otherwise create thousands of empty ones).
    feature_names : list of str, optional
        Term names when ``models`` is an array.

    Returns
    -------
    Consensus
        ``coefficients``, ``histograms`` (for Figure 12), ``frequency_nonzero``, ``spread``, ...

    Examples
    --------
    >>> import pysindy as ps
    >>> from sindy_impulse import ImpulseSINDy, damped_oscillator
    >>> from sindy_impulse.analysis import consensus
    >>> rings = [damped_oscillator(x0=(a, v)) for a, v in [(1, 0), (0.6, -2), (-0.2, 1), (0.2, 5), (-1, 0)]]
    >>> models = [ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=1)).fit(r.x, t=r.t) for r in rings]
    >>> result = consensus(models)
    >>> result.equations(precision=1)
    ['1.0 x1', '-64.0 x0 + -3.2 x1']
    """
    if method not in _METHODS:
        raise ValueError(
            f"method must be one of {_METHODS}, got {method!r} (for one fit on all data use consensus_fit)"
        )
    if isinstance(min_frequency, bool) or not (
        isinstance(min_frequency, (int, float, np.number)) and 0 < min_frequency <= 1
    ):
        raise ValueError(f"min_frequency must be in (0, 1], got {min_frequency!r}")
    if isinstance(max_bins, bool) or not (isinstance(max_bins, (int, np.integer)) and max_bins >= 1):
        raise ValueError(f"max_bins must be a positive integer, got {max_bins!r}")
    stack, names, states, library = coefficient_stack(models, feature_names)
    n_models, n_states, n_features = stack.shape
    nonzero = stack != 0
    frequency = nonzero.mean(axis=0)
    coef = np.zeros((n_states, n_features))
    spread = np.zeros((n_states, n_features))
    histograms = {}
    for i in range(n_states):
        for k in range(n_features):
            values = stack[nonzero[:, i, k], i, k]
            if values.size == 0:
                continue
            h = _histogram(values, bins, max_bins)
            histograms[(i, k)] = h
            spread[i, k] = _iqr(values)
            if frequency[i, k] < min_frequency:
                continue
            coef[i, k] = _peak_value(h) if method == "mode" else float(np.median(values))
    return Consensus(
        coefficients=coef,
        feature_names=list(names),
        state_names=list(states),
        method=method,
        n_models=n_models,
        frequency_nonzero=frequency,
        spread=spread,
        histograms=histograms,
        estimates=stack,
        library=library,
    )


def consensus_fit(estimator, trajectories, t=None, **fit_params) -> Consensus:
    """The alternative to :func:`consensus`: one fit on all trajectories together (Brunton et al.).

    A clone of ``estimator`` is fitted to the list of trajectories (for
    :class:`~sindy_impulse.ImpulseSINDy` the library rows of all records are stacked into one regression,
    and Gamma sums over the records).

    Parameters
    ----------
    estimator : unfitted SINDy estimator
        Template (cloned).
    trajectories : list of arrays (n_i, n_states)
        The records.
    t : float, array or list of arrays, optional
        Time step or per-record time vectors.
    **fit_params
        Passed to ``fit`` (e.g. ``feature_names``).

    Returns
    -------
    Consensus
        ``method="stacked"``, ``n_models=1``, the fitted estimator in ``model``, no histograms.

    Examples
    --------
    >>> import pysindy as ps
    >>> from sindy_impulse import ImpulseSINDy, damped_oscillator
    >>> from sindy_impulse.analysis.consensus import consensus_fit
    >>> rings = [damped_oscillator(x0=(a, 0)) for a in (1.0, 0.5, -0.3)]
    >>> est = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=1))
    >>> consensus_fit(est, [r.x for r in rings], t=0.01).equations(precision=1)
    ['1.0 x1', '-64.0 x0 + -3.2 x1']
    """
    if not isinstance(trajectories, (list, tuple)) or len(trajectories) == 0:
        raise ValueError("trajectories must be a non-empty list of arrays (n_samples, n_states)")
    trajectories = [check_signal(x, f"trajectories[{i}]") for i, x in enumerate(trajectories)]
    model = clone(estimator).fit(trajectories, t=t, **fit_params)
    stack, names, states, library = coefficient_stack([model])
    coef = stack[0]
    return Consensus(
        coefficients=coef.copy(),
        feature_names=names,
        state_names=states,
        method="stacked",
        n_models=1,
        frequency_nonzero=(coef != 0).astype(float),
        spread=np.zeros_like(coef),
        histograms={},
        estimates=stack,
        library=library,
        model=model,
    )

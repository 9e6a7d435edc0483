"""The candidates of a fit: the threshold path of any optimizer, or its single model.

The seam between the estimator and its optimizer. An optimizer that enumerates the path itself (the *sweep
protocol*) exposes, after ``fit``, ``candidates_`` (ndarray (n_candidates, n_targets, n_features)) and
``thresholds_`` (ndarray (n_candidates,)): :class:`~sindy_impulse.ThresholdSweep` does. Any other optimizer
with a ``threshold`` parameter (e.g. PySINDy's ``STLSQ``) is refitted along a grid of thresholds taken from
the magnitudes of its coefficients at threshold 0, and each distinct support is a candidate. An optimizer
without a threshold gives one candidate.

A path can also be run on a *sub-library* (some of the library's columns, e.g. its linear terms), and its
supports join the candidates. Thresholding a whole library can pass by a sparse model of a few of its
terms when other terms are collinear with them on the data: on a decaying oscillation ``x**3`` is nearly
proportional to ``x`` over each period (``x**3 ~ 3/4 A**2 x``) and ``x**2 v`` to ``v``, so cubic terms
share the work of the stiffness and damping with large, opposite coefficients; once a weak true term (a
damping) is thresholded, the cubic terms absorb its share and stay, and the path's sparse end lacks the
damping. The same sweep over the sub-library alone contains that model.
"""

from __future__ import annotations

import copy
import warnings

import numpy as np
from sklearn.base import clone

__all__ = ["candidate_path", "fresh_copy", "least_squares", "MAX_REFITS"]

#: Most refits of a thresholded optimizer when its path is enumerated by a grid.
MAX_REFITS = 60


def fresh_copy(obj):
    """An unfitted copy: scikit-learn's ``clone``, or a deep copy for objects clone cannot rebuild.

    Clone fails on objects whose ``get_params`` does not match their constructor (PySINDy's
    ``CustomLibrary`` stores ``library_functions`` as ``functions``: an ``AttributeError``) or that change
    their parameters in ``__init__`` (``WrappedOptimizer``: a ``RuntimeError``).
    """
    try:
        return clone(obj)
    except (AttributeError, RuntimeError, TypeError, ValueError):
        return copy.deepcopy(obj)


def least_squares(theta: np.ndarray, y: np.ndarray, support: np.ndarray, rcond=None) -> np.ndarray:
    """Least-squares coefficients of each equation on its support (rows with NaN dropped).

    Parameters
    ----------
    theta : ndarray (n_samples, n_features)
    y : ndarray (n_samples, n_targets)
    support : ndarray of bool (n_targets, n_features)
    rcond : float, optional
        Relative cut-off of small singular values (``numpy.linalg.lstsq``'s; default: its own).

    Examples
    --------
    >>> theta = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]); y = theta @ [[2.0], [3.0]]
    >>> least_squares(theta, y, np.array([[True, True]])).round(6).tolist()
    [[2.0, 3.0]]
    """
    theta = np.asarray(theta, dtype=float)
    y = np.asarray(y, dtype=float).reshape(theta.shape[0], -1)
    rows = np.all(np.isfinite(theta), axis=1) & np.all(np.isfinite(y), axis=1)
    coef = np.zeros(support.shape)
    for i in range(support.shape[0]):
        cols = np.flatnonzero(support[i])
        if cols.size:
            coef[i, cols] = np.linalg.lstsq(theta[rows][:, cols], y[rows, i], rcond=rcond)[0]
    return coef


def _with_threshold(optimizer, threshold: float):
    """An unfitted copy at another threshold (PySINDy's ``set_params`` returns None: no chaining)."""
    opt = fresh_copy(optimizer)
    opt.set_params(threshold=threshold)
    return opt


def _threshold_grid(optimizer, theta, y):
    """Refit clones of a thresholded optimizer at breakpoints taken from its threshold-0 coefficients."""
    dense = _with_threshold(optimizer, 0.0)
    dense.fit(theta, y)
    magnitudes = np.unique(np.abs(np.asarray(dense.coef_))[np.asarray(dense.coef_) != 0])
    # cuts between successive magnitudes (geometric midpoints) and beyond the largest, plus a log grid:
    # a refit's coefficients differ from the dense ones, so breakpoints move a little
    cuts = np.sqrt(magnitudes[:-1] * magnitudes[1:]) if magnitudes.size > 1 else np.empty(0)
    grid = np.geomspace(magnitudes[0], 2 * magnitudes[-1], 4 * 8) if magnitudes.size else np.empty(0)
    cuts = np.unique(np.concatenate([cuts, grid, 2 * magnitudes[-1:]]))
    if cuts.size > MAX_REFITS:
        cuts = cuts[np.unique(np.linspace(0, cuts.size - 1, MAX_REFITS).astype(int))]
    thresholds, coefs, seen = [0.0], [np.asarray(dense.coef_, dtype=float).copy()], set()
    seen.add((np.asarray(dense.coef_) != 0).tobytes())
    for lam in cuts:
        opt = _with_threshold(optimizer, float(lam))
        with warnings.catch_warnings():  # "eliminated all coefficients" is the end of the path, not news
            warnings.simplefilter("ignore", UserWarning)
            opt.fit(theta, y)
        coef = np.asarray(opt.coef_, dtype=float)
        key = (coef != 0).tobytes()
        if key not in seen:
            seen.add(key)
            thresholds.append(float(lam))
            coefs.append(coef.copy())
    return np.asarray(thresholds), np.asarray(coefs)


def candidate_path(optimizer, theta: np.ndarray, y: np.ndarray, sweep: bool = True, sub_libraries=()):
    """Fit ``optimizer`` and return the candidate models.

    Parameters
    ----------
    optimizer : PySINDy optimizer
        Fitted in place on ``(theta, y)`` (its ``coef_`` is its own choice, as in PySINDy).
    theta : ndarray (n_samples, n_features)
        Library matrix.
    y : ndarray (n_samples, n_targets)
        Derivatives (rows with NaN are dropped by the optimizer).
    sweep : bool
        Enumerate the threshold path (True) or return the optimizer's single model (False).
    sub_libraries : sequence of boolean masks (n_features,), optional
        With ``sweep``, the path of each sub-library (a copy of the optimizer fitted on those columns alone,
        its ``protected`` terms restricted to them) is enumerated too; its supports that the full path
        lacks join the candidates, with their thresholds on the sub-library's scale (all in the order of
        their number of terms, densest first; the full path's own order kept).

    Returns
    -------
    thresholds : ndarray (n_candidates,)
        Threshold of each candidate (NaN for a single model).
    candidates : ndarray (n_candidates, n_targets, n_features)

    Examples
    --------
    >>> import pysindy as ps
    >>> rng = np.random.default_rng(0)
    >>> theta = rng.normal(size=(50, 3)); y = theta @ [[2.0], [0.0], [0.1]]
    >>> thresholds, candidates = candidate_path(ps.STLSQ(threshold=0.05), theta, y)
    >>> [int(np.count_nonzero(c)) for c in candidates]
    [3, 2, 1, 0]

    A third term nearly collinear with the first (and a little of the weak second) takes the weak term's
    place along the path; the path of the first two terms alone adds the true model ``[0, 1]``:

    >>> theta[:, 2] = theta[:, 0] + 0.02 * theta[:, 1] + 0.01 * rng.normal(size=50)
    >>> y = theta[:, :2] @ [[2.0], [0.1]]
    >>> _, candidates = candidate_path(ps.STLSQ(threshold=0.05), theta, y)
    >>> [np.flatnonzero(c[0]).tolist() for c in candidates]
    [[0, 1, 2], [0, 2], []]
    >>> _, candidates = candidate_path(ps.STLSQ(threshold=0.05), theta, y,
    ...                                sub_libraries=[np.array([True, True, False])])
    >>> [np.flatnonzero(c[0]).tolist() for c in candidates]
    [[0, 1, 2], [0, 2], [0, 1], [0], []]
    """
    optimizer.fit(theta, y)
    if not sweep:
        return np.array([np.nan]), np.asarray(optimizer.coef_, dtype=float)[None].copy()
    thresholds, candidates = _path_of(optimizer, theta, y, fitted=True)
    seen = {(c != 0).tobytes() for c in candidates}
    extra_thresholds, extra = [], []
    for mask in sub_libraries:
        mask = np.asarray(mask, dtype=bool)
        if not mask.any() or mask.all():
            continue
        sub_thresholds, sub = _path_of(_restricted(optimizer, mask), theta[:, mask], y, fitted=False)
        for lam, coef in zip(sub_thresholds, sub):
            full = np.zeros(candidates.shape[1:])
            full[:, mask] = coef
            key = (full != 0).tobytes()
            if key not in seen:
                seen.add(key)
                extra_thresholds.append(lam)
                extra.append(full)
    if not extra:
        return thresholds, candidates
    thresholds = np.concatenate([thresholds, extra_thresholds])
    candidates = np.concatenate([candidates, extra])
    order = np.argsort([-np.count_nonzero(c) for c in candidates], kind="stable")  # densest first
    return thresholds[order], candidates[order]


def _path_of(optimizer, theta, y, fitted: bool):
    """Thresholds and candidates of one optimizer on ``(theta, y)`` (``fitted``: already fitted there)."""
    if not fitted:
        optimizer.fit(theta, y)
    if hasattr(optimizer, "candidates_") and hasattr(optimizer, "thresholds_"):
        return np.asarray(optimizer.thresholds_, dtype=float), np.asarray(optimizer.candidates_, dtype=float)
    if "threshold" in _parameters(optimizer):
        return _threshold_grid(optimizer, theta, y)
    coef = np.asarray(optimizer.coef_, dtype=float)
    return np.array([np.nan]), coef.reshape(-1, theta.shape[1])[None].copy()


def _restricted(optimizer, mask: np.ndarray):
    """An unfitted copy of ``optimizer`` for the columns ``mask``: a ``protected`` mask (per term, or per
    equation and term) restricted to them."""
    opt = fresh_copy(optimizer)
    protected = _parameters(opt).get("protected")
    if protected is not None:
        protected = np.asarray(protected, dtype=bool)
        if protected.shape[-1] == mask.size:
            opt.set_params(protected=protected[..., mask])
    return opt


def _parameters(optimizer) -> dict:
    """The optimizer's parameters; none for one whose ``get_params`` fails (``WrappedOptimizer``)."""
    try:
        return optimizer.get_params(deep=False)
    except (AttributeError, RuntimeError, TypeError):
        return {}

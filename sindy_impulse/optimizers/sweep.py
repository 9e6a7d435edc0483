"""ThresholdSweep: every distinct sparse support along the sequential-thresholding path.

Sequentially thresholded least squares (STLSQ) gives coefficients that are piecewise constant in the
threshold lambda (paper section 2.5). Instead of a grid of lambdas, the sweep walks the breakpoints:
starting from the full least-squares solution, it raises lambda to the smallest remaining relative
coefficient, re-runs the thresholding iteration from there, and records each new support, until no
term is left. Coefficients are compared on a unit-free scale, ``|xi_ik| * ||theta_k|| / ||x_dot_i||``
(the term's share of the derivative it models), so the path does not depend on the units of the states.
"""

from __future__ import annotations

import numpy as np
from pysindy.optimizers import BaseOptimizer

from .._validation import check_signal

__all__ = ["ThresholdSweep", "threshold_path"]


def _lstsq_on_support(X: np.ndarray, y: np.ndarray, support: np.ndarray) -> np.ndarray:
    coef = np.zeros(X.shape[1])
    if support.any():
        coef[support] = np.linalg.lstsq(X[:, support], y, rcond=None)[0]
    return coef


def threshold_path(X: np.ndarray, Y: np.ndarray, max_iter: int = 20):
    """All distinct STLSQ supports from the full model down to the empty one.

    Parameters
    ----------
    X : ndarray (n_samples, n_features)
        Library matrix.
    Y : ndarray (n_samples, n_targets)
        Derivatives.
    max_iter : int
        Thresholding iterations per breakpoint.

    Returns
    -------
    thresholds : ndarray (n_candidates,)
        The relative threshold at which each support appears (0 for the full model).
    coefficients : ndarray (n_candidates, n_targets, n_features)
        Least-squares coefficients on each support, in the units of ``X`` and ``Y``.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> X = rng.normal(size=(100, 3)); Y = X @ [[1.0], [0.0], [0.01]]
    >>> thresholds, coefs = threshold_path(X, Y)
    >>> [int(np.count_nonzero(c)) for c in coefs]
    [3, 2, 1, 0]
    """
    X = np.asarray(X, dtype=float)
    Y = np.asarray(Y, dtype=float).reshape(X.shape[0], -1)
    col_norm = np.linalg.norm(X, axis=0)
    col_norm = np.where(col_norm > 0, col_norm, 1.0)
    target_norm = np.linalg.norm(Y, axis=0)
    target_norm = np.where(target_norm > 0, target_norm, 1.0)
    Xn = X / col_norm  # well-conditioned columns whatever the units
    Yn = Y / target_norm
    n_targets, n_features = Y.shape[1], X.shape[1]

    def solve(support, coef=None, rows=None):
        # Only the equations whose support changed are solved again (the others keep their solution).
        coef = np.zeros((n_targets, n_features)) if coef is None else coef.copy()
        for i in range(n_targets) if rows is None else np.flatnonzero(rows):
            coef[i] = _lstsq_on_support(Xn, Yn[:, i], support[i])
        return coef

    support = np.ones((n_targets, n_features), dtype=bool)
    support[:, np.all(X == 0, axis=0)] = False  # an all-zero column carries no information
    coef = solve(support)
    thresholds, coefs, seen = [0.0], [coef.copy()], {support.tobytes()}
    while support.any():
        lam = np.min(np.abs(coef[support]))
        lam = lam * (1 + 1e-9) + 1e-300
        for _ in range(max_iter):
            new_support = support & (np.abs(coef) > lam)
            changed = np.any(new_support != support, axis=1)
            if not changed.any():
                break
            support = new_support
            coef = solve(support, coef, changed)
        key = support.tobytes()
        if key not in seen:
            seen.add(key)
            thresholds.append(lam)
            coefs.append(coef.copy())
    scale = target_norm[None, :, None] / col_norm[None, None, :]
    return np.asarray(thresholds), np.asarray(coefs) * scale


class ThresholdSweep(BaseOptimizer):
    """The whole sequential-thresholding path as a PySINDy optimizer.

    ``fit`` computes every distinct support from all terms down to none and keeps them in
    ``history_`` (coefficient matrices) and ``thresholds_``. Used alone with :class:`pysindy.SINDy`, it
    keeps the candidate with the smallest corrected Akaike information criterion of the derivative fit;
    :class:`sindy_impulse.ImpulseSINDy` instead simulates every candidate and selects by Gamma.

    Parameters
    ----------
    max_iter : int, default=20
        Thresholding iterations per breakpoint.

    Attributes
    ----------
    coef_ : ndarray (n_targets, n_features)
        The selected coefficients.
    history_ : list of ndarray
        Coefficients of every candidate along the path, densest first.
    thresholds_ : ndarray
        Relative threshold at which each candidate appears.
    aicc_ : ndarray
        The information criterion of each candidate.
    best_index_ : int
        Index of the selected candidate.

    Examples
    --------
    >>> import pysindy as ps
    >>> from sindy_impulse.datasets import damped_oscillator
    >>> t, x, x_dot = damped_oscillator()
    >>> model = ps.SINDy(optimizer=ThresholdSweep()).fit(x, t=t, x_dot=x_dot)
    >>> int(model.complexity)
    3
    """

    def __init__(self, max_iter: int = 20):
        super().__init__(max_iter=max_iter, normalize_columns=False, unbias=False)

    @property
    def candidates_(self) -> np.ndarray:
        """The path as one array (n_candidates, n_targets, n_features): the sweep protocol of
        :func:`sindy_impulse.optimizers.candidate_path`."""
        return np.asarray(self.history_)

    def set_params(self, **params):
        super().set_params(**params)
        return self

    def fit(self, x_, y, sample_weight=None, **reduce_kws):
        """Compute the path for the library matrix ``x_`` (n_samples, n_features) and targets ``y``.

        Rows with NaN (e.g. the trimmed ends of a derivative) are dropped, as in PySINDy.
        """
        X = check_signal(x_, "x", ndim=(2,), allow_nan=True)
        Y = check_signal(y, "y", allow_nan=True, as_2d=False)
        if Y.shape[0] != X.shape[0]:
            raise ValueError(f"y has {Y.shape[0]} samples but x has {X.shape[0]}")
        complete = np.all(np.isfinite(X), axis=1) & np.all(np.isfinite(Y.reshape(len(Y), -1)), axis=1)
        if not complete.any():
            raise ValueError(f"x and y have no sample without NaN (of {X.shape[0]})")
        return super().fit(X, Y, sample_weight=sample_weight, **reduce_kws)

    def _reduce(self, x, y):
        thresholds, coefs = threshold_path(x, y, max_iter=self.max_iter)
        n = x.shape[0] * y.shape[1]
        aicc = np.empty(len(coefs))
        for j, c in enumerate(coefs):
            k = int(np.count_nonzero(c))
            rss = float(np.sum((y - x @ c.T) ** 2))
            rss = max(rss, 1e-300 * n)
            penalty = 2 * k + (2 * k * (k + 1) / (n - k - 1) if n - k - 1 > 0 else np.inf)
            aicc[j] = n * np.log(rss / n) + penalty
        self.thresholds_ = thresholds
        self.history_ = list(coefs)
        self.aicc_ = aicc
        self.best_index_ = int(np.argmin(aicc))
        self.coef_ = coefs[self.best_index_].copy()

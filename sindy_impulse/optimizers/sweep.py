"""ThresholdSweep: every distinct sparse support along the sequential-thresholding path.

Sequentially thresholded least squares (STLSQ) gives coefficients that are piecewise constant in the
threshold lambda (paper section 2.5). Instead of a grid of lambdas, the sweep walks the breakpoints:
starting from the full least-squares solution, it raises lambda to the smallest remaining relative
coefficient, re-runs the thresholding iteration from there, and records each new support, until no
term is left. Coefficients are compared on a unit-free scale, ``|xi_ik| * ||theta_k|| / ||x_dot_i||``
(the term's share of the derivative it models), so the path does not depend on the units of the states.
"""

from __future__ import annotations

from numbers import Integral, Real

import numpy as np
from pysindy.optimizers import BaseOptimizer
from scipy.linalg import solve_triangular
from sklearn.utils.validation import check_is_fitted

from .._utils.params import Interval, validate_params
from .._utils.validation import check_array, check_signal

__all__ = ["ThresholdSweep", "threshold_path"]


def threshold_path(X: np.ndarray, Y: np.ndarray, max_iter: int = 20, protected=None):
    """All distinct STLSQ supports from the full model down to the empty one (or the protected terms).

    Parameters
    ----------
    X : ndarray (n_samples, n_features)
        Library matrix.
    Y : ndarray (n_samples, n_targets)
        Derivatives.
    max_iter : int
        Thresholding iterations per breakpoint.
    protected : ndarray of bool (n_features,) or (n_targets, n_features), optional
        Terms never thresholded (e.g. a mode's linear stiffness and damping): the path ends with them.

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
    complete = np.all(np.isfinite(X), axis=1) & np.all(np.isfinite(Y), axis=1)
    if not complete.all():
        X, Y = X[complete], Y[complete]
    X, Y, rcond = reduced(X, Y)
    thresholds, coefficients, _ = _path(X, Y, max_iter, rcond, protected)
    return thresholds, coefficients


#: Rows per block of the QR reduction (bounds its memory on long records).
_BLOCK = 1 << 16
#: Records of more samples than this run the path on the QR-reduced problem. Shorter ones keep the full
#: library matrix, where a support's least squares do not depend on the other columns of the library
#: (the same candidate from any library that contains its terms).
REDUCE_ABOVE = 20_000


def reduced(X: np.ndarray, Y: np.ndarray):
    """A square problem with the same least squares as ``(X, Y)`` on every subset of columns.

    ``[X Y] = Q R``: ``||X_S c - y||`` equals ``||R_x,S c - R_y||`` for every column subset ``S``, and
    column norms are kept. Returns ``(R_x, R_y, rcond)``, ``rcond`` the cut-off ``numpy.linalg.lstsq``
    would have used on ``X`` (None when ``X`` is returned unchanged: at most :data:`REDUCE_ABOVE` rows).
    The cost of the path then does not depend on the record length.
    """
    n, p = X.shape
    if n <= REDUCE_ABOVE:
        return X, Y, None
    R = _triangular_factor(X, Y)
    return R[:, :p], R[:, p:], np.finfo(float).eps * n


def _triangular_factor(X, Y) -> np.ndarray:
    """``R`` of ``[X Y] = Q R`` without forming ``[X Y]`` or ``Q`` (memory: a block of rows).

    Cholesky QR twice on unit-norm columns (two passes of matrix products, accurate while the columns are
    not nearly dependent); Householder QR block by block when they are.
    """
    norms = np.sqrt(np.concatenate([np.einsum("ij,ij->j", X, X), np.einsum("ij,ij->j", Y, Y)]))
    norms = np.where(norms > 0, norms, 1.0)
    gram = np.block([[X.T @ X, X.T @ Y], [Y.T @ X, Y.T @ Y]]) / np.outer(norms, norms)
    try:
        r1 = np.linalg.cholesky(gram).T
        if np.linalg.cond(r1) < 1e6:
            gram2 = np.zeros_like(gram)
            inverse = solve_triangular(r1, np.eye(r1.shape[0])) / norms[:, None]
            for start in range(0, X.shape[0], _BLOCK):
                q = np.hstack([X[start : start + _BLOCK], Y[start : start + _BLOCK]]) @ inverse
                gram2 += q.T @ q
            return (np.linalg.cholesky(gram2).T @ r1) * norms
    except np.linalg.LinAlgError:
        pass
    R = np.zeros((0, gram.shape[0]))
    for start in range(0, X.shape[0], _BLOCK):
        block = np.hstack([X[start : start + _BLOCK], Y[start : start + _BLOCK]])
        R = np.linalg.qr(np.vstack([R, block]), mode="r")
    return R


def _protection(protected, n_targets: int, n_features: int) -> np.ndarray:
    """The protected terms as a boolean (n_targets, n_features) mask."""
    if protected is None:
        return np.zeros((n_targets, n_features), dtype=bool)
    mask = np.asarray(protected, dtype=bool)
    if mask.shape == (n_features,):
        mask = np.broadcast_to(mask, (n_targets, n_features))
    if mask.shape != (n_targets, n_features):
        raise ValueError(
            f"protected must have shape ({n_features},) or ({n_targets}, {n_features}), got {mask.shape}"
        )
    return mask


def _path(X, Y, max_iter: int, rcond=None, protected=None):
    """:func:`threshold_path` plus the number of thresholding iterations it ran (rows without NaN)."""
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
        # Only the equations whose support changed are solved again (the others keep their solution);
        # the rows are complete (the callers drop rows with NaN), so least squares on the columns directly
        coef = np.zeros((n_targets, n_features)) if coef is None else coef.copy()
        for i in range(n_targets) if rows is None else np.flatnonzero(rows):
            cols = np.flatnonzero(support[i])
            coef[i] = 0.0
            if cols.size:
                coef[i, cols] = np.linalg.lstsq(Xn[:, cols], Yn[:, i], rcond=rcond)[0]
        return coef

    n_iter = 0
    keep = _protection(protected, n_targets, n_features)
    support = np.ones((n_targets, n_features), dtype=bool)
    support[:, np.all(X == 0, axis=0)] = False  # an all-zero column carries no information
    coef = solve(support)
    thresholds, coefs, seen = [0.0], [coef.copy()], {support.tobytes()}
    while (support & ~keep).any():
        lam = np.min(np.abs(coef[support & ~keep]))
        lam = lam * (1 + 1e-9) + 1e-300
        for _ in range(max_iter):
            n_iter += 1
            new_support = support & ((np.abs(coef) > lam) | keep)
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
    return np.asarray(thresholds), np.asarray(coefs) * scale, n_iter


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
    protected : array-like of bool (n_features,) or (n_targets, n_features), optional
        Terms the sweep never removes (e.g. the linear stiffness and damping of a mode's oscillator, so
        that no candidate lacks them); the path then ends with the protected terms instead of no term.

    Attributes
    ----------
    coef_ : ndarray (n_targets, n_features), or (n_features,) for a 1-D ``y``
        The selected coefficients.
    history_ : list of ndarray (n_targets, n_features)
        Coefficients of every candidate along the path, densest first.
    thresholds_ : ndarray
        Relative threshold at which each candidate appears.
    aicc_ : ndarray
        The information criterion of each candidate.
    best_index_ : int
        Index of the selected candidate.
    n_iter_ : int
        Thresholding iterations run along the whole path.
    n_features_in_ : int
        Number of library terms (columns of ``x``).

    Notes
    -----
    ``sample_weight`` weighs the samples' squared residuals (rows scaled by its square root, as in
    PySINDy); the information criterion counts ``sum(sample_weight)`` samples, so an integer weight is the
    same as repeating the sample.

    Examples
    --------
    >>> import pysindy as ps
    >>> from sindy_impulse.datasets import damped_oscillator
    >>> t, x, x_dot = damped_oscillator()
    >>> model = ps.SINDy(optimizer=ThresholdSweep()).fit(x, t=t, x_dot=x_dot)
    >>> int(model.complexity)
    3
    """

    _parameter_constraints = {
        "max_iter": [Interval(Integral, 1, None, "left")],
        "protected": [None, "array-like"],
    }

    # BaseOptimizer's settings, fixed for the sweep (class attributes: not parameters, not set in __init__)
    normalize_columns = False
    unbias = False
    initial_guess = None
    copy_X = True
    fit_intercept = False
    positive = False  # LinearRegression reads it (tags)

    def __init__(self, max_iter: int = 20, protected=None):
        self.max_iter = max_iter
        self.protected = protected

    @property
    def candidates_(self) -> np.ndarray:
        """The path as one array (n_candidates, n_targets, n_features): the sweep protocol of
        :func:`sindy_impulse.optimizers.candidate_path`."""
        return np.asarray(self.history_)

    def set_params(self, **params):
        super().set_params(**params)
        return self

    def fit(self, x_, y=None, sample_weight=None, **reduce_kws):
        """Compute the path for the library matrix ``x_`` (n_samples, n_features) and targets ``y``.

        Rows with NaN (e.g. the trimmed ends of a derivative) are dropped, as in PySINDy.
        """
        validate_params(self)
        X = check_signal(x_, "x", ndim=(2,), allow_nan=True)
        if y is None:
            raise ValueError("ThresholdSweep requires y to be passed, but the target y is None")
        Y = check_signal(y, "y", allow_nan=True, as_2d=False)
        if Y.shape[0] != X.shape[0]:
            raise ValueError(f"y has {Y.shape[0]} samples but x has {X.shape[0]}")
        weights = _sample_weights(sample_weight, X.shape[0])
        complete = np.all(np.isfinite(X), axis=1) & np.all(np.isfinite(Y.reshape(len(Y), -1)), axis=1)
        if not complete.any():
            raise ValueError(f"x and y have no sample without NaN (of {X.shape[0]})")
        if not complete.all():
            X, Y = X[complete], Y[complete]
        if weights is not None:
            weights = weights[complete]
            if not np.any(weights > 0):
                raise ValueError("sample_weight is zero for every sample (without NaN): nothing to fit")
        self._n_weighted = float(X.shape[0] if weights is None else np.sum(weights))
        Y2 = Y.reshape(len(Y), -1)
        if weights is not None:  # weighted least squares: rows scaled by sqrt(weight), as in PySINDy
            root = np.sqrt(weights)[:, None]
            X, Y2 = X * root, Y2 * root
        self.Theta_ = X
        self._reduce(X, Y2, **reduce_kws)
        self.ind_ = np.abs(self.coef_) > 1e-14
        self.intercept_ = 0.0
        if Y.ndim == 1:  # scikit-learn's convention: a 1-D target gives 1-D coefficients
            self.coef_, self.ind_ = self.coef_[0], self.ind_[0]
        self.n_features_in_ = X.shape[1]
        return self

    def predict(self, x):
        """``x @ coef_.T`` for library matrices ``x`` (n_samples, n_features); NaN rows give NaN."""
        check_is_fitted(self, "coef_")
        X = check_signal(x, "x", ndim=(2,), allow_nan=True)
        if X.shape[1] != self.n_features_in_:
            raise ValueError(
                f"X has {X.shape[1]} features, but ThresholdSweep is expecting {self.n_features_in_} "
                "features as input"
            )
        return X @ self.coef_.T

    def _reduce(self, x, y):
        x, y, rcond = reduced(x, y)  # the same least squares and residuals, whatever the record length
        thresholds, coefs, n_iter = _path(x, y, self.max_iter, rcond, self.protected)
        n = self._n_weighted * y.shape[1]
        # residuals below rounding (exact derivatives) carry no information: floor them there
        floor = max(float((x.shape[1] * np.finfo(float).eps) ** 2 * np.sum(y**2)), 1e-300 * n)
        aicc = np.empty(len(coefs))
        for j, c in enumerate(coefs):
            k = int(np.count_nonzero(c))
            rss = max(float(np.sum((y - x @ c.T) ** 2)), floor)
            penalty = 2 * k + (2 * k * (k + 1) / (n - k - 1) if n - k - 1 > 0 else np.inf)
            aicc[j] = n * np.log(rss / n) + penalty
        self.thresholds_ = thresholds
        self.history_ = list(coefs)
        self.aicc_ = aicc
        self.best_index_ = int(np.argmin(aicc))
        self.coef_ = coefs[self.best_index_].copy()
        self.n_iter_ = n_iter

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.sparse = False
        tags.input_tags.allow_nan = True  # NaN rows (a trimmed derivative) are dropped
        return tags


def _sample_weights(sample_weight, n_samples: int) -> np.ndarray | None:
    """``sample_weight`` as a non-negative array of ``n_samples`` entries (None stays None)."""
    if sample_weight is None:
        return None
    if isinstance(sample_weight, Real) and not isinstance(sample_weight, bool):
        sample_weight = np.full(n_samples, float(sample_weight))
    weights = check_array(sample_weight, "sample_weight", ndim=(1,))
    if weights.shape[0] != n_samples:
        raise ValueError(f"sample_weight has {weights.shape[0]} entries but x has {n_samples} samples")
    if np.any(weights < 0):
        raise ValueError("sample_weight must be non-negative")
    return weights

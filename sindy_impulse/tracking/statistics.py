"""The tests of the tracker: a new value against the reference surveys' values, the many tests of one
survey together, and a trend over a sequence.

**One value against the reference.** The reference surveys give values ``x_i`` with the fit's standard
deviations ``s_i``. Between tests a structure scatters beyond the fit's ± (where the hammer hits, how
hard, the temperature), and the fit's ± may itself be too small, too large or missing. The model

    x_i = mu + e_i,     var(e_i) = sigma^2 ((1 - lam) + lam s_i^2 / mean(s^2)),

covers these with one scale ``sigma^2`` and one share ``lam`` in [0, 1] of the variance that follows the
fit's ± (``lam = 0``: a scatter the same for every test, the fit's ± ignored; ``lam = 1``: the fit's ±
times a calibration factor, however wrong they are). For each ``lam`` of a grid, ``mu`` (the weighted
mean) and ``sigma^2`` come from the reference by restricted maximum likelihood. A new value ``x_0`` with
its ± ``s_0`` gives the prediction-interval statistic

    T = (x_0 - mu) / sqrt(sigma^2 (d_0 + 1 / sum(w))),    d_0 = (1 - lam) + lam s_0^2 / mean(s^2),

in which the reference's own estimation error enters twice: through ``1 / sum(w)`` (that of its mean)
and through Student's t with ``n - 1`` degrees of freedom (``n - 2`` with ``lam > 0``) instead of the
normal law (that of its scatter). This matters in the far tail where a family of tests puts each
threshold: a normal threshold with 20 reference values gives 2.1 % false alarms for a nominal 1 %, and
5.5 times the nominal rate at the 0.06 % that one test of a family of 16 gets.

Twenty values cannot tell the share ``lam`` well, and a wrong share misjudges exactly the tests whose ±
is far from the typical one (a light hit, a strong one). So the test is the least significant over every
share the reference does not rule out: those whose restricted likelihood is within 1 (half the chi-square
unit) of the best. The share is further bounded by what the fit's ± can explain: the scatter that follows
them is at most :data:`MAX_UNDERESTIMATE` squared times their own variance (the frequencies of a structure
whose test-to-test scatter is fifty times the fit's ± are then tested as by the textbook prediction
interval, which is exact for a scatter the same for every test). A value is never judged more precise
than its own ± (the variance is at least ``s_0^2``), unless the reference shows the ± too large: its
values scatter less than their ± say (then at least ``s_0^2`` times that ratio of variances). Where the fit
gives no ± the reference scatter carries the uncertainty, shared out between the tests by a stand-in
proportional to the noise the fit saw (``10^(-SNR / 20)`` of the band, when the caller gives it: a light
hit is noisier). When every reference
value is the same (a term no reference model has: all zeros), a new value is judged by its own ± alone.
Simulated with 20 reference values, the false-alarm rate holds at 1 % and in the tail at 0.06 % with
the ± right, missing, three and ten times too small (or too large: then it falls below), with or without
a scatter beyond them (``benchmarks/tracking/track_study.py``, its statistics part).

**Many tests per survey.** Each survey is tested on every mode and quantity; the family is corrected by
Holm's step-down procedure, so that the chance of any false alarm on a survey of an unchanged structure is
at most the rate asked (Bonferroni's bound, which Holm's first step is; the quantities of one mode and
the modes of one structure move together with the temperature, which makes it conservative).

**A trend.** The Mann-Kendall test over the new surveys in their order (the sign of every later-minus-
earlier difference, normal approximation with the ties' correction) finds a slow drift that no single test
flags; it assumes independent tests (a drift of the conditions during the sequence is a trend too).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import stats

__all__ = [
    "Scatter",
    "fit_scatter",
    "fit_scatter_rows",
    "prediction_test",
    "holm",
    "mann_kendall",
    "running_trend",
]

#: The shares of the fit's ± in the variance tried.
LAMBDA_GRID = np.linspace(0.0, 1.0, 41)
#: Shares whose twice log restricted likelihood is within this of the best are not ruled out.
PLAUSIBLE = 1.0
#: How many times too small the fit's ± may be: the share of the scatter that follows them is bounded by
#: this factor squared times their mean variance.
MAX_UNDERESTIMATE = 10.0


@dataclass(frozen=True)
class Scatter:
    """The reference distribution of one quantity of one mode (:func:`fit_scatter`), for every share of
    the fit's ± not ruled out (module docstring). The fields are arrays over the shares (and, from
    :func:`fit_scatter_rows`, over rows first).

    Attributes
    ----------
    shares : ndarray (k,)
        The shares ``lam`` tried (one, 0, when the ± are not used).
    means, scales, sum_w : ndarray (..., k)
        Per share: the weighted mean ``mu``, the scale ``sigma^2`` and ``sum(w)``.
    allowed : ndarray of bool (..., k)
        The shares the reference does not rule out.
    best : int or ndarray
        Index of the most likely allowed share.
    mean_s2 : float or ndarray
        The mean squared ± (or stand-in) of the reference values (NaN when there are none).
    n : int
        Number of reference values.
    absolute : bool
        Whether the ± are the fit's (then a value is never judged more precise than its own ±) rather
        than a stand-in proportional to them, or none.
    """

    shares: np.ndarray
    means: np.ndarray
    scales: np.ndarray
    sum_w: np.ndarray
    allowed: np.ndarray
    best: int | np.ndarray
    mean_s2: float | np.ndarray
    n: int
    absolute: bool

    def _at_best(self, values):
        return np.take_along_axis(values, np.expand_dims(np.asarray(self.best), -1), -1)[..., 0]

    @property
    def mean(self):
        """The reference's mean at the most likely share."""
        return self._at_best(self.means)

    @property
    def std(self):
        """The scatter's standard deviation for a test of typical ± at the most likely share."""
        return np.sqrt(self._at_best(self.scales))

    @property
    def share(self):
        """The most likely share of the scatter that follows the fit's ±."""
        return self.shares[self.best]

    @property
    def uses_std(self) -> bool:
        """Whether the fit's ± (or a stand-in) entered the test."""
        return self.shares.size > 1


def _stds(s, n: int) -> np.ndarray | None:
    """The reference ± with missing ones given the median of the others; None when too few are known."""
    s = np.full(n, np.nan) if s is None else np.asarray(s, float)
    known = np.isfinite(s) & (s > 0)
    if known.sum() < max(2, (n + 1) // 2):
        return None
    return np.where(known, s, np.median(s[known]))


def _profile(x: np.ndarray, r: np.ndarray) -> tuple:
    """The restricted likelihood over :data:`LAMBDA_GRID` for each row of ``x`` (reference values) with
    relative squared ± ``r`` (same shape): ``(mu, scale, sum_w, loglik)``, each (n_rows, n_grid)."""
    n = x.shape[1]
    d = (1 - LAMBDA_GRID)[None, :, None] + LAMBDA_GRID[None, :, None] * r[:, None, :]
    w = 1 / d
    sum_w = w.sum(axis=2)
    mu = np.einsum("rgn,rn->rg", w, x) / sum_w
    rss = (w * (x[:, None, :] - mu[:, :, None]) ** 2).sum(axis=2)
    scale = rss / (n - 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        loglik = -0.5 * ((n - 1) * np.log(scale) + np.log(d).sum(axis=2) + np.log(sum_w))
    return mu, scale, sum_w, np.where(np.isfinite(loglik), loglik, -np.inf)


def _allowed(scale: np.ndarray, loglik: np.ndarray, mean_s2: np.ndarray, absolute: bool) -> np.ndarray:
    """The shares not ruled out: likely enough and, for the fit's own ±, within what they can explain
    (module docstring); at least the largest share within that bound."""
    ok = 2 * (loglik.max(axis=1, keepdims=True) - loglik) <= PLAUSIBLE
    ok[:, 0] = True  # the scatter alone is always a candidate: a share never makes a test more sensitive
    if absolute:
        bound = LAMBDA_GRID[None, :] * scale <= MAX_UNDERESTIMATE**2 * mean_s2[:, None]
        bound[:, 0] = True
        ok &= bound
        last = np.where(bound, np.arange(LAMBDA_GRID.size)[None, :], 0).max(axis=1)
        empty = ~ok.any(axis=1)
        ok[empty, last[empty]] = True
    return ok


def _rows(x: np.ndarray, s2: np.ndarray, absolute: bool) -> Scatter:
    """:class:`Scatter` of each row of ``x`` given squared ± ``s2`` (rows, n), all known and positive."""
    mean_s2 = s2.mean(axis=1)
    mu, scale, sum_w, loglik = _profile(x, s2 / mean_s2[:, None])
    allowed = _allowed(scale, loglik, mean_s2, absolute)
    best = np.argmax(np.where(allowed, loglik, -np.inf), axis=1)
    return Scatter(LAMBDA_GRID, mu, scale, sum_w, allowed, best, mean_s2, x.shape[1], absolute)


def _plain(mean, var, n: int, mean_s2=math.nan, absolute: bool = False) -> Scatter:
    """The reference's scatter alone (no ±): one share, 0 (``mean``, ``var`` of shape (..., 1))."""
    mean = np.asarray(mean, float).reshape(np.shape(mean) or (1,))
    var = np.asarray(var, float).reshape(mean.shape)
    ones = np.ones_like(mean)
    best = np.zeros(mean.shape[:-1], int) if mean.ndim > 1 else 0
    return Scatter(np.zeros(1), mean, var, n * ones, ones.astype(bool), best, mean_s2, n, absolute)


def _single(scatter: Scatter) -> Scatter:
    """Row 0 of a :class:`Scatter` of rows."""
    return Scatter(
        scatter.shares,
        scatter.means[0],
        scatter.scales[0],
        scatter.sum_w[0],
        scatter.allowed[0],
        int(scatter.best[0]),
        float(scatter.mean_s2[0]),
        scatter.n,
        scatter.absolute,
    )


def fit_scatter(x, s=None, proxy=None) -> Scatter | None:
    """The reference distribution of one quantity (module docstring); None with fewer than 2 values.

    Parameters
    ----------
    x : array-like
        The reference values (NaN ones, a mode a survey missed, are left out).
    s : array-like, optional
        Their standard deviations from the fit (NaN where unknown).
    proxy : array-like, optional
        Used where the ± are unknown: a number proportional to each test's noise (``10^(-SNR/20)``).

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> x = 100 + 0.05 * rng.standard_normal(20)
    >>> ref = fit_scatter(x, np.full(20, 0.001))   # the fit's ± far below the test-to-test scatter
    >>> round(float(ref.mean), 2), round(float(ref.std), 3), float(ref.share)
    (99.99, 0.044, 0.0)
    """
    x = np.asarray(x, float)
    ok = np.isfinite(x)
    x = x[ok]
    n = x.size
    if n < 2:
        return None
    if np.all(x == x[0]):  # every value the same (a term no model has): a new one judged by its own ±
        return _plain(x[0], 0.0, n, math.nan, True)
    stds, absolute = _stds(None if s is None else np.asarray(s, float)[ok], n), True
    if stds is None and proxy is not None:
        stds, absolute = _stds(np.asarray(proxy, float)[ok], n), False
    if stds is None:
        return _plain(x.mean(), x.var(ddof=1), n)
    return _single(_rows(x[None, :], (stds**2)[None, :], absolute))


def fit_scatter_rows(x, s=None) -> Scatter:
    """:func:`fit_scatter` of each row of ``x`` (n_rows, n) at once, every value finite and, when ``s`` is
    given, every ± known and positive: a :class:`Scatter` of arrays that :func:`prediction_test` takes as
    it takes one (row ``i`` tested against new value ``i``), for studies of the test by simulation."""
    x = np.asarray(x, float)
    if s is None:
        return _plain(x.mean(axis=1, keepdims=True), x.var(axis=1, ddof=1, keepdims=True), x.shape[1])
    return _rows(x, np.asarray(s, float) ** 2, True)


def prediction_test(ref: Scatter, x, s=None, proxy=None) -> tuple[np.ndarray, np.ndarray]:
    """The statistic ``T`` and two-sided p-value of new values against the reference, the least
    significant over the shares not ruled out (module docstring).

    Parameters
    ----------
    ref : Scatter
        From :func:`fit_scatter` (or :func:`fit_scatter_rows`: one new value per row).
    x, s : array-like
        New values and their ± from the fit (NaN allowed). A NaN value gives NaN (not tested), and so
        does a value that differs from a reference without any scatter when it has no ± of its own.
    proxy : array-like, optional
        The stand-in of each new value where the reference used one (:func:`fit_scatter`).

    Examples
    --------
    >>> ref = fit_scatter(np.array([10.0, 10.2, 9.9, 10.1, 9.8, 10.0, 10.1, 9.9]))
    >>> t, p = prediction_test(ref, [10.05, 11.5])
    >>> np.round(t, 2), bool(p[0] > 0.5), bool(p[1] < 1e-4)
    (array([ 0.36, 10.8 ]), True, True)
    """
    x = np.atleast_1d(np.asarray(x, float))
    s = np.full(x.shape, np.nan) if s is None else np.broadcast_to(np.asarray(s, float), x.shape)
    scaled = s if ref.absolute else np.full(x.shape, np.nan) if proxy is None else np.broadcast_to(
        np.asarray(proxy, float), x.shape)
    mean_s2 = np.expand_dims(np.asarray(ref.mean_s2, float), -1) if np.ndim(ref.mean_s2) else ref.mean_s2
    with np.errstate(invalid="ignore", divide="ignore"):
        typical = np.where(np.isfinite(scaled), scaled**2, np.nan)[..., None] / mean_s2
        kappa2 = ref.scales[..., 0] / ref.mean_s2 if ref.absolute else np.nan  # scatter over the ±
    typical = np.where(np.isfinite(typical), typical, 1.0)
    d0 = (1 - ref.shares) + ref.shares * typical
    var = ref.scales * (d0 + 1 / ref.sum_w)
    # never more precise than its own ±, unless the reference shows its ± too large
    floor = np.where(np.isfinite(s), s**2, 0.0) * np.minimum(np.where(np.isfinite(kappa2), kappa2, 1.0), 1.0)
    var = np.maximum(var, floor[..., None])
    diff = x[..., None] - ref.means
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(var > 0, diff / np.sqrt(var), np.where(diff == 0, 0.0, np.nan))
    dof = np.maximum(ref.n - np.where(ref.shares > 0, 2, 1), 1)
    p = 2 * stats.t.sf(np.abs(t), dof)
    p = np.where(ref.allowed & np.isfinite(t), p, -np.inf)
    k = np.argmax(p, axis=-1)[..., None]
    t_out, p_out = np.take_along_axis(t, k, -1)[..., 0], np.take_along_axis(p, k, -1)[..., 0]
    return t_out, np.where(np.isfinite(t_out) & (p_out >= 0), p_out, np.nan)


def holm(p, alpha: float) -> np.ndarray:
    """Holm's step-down rejections of each row of p-values (NaN: not tested), family-wise rate ``alpha``.

    Examples
    --------
    >>> holm(np.array([[0.001, 0.02, np.nan, 0.5], [0.2, 0.3, 0.4, 0.5]]), 0.05).astype(int)
    array([[1, 1, 0, 0],
           [0, 0, 0, 0]])
    """
    p = np.atleast_2d(np.asarray(p, float))
    filled = np.where(np.isfinite(p), p, np.inf)
    order = np.argsort(filled, axis=1)
    ranked = np.take_along_axis(filled, order, axis=1)
    m = np.isfinite(p).sum(axis=1, keepdims=True)
    k = np.arange(p.shape[1])[None, :]
    ok = ranked <= alpha / np.maximum(m - k, 1)
    keep = np.cumprod(ok, axis=1).astype(bool)  # stop at the first step that fails
    out = np.zeros_like(keep)
    np.put_along_axis(out, order, keep, axis=1)
    return out & np.isfinite(p)


def _mk_variance(x: np.ndarray) -> float:
    n = x.size
    _, counts = np.unique(x, return_counts=True)
    return (n * (n - 1) * (2 * n + 5) - np.sum(counts * (counts - 1) * (2 * counts + 5))) / 18.0


def mann_kendall(x) -> tuple[float, float]:
    """Mann-Kendall trend test over a sequence in its order: ``(z, p)``, z > 0 for a rising trend.

    NaN values (a survey without the mode) are left out; fewer than 4 values give NaN.

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> z, p = mann_kendall(np.arange(30) * 0.1 + rng.standard_normal(30))
    >>> bool(z > 0 and p < 0.01)
    True
    """
    x = np.asarray(x, float)
    x = x[np.isfinite(x)]
    if x.size < 4:
        return math.nan, math.nan
    s = float(np.sum(np.triu(np.sign(x[None, :] - x[:, None]), 1)))
    var = _mk_variance(x)
    if var <= 0:
        return 0.0, 1.0
    z = (s - math.copysign(1.0, s)) / math.sqrt(var) if s != 0 else 0.0
    return z, float(2 * stats.norm.sf(abs(z)))


def running_trend(x) -> np.ndarray:
    """The Mann-Kendall p-value over the first k values, for every k (NaN before 4 values): when a
    drift became visible. Each entry is a test of its own (looking at every k raises the chance of a
    false trend; the tracker's trend verdict is the test over the whole sequence)."""
    x = np.asarray(x, float)
    out = np.full(x.size, np.nan)
    for k in range(x.size):
        out[k] = mann_kendall(x[: k + 1])[1]
    return out

"""Uniform cubic B-splines for long or non-uniformly sampled records (P-splines, Eilers & Marx 1996).

``y(tau) = sum_k c_k B_k(tau)``: each sample touches 4 coefficients, so ``G = B^T B`` has 3 off-diagonals
and ``B^T f`` is 4 weighted bincounts. The basis keeps only each sample's knot interval and position in
it (16 bytes a sample) and evaluates the spline, its derivative and the selection scores of a solution in
one compiled pass over the samples: the cost of choosing alpha on a million-sample record is a few
passes over the data, not a few per alpha and array.
"""

from __future__ import annotations

import numpy as np

from .._utils.jit import jit, kernel

__all__ = ["SplineBasis"]


@jit(_nrt=False)
def _weight(v, a):
    """Value of the ``a``-th of the 4 cubic B-splines touching a sample at position ``v`` in [0, 1)."""
    if a == 0:
        w = 1 - v
        return w * w * w / 6.0
    v2 = v * v
    v3 = v2 * v
    if a == 1:
        return (3 * v3 - 6 * v2 + 4) / 6.0
    if a == 2:
        return (-3 * v3 + 3 * v2 + 3 * v + 1) / 6.0
    return v3 / 6.0


@kernel
def _bincounts(start, u, f, shift, partner, out, work):
    """``out += sum_a bincount(start + a, w_a * w_(a + shift) * f)`` over ``a < 4 - shift`` (``f`` and the
    partner weight optional: ``partner`` False drops it), each bincount summed from zero in sample order
    and then added, as numpy's would be: the Gram matrix's diagonals and ``B^T f`` in one pass a term,
    without an array per weight."""
    for a in range(4 - shift):
        work[:] = 0.0
        for i in range(start.shape[0]):
            w = _weight(u[i], a)
            if partner:
                w = w * _weight(u[i], a + shift)
            else:
                w = w * f[i]
            work[start[i] + a] += w
        for k in range(out.shape[0]):
            out[k] += work[k]


@jit(_nrt=False)
def _at(c, j, v):
    """The spline with coefficients ``c`` and its derivative (per knot interval) at ``u = v`` in interval
    ``j``."""
    w = 1.0 - v
    v2 = v * v
    v3 = v2 * v
    y = (w * w * w * c[j] + (3 * v3 - 6 * v2 + 4) * c[j + 1] + (-3 * v3 + 3 * v2 + 3 * v + 1) * c[j + 2]
         + v3 * c[j + 3]) / 6.0  # fmt: skip
    dy = -w * w * c[j] + (3 * v2 - 4 * v) * c[j + 1] + (-3 * v2 + 2 * v + 1) * c[j + 2] + v2 * c[j + 3]
    dy *= 0.5
    return y, dy


@kernel
def _evaluate(c, start, u, spacing, values, slopes):
    """The spline and its derivative (per unit of ``tau``) at every sample."""
    for i in range(start.shape[0]):
        y, dy = _at(c, start[i], u[i])
        values[i] = y
        slopes[i] = dy / spacing


#: Samples per block of the consistency's running moments in :func:`_scores`.
_BLOCK = 4096


@kernel
def _scores(c, start, u, spacing, g, tau, lo, hi):
    """``(rss, consistency)`` of the spline ``c`` against ``g`` in one pass (``SplineBasis.fit_scores``).

    The consistency is the standard deviation of ``g`` minus the trapezoid integral of the spline's slope
    over the samples ``lo:hi`` (the mean, a free constant, removed): summed about each block's first value
    and the blocks merged by Chan's formula, which leaves the loop without a division in its chain of
    dependent operations (Welford's update per sample took 40 % of the pass); the residual sum is
    accumulated sample by sample in order, as before.
    """
    n = start.shape[0]
    lo = max(lo, 0)
    hi = max(min(hi, n), lo)
    rss = 0.0
    for i in range(lo):
        y, dy = _at(c, start[i], u[i])
        rss += (g[i] - y) ** 2
    integral = 0.0
    mean = 0.0
    m2 = 0.0
    count = 0
    previous = 0.0
    first = lo
    while first < hi:
        stop = min(first + _BLOCK, hi)
        shift = 0.0
        s1 = 0.0
        s2 = 0.0
        for i in range(first, stop):
            y, dy = _at(c, start[i], u[i])
            rss += (g[i] - y) ** 2
            slope = dy / spacing
            if i > lo:  # trapezoid rule, as for the samples of any other basis
                integral += 0.5 * (previous + slope) * (tau[i] - tau[i - 1])
            previous = slope
            if i == first:
                shift = g[i] - integral
            d = g[i] - integral - shift
            s1 += d
            s2 += d * d
        k = stop - first
        block_mean = s1 / k
        total = count + k
        delta = shift + block_mean - mean
        mean += delta * k / total
        m2 += (s2 - s1 * block_mean) + delta * delta * count * k / total
        count = total
        first = stop
    for i in range(hi, n):
        y, dy = _at(c, start[i], u[i])
        rss += (g[i] - y) ** 2
    return rss, np.sqrt(max(m2, 0.0) / max(count, 1))


class SplineBasis:
    """Uniform cubic B-splines with ``n_intervals`` knot intervals spanning ``tau``.

    The derivative is the exact derivative of the spline, so ``y`` is exactly the time integral of the
    derivative.
    """

    def __init__(self, tau: np.ndarray, n_intervals: int):
        self.tau = np.ascontiguousarray(tau, dtype=float)
        self.n_coef = n_intervals + 3
        self.spacing = float(tau[-1] - tau[0]) / n_intervals
        pos = (self.tau - self.tau[0]) / self.spacing
        self.start_index = np.clip(np.floor(pos).astype(np.int64), 0, n_intervals - 1)
        self.u = pos - self.start_index
        gram = np.zeros((4, self.n_coef))
        work = np.empty(self.n_coef)
        for s in range(4):
            _bincounts(self.start_index, self.u, self.u, s, True, gram[s], work)
        # a tiny ridge keeps G + lam P positive definite where knot intervals hold no sample
        gram[0] += 1e-10 * max(float(np.max(gram[0])), 1.0)
        self.gram = gram

    def rhs(self, f: np.ndarray) -> np.ndarray:
        """``B^T f``."""
        out = np.zeros(self.n_coef)
        f = np.ascontiguousarray(f, dtype=float)
        _bincounts(self.start_index, self.u, f, 0, False, out, np.empty(self.n_coef))
        return out

    def evaluate(self, c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The spline ``B c`` and its derivative per unit of ``tau`` at the samples."""
        values = np.empty(self.tau.shape[0])
        slopes = np.empty(self.tau.shape[0])
        c = np.ascontiguousarray(c, dtype=float)
        _evaluate(c, self.start_index, self.u, self.spacing, values, slopes)
        return values, slopes

    def values(self, c: np.ndarray) -> np.ndarray:
        return self.evaluate(c)[0]

    def slopes(self, c: np.ndarray) -> np.ndarray:
        return self.evaluate(c)[1]

    def fit_scores(self, c: np.ndarray, g: np.ndarray, trim: int) -> tuple[float, float]:
        """Residual sum of squares against ``g`` and the paper's consistency error (see
        :func:`._banded.consistency_error`), without forming the spline at the samples."""
        n = self.tau.shape[0]
        rss, consistency = _scores(
            np.ascontiguousarray(c, dtype=float), self.start_index, self.u, self.spacing,
            np.ascontiguousarray(g, dtype=float), self.tau, trim, n - trim,
        )  # fmt: skip
        return float(rss), float(consistency)

    def start(self, f: np.ndarray) -> np.ndarray:
        centres = self.tau[0] + (np.arange(self.n_coef) - 1) * self.spacing
        return np.interp(centres, self.tau, f)

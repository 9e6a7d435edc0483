"""Banded building blocks of the total-variation regularized derivative.

Everything here works in *sample units*: the time axis is ``tau = t / mean(dt)`` (so a uniform grid has
unit spacing) and the signal is already normalized by the caller. All operations are O(N) in time and
memory for a fixed difference order ``m``: the difference operator is stored as its ``m + 1`` stencil
coefficients per row, and the normal matrix ``G + lam D^T W D`` in the lower banded form that
:func:`scipy.linalg.solveh_banded` expects.

The smoothed signal is ``y = B c``: ``B`` is the identity (``c`` are the smoothed samples, ``G = I``) or,
for long records, a uniform cubic B-spline basis with fewer coefficients than samples (P-splines, Eilers &
Marx 1996; ``G = B^T B`` banded; :mod:`._spline`). The penalty acts on differences of ``c``.
"""

from __future__ import annotations

from math import comb

import numpy as np
from scipy.linalg import solveh_banded
from scipy.linalg.lapack import dpbsv

from .._utils.jit import kernel
from ._smoother import smooth

__all__ = [
    "difference_stencil",
    "apply_difference",
    "apply_difference_transpose",
    "normal_band",
    "lambda_max",
    "tv_smooth",
    "trace_inverse",
    "IdentityBasis",
    "centred_slopes",
    "consistency_error",
    "penalty_weight",
    "polynomial_residual",
]

# Upper bound on lam * w (normalized units): keeps I + lam D^T W D numerically positive definite where
# the current iterate is locally polynomial (D y ~ 0, so 1/|D y| explodes).
_MAX_PENALTY_WEIGHT = 1e12


def difference_stencil(tau: np.ndarray | None, n: int, m: int) -> tuple[np.ndarray, np.ndarray]:
    """Coefficients of the m-th derivative difference operator ``D`` (shape (n - m, n)).

    Row ``r`` of ``D`` has the nonzero entries ``coef[r, 0..m]`` in columns ``r..r + m`` and approximates
    the m-th derivative (``m!`` times the Newton divided difference). ``h[r]`` is the mean spacing under
    the stencil, the quadrature weight of row ``r`` in the total-variation sum.

    For a uniform grid (``tau is None``) both are broadcastable single rows: the binomial stencil and 1.
    """
    if tau is None:
        coef = np.array([(-1) ** (m - p) * comb(m, p) for p in range(m + 1)], dtype=float)[None, :]
        return coef, np.ones(1)
    coef = np.ones((n, 1))
    for k in range(1, m + 1):
        span = (tau[k:] - tau[:-k]) / k  # mean spacing over the k + 1 points of each row
        new = np.zeros((n - k, k + 1))
        new[:, 1:] += coef[1:]
        new[:, :-1] -= coef[:-1]
        coef = new / span[:, None]
    return coef, (tau[m:] - tau[:-m]) / m


def apply_difference(coef: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``D @ y`` for the stencil ``coef`` (see :func:`difference_stencil`)."""
    m = coef.shape[1] - 1
    rows = y.shape[0] - m
    d = coef[:, 0] * y[:rows]
    for p in range(1, m + 1):
        d = d + coef[:, p] * y[p : p + rows]
    return d


def apply_difference_transpose(coef: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``D.T @ v`` for the stencil ``coef``."""
    m = coef.shape[1] - 1
    rows = v.shape[0]
    out = np.zeros(rows + m)
    for p in range(m + 1):
        out[p : p + rows] += coef[:, p] * v
    return out


def normal_band(coef: np.ndarray, weight: np.ndarray, n: int, gram: np.ndarray | None = None) -> np.ndarray:
    """``G + D^T diag(weight) D`` in lower banded storage (``G = I`` when ``gram`` is None).

    ``band[s, j]`` holds the entry (j + s, j). Cost: (m + 1)(m + 2)/2 vector operations of length n.
    """
    m = coef.shape[1] - 1
    rows = n - m
    width = m if gram is None else max(m, gram.shape[0] - 1)
    band = np.zeros((width + 1, n))
    if gram is None:
        band[0] = 1.0
    else:
        band[: gram.shape[0]] = gram
    if coef.shape[0] == 1:
        # uniform stencil: each band is the convolution of the weights with a fixed kernel
        for s in range(m + 1):
            kernel = coef[0, : m + 1 - s] * coef[0, s:]
            band[s, : n - s] += np.convolve(weight, kernel)
        return band
    for s in range(m + 1):
        for p in range(m + 1 - s):
            band[s, p : p + rows] += weight * (coef[:, p] * coef[:, p + s])
    return band


class IdentityBasis:
    """``y = c``: one coefficient per sample (``tau`` in units of the mean sample spacing)."""

    def __init__(self, tau: np.ndarray):
        self.tau = tau
        self.n_coef = tau.shape[0]
        self.gram = None
        self.spacing = 1.0

    def rhs(self, f: np.ndarray) -> np.ndarray:
        return f

    def values(self, c: np.ndarray) -> np.ndarray:
        return c

    def slopes(self, c: np.ndarray) -> np.ndarray:
        """d y / d tau at the samples: centred differences (see :func:`centred_slopes`)."""
        return centred_slopes(c)

    def evaluate(self, c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The smoothed samples and their derivative per unit of ``tau``."""
        return c, self.slopes(c)

    def fit_scores(self, c: np.ndarray, g: np.ndarray, trim: int) -> tuple[float, float]:
        """Residual sum of squares against ``g`` and the paper's consistency error."""
        return float(np.sum((g - c) ** 2)), consistency_error(g, self.slopes(c), self.tau, trim)

    def start(self, f: np.ndarray) -> np.ndarray:
        return f.copy()


def centred_slopes(c: np.ndarray) -> np.ndarray:
    """The derivative of samples ``c`` at unit spacing by centred differences of sixth order (no lag),
    of fourth and second order at the second and third samples from each end, one-sided at the ends.

    A centred difference of order ``2p`` sees ``cos(w t)`` with the gain ``1 - O((w h)^(2p))``: at 10
    samples per period the second-order one (``sin(w h) / (w h)``) under-estimates the derivative by
    6.5 %, enough to put every regression's frequencies that much low, the sixth-order one by 0.05 %. The
    smoothed signal is smooth (its penalized derivative is small), so the longer stencil does not bring
    its noise back.

    Examples
    --------
    >>> tau = np.arange(40.0)
    >>> w = 2 * np.pi / 10  # 10 samples per period
    >>> slopes = centred_slopes(np.sin(w * tau))
    >>> bool(np.max(np.abs(slopes[3:-3] - w * np.cos(w * tau[3:-3]))) < 1e-3 * w)
    True
    >>> bool(np.max(np.abs(np.gradient(np.sin(w * tau))[3:-3] - w * np.cos(w * tau[3:-3]))) > 0.06 * w)
    True
    """
    c = np.asarray(c, dtype=float)
    n = c.shape[0]
    out = np.gradient(c) if n > 1 else np.zeros(n)
    if n >= 5:
        i = np.arange(2, n - 2)
        out[i] = (8.0 * (c[i + 1] - c[i - 1]) - (c[i + 2] - c[i - 2])) / 12.0
    if n >= 7:
        i = np.arange(3, n - 3)
        out[i] = (45.0 * (c[i + 1] - c[i - 1]) - 9.0 * (c[i + 2] - c[i - 2]) + (c[i + 3] - c[i - 3])) / 60.0
    return out


def consistency_error(g: np.ndarray, slopes: np.ndarray, tau: np.ndarray, trim: int) -> float:
    """Paper's criterion: RMS(input - time-integrated derivative) on the kept samples, offset free."""
    n = g.shape[0]
    lo, hi = trim, n - trim
    u = slopes[lo:hi]
    integral = np.concatenate(([0.0], np.cumsum(0.5 * (u[1:] + u[:-1]) * np.diff(tau[lo:hi]))))
    diff = g[lo:hi] - integral
    diff -= np.mean(diff)  # free integration constant (least squares)
    return float(np.sqrt(np.mean(diff**2)))


def lambda_max(grad: np.ndarray, coef: np.ndarray, h: np.ndarray) -> float:
    """Smallest ``lam`` for which the (eps = 0) TV solution lies in the null space of ``D``.

    ``grad = B^T (f - p)`` with ``p`` the least-squares polynomial of degree m - 1 (so ``grad`` is
    orthogonal to the null space). The answer is ``max |v / h|`` with ``D^T v = grad`` (Kim, Koh, Boyd &
    Gorinevsky 2009, for l1 trend filtering), solved exactly and in O(N) by forward substitution, i.e.
    repeated cumulative sums, never forming ``D D^T`` (whose condition number grows like N^(2m)).
    """
    m = coef.shape[1] - 1
    rows = grad.shape[0] - m
    if rows <= 0:
        return 0.0
    if coef.shape[0] == 1:
        # Uniform grid: D = Delta^m, and Delta^T z = r is solved by z = -cumsum(r)[:-1].
        v = grad
        for _ in range(m):
            v = -np.cumsum(v)[:-1]
    else:
        # (D^T v)[i] = sum_q coef[i - q, q] v[i - q]; the diagonal coefficient of row i is coef[i, 0].
        v = np.zeros(rows)
        c0 = coef[:, 0]
        for i in range(rows):
            acc = grad[i]
            for q in range(1, min(m, i) + 1):
                acc -= coef[i - q, q] * v[i - q]
            v[i] = acc / c0[i]
    return float(np.max(np.abs(v / h)))


def polynomial_residual(f: np.ndarray, tau: np.ndarray, degree: int) -> np.ndarray:
    """``f`` minus its least-squares polynomial fit of ``degree`` in ``tau`` (Legendre basis)."""
    x = (tau - tau[0]) / max(float(tau[-1] - tau[0]), 1e-300) * 2.0 - 1.0
    vander = np.polynomial.legendre.legvander(x, degree)
    # Legendre polynomials on [-1, 1] are close to orthogonal: the normal equations are well conditioned
    return f - vander @ np.linalg.solve(vander.T @ vander, vander.T @ f)


def tv_smooth(
    rhs: np.ndarray,
    coef: np.ndarray,
    h: np.ndarray,
    lam: float,
    c0: np.ndarray,
    gram: np.ndarray | None = None,
    *,
    max_iter: int = 30,
    tol: float = 1e-4,
    eps_rel: float = 1.0,
) -> tuple[np.ndarray, int]:
    """Minimize ``1/2 ||B c - f||^2 + lam * sum_r h_r |(D c)_r|`` by lagged diffusivity.

    ``rhs = B^T f`` and ``gram = B^T B`` (None: ``B = I``). Each iteration solves the banded SPD system
    ``(G + lam D^T W D) c = B^T f`` with ``W = diag(h / sqrt((D c_old)^2 + eps^2))``,
    ``eps = eps_rel * rms(D c_old)`` (scale free; ``eps_rel -> 0`` is pure TV), in O(N) with
    :func:`scipy.linalg.solveh_banded`, starting from ``c0``. Stops when the RMS change of ``c`` is below
    ``tol`` times the RMS of ``c0``.

    Returns the coefficients and the number of iterations used.
    """
    if lam <= 0 and gram is None:
        return rhs.copy(), 0
    compiled = smooth(rhs, coef, h, lam, c0, gram, max_iter, tol, eps_rel)  # the same steps, compiled
    if compiled is not None:
        return compiled
    return lapack_smooth(rhs, coef, h, lam, c0, gram, max_iter, tol, eps_rel)  # a pivot was not positive


def lapack_smooth(rhs, coef, h, lam, c0, gram, max_iter, tol, eps_rel) -> tuple[np.ndarray, int]:
    """:func:`tv_smooth`'s iteration in numpy with LAPACK's banded solver (a ridge where it fails)."""
    n = rhs.shape[0]
    c = c0.copy()
    scale = max(float(np.sqrt(np.mean(c0**2))), 1e-300)
    it = 0
    for it in range(1, max_iter + 1):  # noqa: B007
        weight = penalty_weight(coef, h, lam, c, eps_rel)
        band = normal_band(coef, weight, n, gram)
        _, c_new, info = dpbsv(band, rhs, lower=1)  # LAPACK banded Cholesky solve, no wrapper overhead
        if info != 0:  # only for pathological weights
            band[0] += 1e-10 * np.max(band[0])
            c_new = solveh_banded(band, rhs, lower=True, check_finite=False)
        change = float(np.sqrt(np.mean((c_new - c) ** 2)))
        c = c_new
        if change <= tol * scale or lam <= 0:
            break
    return c, it


def penalty_weight(coef: np.ndarray, h: np.ndarray, lam: float, c: np.ndarray, eps_rel: float) -> np.ndarray:
    """Lagged-diffusivity weights ``lam * h / sqrt(d^2 + eps^2)``, ``d = D c``, capped for conditioning."""
    d = apply_difference(coef, c)
    rms = float(np.sqrt(np.mean(d**2)))
    eps = max(eps_rel * rms, 1e-14 * max(float(np.max(np.abs(c))), 1e-300))
    return np.minimum(lam * h / np.sqrt(d * d + eps * eps), _MAX_PENALTY_WEIGHT)


def _trace_inverse_py(band: np.ndarray, gram: np.ndarray) -> float:
    """``trace(A^-1 G)`` for SPD banded ``A`` and symmetric banded ``G`` (lower storage), in O(N b^2).

    LDL^T factorization followed by the selected-inversion recursion of Hutchinson & de Hoog (1985):
    only the entries of ``A^-1`` inside the band of ``A`` are computed, from the last row upwards; ``G``'s
    band must not be wider than ``A``'s. (Python; :func:`trace_inverse` runs the same code compiled.)
    """
    return _selected_trace(band, gram, np.zeros(band.shape), np.zeros(band.shape[1]), np.zeros(band.shape))


def _selected_trace(band, gram, low, diag, inv) -> float:
    """:func:`_trace_inverse_py` with its work arrays given (``low[s, j] = L[j + s, j]`` of the unit lower
    factor, the diagonal ``D``, ``inv[s, i] = (A^-1)[i + s, i]``): the compiled kernel allocates nothing."""
    b = band.shape[0] - 1
    n = band.shape[1]
    for j in range(n):
        acc = band[0, j]
        for k in range(max(0, j - b), j):
            lk = low[j - k, k]
            acc -= lk * lk * diag[k]
        diag[j] = acc
        for s in range(1, b + 1):
            i = j + s
            if i >= n:
                break
            acc = band[s, j]
            for k in range(max(0, i - b), j):
                acc -= low[i - k, k] * low[j - k, k] * diag[k]
            low[s, j] = acc / diag[j]
    trace = 0.0
    for i in range(n - 1, -1, -1):
        for s in range(1, b + 1):
            if i + s >= n:
                break
            acc = 0.0
            for q in range(1, b + 1):
                k = i + q
                if k >= n:
                    break
                c = i + s
                acc -= low[q, i] * (inv[k - c, c] if k >= c else inv[c - k, k])
            inv[s, i] = acc
        acc = 1.0 / diag[i]
        for q in range(1, b + 1):
            if i + q >= n:
                break
            acc -= low[q, i] * inv[q, i]
        inv[0, i] = acc
        trace += acc * gram[0, i]
        for s in range(1, gram.shape[0]):
            if i + s >= n:
                break
            trace += 2.0 * inv[s, i] * gram[s, i]
    return trace


_trace_inverse_kernel = kernel(_selected_trace)


def trace_inverse(band: np.ndarray, gram: np.ndarray | None = None) -> float:
    """``trace((G + lam D^T W D)^-1 G)``: the effective number of parameters of the linearized smoother.

    Compiled with numba (cached on disk; ``_trace_inverse_py`` is the same code in Python).
    """
    band = np.ascontiguousarray(band, dtype=float)
    gram = np.ones((1, band.shape[1])) if gram is None else np.ascontiguousarray(gram, dtype=float)
    work = np.zeros((3, *band.shape))
    return float(_trace_inverse_kernel(band, gram, work[0], work[1, 0], work[2]))

"""Banded building blocks of the total-variation regularized derivative.

Everything here works in *sample units*: the time axis is ``tau = t / mean(dt)`` (so a uniform grid has
unit spacing) and the signal is already normalized by the caller. All operations are O(N) in time and
memory for a fixed difference order ``m``: the difference operator is stored as its ``m + 1`` stencil
coefficients per row, and the normal matrix ``I + lam D^T W D`` in the lower banded form that
:func:`scipy.linalg.solveh_banded` expects.
"""

from __future__ import annotations

from math import comb

import numpy as np
from scipy.linalg import LinAlgError, solveh_banded

__all__ = [
    "difference_stencil",
    "apply_difference",
    "apply_difference_transpose",
    "normal_band",
    "lambda_max",
    "tv_smooth",
    "trace_inverse",
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


def normal_band(coef: np.ndarray, weight: np.ndarray, n: int) -> np.ndarray:
    """``I + D^T diag(weight) D`` in lower banded storage, shape (m + 1, n).

    ``band[s, j]`` holds the entry (j + s, j). Cost: (m + 1)(m + 2)/2 vector operations of length n.
    """
    m = coef.shape[1] - 1
    rows = n - m
    band = np.zeros((m + 1, n))
    band[0] = 1.0
    for s in range(m + 1):
        for p in range(m + 1 - s):
            band[s, p : p + rows] += weight * (coef[:, p] * coef[:, p + s])
    return band


def lambda_max(f: np.ndarray, tau: np.ndarray, coef: np.ndarray, h: np.ndarray) -> float:
    """Smallest ``lam`` for which the (eps = 0) TV solution is the least-squares polynomial of degree m-1.

    It is ``max |v / h|`` with ``D^T v = f - p`` (Kim, Koh, Boyd & Gorinevsky 2009, for l1 trend filtering);
    ``D^T v = r`` is solved exactly and in O(N) by forward substitution, i.e. repeated cumulative sums,
    never forming ``D D^T`` (whose condition number grows like N^(2m)).
    """
    m = coef.shape[1] - 1
    n = f.shape[0]
    x = (tau - tau[0]) / max(tau[-1] - tau[0], 1e-300) * 2.0 - 1.0
    vander = np.polynomial.legendre.legvander(x, m - 1)
    p = vander @ np.linalg.lstsq(vander, f, rcond=None)[0]
    resid = f - p
    # Forward substitution on the lower-triangular top (n - m) x (n - m) block of D^T.
    # (D^T v)[i] = sum_{q=0..m} coef[i - q, q] v[i - q]; the diagonal coefficient of row i is coef[i, 0].
    rows = n - m
    if coef.shape[0] == 1:
        # Uniform grid: D = Delta^m, and Delta^T z = r is solved by z = -cumsum(r)[:-1].
        z = resid
        for _ in range(m):
            z = -np.cumsum(z)[:-1]
        v = z
    else:
        v = np.zeros(rows)
        c0 = coef[:, 0]
        for i in range(rows):
            acc = resid[i]
            for q in range(1, min(m, i) + 1):
                acc -= coef[i - q, q] * v[i - q]
            v[i] = acc / c0[i]
    return float(np.max(np.abs(v / h))) if rows > 0 else 0.0


def tv_smooth(
    f: np.ndarray,
    coef: np.ndarray,
    h: np.ndarray,
    lam: float,
    y0: np.ndarray | None = None,
    *,
    max_iter: int = 30,
    tol: float = 1e-4,
    eps_rel: float = 1e-3,
) -> tuple[np.ndarray, int]:
    """Minimize ``1/2 ||y - f||^2 + lam * sum_r h_r |(D y)_r|`` by lagged diffusivity.

    Each iteration solves the banded SPD system ``(I + lam D^T W D) y = f`` with
    ``W = diag(h / sqrt((D y_old)^2 + eps^2))``, ``eps = eps_rel * rms(D y_old)`` (scale free;
    ``eps_rel -> 0`` is pure TV), in O(N) with :func:`scipy.linalg.solveh_banded`. Stops when the
    relative change of ``y`` is below ``tol``.

    Returns the smoothed signal and the number of iterations used.
    """
    n = f.shape[0]
    if lam <= 0:
        return f.copy(), 0
    y = f.copy() if y0 is None else y0.copy()
    scale = max(float(np.sqrt(np.mean(f**2))), 1e-300)
    it = 0
    for it in range(1, max_iter + 1):  # noqa: B007
        d = apply_difference(coef, y)
        rms = float(np.sqrt(np.mean(d**2)))
        eps = max(eps_rel * rms, 1e-14 * scale)
        weight = np.minimum(lam * h / np.sqrt(d * d + eps * eps), _MAX_PENALTY_WEIGHT)
        band = normal_band(coef, weight, n)
        try:
            y_new = solveh_banded(band, f, lower=True, check_finite=False)
        except LinAlgError:  # pragma: no cover - only for pathological weights
            band[0] += 1e-10 * np.max(band[0])
            y_new = solveh_banded(band, f, lower=True, check_finite=False)
        change = float(np.sqrt(np.mean((y_new - y) ** 2)))
        y = y_new
        if change <= tol * scale:
            break
    return y, it


def _trace_inverse_py(band: np.ndarray) -> float:
    """``trace(A^-1)`` for a symmetric positive definite banded ``A`` (lower storage), in O(N b^2).

    LDL^T factorization followed by the selected-inversion recursion of Hutchinson & de Hoog (1985):
    only the entries of ``A^-1`` inside the band are computed, from the last row upwards.
    """
    b = band.shape[0] - 1
    n = band.shape[1]
    low = np.zeros((b + 1, n))  # low[s, j] = L[j + s, j] (unit lower factor)
    diag = np.zeros(n)
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
    inv = np.zeros((b + 1, n))  # inv[s, i] = (A^-1)[i + s, i]
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
        trace += acc
    return trace


_trace_inverse_jit = None


def trace_inverse(band: np.ndarray) -> float:
    """``trace((I + lam D^T W D)^-1)``, the effective number of parameters of the linearized smoother.

    Compiled with numba on first use (cached on disk); the pure-Python version is the fallback.
    """
    global _trace_inverse_jit
    if _trace_inverse_jit is None:
        try:
            import numba

            _trace_inverse_jit = numba.njit(cache=True)(_trace_inverse_py)
        except Exception:  # pragma: no cover - numba missing or broken
            _trace_inverse_jit = _trace_inverse_py
    return float(_trace_inverse_jit(np.ascontiguousarray(band)))

"""The lagged-diffusivity iteration of TVRegDiff, compiled: one call runs every iteration.

The same steps as :func:`._banded.tv_smooth` (weights from the current iterate, the banded normal matrix
``G + lam D^T W D``, its Cholesky solve, the stopping test), without a Python round trip per step: on a
ring-down of a few hundred samples the numpy version spends most of its time in call overhead. The
Cholesky factorization is the textbook banded one (``L L^T``, left-looking); where a pivot is not positive
the caller falls back to the LAPACK path, which adds a ridge.
"""

from __future__ import annotations

import math

import numpy as np

from .._utils.jit import kernel

__all__ = ["lagged_diffusivity"]

#: Upper bound on lam * w (normalized units); the same as :data:`._banded._MAX_PENALTY_WEIGHT`.
MAX_PENALTY_WEIGHT = 1e12


@kernel
def lagged_diffusivity(rhs, coef, h, lam, c, gram, max_iter, tol, eps_rel, w, band, low, c_new):
    """Iterate from ``c`` (updated in place); returns the iterations used, or -1 if a solve failed.

    Each iteration: the weights ``w = min(lam h / sqrt(d^2 + eps^2), MAX)`` of ``d = D c`` (``eps = eps_rel
    rms(d)``, floored), ``band = G + D^T diag(w) D`` (lower banded storage, ``band[s, j]`` is entry
    ``(j + s, j)``), its Cholesky factor ``low[s, k] = L[k + s, k]``, the two triangular solves. One
    function: each compiled function costs a fixed share of the first start on a new machine.
    """
    n, m, rows, width = rhs.shape[0], coef.shape[1] - 1, w.shape[0], band.shape[0] - 1
    scale = 0.0
    for i in range(n):
        scale += c[i] * c[i]
    scale = max(math.sqrt(scale / n), 1e-300)
    for it in range(1, max_iter + 1):
        total, largest = 0.0, 0.0  # (loops, not numpy calls: they would compile much more code)
        for r in range(rows):  # d = D c
            d = 0.0
            for p in range(m + 1):
                d += coef[r if coef.shape[0] > 1 else 0, p] * c[r + p]
            w[r] = d
            total += d * d
        for i in range(n):
            largest = max(largest, abs(c[i]))
        eps = max(eps_rel * math.sqrt(total / rows), 1e-14 * max(largest, 1e-300))
        for s in range(width + 1):
            for j in range(n):
                band[s, j] = gram[s, j] if s < gram.shape[0] else 0.0
        for r in range(rows):
            hr = h[r if h.shape[0] > 1 else 0]
            w[r] = min(lam * hr / math.sqrt(w[r] * w[r] + eps * eps), MAX_PENALTY_WEIGHT)
            cr = r if coef.shape[0] > 1 else 0
            for p in range(m + 1):
                for s in range(m + 1 - p):
                    band[s, r + p] += w[r] * coef[cr, p] * coef[cr, p + s]
        for j in range(n):  # banded Cholesky, left-looking
            d = band[0, j]
            for k in range(max(0, j - width), j):
                d -= low[j - k, k] * low[j - k, k]
            if not d > 0.0:
                return -1
            low[0, j] = math.sqrt(d)
            for s in range(1, min(width, n - 1 - j) + 1):
                v = band[s, j]
                for k in range(max(0, j + s - width), j):
                    v -= low[j + s - k, k] * low[j - k, k]
                low[s, j] = v / low[0, j]
        for j in range(n):  # L y = rhs
            v = rhs[j]
            for k in range(max(0, j - width), j):
                v -= low[j - k, k] * c_new[k]
            c_new[j] = v / low[0, j]
        for j in range(n - 1, -1, -1):  # L^T c_new = y
            v = c_new[j]
            for s in range(1, min(width, n - 1 - j) + 1):
                v -= low[s, j] * c_new[j + s]
            c_new[j] = v / low[0, j]
        change = 0.0
        for i in range(n):
            change += (c_new[i] - c[i]) ** 2
            c[i] = c_new[i]
        if math.sqrt(change / n) <= tol * scale or lam <= 0:
            return it
    return max_iter


def smooth(rhs, coef, h, lam, c0, gram, max_iter, tol, eps_rel):
    """``(c, iterations)`` by the compiled iteration, or None where a Cholesky pivot was not positive."""
    n = rhs.shape[0]
    m = coef.shape[1] - 1
    gram = np.ones((1, n)) if gram is None else np.ascontiguousarray(gram, dtype=float)
    width = max(m, gram.shape[0] - 1)
    c = np.array(c0, dtype=float)
    work = np.empty((2 * (width + 1) + 1, n))
    its = lagged_diffusivity(
        np.ascontiguousarray(rhs, dtype=float), np.ascontiguousarray(coef, dtype=float),
        np.ascontiguousarray(h, dtype=float), float(lam), c, gram, int(max_iter), float(tol),
        float(eps_rel), np.empty(n - m), work[: width + 1], work[width + 1 : 2 * width + 2], work[-1],
    )  # fmt: skip
    return None if its < 0 else (c, int(its))

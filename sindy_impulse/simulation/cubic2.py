"""The two-state polynomial model of degree <= 3 (the paper's, every mode of ``identify_modes``) integrated
with its monomials in registers.

The general kernel (:mod:`.integrators`) evaluates a model's terms through its product tree in memory,
which costs 4-6x a hand-written RK4 of the same model. For two states and a cubic library the ten
monomials of each equation are few enough to write out: :func:`cubic2_coefficients` turns a packed model
into dense coefficients (per equation: 1, x0, x1, x0^2, x0 x1, x1^2, x0^3, x0^2 x1, x0 x1^2, x1^3) and
flags of the parts present; :func:`rk4_interval_cubic2` steps it, computing the quadratic and cubic parts
only where present. Measured (``benchmarks/run.py``, a 4-term Duffing model, 401 samples, 5 sub-steps):
1.5x a minimal hand-written numba RK4, against 4-6x through the product tree. Its results equal RK4 on
the model's equations to rounding (``tests/test_simulation.py``), not bit for bit the product tree's
(the sums run in another order).
"""

from __future__ import annotations

from .._jit import jit

__all__ = ["CUBIC2", "cubic2_coefficients", "rk4_interval_cubic2"]

#: Dense coefficients of a two-state polynomial model of degree <= 3 and which of its parts are present
#: (:func:`cubic2_coefficients`): scratch floats the kernels reserve for it.
CUBIC2 = 26


@jit(_nrt=False)
def cubic2_coefficients(prog, vals, n, n_z, dense) -> bool:
    """Fill ``dense`` with the coefficients of a two-state polynomial model of degree <= 3 without inputs
    (per equation: 1, x0, x1, x0^2, x0 x1, x1^2, x0^3, x0^2 x1, x0 x1^2, x1^3; then per equation whether
    a quadratic and a cubic term are present, non-zero if so); False for another model.

    Such a model (the paper's, every mode of :func:`~sindy_impulse.identify_modes`) is integrated by
    :func:`rk4_interval_cubic2`, its monomials in registers instead of the product tree in memory.
    """
    parent, var, fcode, fslot, finput, fparam, eq_ptr, slot = prog
    if n != 2 or n_z != 2 or fcode.shape[0] > 0:
        return False
    for k in range(CUBIC2):
        dense[k] = 0.0
    for i in range(2):
        for p in range(eq_ptr[i], eq_ptr[i + 1]):
            q, a, c = slot[p], 0, 0  # the powers of x0 and x1 of the term, by the product tree
            while q > n_z:
                a += var[q] == 0
                c += var[q] == 1
                q = parent[q]
            a += q == 1
            c += q == 2
            d = a + c
            if d > 3:
                return False
            dense[10 * i + d * (d + 1) // 2 + c] += vals[p]
    for i in range(2):  # per equation: quadratic terms, cubic terms with x0^2, with x1^2 present
        for k in range(3, 10):
            dense[20 + 3 * i + (0 if k < 6 else (1 if k < 8 else 2))] += dense[10 * i + k] != 0.0
    return True


@jit(_nrt=False, inline="always")
def _cubic2_rhs(p, q, c, o, quadratic, cubic_p, cubic_q):
    """One equation of a :func:`cubic2_coefficients` model (coefficients ``c[o : o + 10]``): its
    quadratic terms and its cubic terms with ``x0^2`` and with ``x1^2`` only where present (the same
    branches at every call), in nested form."""
    value = c[o] + (c[o + 1] * p + c[o + 2] * q)
    if quadratic:
        value += p * (c[o + 3] * p + c[o + 4] * q) + c[o + 5] * (q * q)
    if cubic_p:
        value += (p * p) * (c[o + 6] * p + c[o + 7] * q)
    if cubic_q:
        value += (q * q) * (c[o + 8] * p + c[o + 9] * q)
    return value


@jit(_nrt=False)
def rk4_interval_cubic2(x, t, s, substeps, c):
    """:func:`.integrators._rk4_interval` for a two-state cubic model (``c``: :func:`cubic2_coefficients`)."""
    h = (t[s] - t[s - 1]) / substeps
    a0, b0, d0 = c[20] != 0.0, c[21] != 0.0, c[22] != 0.0
    a1, b1, d1 = c[23] != 0.0, c[24] != 0.0, c[25] != 0.0
    p, q = x[0], x[1]
    for _ in range(substeps):
        k1p, k1q = _cubic2_rhs(p, q, c, 0, a0, b0, d0), _cubic2_rhs(p, q, c, 10, a1, b1, d1)
        y0, y1 = p + 0.5 * h * k1p, q + 0.5 * h * k1q
        k2p, k2q = _cubic2_rhs(y0, y1, c, 0, a0, b0, d0), _cubic2_rhs(y0, y1, c, 10, a1, b1, d1)
        y0, y1 = p + 0.5 * h * k2p, q + 0.5 * h * k2q
        k3p, k3q = _cubic2_rhs(y0, y1, c, 0, a0, b0, d0), _cubic2_rhs(y0, y1, c, 10, a1, b1, d1)
        y0, y1 = p + h * k3p, q + h * k3q
        k4p, k4q = _cubic2_rhs(y0, y1, c, 0, a0, b0, d0), _cubic2_rhs(y0, y1, c, 10, a1, b1, d1)
        p += h / 6.0 * (((k1p + 2.0 * k2p) + 2.0 * k3p) + k4p)
        q += h / 6.0 * (((k1q + 2.0 * k2q) + 2.0 * k3q) + k4q)
    x[0], x[1] = p, q

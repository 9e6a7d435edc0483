"""The two-state polynomial model of degree <= 3 (the paper's, every mode of ``identify_modes``) integrated
with its monomials in registers.

The general kernel (:mod:`.integrators`) evaluates a model's terms through its product tree in memory,
which costs 4-6x a hand-written RK4 of the same model. For two states and a cubic library the ten
monomials of each equation are few enough to write out: :func:`dense_coefficients` turns a batch of
coefficient matrices into dense rows (per equation: 1, x0, x1, x0^2, x0 x1, x1^2, x0^3, x0^2 x1, x0 x1^2,
x1^3) and flags of the parts present, in numpy; :func:`rk4_interval_cubic2` steps a model, computing the
quadratic and cubic parts only where present. :func:`integrate_cubic2` is the kernel of these models (and
of linear two-state ones, by their propagator): :func:`.integrators.integrate`'s loop
(:func:`.integrators.segment_loop`) around this step, without the product tree, so that it compiles fast
(1.2 s; the general kernel takes 1.1 s more): the first fit of the paper's case after installation waits
for it and TVRegDiff's kernels only.

Measured (``benchmarks/speed/speed.py``, a 4-term Duffing model, 401 samples, 5 sub-steps): 1.25-1.3x a
minimal hand-written numba RK4, against 4-6x through the product tree. Its results equal RK4 on the model's
equations to rounding (``tests/test_simulation.py``), not bit for bit the product tree's (the sums run in
another order).
"""

from __future__ import annotations

import numpy as np

from .._utils.jit import jit, kernel
from .integrators import segment_loop
from .terms import PLAIN, TermTable

__all__ = ["CUBIC2", "dense_coefficients", "dense_positions", "is_cubic2", "integrate_cubic2"]

#: Length of a model's dense row: ten coefficients per equation, then per equation whether it has quadratic
#: terms, cubic terms with ``x0^2``, cubic terms with ``x1^2`` (non-zero if so).
CUBIC2 = 26


def is_cubic2(terms: TermTable, n_states: int) -> bool:
    """Whether a model's active terms are a two-state polynomial of degree <= 3 without inputs (the models
    :func:`rk4_interval_cubic2` steps)."""
    return (
        n_states == 2
        and terms.n_inputs == 2
        and bool(np.all(terms.func == PLAIN))
        and bool(np.all(terms.powers.sum(axis=1) <= 3))
    )


def dense_positions(terms: TermTable) -> np.ndarray:
    """Position of each term of a :func:`is_cubic2` model in an equation's dense row.

    Examples
    --------
    >>> dense_positions(TermTable.polynomial([[0, 1], [1, 0], [3, 0], [1, 2]])).tolist()
    [2, 1, 6, 8]
    """
    degree = terms.powers.sum(axis=1)
    return (degree * (degree + 1) // 2 + terms.powers[:, 1]).astype(np.int64)


def dense_coefficients(coefs: np.ndarray, positions: np.ndarray) -> np.ndarray:
    """Dense rows (n_models, :data:`CUBIC2`) of a batch of active-coefficient matrices (n_models, 2,
    n_terms) whose terms sit at ``positions`` (:func:`dense_positions`)."""
    dense = np.zeros((coefs.shape[0], CUBIC2))
    for i in range(2):
        dense[:, 10 * i + positions] = coefs[:, i, :]
        present = dense[:, 10 * i : 10 * i + 10] != 0.0
        dense[:, 20 + 3 * i] = present[:, 3:6].any(axis=1)
        dense[:, 21 + 3 * i] = present[:, 6:8].any(axis=1)
        dense[:, 22 + 3 * i] = present[:, 8:10].any(axis=1)
    return dense


@jit(_nrt=False)
def _cubic2_rhs(p, q, c, o, quadratic, cubic_p, cubic_q):
    """One equation of a :func:`dense_coefficients` row (coefficients ``c[o : o + 10]``): its
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
def rk4_interval_cubic2(x, t, s, substeps, dense, b):
    """:func:`.integrators._rk4_interval` for two-state cubic models: model ``b`` of the rows ``dense`` of
    :func:`dense_coefficients`."""
    c = dense[b]
    h = (t[s] - t[s - 1]) / substeps
    a0, b0, d0 = c[20] != 0.0, c[21] != 0.0, c[22] != 0.0
    a1, b1, d1 = c[23] != 0.0, c[24] != 0.0, c[25] != 0.0
    p, q = x[0], x[1]
    for _ in range(substeps):
        y0, y1, acc0, acc1 = p, q, 0.0, 0.0
        for stage in range(4):  # the classical stages: weights 1, 2, 2, 1; steps h/2, h/2, h
            k0, k1 = _cubic2_rhs(y0, y1, c, 0, a0, b0, d0), _cubic2_rhs(y0, y1, c, 10, a1, b1, d1)
            weight = 1.0 if (stage == 0 or stage == 3) else 2.0
            acc0, acc1 = acc0 + weight * k0, acc1 + weight * k1
            step = h if stage == 2 else 0.5 * h
            y0, y1 = p + step * k0, q + step * k1
        p, q = p + h / 6.0 * acc0, q + h / 6.0 * acc1
    x[0], x[1] = p, q


_integrate_dense = segment_loop(rk4_interval_cubic2)


@kernel
def integrate_cubic2(ref, t, starts, weights, substeps, props, dense, bound, work, out, errors, rows):
    """:func:`.integrators.integrate` for two-state cubic models: model ``b`` is stepped by its propagator
    ``props[b]`` if ``props`` is not empty (a linear model), else by its dense row ``dense[b]``
    (:func:`rk4_interval_cubic2`). The loop of ``integrate`` (:func:`.integrators.segment_loop`:
    segments; the same propagator step and the same accounting of divergence, stored trajectory or
    weighted error) around this step only, without the general model's code so that it compiles fast (see
    the module). ``work`` holds at least 4 floats.
    """
    n_models = max(props.shape[0], dense.shape[0])
    x, x_old = work[0:2], work[2:4]
    _integrate_dense(
        ref, t, starts, weights, substeps, n_models, dense, props, bound, x, x_old, out, errors, rows
    )

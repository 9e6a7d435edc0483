"""A sparse model as the kernels read it: a product tree of monomials, compressed coefficient rows and,
for a linear model, its RK4 propagator (see :mod:`.integrators`).

:func:`build_program` runs once per model (it depends on the active terms only); :func:`pack` once per
batch of coefficient matrices (only their non-zero entries are kept); :func:`propagators` when the model
is linear and the time grid uniform; :func:`term_values` evaluates the terms at many points in numpy.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .integrators import NO_PROPAGATOR
from .terms import PLAIN, TermTable

__all__ = ["Program", "build_program", "pack", "propagators", "term_values", "uniform_step"]


@dataclass(frozen=True)
class Program:
    """The terms of a model as evaluation instructions.

    Attributes
    ----------
    parent, var : ndarray of int (n_monomials,)
        Monomial ``q`` is monomial ``parent[q]`` times input ``var[q]``; slot 0 is the constant 1, slots
        1 to ``n_inputs`` the inputs (states, then control inputs) themselves.
    fcode, fslot, finput : ndarray of int (n_functions,)
        Non-polynomial term ``f``: code (see :mod:`.terms`), monomial slot it multiplies, its input.
    fparam : ndarray of float (n_functions,)
    term_slot : ndarray of int (n_terms,)
        Where each term's value is found (monomials first, then the non-polynomial terms).
    linear_state : ndarray of int (n_terms,) or None
        For a linear model without inputs: the state of each term (-1 for the constant); else None.
    """

    parent: np.ndarray
    var: np.ndarray
    fcode: np.ndarray
    fslot: np.ndarray
    finput: np.ndarray
    fparam: np.ndarray
    term_slot: np.ndarray
    linear_state: np.ndarray | None

    @property
    def n_values(self) -> int:
        """Number of term values the kernels hold (monomial slots plus non-polynomial terms)."""
        return self.parent.shape[0] + self.fcode.shape[0]


def _i64(values) -> np.ndarray:
    return np.ascontiguousarray(np.asarray(values, dtype=np.int64).reshape(-1))


def build_program(terms: TermTable, n_states: int) -> Program:
    """The evaluation instructions of ``terms`` (the model's active terms) over ``n_states`` states.

    Examples
    --------
    >>> program = build_program(TermTable.polynomial([[1, 0], [2, 1], [3, 0]]), 2)
    >>> program.parent.tolist(), program.var.tolist()   # 1, x0, x1, x0^2, x0^2 x1, x0^3
    ([0, 0, 0, 1, 3, 3], [0, 0, 1, 0, 1, 0])
    >>> program.term_slot.tolist()
    [1, 4, 5]
    """
    n_z = terms.n_inputs
    slots = {(): 0, **{(j,): 1 + j for j in range(n_z)}}  # the inputs themselves: slots 1 .. n_z
    parent, var = [0] * (1 + n_z), [0, *range(n_z)]

    def monomial(powers) -> int:
        factors = tuple(j for j, p in enumerate(powers) for _ in range(p))
        for d in range(1, len(factors) + 1):
            if factors[:d] not in slots:
                slots[factors[:d]] = len(parent)
                parent.append(slots[factors[: d - 1]])
                var.append(factors[d - 1])
        return slots[factors]

    mono_slot = [monomial(row) for row in terms.powers.tolist()]  # plain ints: no numpy scalars
    functions = np.flatnonzero(terms.func != PLAIN)
    n_mono = len(parent)
    term_slot = np.array(mono_slot, dtype=np.int64)
    term_slot[functions] = n_mono + np.arange(functions.size)
    linear = (
        terms.n_inputs == n_states
        and bool(np.all(terms.func == PLAIN))
        and bool(np.all(terms.powers.sum(axis=1) <= 1))
    )
    linear_state = None
    if linear:
        linear_state = np.where(terms.powers.sum(axis=1) == 1, np.argmax(terms.powers, axis=1), -1)
    return Program(
        _i64(parent),
        _i64(var),
        _i64(terms.func[functions]),
        _i64(np.asarray(mono_slot, dtype=np.int64)[functions]),
        _i64(terms.func_state[functions]),
        np.ascontiguousarray(terms.func_param[functions], dtype=float),
        term_slot,
        None if linear_state is None else _i64(linear_state),
    )


_FACTORS = {
    1: lambda z, p: z * np.abs(z),
    2: lambda z, p: np.tanh(z / p),
    3: lambda z, p: np.abs(z),
    4: lambda z, p: np.sin(p * z),
    5: lambda z, p: np.cos(p * z),
}


def term_values(program: Program, Z: np.ndarray) -> np.ndarray:
    """The terms at the points ``Z`` (n_points, n_inputs), by the product tree: (n_points, n_terms).

    Numpy, vectorized over the points (the right-hand side at many points, e.g. ``predict``, and the
    Jacobian probes need no compiled kernel).
    """
    n_mono, n_z = program.parent.shape[0], Z.shape[1]
    theta = np.empty((Z.shape[0], program.n_values))
    theta[:, 0] = 1.0
    theta[:, 1 : 1 + n_z] = Z
    for q in range(1 + n_z, n_mono):
        np.multiply(theta[:, program.parent[q]], Z[:, program.var[q]], out=theta[:, q])
    for f, code in enumerate(program.fcode):
        g = _FACTORS[int(code)](Z[:, program.finput[f]], program.fparam[f])
        np.multiply(theta[:, program.fslot[f]], g, out=theta[:, n_mono + f])
    return theta[:, program.term_slot]


def pack(program: Program, coefs: np.ndarray) -> tuple[tuple, np.ndarray]:
    """The kernel program and the coefficient values of a batch ``coefs`` (n_models, n_states, n_terms).

    Only entries non-zero in some model of the batch are kept, in compressed rows per equation.
    """
    nonzero = np.any(coefs != 0, axis=0)
    eq_ptr = np.concatenate([[0], np.cumsum(nonzero.sum(axis=1))])
    slot = np.broadcast_to(program.term_slot, nonzero.shape)[nonzero]
    prog = (
        program.parent,
        program.var,
        program.fcode,
        program.fslot,
        program.finput,
        program.fparam,
        _i64(eq_ptr),
        _i64(slot),
    )
    return prog, np.ascontiguousarray(coefs[:, nonzero], dtype=float)


def uniform_step(t: np.ndarray) -> float | None:
    """The grid's step if ``t`` is uniform (to 1e-9 relative), else None."""
    if t.shape[0] < 2:
        return None
    steps = np.diff(t)
    mean = (t[-1] - t[0]) / (t.shape[0] - 1)
    return float(mean) if mean > 0 and np.max(np.abs(steps - mean)) <= 1e-9 * mean else None


def propagators(program: Program, coefs: np.ndarray, dt: float | None, substeps: int) -> np.ndarray:
    """RK4's map over one interval of a uniform grid of step ``dt``, per model of the batch ``coefs``.

    ``M = P(h A)^substeps`` with ``P(z) = 1 + z + z^2/2 + z^3/6 + z^4/24`` (an extra row and column carry
    a constant term). :data:`~.integrators.NO_PROPAGATOR` when the model is not linear or the grid not
    uniform (``dt`` None).
    """
    if dt is None or program.linear_state is None:
        return NO_PROPAGATOR
    n_models, n = coefs.shape[0], coefs.shape[1]
    constant = program.linear_state < 0
    m = n + 1 if constant.any() and np.any(coefs[:, :, constant]) else n
    A = np.zeros((n_models, m, m))
    for k, j in enumerate(program.linear_state.tolist()):
        if j >= 0 or m > n:
            A[:, :n, n if j < 0 else j] += coefs[:, :, k]
    hA = A * (dt / substeps)
    eye = np.eye(m)  # broadcast by the additions: the same values as a stacked identity, not built
    P = eye + hA @ (eye + hA @ (eye + hA @ (eye + hA / 4.0) / 3.0) / 2.0)
    return np.ascontiguousarray(np.linalg.matrix_power(P, int(substeps)))

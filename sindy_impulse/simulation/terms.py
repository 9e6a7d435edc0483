"""The simulator's description of library terms (what a compiled model evaluates).

Every term the compiled simulator supports is ``prod_j z_j**powers[j] * g(z_v)``, a monomial of the inputs
``z`` (the states followed by the control inputs, if any) times one of a few scalar functions of one input
``v``:

=====  =====================  ==================================================
code   g(z_v)                 used for
=====  =====================  ==================================================
0      1                      polynomial terms
1      z_v * |z_v|            quadratic (velocity-squared) damping
2      tanh(z_v / width)      smooth sign: Coulomb-like friction
3      |z_v|                  amplitude-proportional terms, e.g. ``|x| v``
4      sin(p * z_v)           Fourier terms
5      cos(p * z_v)           Fourier terms
=====  =====================  ==================================================

Libraries describe themselves in these terms (see
:func:`sindy_impulse.feature_library.term_table`); anything else is simulated by the general fallback.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["TermTable", "PLAIN", "SIGNED_SQUARE", "SMOOTH_SIGN", "ABS", "SIN", "COS"]

PLAIN, SIGNED_SQUARE, SMOOTH_SIGN, ABS, SIN, COS = 0, 1, 2, 3, 4, 5


@dataclass(frozen=True)
class TermTable:
    """Terms of a feature library as arrays (one row per library feature).

    Attributes
    ----------
    powers : ndarray of int, shape (n_features, n_inputs)
        Exponent of each input (states, then control inputs) in the monomial factor.
    func : ndarray of int, shape (n_features,)
        Code of the extra scalar factor (``PLAIN``, ``SIGNED_SQUARE``, ``SMOOTH_SIGN``, ``ABS``, ``SIN``,
        ``COS``).
    func_state : ndarray of int, shape (n_features,)
        The input the extra factor acts on.
    func_param : ndarray of float, shape (n_features,)
        Its parameter (the width of the smooth sign, the frequency of a Fourier term).

    Examples
    --------
    >>> table = TermTable.polynomial([[1, 0], [0, 1], [3, 0]])
    >>> table.evaluate(np.array([[2.0, 3.0]])).tolist()
    [[2.0, 3.0, 8.0]]
    """

    powers: np.ndarray
    func: np.ndarray
    func_state: np.ndarray
    func_param: np.ndarray

    @classmethod
    def polynomial(cls, powers) -> TermTable:
        """Monomials only: one row of exponents per term."""
        powers = np.ascontiguousarray(powers, dtype=np.int64)
        n = powers.shape[0]
        return cls(powers, np.zeros(n, np.int64), np.zeros(n, np.int64), np.ones(n))

    @classmethod
    def concatenate(cls, tables) -> TermTable:
        """The terms of several tables over the same inputs, in order."""
        tables = list(tables)
        return cls(
            np.ascontiguousarray(np.vstack([t.powers for t in tables]), dtype=np.int64),
            np.concatenate([t.func for t in tables]).astype(np.int64),
            np.concatenate([t.func_state for t in tables]).astype(np.int64),
            np.concatenate([t.func_param for t in tables]).astype(float),
        )

    @property
    def linear(self) -> np.ndarray:
        """Mask of the terms that are a constant or one input itself (no product, no extra factor).

        >>> TermTable.polynomial([[0, 0], [1, 0], [0, 1], [1, 1]]).linear.tolist()
        [True, True, True, False]
        """
        return (self.func == PLAIN) & (self.powers.sum(axis=1) <= 1)

    @property
    def n_features(self) -> int:
        return self.powers.shape[0]

    @property
    def n_inputs(self) -> int:
        """Number of inputs the terms act on (states plus control inputs)."""
        return self.powers.shape[1]

    def subset(self, columns) -> TermTable:
        """The table restricted to the given feature columns."""
        columns = np.asarray(columns, dtype=np.int64)
        return TermTable(
            np.ascontiguousarray(self.powers[columns]),
            np.ascontiguousarray(self.func[columns]),
            np.ascontiguousarray(self.func_state[columns]),
            np.ascontiguousarray(self.func_param[columns]),
        )

    def evaluate(self, z: np.ndarray) -> np.ndarray:
        """Evaluate all terms on inputs ``z`` of shape (n_samples, n_inputs) (numpy reference).

        Each monomial is the product of its factors taken one at a time in the order of the inputs (the
        order of PySINDy's ``PolynomialLibrary``, whose matrix this reproduces bit for bit), and the extra
        factors are evaluated for the terms that have one: a library matrix of thousands of rows costs tens
        of microseconds a column.
        """
        z = np.asarray(z, dtype=float)
        theta = np.ones((z.shape[0], self.n_features), order="F")  # contiguous columns to build
        for i, powers in enumerate(self.powers):
            factors = np.repeat(np.arange(powers.size), powers)
            if factors.size:
                column = theta[:, i]
                column[:] = z[:, factors[0]]
                for j in factors[1:]:
                    column *= z[:, j]
        for i in np.flatnonzero(self.func != PLAIN):
            theta[:, i] *= _extra(self.func[i], z[:, self.func_state[i]], self.func_param[i])
        return np.ascontiguousarray(theta)


def _extra(code: int, v: np.ndarray, p: float) -> np.ndarray:
    """The extra scalar factor of code ``code`` on input values ``v`` with parameter ``p``."""
    if code == SIGNED_SQUARE:
        return v * np.abs(v)
    if code == SMOOTH_SIGN:
        return np.tanh(v / p)
    if code == ABS:
        return np.abs(v)
    if code == SIN:
        return np.sin(p * v)
    if code == COS:
        return np.cos(p * v)
    raise ValueError(f"unknown term code {code}")

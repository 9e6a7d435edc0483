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
        """Evaluate all terms on inputs ``z`` of shape (n_samples, n_inputs) (numpy reference)."""
        z = np.asarray(z, dtype=float)
        theta = np.prod(z[:, None, :] ** self.powers[None, :, :], axis=2)
        zv = z[:, self.func_state]
        p = self.func_param
        extra = np.select(
            [
                self.func == SIGNED_SQUARE,
                self.func == SMOOTH_SIGN,
                self.func == ABS,
                self.func == SIN,
                self.func == COS,
            ],
            [zv * np.abs(zv), np.tanh(zv / p), np.abs(zv), np.sin(p * zv), np.cos(p * zv)],
            1.0,
        )
        return theta * extra

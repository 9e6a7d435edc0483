"""A compact description of library terms that the compiled simulator evaluates.

Every term the simulator supports is ``prod_j x_j**powers[j] * g(x_v)`` where ``g`` is one of a few
scalar functions of one state ``v``:

=====  ======================  ==========================================
code   g(x_v)                  use
=====  ======================  ==========================================
0      1                       polynomial terms
1      x_v * |x_v|             quadratic (velocity-squared) damping
2      tanh(x_v / width)       smooth sign: Coulomb-like friction
=====  ======================  ==========================================
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["TermTable", "term_table", "PLAIN", "SIGNED_SQUARE", "SMOOTH_SIGN"]

PLAIN, SIGNED_SQUARE, SMOOTH_SIGN = 0, 1, 2


@dataclass(frozen=True)
class TermTable:
    """Terms of a feature library as arrays (one row per library feature).

    Attributes
    ----------
    powers : ndarray of int, shape (n_features, n_states)
        Exponent of each state in the monomial factor.
    func : ndarray of int, shape (n_features,)
        Code of the extra scalar factor (``PLAIN``, ``SIGNED_SQUARE``, ``SMOOTH_SIGN``).
    func_state : ndarray of int, shape (n_features,)
        The state the extra factor acts on.
    func_param : ndarray of float, shape (n_features,)
        Its parameter (the width of the smooth sign).
    """

    powers: np.ndarray
    func: np.ndarray
    func_state: np.ndarray
    func_param: np.ndarray

    @classmethod
    def polynomial(cls, powers) -> TermTable:
        powers = np.ascontiguousarray(powers, dtype=np.int64)
        n = powers.shape[0]
        return cls(powers, np.zeros(n, np.int64), np.zeros(n, np.int64), np.ones(n))

    @property
    def n_features(self) -> int:
        return self.powers.shape[0]

    def subset(self, columns) -> TermTable:
        """The table restricted to the given feature columns."""
        columns = np.asarray(columns, dtype=np.int64)
        return TermTable(
            np.ascontiguousarray(self.powers[columns]),
            np.ascontiguousarray(self.func[columns]),
            np.ascontiguousarray(self.func_state[columns]),
            np.ascontiguousarray(self.func_param[columns]),
        )

    def evaluate(self, x: np.ndarray) -> np.ndarray:
        """Evaluate all terms on states ``x`` of shape (n_samples, n_states) (numpy reference)."""
        x = np.asarray(x, dtype=float)
        theta = np.prod(x[:, None, :] ** self.powers[None, :, :], axis=2)
        xv = x[:, self.func_state]
        extra = np.where(
            self.func == SIGNED_SQUARE,
            xv * np.abs(xv),
            np.where(self.func == SMOOTH_SIGN, np.tanh(xv / self.func_param), 1.0),
        )
        return theta * extra


def term_table(library, n_states: int) -> TermTable:
    """The :class:`TermTable` of a fitted feature library.

    Supports :class:`pysindy.PolynomialLibrary` and :class:`sindy_impulse.MechanicalLibrary`
    (anything with a ``term_table_`` attribute).

    Raises
    ------
    TypeError
        For a library whose terms the compiled simulator cannot evaluate.
    """
    table = getattr(library, "term_table_", None)
    if table is not None:
        return table
    powers = getattr(library, "powers_", None)
    if powers is not None and type(library).__name__ == "PolynomialLibrary":
        powers = np.asarray(powers)
        if powers.shape[1] != n_states:
            raise ValueError(f"library was fitted on {powers.shape[1]} states, data have {n_states}")
        return TermTable.polynomial(powers)
    raise TypeError(
        f"{type(library).__name__} is not supported by the compiled simulator; use "
        "pysindy.PolynomialLibrary or sindy_impulse.MechanicalLibrary"
    )

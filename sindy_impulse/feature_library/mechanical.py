"""MechanicalLibrary: polynomial terms plus the nonlinearities common in structures."""

from __future__ import annotations

from numbers import Integral, Real

import numpy as np
from pysindy.feature_library.base import BaseFeatureLibrary
from pysindy.utils import AxesArray
from sklearn.preprocessing import PolynomialFeatures
from sklearn.utils.validation import check_is_fitted

from .._params import Interval, validate_params
from .._trajectories import check_trajectories
from ..simulation.terms import PLAIN, SIGNED_SQUARE, SMOOTH_SIGN, TermTable

__all__ = ["MechanicalLibrary"]


class MechanicalLibrary(BaseFeatureLibrary):
    """Candidate terms for mechanical oscillators (a PySINDy feature library).

    Polynomial terms of the states up to ``degree`` plus, per state, the quadratic-damping term
    ``x|x|`` and a Coulomb-like friction term ``tanh(x / w)``, a smooth sign whose width ``w`` is
    ``friction_width`` times the state's largest absolute value in the fitted data (so the library
    does not depend on units).

    Parameters
    ----------
    degree : int, default=3
        Highest total degree of the polynomial terms.
    include_bias : bool, default=False
        Include the constant term ``1``.
    quadratic_damping : bool, default=True
        Include ``x_j|x_j|`` for each state.
    friction : bool, default=True
        Include ``tanh(x_j / w_j)`` for each state.
    friction_width : float, default=0.01
        Width of the smooth sign relative to the state's amplitude.

    Attributes
    ----------
    term_table_ : TermTable
        The terms as arrays, read by the compiled simulator.
    friction_scale_ : ndarray of shape (n_states,)
        Absolute width ``w_j`` of the smooth sign per state.

    Examples
    --------
    >>> import numpy as np
    >>> lib = MechanicalLibrary(degree=2).fit(np.random.default_rng(0).normal(size=(50, 2)))
    >>> lib.get_feature_names(["x", "v"])
    ['x', 'v', 'x^2', 'x v', 'v^2', 'x|x|', 'v|v|', 'sgn(x)', 'sgn(v)']
    """

    _parameter_constraints = {
        "degree": [Interval(Integral, 0, None, "left")],
        "include_bias": ["boolean"],
        "quadratic_damping": ["boolean"],
        "friction": ["boolean"],
        "friction_width": [Interval(Real, 0, None, "neither")],
    }

    def __init__(
        self,
        degree: int = 3,
        include_bias: bool = False,
        quadratic_damping: bool = True,
        friction: bool = True,
        friction_width: float = 0.01,
    ):
        self.degree = degree
        self.include_bias = include_bias
        self.quadratic_damping = quadratic_damping
        self.friction = friction
        self.friction_width = friction_width

    def fit(self, x, y=None):
        """Build the term table for data of shape (n_samples, n_states) (or a list of such).

        A 1-D array is refused (scikit-learn convention): pass one state as ``x.reshape(-1, 1)``.
        """
        validate_params(self)
        x_full, _ = _check_states(x)
        n_states = x_full[0].shape[-1]
        combos = PolynomialFeatures(degree=self.degree, include_bias=self.include_bias)
        combos.fit(np.zeros((1, n_states)))
        poly_powers = np.asarray(combos.powers_, dtype=np.int64)
        n_poly = poly_powers.shape[0]
        rows, func, state = [poly_powers], [np.full(n_poly, PLAIN)], [np.zeros(n_poly, np.int64)]
        param = [np.ones(n_poly)]
        amplitude = np.max([np.max(np.abs(np.asarray(xi)), axis=0) for xi in x_full], axis=0)
        amplitude = np.where(amplitude > 0, amplitude, 1.0)
        self.friction_scale_ = self.friction_width * amplitude
        for enabled, code in ((self.quadratic_damping, SIGNED_SQUARE), (self.friction, SMOOTH_SIGN)):
            if enabled:
                rows.append(np.zeros((n_states, n_states), np.int64))
                func.append(np.full(n_states, code))
                state.append(np.arange(n_states))
                param.append(self.friction_scale_ if code == SMOOTH_SIGN else np.ones(n_states))
        self.term_table_ = TermTable(
            np.ascontiguousarray(np.vstack(rows)),
            np.concatenate(func).astype(np.int64),
            np.concatenate(state).astype(np.int64),
            np.concatenate(param).astype(float),
        )
        self.n_features_in_ = n_states
        self.n_output_features_ = self.term_table_.n_features
        return self

    def transform(self, x):
        """Evaluate the terms on data of shape (n_samples, n_states) (or a list of such)."""
        check_is_fitted(self, "term_table_")
        x_full, multiple = _check_states(x)
        out = []
        for xi in x_full:
            if xi.shape[-1] != self.n_features_in_:
                raise ValueError(
                    f"X has {xi.shape[-1]} features, but MechanicalLibrary is expecting "
                    f"{self.n_features_in_} features as input (x has {xi.shape[-1]} states, the library "
                    f"was fitted on {self.n_features_in_})"
                )
            out.append(AxesArray(self.term_table_.evaluate(xi), {"ax_time": 0, "ax_coord": 1}))
        return out if multiple else out[0]

    def get_feature_names(self, input_features=None) -> list[str]:
        """Readable names: ``x^2 v``, ``v|v|``, ``sgn(v)``."""
        check_is_fitted(self, "term_table_")
        table = self.term_table_
        if input_features is None:
            input_features = [f"x{i}" for i in range(self.n_features_in_)]
        names = []
        for p, f, v in zip(table.powers, table.func, table.func_state):
            parts = [
                name if e == 1 else f"{name}^{e}" for name, e in zip(input_features, p) if e > 0
            ]
            if f == SIGNED_SQUARE:
                parts.append(f"{input_features[v]}|{input_features[v]}|")
            elif f == SMOOTH_SIGN:
                parts.append(f"sgn({input_features[v]})")
            names.append(" ".join(parts) if parts else "1")
        return names


def _check_states(x):
    """``check_trajectories`` without its 1-D convenience: a library sees (n_samples, n_states) arrays."""
    trajectories, multiple = check_trajectories(x, "x")
    for i, raw in enumerate(x if multiple else [x]):
        if np.asarray(raw).ndim == 1:
            name, shape = (f"x[{i}]" if multiple else "x"), np.asarray(raw).shape
            raise ValueError(
                f"{name} must be 2-D (n_samples, n_states), got an array of shape {shape}; Reshape your data "
                f"with {name}.reshape(-1, 1) for a single state"
            )
    return trajectories, multiple

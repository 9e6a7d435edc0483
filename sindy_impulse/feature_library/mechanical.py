"""MechanicalLibrary: the terms a vibrating structure's nonlinearity is made of, compiled for simulation."""

from __future__ import annotations

from numbers import Integral, Real

import numpy as np
from pysindy.feature_library.base import BaseFeatureLibrary
from pysindy.utils import AxesArray
from sklearn.preprocessing import PolynomialFeatures
from sklearn.utils.validation import check_is_fitted

from .._utils.params import Interval, Options, validate_params
from .._utils.trajectories import check_trajectories
from ..simulation.terms import ABS, SIGNED_SQUARE, SMOOTH_SIGN, TermTable

__all__ = ["MechanicalLibrary"]


class MechanicalLibrary(BaseFeatureLibrary):
    """Candidate terms for mechanical oscillators (a PySINDy feature library).

    Four families of terms of the states ``x_j``, each switched on by a parameter:

    ==================  ======================  ===================================================
    family              terms                   for a single mode with states ``(x, v)``
    ==================  ======================  ===================================================
    polynomial          monomials to degree     ``x``, ``v``; ``x^3`` a Duffing spring (frequency
                                                ~ ``a^2``), ``x^2 v`` and ``v^3`` damping ~ ``a^2``
    quadratic_damping   ``x_j|x_j|``            ``v|v|`` drag (damping ~ ``a``), ``x|x|`` a spring
                                                stiffening ~ ``a``
    amplitude_damping   ``|x_j| v_k``, j != k   ``|x| v`` damping ~ ``a`` (joints, microslip)
    friction            ``tanh(v_k / w_k)``     ``sgn(v)`` Coulomb friction (damping ~ ``1/a``)
    ==================  ======================  ===================================================

    (``a`` is the vibration amplitude; "damping ~ a^2" means the damping ratio grows with ``a^2``.) With
    ``odd=True`` (the default) only the polynomial terms of odd total degree are kept: they, like every
    other family, change sign with the state, the symmetry of a structure vibrating about its equilibrium,
    and they are the ones that change a mode's frequency and damping with amplitude (even terms such as
    ``x^2`` or ``x v`` shift the mean and add harmonics; set ``odd=False`` for a gap or a preload).

    ``v_k`` are the states named by ``velocities``: friction is a force against the velocity, and an
    amplitude-dependent damper a velocity times a magnitude. By default (``"auto"``) two states are taken
    as ``(x, v)`` and every state counts as a velocity otherwise. The defaults give 10 terms for ``(x, v)``:
    ``x, v, x^3, x^2 v, x v^2, v^3, x|x|, v|v|, |x| v, sgn(v)`` (``x v^2`` describes a Duffing spring
    measured by an accelerometer).

    The smooth sign's width ``w_j`` is ``friction_width`` times the state's largest absolute value in the
    fitted data, so the library does not depend on units. Every term is a monomial times one scalar
    function of one state (:mod:`sindy_impulse.simulation.terms`): models over this library run in the
    compiled simulator (``term_table_``).

    Parameters
    ----------
    degree : int, default=3
        Highest total degree of the polynomial terms.
    include_bias : bool, default=False
        Include the constant term ``1``.
    odd : bool, default=True
        Keep only the polynomial terms of odd total degree.
    quadratic_damping : bool, default=True
        Include ``x_j|x_j|`` for each state.
    amplitude_damping : bool, default=True
        Include ``|x_j| v_k`` for each velocity ``v_k`` and each other state ``x_j``.
    friction : bool, default=True
        Include ``tanh(v_k / w_k)`` for each velocity.
    velocities : "auto", None or list of int, default="auto"
        The states that are velocities: ``"auto"`` is the second of two states, every state otherwise;
        None is every state.
    friction_width : float, default=0.01
        Width of the smooth sign relative to the state's amplitude.

    Attributes
    ----------
    term_table_ : TermTable
        The terms as arrays, read by the compiled simulator.
    friction_scale_ : ndarray of shape (n_states,)
        Absolute width ``w_j`` of the smooth sign per state.
    velocities_ : ndarray of int
        The velocity states.

    Examples
    --------
    >>> import numpy as np
    >>> lib = MechanicalLibrary().fit(np.random.default_rng(0).normal(size=(50, 2)))
    >>> lib.get_feature_names(["x", "v"])
    ['x', 'v', 'x^3', 'x^2 v', 'x v^2', 'v^3', 'x|x|', 'v|v|', '|x| v', 'sgn(v)']
    >>> MechanicalLibrary(degree=1, velocities=None).fit(np.ones((3, 2))).get_feature_names(["x", "v"])
    ['x', 'v', 'x|x|', 'v|v|', '|v| x', '|x| v', 'sgn(x)', 'sgn(v)']
    >>> MechanicalLibrary(degree=2, odd=False, amplitude_damping=False, friction=False).fit(
    ...     np.ones((3, 2))).get_feature_names(["x", "v"])
    ['x', 'v', 'x^2', 'x v', 'v^2', 'x|x|', 'v|v|']
    """

    _parameter_constraints = {
        "degree": [Interval(Integral, 0, None, "left")],
        "include_bias": ["boolean"],
        "odd": ["boolean"],
        "quadratic_damping": ["boolean"],
        "amplitude_damping": ["boolean"],
        "friction": ["boolean"],
        "friction_width": [Interval(Real, 0, None, "neither")],
        "velocities": [Options({"auto"}), None, "array-like"],
    }

    def __init__(
        self,
        degree: int = 3,
        include_bias: bool = False,
        odd: bool = True,
        quadratic_damping: bool = True,
        amplitude_damping: bool = True,
        friction: bool = True,
        friction_width: float = 0.01,
        velocities="auto",
    ):
        self.degree = degree
        self.include_bias = include_bias
        self.odd = odd
        self.quadratic_damping = quadratic_damping
        self.amplitude_damping = amplitude_damping
        self.friction = friction
        self.friction_width = friction_width
        self.velocities = velocities

    def fit(self, x, y=None):
        """Build the term table for data of shape (n_samples, n_states) (or a list of such).

        A 1-D array is refused (scikit-learn convention): pass one state as ``x.reshape(-1, 1)``.
        """
        validate_params(self)
        x_full, _ = _check_states(x)
        n = x_full[0].shape[-1]
        amplitude = np.max([np.max(np.abs(np.asarray(xi)), axis=0) for xi in x_full], axis=0)
        self.friction_scale_ = self.friction_width * np.where(amplitude > 0, amplitude, 1.0)
        self.velocities_ = velocity = _velocities(self.velocities, n)
        tables = [self._polynomials(n)]
        eye = np.eye(n, dtype=np.int64)
        if self.quadratic_damping:
            tables.append(_table(np.zeros((n, n), np.int64), SIGNED_SQUARE, np.arange(n), np.ones(n)))
        pairs = [(j, k) for k in velocity for j in range(n) if j != k]
        if self.amplitude_damping and pairs:
            j, k = np.array(pairs).T
            tables.append(_table(eye[k], ABS, j, np.ones(len(pairs))))
        if self.friction:
            zeros = np.zeros((velocity.size, n), np.int64)
            tables.append(_table(zeros, SMOOTH_SIGN, velocity, self.friction_scale_[velocity]))
        self.term_table_ = TermTable.concatenate(tables)
        if self.term_table_.n_features == 0:
            raise ValueError(
                "MechanicalLibrary has no terms: raise degree, set include_bias or enable a family of terms"
            )
        self.n_features_in_ = n
        self.n_output_features_ = self.term_table_.n_features
        return self

    def _polynomials(self, n: int) -> TermTable:
        if self.degree == 0 and not self.include_bias:
            return TermTable.polynomial(np.zeros((0, n), np.int64))
        combos = PolynomialFeatures(degree=self.degree, include_bias=self.include_bias)
        powers = np.asarray(combos.fit(np.zeros((1, n))).powers_, dtype=np.int64)
        degree = powers.sum(axis=1)
        if self.odd:
            powers = powers[(degree % 2 == 1) | (degree == 0)]
        return TermTable.polynomial(powers.reshape(-1, n))

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
        """Readable names: ``x^2 v``, ``v|v|``, ``|x| v``, ``sgn(v)``."""
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
            elif f == ABS:
                parts.insert(0, f"|{input_features[v]}|")
            names.append(" ".join(parts) if parts else "1")
        return names


def _velocities(spec, n: int) -> np.ndarray:
    """The velocity states: ``"auto"`` (the second of two, else all), None (all) or the given indices."""
    if isinstance(spec, str):
        return np.array([1]) if n == 2 else np.arange(n)
    if spec is None:
        return np.arange(n)
    idx = np.asarray(spec)
    integers = idx.ndim == 1 and idx.size > 0 and np.issubdtype(idx.dtype, np.integer)
    if not integers or np.any(idx < 0) or np.any(idx >= n):
        raise ValueError(f"velocities must be state indices in [0, {n - 1}], got {spec!r}")
    return np.unique(idx.astype(np.int64))


def _table(powers, code: int, state, param) -> TermTable:
    """Terms ``monomial(powers) * g_code(x_state)`` with parameter ``param`` (one row each)."""
    n = len(state)
    return TermTable(
        np.ascontiguousarray(np.asarray(powers, np.int64).reshape(n, -1)),
        np.full(n, code, np.int64),
        np.asarray(state, np.int64),
        np.asarray(param, float),
    )


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

"""Which terms follow a control parameter (paper section 3.3.1, Figure 11).

Models reconstructed along a control parameter (e.g. the damping) are compared coefficient by
coefficient with a reference model: ``ratio = xi / xi_ref`` (the quantity of Figure 11) and the relative
change ``ratio - 1``. A term varies when its relative change exceeds ``threshold`` (1 %) somewhere along
the parameter; a term that appears or vanishes (zero in exactly one of the two models) always varies.
Beyond the paper, the elasticity ``d ln|xi| / d ln p`` (slope of a log-log fit, where the coefficient and
the parameter are non-zero) tells how a varying term scales with the parameter: 1 for a coefficient
proportional to it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._utils.validation import check_array
from .consensus import coefficient_stack

__all__ = ["parameter_dependency", "ParameterDependency"]


@dataclass
class ParameterDependency:
    """Coefficients along a control parameter, relative to a reference model.

    Attributes
    ----------
    values : ndarray (n_models,)
        Control parameter of each model (sorted ascending; the other arrays follow this order).
    reference_index : int
        Index (in ``values``) of the reference model.
    coefficients : ndarray (n_models, n_states, n_features)
    ratio : ndarray (n_models, n_states, n_features)
        ``xi / xi_ref``; 1 where both are zero, ``inf`` (signed) where only the reference is zero.
    relative_change : ndarray (n_models, n_states, n_features)
        ``ratio - 1`` (0 where both are zero; ``inf`` where only the reference is zero, -1 where only the
        model is).
    max_change : ndarray (n_states, n_features)
        Largest ``|relative_change|`` along the parameter.
    varies : ndarray of bool (n_states, n_features)
        ``max_change > threshold``.
    elasticity : ndarray (n_states, n_features)
        Slope of ``ln|xi|`` against ``ln|p|`` (NaN where not defined).
    threshold : float
    feature_names, state_names : list of str
    """

    values: np.ndarray
    reference_index: int
    coefficients: np.ndarray
    ratio: np.ndarray
    relative_change: np.ndarray
    max_change: np.ndarray
    varies: np.ndarray
    elasticity: np.ndarray
    threshold: float
    feature_names: list[str]
    state_names: list[str]

    def names(self) -> np.ndarray:
        """Coefficient names ``"x1' : x0"`` as an array (n_states, n_features)."""
        return np.array([[f"{s}' : {f}" for f in self.feature_names] for s in self.state_names], dtype=object)

    @property
    def varying_terms(self) -> list[str]:
        """Names of the coefficients that vary with the parameter."""
        return [str(n) for n in self.names()[self.varies]]

    @property
    def invariant_terms(self) -> list[str]:
        """Names of the coefficients that are non-zero in the reference and do not vary."""
        ref = self.coefficients[self.reference_index] != 0
        return [str(n) for n in self.names()[ref & ~self.varies]]

    def __repr__(self) -> str:
        return (
            f"ParameterDependency(n_models={len(self.values)}, "
            f"reference={float(self.values[self.reference_index])!r}, "
            f"threshold={self.threshold}, varying={self.varying_terms}, invariant={self.invariant_terms})"
        )


def parameter_dependency(
    models,
    values,
    reference=None,
    *,
    threshold: float = 0.01,
    feature_names=None,
) -> ParameterDependency:
    """Relative change of every coefficient against a reference model along a control parameter.

    Parameters
    ----------
    models : list of fitted estimators, or array (n_models, n_states, n_features)
        One model per control parameter value, all with the same library.
    values : array-like (n_models,)
        The control parameter of each model.
    reference : float, optional
        The parameter value of the reference model (must be one of ``values``). Default: the value
        closest to the median.
    threshold : float, default=0.01
        Relative change above which a term counts as varying.
    feature_names : list of str, optional
        Term names when ``models`` is an array.

    Returns
    -------
    ParameterDependency

    Examples
    --------
    >>> import pysindy as ps
    >>> from sindy_impulse import ImpulseSINDy, damped_oscillator
    >>> from sindy_impulse.analysis import parameter_dependency
    >>> deltas = [0.15, 0.2, 0.25]
    >>> models = [ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=1))
    ...           .fit(damped_oscillator(c=2 * d * 8).x, t=0.01) for d in deltas]
    >>> dep = parameter_dependency(models, deltas, reference=0.2)
    >>> dep.varying_terms
    ["x1' : x1"]
    """
    stack, names, states, _ = coefficient_stack(models, feature_names)
    vals = check_array(values, "values")
    if vals.ndim != 1 or vals.size != stack.shape[0]:
        raise ValueError(
            f"values must be 1-D with one value per model ({stack.shape[0]}), got shape {vals.shape}"
        )
    if isinstance(threshold, bool) or not (isinstance(threshold, (int, float, np.number)) and threshold >= 0):
        raise ValueError(f"threshold must be a non-negative number, got {threshold!r}")
    order = np.argsort(vals, kind="stable")
    vals, stack = vals[order], stack[order]
    if reference is None:
        ref = int(np.argmin(np.abs(vals - np.median(vals))))
    else:
        matches = np.flatnonzero(np.isclose(vals, float(reference), rtol=1e-9, atol=1e-12))
        if matches.size == 0:
            raise ValueError(f"reference {reference!r} is not one of the values {vals.tolist()}")
        ref = int(matches[0])
    xi_ref = stack[ref]
    both_zero = (stack == 0) & (xi_ref == 0)[None]
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(
            xi_ref[None] != 0,
            stack / np.where(xi_ref == 0, 1.0, xi_ref)[None],
            np.sign(stack) * np.inf,
        )
    ratio = np.where(both_zero, 1.0, ratio)
    change = ratio - 1.0
    max_change = np.max(np.abs(change), axis=0)
    varies = max_change > threshold

    elasticity = np.full(xi_ref.shape, np.nan)
    for i in range(xi_ref.shape[0]):
        for k in range(xi_ref.shape[1]):
            ok = (stack[:, i, k] != 0) & (vals != 0)
            if ok.sum() >= 2 and np.ptp(np.log(np.abs(vals[ok]))) > 0:
                elasticity[i, k] = np.polyfit(np.log(np.abs(vals[ok])), np.log(np.abs(stack[ok, i, k])), 1)[0]
    return ParameterDependency(
        values=vals,
        reference_index=ref,
        coefficients=stack,
        ratio=ratio,
        relative_change=change,
        max_change=max_change,
        varies=varies,
        elasticity=elasticity,
        threshold=float(threshold),
        feature_names=list(names),
        state_names=list(states),
    )

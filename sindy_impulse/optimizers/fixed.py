"""FixedCoefficients: a model whose coefficients come from elsewhere, carried as a PySINDy optimizer.

The modal survey identifies a linear mode's equation ``dy' = -k y - c dy`` from the poles of its free decay
(:mod:`sindy_impulse.poles.decay_fit`: ``k = |s|^2``, ``c = 2 sigma``), not by regression. The mode's model is
still an :class:`~sindy_impulse.ImpulseSINDy` fitted on the mode's states, so that simulation, backbones,
diagnostics and every analysis work on it as on any other: its optimizer is this one, which hands back the
given coefficients instead of solving the regression.
"""

from __future__ import annotations

import numpy as np
from pysindy.optimizers import BaseOptimizer

__all__ = ["FixedCoefficients"]


class FixedCoefficients(BaseOptimizer):
    """A PySINDy optimizer whose fit returns ``coefficients`` (one row per state, one column per library
    term) whatever the data.

    Parameters
    ----------
    coefficients : array-like (n_targets, n_features)
        The model's coefficients, in the library's column order.

    Examples
    --------
    >>> import pysindy as ps
    >>> from sindy_impulse import ImpulseSINDy
    >>> t = np.arange(400) * 0.01
    >>> y = np.exp(-0.2 * t) * np.cos(2 * t)  # y'' + 0.4 y' + 4.04 y = 0
    >>> x = np.column_stack([y, -0.2 * y - 2 * np.exp(-0.2 * t) * np.sin(2 * t)])
    >>> model = ImpulseSINDy(optimizer=FixedCoefficients([[0.0, 1.0], [-4.04, -0.4]]),
    ...                      feature_library=ps.PolynomialLibrary(degree=1, include_bias=False),
    ...                      sweep=False, refine=False).fit(x, t=t, feature_names=["y", "dy"])
    >>> model.coefficients().tolist()
    [[0.0, 1.0], [-4.04, -0.4]]
    """

    def __init__(self, coefficients=None):
        super().__init__(unbias=False)
        self.coefficients = coefficients

    def fit(self, x_, y, sample_weight=None, **reduce_kws):
        """Hand back the coefficients (checked against the library's shape): no regression is solved, so
        none of the base class's scaling or least squares is done."""
        x = np.asarray(x_, dtype=float)
        y = np.asarray(y, dtype=float)
        y = y.reshape(-1, 1) if y.ndim == 1 else y
        keep = np.all(np.isfinite(x), axis=1) & np.all(np.isfinite(y), axis=1)
        self.iters = 0
        self.Theta_ = x[keep]
        self._reduce(x, y)
        self.ind_ = np.abs(self.coef_) > 1e-14
        return self

    def _reduce(self, x, y, **kwargs):
        coef = np.atleast_2d(np.asarray(self.coefficients, dtype=float))
        want = (np.shape(y)[1] if np.ndim(y) == 2 else 1, np.shape(x)[1])
        if coef.shape != want:
            raise ValueError(f"FixedCoefficients: coefficients of shape {coef.shape} do not match the "
                             f"library's (n_targets, n_features) = {want}")
        self.coef_ = coef.copy()
        self.history_ = [self.coef_]

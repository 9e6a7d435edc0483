"""Least squares whose columns differ by many orders of magnitude, solved and inverted scaled.

A mode's amplitude beside its decay rate and frequency, a weak component's pole beside a strong
neighbour's amplitude, a squared amplitude's integral in a record's units squared: the columns of such a
Jacobian or design differ by many orders, and unscaled, a pseudo-inverse or a least-squares cut-off drops
the small ones' directions as round-off and reports them as known exactly. Every such problem of the
package is scaled here, its columns to unit norm, and its covariance brought back to the parameters'
units: the answer does not depend on the data's units.
"""

from __future__ import annotations

import numpy as np

__all__ = ["scaled_normal", "scaled_covariance"]


def scaled_normal(jac: np.ndarray, scaled: bool = False) -> tuple:
    """The normal matrix of ``jac`` with its columns scaled to unit norm, and the scales; with ``scaled``,
    the scaled ``jac`` too.

    Examples
    --------
    >>> jac = np.array([[1.0, 1e-9], [1.0, 2e-9], [1.0, 3e-9]])
    >>> normal, scale = scaled_normal(jac)
    >>> np.diag(normal).round(12).tolist(), (scale * [1.0, 1e9]).round(4).tolist()  # the columns' norms
    ([1.0, 1.0], [1.7321, 3.7417])
    """
    scale = np.sqrt(np.einsum("ij,ij->j", jac, jac))
    scale[scale == 0] = 1.0
    columns = jac / scale
    normal = columns.T @ columns
    return (normal, scale, columns) if scaled else (normal, scale)


def scaled_covariance(normal: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """The inverse of a scaled normal matrix (:func:`scaled_normal`) in the parameters' own units, for unit
    residual variance: the pseudo-inverse of ``normal`` divided by the outer product of the scales.

    Examples
    --------
    A straight line's intercept and a slope in units a billion times smaller (the slope's variance is a
    billion squared times larger, not dropped):

    >>> x = np.arange(10.0)
    >>> cov = scaled_covariance(*scaled_normal(np.column_stack([np.ones(10), 1e-9 * x])))
    >>> float(np.sqrt(cov[1, 1]) * 1e-9).__round__(4)
    0.1101
    """
    return np.linalg.pinv(normal) / np.outer(scale, scale)

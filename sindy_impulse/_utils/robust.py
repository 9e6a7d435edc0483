"""The robust standard deviation every noise estimate of the package uses: the median absolute deviation
from the median, scaled to a Gaussian's standard deviation (:data:`MAD_TO_STD`). Unlike the plain standard
deviation it is not moved by an offset, by a few spikes or by the onset of a hit inside the stretch.
"""

from __future__ import annotations

import numpy as np

__all__ = ["MAD_TO_STD", "robust_std"]

#: The median absolute deviation of a Gaussian times this is its standard deviation (1 / Phi^-1(3/4)).
MAD_TO_STD = 1.4826


def robust_std(x, axis: int | None = None, centre=None):
    """Robust standard deviation of ``x``: :data:`MAD_TO_STD` times its median absolute deviation from its
    median (along ``axis``; a float for ``axis=None``). ``centre``: that median when the caller already has
    it (it is not computed again).

    Examples
    --------
    >>> round(robust_std(np.r_[np.random.default_rng(0).normal(0, 2, 10_000), 1e6]), 1)
    2.0
    """
    x = np.asarray(x, float)
    if centre is None:
        centre = np.median(x, axis=axis)
    if axis is not None:
        centre = np.expand_dims(centre, axis)
    spread = MAD_TO_STD * np.median(np.abs(x - centre), axis=axis)
    return float(spread) if axis is None else spread

"""Saturated stretches of a record: runs of samples at its extremes (a sensor or ADC at its limit).

The data-quality checks (:mod:`.quality`), the end of the hammer contact (:mod:`.contact`) and the repair of
clipped ring-downs (:mod:`.pipeline`) read them.
"""

from __future__ import annotations

from numbers import Integral

import numpy as np

from .._utils.params import Interval, check_param
from ._record import check_signal_1d

__all__ = ["clipping_mask", "runs"]


def runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """``(first, last)`` index of every run of True in ``mask``.

    Examples
    --------
    >>> runs(np.array([0, 1, 1, 0, 1], bool))
    [(1, 2), (4, 4)]
    """
    edges = np.diff(np.concatenate(([0], mask.astype(np.int8), [0])))
    return [(int(a), int(b)) for a, b in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1)]


def clipping_mask(y, *, min_run: int = 3) -> np.ndarray:
    """Samples in runs of at least ``min_run`` equal to the record's maximum or minimum (saturation).

    Examples
    --------
    >>> y = np.clip(np.sin(np.arange(100) / 5), -2, 0.9)
    >>> mask = clipping_mask(y)
    >>> int(mask.sum()), bool(clipping_mask(np.sin(np.arange(100) / 5)).any())
    (13, False)
    >>> bool(clipping_mask(np.ones(50)).any())  # constant: no signal, not saturation
    False
    """
    arr = check_signal_1d(y, "y", 1)
    check_param("min_run", min_run, [Interval(Integral, 2, None)], "clipping_mask")
    mask = np.zeros(arr.size, bool)
    if np.ptp(arr) == 0:  # a constant record has no extremes to saturate at (it has no signal at all)
        return mask
    tol = 1e-12 * np.ptp(arr)
    for at_extreme in (arr >= arr.max() - tol, arr <= arr.min() + tol):
        for first, last in runs(at_extreme):
            if last - first + 1 >= min_run:
                mask[first : last + 1] = True
    return mask

"""The one place a differentiation method is applied to trajectories.

Every caller that needs derivatives and filtered states -- the estimator's fit, the test for nonlinearity,
the diagnostics -- calls :func:`differentiate`, so they all see the data exactly as the fit did.
"""

from __future__ import annotations

import warnings

import numpy as np
import pysindy as ps
from pysindy.utils import AxesArray

from ..exceptions import DataWarning

__all__ = ["differentiate"]


def _for_short_records(method, trajectories, stacklevel: int):
    """``method``, or PySINDy's finite differences (with a DataWarning) when a trajectory is shorter than
    ``method`` needs (plain PySINDy mode accepts what PySINDy accepts)."""
    needed = getattr(method, "_min_samples", None)
    shortest = min(x.shape[0] for x in trajectories)
    if needed is None or shortest >= needed():
        return method
    warnings.warn(
        f"{shortest} samples are too few for {type(method).__name__} (it needs {needed()}): the derivatives "
        "are PySINDy's finite differences, unfiltered; use a longer record",
        DataWarning,
        stacklevel=stacklevel + 1,
    )
    return ps.FiniteDifference()


def differentiate(
    method, trajectories, times, short_fallback: bool = False, stacklevel: int = 4
) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Filtered states and derivatives of each trajectory.

    Parameters
    ----------
    method : PySINDy differentiation method
        Called as ``method(x, t)``; its ``smoothed_x_`` (if it sets one) are the filtered states, as in
        PySINDy and the paper's section 2.3 (the time-integrated regularized derivative).
    trajectories : list of ndarray (n_i, n_states)
    times : list of ndarray (n_i,)
    short_fallback : bool, default=False
        Use finite differences, with a warning, when a trajectory is too short for ``method`` (instead of
        its ValueError): plain PySINDy mode.
    stacklevel : int, default=4
        Where that warning points: 4 is the caller of a method that calls a function that calls this one
        (the user's ``fit``).

    Returns
    -------
    (filtered, derivatives) : lists of ndarray (n_i, n_states)
        Derivatives may hold NaN rows at the ends (trimmed samples).

    Examples
    --------
    >>> from sindy_impulse.differentiation import TVRegDiff
    >>> from sindy_impulse.datasets import damped_oscillator
    >>> t, x, _ = damped_oscillator(snr_db=30, random_state=0)
    >>> filtered, derivs = differentiate(TVRegDiff(), [x], [t])
    >>> filtered[0].shape, derivs[0].shape
    ((401, 2), (401, 2))
    """
    if short_fallback:
        method = _for_short_records(method, trajectories, stacklevel=stacklevel)
    filtered, derivs = [], []
    for xi, ti in zip(trajectories, times):
        d = np.asarray(method(AxesArray(xi, {"ax_time": 0, "ax_coord": 1}), ti), dtype=float)
        smoothed = getattr(method, "smoothed_x_", None)
        filtered.append(
            xi.copy() if smoothed is None else np.asarray(smoothed, dtype=float).reshape(xi.shape)
        )
        derivs.append(d.reshape(xi.shape))
    return filtered, derivs

"""The one place a differentiation method is applied to trajectories.

Every caller that needs derivatives and filtered states -- the estimator's fit, the test for nonlinearity,
the diagnostics -- calls :func:`differentiate`, so they all see the data exactly as the fit did.
"""

from __future__ import annotations

import numpy as np
from pysindy.utils import AxesArray

__all__ = ["differentiate"]


def differentiate(method, trajectories, times) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Filtered states and derivatives of each trajectory.

    Parameters
    ----------
    method : PySINDy differentiation method
        Called as ``method(x, t)``; its ``smoothed_x_`` (if it sets one) are the filtered states, as in
        PySINDy and the paper's section 2.3 (the time-integrated regularized derivative).
    trajectories : list of ndarray (n_i, n_states)
    times : list of ndarray (n_i,)

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
    filtered, derivs = [], []
    for xi, ti in zip(trajectories, times):
        d = np.asarray(method(AxesArray(xi, {"ax_time": 0, "ax_coord": 1}), ti), dtype=float)
        smoothed = getattr(method, "smoothed_x_", None)
        filtered.append(
            xi.copy() if smoothed is None else np.asarray(smoothed, dtype=float).reshape(xi.shape)
        )
        derivs.append(d.reshape(xi.shape))
    return filtered, derivs

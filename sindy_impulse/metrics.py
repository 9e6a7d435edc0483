"""Time-series comparison measures (paper section 2.4 and 3.1)."""

from __future__ import annotations

import numpy as np

from ._validation import check_signal

__all__ = ["gamma", "gamma_from_arrays"]


def gamma_from_arrays(x_true: np.ndarray, x_recon: np.ndarray, scale: np.ndarray | None = None) -> float:
    """Gamma on validated float arrays of equal shape (the unchecked fast path).

    A reconstruction with any non-finite value gives ``inf``.
    """
    if scale is None:
        scale = np.max(np.abs(x_true), axis=0)
        scale = np.where(scale > 0, scale, 1.0)
    value = float(np.sum(np.abs(x_true - x_recon) / scale))
    return value if np.isfinite(value) else np.inf


def gamma(x_true, x_recon) -> float:
    """The paper's reconstruction error Gamma (section 3.1).

    ``Gamma = sum_i sum_j |x_true_i(t_j) - x_recon_i(t_j)| / max_j |x_true_i(t_j)|``, summed over states
    ``i`` and samples ``j``: each state normalized by its largest absolute value, so that deflection and
    velocity weigh the same. A state that is identically zero is not normalized. A reconstruction that
    is non-finite anywhere (a diverged simulation) gives ``inf``. Lists of trajectories are summed.

    Parameters
    ----------
    x_true, x_recon : array-like of shape (n_samples,) or (n_samples, n_states), or lists of them
        The measured (or filtered) states and the simulated model states.

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> x = np.array([[1.0, 0.0], [0.5, -2.0]])
    >>> gamma(x, x)
    0.0
    >>> gamma(x, x + [0.1, 0.2])
    0.4
    """
    if isinstance(x_true, (list, tuple)) and x_true and hasattr(x_true[0], "shape"):
        if not isinstance(x_recon, (list, tuple)) or len(x_recon) != len(x_true):
            raise ValueError("x_recon must be a list with one reconstruction per trajectory in x_true")
        return float(sum(gamma(a, b) for a, b in zip(x_true, x_recon)))
    xt = check_signal(x_true, "x_true")
    # a diverged reconstruction (NaN/inf) is valid input: its Gamma is inf
    xr = check_signal(x_recon, "x_recon", allow_nan=True, allow_inf=True)
    if xr.shape != xt.shape:
        raise ValueError(f"x_recon has shape {xr.shape} but x_true has shape {xt.shape}")
    return gamma_from_arrays(xt, xr)

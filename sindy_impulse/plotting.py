"""One function per kind of figure in the paper. Each takes fitted objects (or their attributes) and an
optional matplotlib ``Axes``, returns the ``Axes`` (or ``Figure``), and never calls ``plt.show()``."""

from __future__ import annotations

import numpy as np

__all__ = ["plot_reconstruction"]


def _axes(ax=None, nrows: int = 1, **subplot_kw):
    import matplotlib.pyplot as plt

    if ax is not None:
        return ax
    fig, ax = plt.subplots(nrows, 1, sharex=True, squeeze=False, figsize=(7, 2.2 * nrows), **subplot_kw)
    return ax[:, 0] if nrows > 1 else ax[0, 0]


def plot_reconstruction(model, x=None, t=None, ax=None, state_names=None):
    """Input vs reconstruction (the paper's Figures 6b, 8a, 8d): one panel per state.

    Parameters
    ----------
    model : fitted ImpulseSINDy
    x, t : arrays, optional
        The input states and times; default: the model's filtered states ``x_filtered_`` and ``t_``
        (first trajectory if several).
    ax : sequence of Axes, optional
        One per state.
    state_names : list of str, optional

    Returns
    -------
    ndarray of Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sindy_impulse import ImpulseSINDy, damped_oscillator
    >>> t, x, _ = damped_oscillator()
    >>> axes = plot_reconstruction(ImpulseSINDy().fit(x, t=t))
    >>> len(axes)
    2
    """
    if x is None:
        x = model.x_filtered_[0] if isinstance(model.x_filtered_, list) else model.x_filtered_
        t = model.t_[0] if isinstance(model.t_, list) else model.t_
    x = np.asarray(x, dtype=float)
    x = x[:, None] if x.ndim == 1 else x
    if t is None:
        raise ValueError("t is required when x is given")
    t = np.asarray(t, dtype=float)
    recon = model.simulate(x[0], t)
    n = x.shape[1]
    axes = np.atleast_1d(_axes(ax, nrows=n))
    if len(axes) != n:
        raise ValueError(f"ax has {len(axes)} axes for {n} states")
    names = state_names or getattr(model, "feature_names_", None) or [f"x{i}" for i in range(n)]
    for i, a in enumerate(axes):
        a.plot(t, x[:, i], color="0.6", lw=2.5, label="input")
        a.plot(t, recon[:, i], color="C3", lw=1.2, ls="--", label="reconstruction")
        a.set_ylabel(names[i])
    axes[0].set_title(f"Gamma = {model.gamma_:.3g}" if np.isfinite(getattr(model, "gamma_", np.nan)) else "")
    axes[0].legend(loc="upper right", frameon=False)
    axes[-1].set_xlabel("t")
    return axes

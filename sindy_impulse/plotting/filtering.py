"""Figures of the differentiation step: the alpha-selection curve (Figure 7a) and the filtered signal
(Figures 7b and A1)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .._utils.validation import check_signal, check_time, time_vector
from ._common import (
    MARK_STYLE,
    check_choice,
    check_int,
    first,
    fitted_sindy,
    is_tvregdiff,
    many_axes,
    one_axes,
    resolve_state_names,
)

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["plot_alpha_curve", "plot_filtering"]

_CRITERIA = ("error", "gcv", "consistency", "residual", "dof")


# ----------------------------------------------------------------------------------------------------------
# Figure 7a: alpha selection
# ----------------------------------------------------------------------------------------------------------
def _fitted_tvregdiff(obj):
    """The fitted TVRegDiff of ``obj`` (itself, or an ImpulseSINDy's ``differentiation_method_``)."""
    est = obj
    if hasattr(est, "coefficients") and hasattr(est, "differentiation_method"):  # an ImpulseSINDy
        if not hasattr(est, "differentiation_method_"):
            raise ValueError("tvregdiff_or_model is not fitted (no differentiation_method_): call fit first")
        est = est.differentiation_method_
        if not hasattr(est, "alpha_curve_"):
            raise TypeError(
                f"the model's differentiation method is a {type(est).__name__}, not a TVRegDiff: it has no "
                "alpha curve"
            )
    elif not hasattr(est, "alpha_curve_") and not is_tvregdiff(est):
        raise TypeError(
            f"tvregdiff_or_model must be a TVRegDiff or an ImpulseSINDy, got {type(est).__name__}"
        )
    if not hasattr(est, "alpha_curve_"):
        raise ValueError("tvregdiff_or_model is not fitted (no alpha_curve_): call fit first")
    return est


def plot_alpha_curve(tvregdiff_or_model, column: int = 0, criterion: str = "error", ax=None) -> Axes:
    """The alpha-selection criterion over alpha, the chosen alpha marked (the paper's Figure 7a).

    Parameters
    ----------
    tvregdiff_or_model : fitted TVRegDiff, or fitted ImpulseSINDy
        A :class:`~sindy_impulse.TVRegDiff` run with ``alpha="auto"`` (its ``alpha_curve_``), or an
        ImpulseSINDy whose ``differentiation_method_`` is one.
    column : int, default=0
        The state (column) whose curve is drawn.
    criterion : {"error", "gcv", "consistency", "residual", "dof"}, default="error"
        The curve: ``"error"`` is the criterion that chose alpha (``alpha_selection``); ``"consistency"``
        is the paper's RMS difference between the input and the time-integrated derivative.
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib Axes
        ``ax`` (or a new one): the curve, the chosen alpha as a point and as a vertical line.

    Raises
    ------
    TypeError
        Not a TVRegDiff or an ImpulseSINDy differentiated by one.
    ValueError
        Not fitted, ``column`` out of range, unknown ``criterion``, or no curve (alpha was given, or the
        column is constant).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sindy_impulse import ImpulseSINDy, damped_oscillator
    >>> from sindy_impulse.plotting import plot_alpha_curve
    >>> ring_down = damped_oscillator(snr_db=30, random_state=0)
    >>> model = ImpulseSINDy().fit(ring_down.x, t=ring_down.t)
    >>> ax = plot_alpha_curve(model, column=0, criterion="consistency")
    >>> ax.get_xscale()
    'log'
    """
    est = _fitted_tvregdiff(tvregdiff_or_model)
    column = check_int(column, "column", 0, len(est.alpha_curve_))
    criterion = check_choice(criterion, "criterion", _CRITERIA)
    curve = est.alpha_curve_[column]
    alphas = np.asarray(curve["alpha"], dtype=float)
    values = np.asarray(curve[criterion], dtype=float)
    if alphas.size == 0:
        raise ValueError(
            f"column {column} has no alpha curve: alpha was given (not 'auto') or the column is constant"
        )
    chosen = float(np.asarray(est.alpha_)[column])
    ax = one_axes(ax)
    ax.plot(alphas, values, "o-", color="C0", ms=3, lw=1.2, label=criterion)
    ax.set_xscale("log")
    if np.all(values[np.isfinite(values)] > 0):
        ax.set_yscale("log")
    ax.axvline(chosen, **MARK_STYLE)
    near = int(np.argmin(np.abs(np.log(alphas) - np.log(chosen)))) if chosen > 0 else 0
    ax.plot([chosen], [values[near]], "o", color="C3", ms=7, label=f"alpha = {chosen:.3g}")
    selection = getattr(est, "alpha_selection", "")
    label = f"{criterion} ({selection})" if criterion == "error" and selection else criterion
    ax.set_xlabel("alpha")
    ax.set_ylabel(label)
    ax.legend(loc="best", frameon=False)
    return ax


# ----------------------------------------------------------------------------------------------------------
# Figure 7b / A1: filtering
# ----------------------------------------------------------------------------------------------------------
def _filtered_signal(filtered):
    """``(signal, time or None)`` of ``filtered``: an array, a fitted ImpulseSINDy or a fitted TVRegDiff."""
    if hasattr(filtered, "coefficients"):  # ImpulseSINDy
        fitted_sindy(filtered, "filtered")
        return first(filtered.x_filtered_), first(filtered.t_)
    if hasattr(filtered, "alpha_curve_") or is_tvregdiff(filtered):
        if not hasattr(filtered, "smoothed_x_"):
            raise ValueError("filtered is an unfitted TVRegDiff (no smoothed_x_): differentiate first")
        return filtered.smoothed_x_, None
    return filtered, None


def _like_x(values, name: str, x: np.ndarray) -> np.ndarray:
    """``values`` checked as a signal of the same shape as ``x``."""
    arr = check_signal(values, name)
    if arr.shape != x.shape:
        raise ValueError(f"{name} has shape {arr.shape} but x has shape {x.shape}")
    return arr


def plot_filtering(x, filtered, t=None, ax=None, *, clean=None, state_names=None) -> np.ndarray:
    """Input against filtered signal, one panel per state (the paper's Figures 7b and A1).

    Parameters
    ----------
    x : array-like (n_samples,) or (n_samples, n_states)
        The input (noisy) signal ``s_n``.
    filtered : array-like like ``x``, fitted ImpulseSINDy or fitted TVRegDiff
        The filtered signal ``s_f`` (time integral of the regularized derivative): an array, a model's
        ``x_filtered_`` (first trajectory if several) or a TVRegDiff's ``smoothed_x_``.
    t : float or array (n_samples,), optional
        Time step or vector; default: the model's ``t_`` when ``filtered`` is a model, else samples.
    ax : Axes or sequence of Axes, optional
        One per state.
    clean : array-like like ``x``, optional
        The clean signal ``s_c`` (Figure A1), drawn as a thin black line.
    state_names : list of str, optional

    Returns
    -------
    ndarray of Axes
        One per state: the input, the clean signal (if given) and the filtered signal.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sindy_impulse import TVRegDiff, damped_oscillator
    >>> from sindy_impulse.plotting import plot_filtering
    >>> clean = damped_oscillator()
    >>> noisy = damped_oscillator(snr_db=20, random_state=0)
    >>> diff = TVRegDiff()
    >>> _ = diff(noisy.x, noisy.t)
    >>> axes = plot_filtering(noisy.x, diff, noisy.t, clean=clean.x)
    >>> len(axes), len(axes[0].lines)
    (2, 3)
    """
    filtered, model_t = _filtered_signal(filtered)
    x = check_signal(x, "x")
    f = _like_x(filtered, "filtered", x)
    c = None if clean is None else _like_x(clean, "clean", x)
    n, n_states = x.shape
    if t is None and model_t is not None:
        t = model_t
    time = np.arange(n, dtype=float) if t is None else time_vector(check_time(t, n), n)
    names = resolve_state_names(None, n_states, state_names)
    axes = many_axes(ax, n_states, sharex=True)
    for i, a in enumerate(axes):
        a.plot(time, x[:, i], color="0.65", lw=1.0, label="input")
        if c is not None:
            a.plot(time, c[:, i], color="k", lw=0.8, label="clean")
        a.plot(time, f[:, i], color="C3", lw=1.3, label="filtered")
        a.set_ylabel(names[i])
    axes[0].legend(loc="upper right", frameon=False)
    axes[-1].set_xlabel("t" if t is not None else "sample")
    return axes

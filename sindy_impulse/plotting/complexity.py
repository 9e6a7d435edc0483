"""Figure of the complexity-error plane: Gamma against the number of terms, Pareto front marked
(Figure 10b)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ._common import check_choice, one_axes, positive, scatter_groups

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["plot_complexity_error"]


def plot_complexity_error(result, ax=None, *, color_by: str = "estimator", metric: str = "gamma") -> Axes:
    """Gamma against the number of terms, one color per label, the Pareto front marked (Figure 10b).

    Failed fits and diverged models (non-finite Gamma) are left out; their count is given in the title.

    Parameters
    ----------
    result : ComplexityError
        From :func:`sindy_impulse.analysis.complexity_error`.
    ax : matplotlib Axes, optional
    color_by : {"estimator", "input"}, default="estimator"
        Color the points by ``estimator_label`` (e.g. the polynomial degree) or ``input_label``.
    metric : {"gamma", "gamma_filtered", "gamma_sindy"}, default="gamma"

    Returns
    -------
    matplotlib Axes
        ``ax`` (or a new one): one scatter per label in ``ax.collections``, then the Pareto front line.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import pysindy as ps
    >>> from sindy_impulse import ImpulseSINDy, damped_oscillator
    >>> from sindy_impulse.analysis import complexity_error
    >>> from sindy_impulse.plotting import plot_complexity_error
    >>> x = damped_oscillator(snr_db=30, random_state=0).x
    >>> estimators = {p: ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=p)) for p in (1, 2)}
    >>> result = complexity_error(estimators, {"x": x}, t=0.01)
    >>> ax = plot_complexity_error(result)
    >>> len(ax.collections)  # one per degree
    2
    """
    if not (hasattr(result, "pareto_front") and hasattr(result, "n_terms")):
        raise TypeError(f"result must be a ComplexityError, got {type(result).__name__}")
    color_by = check_choice(color_by, "color_by", ("estimator", "input"))
    metric = check_choice(metric, "metric", ("gamma", "gamma_filtered", "gamma_sindy"))
    err = np.asarray(getattr(result, metric), dtype=float)
    terms = np.asarray(result.n_terms)
    labels = np.asarray(getattr(result, f"{color_by}_label"))
    ok = np.asarray(result.succeeded) & np.isfinite(err) & (terms >= 0)
    if not ok.any():
        raise ValueError(f"result has no successful model with a finite {metric}: nothing to plot")
    y = positive(err)
    ax = one_axes(ax)
    groups = dict.fromkeys(labels.tolist())
    scatter_groups(ax, terms, y, labels, groups, ok, lambda lab: f"{color_by} {lab}", s=28, alpha=0.8)
    front = result.pareto_front(metric)
    ax.plot(terms[front], y[front], "s--", color="k", mfc="none", ms=9, lw=0.8, label="Pareto front")
    ax.set_yscale("log")
    ax.set_xlabel("number of terms")
    ax.set_ylabel(metric.replace("gamma", "Gamma"))
    left_out = int((~ok).sum())
    if left_out:
        ax.set_title(f"{left_out} failed or diverged model(s) not shown")
    ax.legend(loc="best", frameon=False, fontsize="small")
    return ax

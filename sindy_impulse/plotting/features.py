"""Figure of the feature space: a 2-D projection of the SINDy features, one color per label (Figure 14b)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .._utils.validation import check_array
from ._common import one_axes, scatter_groups

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["plot_feature_space"]


def plot_feature_space(
    features_2d, labels=None, ax=None, *, axis_names: tuple[str, str] = ("PC1", "PC2")
) -> Axes:
    """2-D scatter of a feature space, one color per label or cluster (the paper's Figure 14b).

    Rows with NaN (e.g. failed reconstructions of :class:`~sindy_impulse.SINDyFeatures`, which the paper
    discards) are left out; their count is given in the title.

    Parameters
    ----------
    features_2d : array-like (n_samples, 2)
        E.g. ``PCA(n_components=2).fit_transform(SINDyFeatures().fit_transform(X))``.
    labels : array-like (n_samples,), optional
        Class or cluster of each row: one scatter (and legend entry) per distinct label.
    ax : matplotlib Axes, optional
    axis_names : pair of str, default=("PC1", "PC2")

    Returns
    -------
    matplotlib Axes
        ``ax`` (or a new one) with one scatter per distinct label in ``ax.collections``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np
    >>> from sindy_impulse.plotting import plot_feature_space
    >>> points = np.random.default_rng(0).standard_normal((20, 2))
    >>> ax = plot_feature_space(points, labels=["linear"] * 10 + ["Duffing"] * 10)
    >>> len(ax.collections)
    2
    """
    f = check_array(features_2d, "features_2d", ndim=(2,), allow_nan=True)
    if f.shape[1] != 2:
        raise ValueError(
            f"features_2d must have 2 columns, got shape {f.shape}; reduce the features first, e.g. with "
            "sklearn.decomposition.PCA(n_components=2)"
        )
    if labels is None:
        lab = np.zeros(f.shape[0], dtype=int)
    else:
        if hasattr(labels, "to_numpy"):
            labels = labels.to_numpy()
        lab = np.asarray(labels)
        if lab.ndim != 1 or lab.shape[0] != f.shape[0]:
            raise ValueError(
                f"labels must be 1-D with one label per row of features_2d ({f.shape[0]}), "
                f"got shape {lab.shape}"
            )
    keep = ~np.isnan(f).any(axis=1)
    if not keep.any():
        raise ValueError("features_2d has no row without NaN: nothing to plot")
    ax = one_axes(ax)
    groups = dict.fromkeys(lab[keep].tolist())
    legend = (lambda value: None) if labels is None else str
    scatter_groups(ax, f[:, 0], f[:, 1], lab, groups, keep, legend, s=22, alpha=0.85)
    ax.set_xlabel(str(axis_names[0]))
    ax.set_ylabel(str(axis_names[1]))
    if (~keep).any():
        ax.set_title(f"{int((~keep).sum())} row(s) with NaN not shown")
    if labels is not None:
        ax.legend(loc="best", frameon=False)
    return ax

"""Figures of model identification across records: the dependency of the coefficients on a control
parameter (Figure 11), the consensus of many models (Figure 12) and linear against nonlinear (Figure 13)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .._utils.validation import check_array, check_signal, check_time, time_vector
from . import _common as common

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["plot_consensus", "plot_linear_vs_nonlinear", "plot_parameter_dependency"]


# ----------------------------------------------------------------------------------------------------------
# Figure 11: parameter dependency
# ----------------------------------------------------------------------------------------------------------
def plot_parameter_dependency(result, ax=None, *, quantity: str = "ratio") -> Axes:
    """Each coefficient relative to the reference model over the control parameter (Figure 11).

    Coefficients that vary (``result.varies``) are drawn in color and named in the legend, invariant ones
    in grey. Coefficients that are zero in the reference model (infinite ratio) are left out.

    Parameters
    ----------
    result : ParameterDependency
        From :func:`sindy_impulse.analysis.parameter_dependency`.
    ax : matplotlib Axes, optional
    quantity : {"ratio", "relative_change"}, default="ratio"
        ``xi / xi_ref`` or ``xi / xi_ref - 1`` (the paper's relative deviation).

    Returns
    -------
    matplotlib Axes
        ``ax`` (or a new one): one line per coefficient shown, the level 1 (or 0), the reference.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np
    >>> from sindy_impulse.analysis import parameter_dependency
    >>> from sindy_impulse.plotting import plot_parameter_dependency
    >>> coef = np.array([[[0, 1.0], [-64.0, -2.4]], [[0, 1.0], [-64.0, -3.2]], [[0, 1.0], [-64.0, -4.0]]])
    >>> dep = parameter_dependency(coef, [0.15, 0.2, 0.25], reference=0.2, feature_names=["x0", "x1"])
    >>> ax = plot_parameter_dependency(dep)
    >>> len(ax.lines)  # 3 coefficients, the reference and the level 1
    5
    """
    if not all(hasattr(result, a) for a in ("values", "ratio", "varies", "reference_index")):
        raise TypeError(f"result must be a ParameterDependency, got {type(result).__name__}")
    quantity = common.check_choice(quantity, "quantity", ("ratio", "relative_change"))
    values = check_array(result.values, "result.values", ndim=(1,))
    data = check_array(
        getattr(result, quantity), f"result.{quantity}", ndim=(3,), allow_inf=True, allow_nan=True
    )
    if data.shape[0] != values.size:
        raise ValueError(f"result.{quantity} has {data.shape[0]} models but result.values has {values.size}")
    varies = np.asarray(result.varies, dtype=bool)
    ref = int(result.reference_index)
    coefficients = np.asarray(result.coefficients, dtype=float)
    shown = np.any(coefficients != 0, axis=0) & (coefficients[ref] != 0)
    names = result.names() if hasattr(result, "names") else None
    ax = common.one_axes(ax)
    j = 0
    for i, k in zip(*np.nonzero(shown)):
        y = np.where(np.isfinite(data[:, i, k]), data[:, i, k], np.nan)
        name = str(names[i, k]) if names is not None else f"xi[{i},{k}]"
        if varies[i, k]:
            ax.plot(values, y, "o-", color=f"C{j % 10}", ms=4, lw=1.4, label=name)
            j += 1
        else:
            ax.plot(values, y, "-", color="0.6", lw=1.0, label="_invariant")
    ax.axhline(1.0 if quantity == "ratio" else 0.0, color="0.3", lw=0.8, ls="--")
    ax.axvline(values[ref], **common.MARK_STYLE)
    ax.set_xlabel("control parameter")
    ax.set_ylabel("xi / xi_ref" if quantity == "ratio" else "xi / xi_ref - 1")
    ax.set_title(f"reference = {values[ref]:g}; {int((shown & ~varies).sum())} invariant term(s) in grey")
    if j:
        ax.legend(loc="best", frameon=False, fontsize="small")
    return ax


# ----------------------------------------------------------------------------------------------------------
# Figure 12: consensus histograms
# ----------------------------------------------------------------------------------------------------------
def plot_consensus(result, axes=None, *, true_coefficients=None) -> np.ndarray:
    """Histograms of the non-zero coefficient estimates, the consensus value marked (Figure 12).

    One panel per coefficient that is non-zero in some model (the keys of ``result.histograms``).

    Parameters
    ----------
    result : Consensus
        From :func:`sindy_impulse.analysis.consensus` (``method="mode"`` or ``"median"``).
    axes : sequence of Axes, optional
        One per histogram (``len(result.histograms)``).
    true_coefficients : array-like (n_states, n_features), optional
        Known coefficients (e.g. of the analytical model), marked dashed.

    Returns
    -------
    ndarray of Axes
        One histogram per coefficient, titled with its name (``result.names()``).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np
    >>> from sindy_impulse.analysis import consensus
    >>> from sindy_impulse.plotting import plot_consensus
    >>> rng = np.random.default_rng(0)
    >>> stack = np.array([[[0, 1.0], [-64.0, -3.2]]]) * (1 + 0.01 * rng.standard_normal((30, 2, 2)))
    >>> axes = plot_consensus(consensus(stack, feature_names=["x0", "x1"]))
    >>> len(axes)
    3
    """
    if not (hasattr(result, "histograms") and hasattr(result, "coefficients")):
        raise TypeError(f"result must be a Consensus, got {type(result).__name__}")
    hist = dict(result.histograms)
    if not hist:
        raise ValueError(
            "result has no histograms (a 'stacked' consensus, or no coefficient is non-zero in any model)"
        )
    coefficients = np.asarray(result.coefficients, dtype=float)
    truth = None
    if true_coefficients is not None:
        truth = check_array(true_coefficients, "true_coefficients", ndim=(2,))
        if truth.shape != coefficients.shape:
            raise ValueError(
                f"true_coefficients has shape {truth.shape} but the consensus has {coefficients.shape}"
            )
    keys = sorted(hist)
    names = result.names() if hasattr(result, "names") else {}
    axes = common.many_axes(axes, len(keys), name="axes", ncols=3)
    for a, key in zip(axes, keys):
        h = hist[key]
        counts = np.asarray(h.counts, dtype=float)
        edges = np.asarray(h.edges, dtype=float)
        widths = np.diff(edges)
        a.bar(edges[:-1], counts, width=widths, align="edge", color="C0", alpha=0.7, edgecolor="white")
        value = coefficients[key]
        a.axvline(value, color="C3", lw=1.5, label=f"consensus {value:.4g}")
        if truth is not None:
            a.axvline(truth[key], color="k", lw=1.0, ls="--", label=f"true {truth[key]:.4g}")
        a.set_title(names.get(key, f"xi{key}"), fontsize="medium")
        a.legend(loc="best", frameon=False, fontsize="x-small")
    for a in axes[:: min(3, len(axes))]:
        a.set_ylabel("count")
    return axes


# ----------------------------------------------------------------------------------------------------------
# Figure 13: linear vs nonlinear
# ----------------------------------------------------------------------------------------------------------
def _coefficient_bars(ax, linear, nonlinear, term_names, state_names, labels) -> None:
    """Grouped bars of the coefficients non-zero in either model (the table of Figure 13, bottom)."""
    shown = np.argwhere((linear != 0) | (nonlinear != 0))
    pos = np.arange(len(shown))
    ax.bar(pos - 0.2, [linear[i, k] for i, k in shown], width=0.4, color="C0", label=labels[0])
    ax.bar(pos + 0.2, [nonlinear[i, k] for i, k in shown], width=0.4, color="C3", label=labels[1])
    ax.set_xticks(pos)
    ax.set_xticklabels(
        [f"{state_names[i]}' : {term_names[k]}" for i, k in shown], rotation=45, ha="right", fontsize="small"
    )
    ax.axhline(0.0, color="0.3", lw=0.8)
    ax.set_yscale("symlog", linthresh=1.0)
    ax.set_ylabel("xi")
    ax.legend(loc="best", frameon=False)


def plot_linear_vs_nonlinear(
    t, x_linear=None, x_nonlinear=None, ax=None, *, column: int = 0, labels=("linear", "nonlinear")
) -> Axes | np.ndarray:
    """Linear against nonlinear ring-down (the paper's Figure 13), in three forms.

    - ``plot_linear_vs_nonlinear(t, x_linear, x_nonlinear)``: the two signals' column ``column`` over
      time (Figure 13, top); returns one Axes.
    - ``plot_linear_vs_nonlinear(model_linear, model_nonlinear)``: two fitted ImpulseSINDy models; their
      filtered states over time and their non-zero coefficients side by side (Figure 13, top and
      bottom); returns 2 Axes (``ax``: a sequence of 2).
    - ``plot_linear_vs_nonlinear(result)``: a :class:`~sindy_impulse.analysis.NonlinearityResult`; the
      coefficients of its refined linear model and nonlinear alternative; returns one Axes.

    Parameters
    ----------
    t : float, array (n_samples,), fitted ImpulseSINDy or NonlinearityResult
        Time step or vector of the signals, or the linear model, or the test result.
    x_linear, x_nonlinear : array-like (n_samples,) or (n_samples, n_states), or fitted ImpulseSINDy
        The two signals (first form), or the nonlinear model as ``x_linear`` (second form).
    ax : Axes (or sequence of 2 Axes for two models), optional
    column : int, default=0
        The state drawn over time.
    labels : pair of str, default=("linear", "nonlinear")

    Returns
    -------
    Axes or ndarray of 2 Axes
        One Axes for signals or a result; for two models, the ring-downs and the coefficient bars.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sindy_impulse import damped_oscillator
    >>> from sindy_impulse.plotting import plot_linear_vs_nonlinear
    >>> lin, duff = damped_oscillator(), damped_oscillator(k_nl=50.0, x0=(2.0, 0.0))
    >>> ax = plot_linear_vs_nonlinear(lin.t, lin.x, duff.x)
    >>> len(ax.lines)
    2
    """
    if not (isinstance(labels, (list, tuple)) and len(labels) == 2):
        raise ValueError(f"labels must be a pair of strings, got {labels!r}")
    labels = (str(labels[0]), str(labels[1]))
    if hasattr(t, "linear_coefficients") and hasattr(t, "nonlinear_coefficients"):  # NonlinearityResult
        if x_linear is not None or x_nonlinear is not None:
            raise TypeError("with a NonlinearityResult, pass no x_linear or x_nonlinear")
        return _from_result(t, ax, labels)
    if common.is_sindy(t):  # two fitted models
        if not common.is_sindy(x_linear):
            raise TypeError(
                "with a model as first argument, pass the nonlinear model as second argument, got "
                f"{type(x_linear).__name__}"
            )
        if x_nonlinear is not None:
            raise TypeError("with two models, pass no x_nonlinear")
        return _from_models(t, x_linear, ax, column, labels)
    if x_linear is None or x_nonlinear is None:
        raise TypeError("pass t, x_linear and x_nonlinear (or two fitted models, or a NonlinearityResult)")
    return _from_signals(t, x_linear, x_nonlinear, ax, column, labels)


def _ring_downs(ax, curves, ylabel: str, labels) -> None:
    """The linear (C0) and the nonlinear (C3) ring-down, each a pair ``(time, values)``."""
    for (time, values), color, label in zip(curves, ("C0", "C3"), labels):
        ax.plot(time, values, color=color, lw=1.2, label=label)
    ax.set_xlabel("t")
    ax.set_ylabel(ylabel)
    ax.legend(loc="upper right", frameon=False)


def _from_result(result, ax, labels) -> Axes:
    """Figure 13 from a NonlinearityResult: the coefficients of its two models."""
    lin = check_array(result.linear_coefficients, "result.linear_coefficients", ndim=(2,))
    non = check_array(result.nonlinear_coefficients, "result.nonlinear_coefficients", ndim=(2,))
    if lin.shape != non.shape:
        raise ValueError(f"result's coefficient matrices differ in shape: {lin.shape} and {non.shape}")
    terms = list(result.feature_names) or [f"f{k}" for k in range(lin.shape[1])]
    ax = common.one_axes(ax)
    _coefficient_bars(ax, lin, non, terms, [f"x{i}" for i in range(lin.shape[0])], labels)
    verdict = "nonlinear" if bool(result) else "linear"
    ax.set_title(
        f"{verdict}: Gamma {result.gamma_linear:.3g} (linear) vs {result.gamma_nonlinear:.3g} (nonlinear)"
    )
    return ax


def _from_models(model_linear, model_nonlinear, ax, column, labels) -> np.ndarray:
    """Figure 13 from two fitted models: their filtered states over time, their coefficients."""
    models = [
        common.fitted_sindy(model_linear, "model_linear"),
        common.fitted_sindy(model_nonlinear, "model_nonlinear"),
    ]
    coefs = [np.asarray(m.coefficients(), dtype=float) for m in models]
    term_lists = [list(m.get_feature_names()) for m in models]
    if coefs[0].shape != coefs[1].shape or term_lists[0] != term_lists[1]:
        raise ValueError("the two models have different libraries: their coefficients cannot be compared")
    axes = common.many_axes(ax, 2)
    n_states = coefs[0].shape[0]
    column = common.check_int(column, "column", 0, n_states)
    states = common.resolve_state_names(models[0], n_states)
    curves = [(common.first(m.t_), common.first(m.x_filtered_)[:, column]) for m in models]
    _ring_downs(axes[0], curves, states[column], labels)
    _coefficient_bars(axes[1], coefs[0], coefs[1], term_lists[0], states, labels)
    return axes


def _from_signals(t, x_linear, x_nonlinear, ax, column, labels) -> Axes:
    """Figure 13 (top) from two signals: their column ``column`` over time."""
    xl = check_signal(x_linear, "x_linear")
    xn = check_signal(x_nonlinear, "x_nonlinear")
    if xl.shape != xn.shape:
        raise ValueError(f"x_nonlinear has shape {xn.shape} but x_linear has shape {xl.shape}")
    n = xl.shape[0]
    time = time_vector(check_time(t, n, "t"), n)
    column = common.check_int(column, "column", 0, xl.shape[1])
    ax = common.one_axes(ax)
    _ring_downs(ax, [(time, xl[:, column]), (time, xn[:, column])], f"x{column}", labels)
    return ax

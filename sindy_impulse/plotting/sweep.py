"""Figures of model selection: the threshold sweep (Figure 6a), the reconstruction (Figures 6b, 8a, 8d) and
the SLSQP refinement (Figures 8b, 8e)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .._utils.validation import check_array, check_signal, check_time, time_vector
from ._common import (
    INPUT_STYLE,
    MODEL_STYLE,
    check_choice,
    check_int,
    first,
    fitted_sindy,
    is_sindy,
    many_axes,
    names_or_default,
    one_axes,
    positive,
    resolve_state_names,
)

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["plot_reconstruction", "plot_refinement", "plot_sweep"]


# ----------------------------------------------------------------------------------------------------------
# Figure 6a: threshold sweep
# ----------------------------------------------------------------------------------------------------------
def _sweep_path(model_or_path):
    """The SweepPath of a fitted ImpulseSINDy (its ``path_``), or ``model_or_path`` if it is one."""
    path = model_or_path
    if is_sindy(path):
        if not hasattr(path, "path_"):
            raise ValueError("model_or_path is not fitted (no path_): call fit first")
        path = path.path_
    if not all(hasattr(path, a) for a in ("threshold", "score", "n_terms", "selected")):
        raise TypeError(
            f"model_or_path must be a fitted ImpulseSINDy or a SweepPath, got {type(path).__name__}"
        )
    return path


def plot_sweep(model_or_path, ax=None, x: str = "n_terms") -> Axes:
    """Gamma of every candidate of the threshold sweep, the selected one marked (the paper's Figure 6a).

    Candidates whose simulation diverged (Gamma = inf) are drawn as crosses at the top of the axes.

    Parameters
    ----------
    model_or_path : fitted ImpulseSINDy or SweepPath
    ax : matplotlib Axes, optional
    x : {"n_terms", "threshold"}, default="n_terms"
        Horizontal axis: the number of non-zero coefficients, or the relative threshold (symlog).

    Returns
    -------
    matplotlib Axes
        ``ax`` (or a new one): the candidates on a log axis, the diverged ones, the selected one.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sindy_impulse import ImpulseSINDy, damped_oscillator
    >>> from sindy_impulse.plotting import plot_sweep
    >>> ring_down = damped_oscillator(snr_db=30, random_state=0)
    >>> ax = plot_sweep(ImpulseSINDy().fit(ring_down.x, t=ring_down.t))
    >>> ax.get_yscale()
    'log'
    """
    path = _sweep_path(model_or_path)
    x = check_choice(x, "x", ("n_terms", "threshold"))
    gamma = check_array(path.score, "path.score", ndim=(1,), allow_inf=True, allow_nan=True)
    xs = check_array(getattr(path, x), f"path.{x}", ndim=(1,), allow_nan=(x == "threshold"))
    if xs.shape != gamma.shape:
        raise ValueError(f"path.{x} has {xs.size} entries but path.score has {gamma.size}")
    if not np.any(np.isfinite(gamma)):
        raise ValueError("no candidate has a finite score (not simulated, or all diverged): nothing to plot")
    selected = check_int(path.selected, "path.selected", 0, gamma.size)
    order = np.argsort(xs, kind="stable")
    finite = np.isfinite(gamma[order])
    g = positive(gamma)
    ax = one_axes(ax)
    ax.plot(xs[order][finite], g[order][finite], "o-", color="C0", ms=4, lw=1.0, label="candidates")
    ax.set_yscale("log")
    diverged = np.isinf(gamma)
    if diverged.any():
        top = np.nanmax(g[np.isfinite(g)]) * 3.0
        ax.plot(xs[diverged], np.full(int(diverged.sum()), top), "x", color="k", ms=6, label="diverged")
    ax.plot(
        [xs[selected]],
        [g[selected]],
        "o",
        mfc="none",
        mec="C3",
        mew=2,
        ms=11,
        label=f"selected (Gamma = {gamma[selected]:.3g})",
    )
    if x == "threshold":
        positives = xs[np.isfinite(xs) & (xs > 0)]
        if positives.size:
            ax.set_xscale("symlog", linthresh=float(positives.min()))
        ax.set_xlabel("relative threshold")
    else:
        ax.set_xlabel("number of terms")
    ax.set_ylabel("Gamma")
    ax.legend(loc="best", frameon=False)
    return ax


# ----------------------------------------------------------------------------------------------------------
# Figures 6b, 8a, 8d: reconstruction
# ----------------------------------------------------------------------------------------------------------
def plot_reconstruction(model, x=None, t=None, ax=None, state_names=None) -> np.ndarray:
    """Input vs reconstruction (the paper's Figures 6b, 8a, 8d): one panel per state.

    The model is simulated from the first sample of ``x`` over ``t``.

    Parameters
    ----------
    model : fitted ImpulseSINDy
    x : array-like (n_samples,) or (n_samples, n_states), optional
        The input states; default: the model's filtered states ``x_filtered_`` (first trajectory if
        several).
    t : float or array (n_samples,), optional
        Time step or vector of ``x``; required with ``x`` (default: the model's ``t_``).
    ax : Axes or sequence of Axes, optional
        One per state.
    state_names : list of str, optional

    Returns
    -------
    ndarray of Axes
        One per state: the input and the reconstruction; the first titled with the model's Gamma.

    Raises
    ------
    TypeError
        ``model`` is not an ImpulseSINDy; ``x`` is sparse, None-like or non-numeric; ``ax`` is not Axes.
    ValueError
        Unfitted model; ``x`` with NaN/inf, complex, empty, not 1-D/2-D or with the wrong number of
        states; ``t`` of the wrong length or not increasing.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sindy_impulse import ImpulseSINDy, damped_oscillator
    >>> from sindy_impulse.plotting import plot_reconstruction
    >>> t, x, _ = damped_oscillator()
    >>> axes = plot_reconstruction(ImpulseSINDy().fit(x, t=t))
    >>> len(axes)
    2
    """
    fitted_sindy(model, "model", ("x_filtered_", "t_", "n_features_in_"))
    if x is None:
        x = first(model.x_filtered_)
        if t is None:
            t = first(model.t_)
    elif t is None:
        raise ValueError("t is required when x is given (a time step or one time per sample of x)")
    x = check_signal(x, "x")
    n, n_states = x.shape
    if n_states != model.n_features_in_:
        raise ValueError(f"x has {n_states} states (columns) but the model has {model.n_features_in_}")
    time = time_vector(check_time(t, n, "t"), n)
    if n < 2:
        raise ValueError(f"x has {n} sample; at least 2 are needed to simulate")
    recon = model.simulate(x[0], time)
    names = resolve_state_names(model, n_states, state_names)
    axes = many_axes(ax, n_states, sharex=True)
    for i, a in enumerate(axes):
        a.plot(time, x[:, i], label="input", **INPUT_STYLE)
        a.plot(time, recon[:, i], label="reconstruction", **MODEL_STYLE)
        a.set_ylabel(names[i])
    gamma = getattr(model, "gamma_", np.nan)
    axes[0].set_title(f"Gamma = {gamma:.3g}" if np.isfinite(gamma) else "")
    axes[0].legend(loc="upper right", frameon=False)
    axes[-1].set_xlabel("t")
    return axes


# ----------------------------------------------------------------------------------------------------------
# Figure 8b, 8e: refinement
# ----------------------------------------------------------------------------------------------------------
def _refinement_history(model):
    """``(history, term names or None, state names or None)`` of a fitted model or a history dict."""
    if isinstance(model, dict):
        return model, None, None
    fitted_sindy(model, "model", ("refinement_history_",))
    try:
        term_names = list(model.get_feature_names())
    except Exception:  # a plain PySINDy library without names
        term_names = None
    return model.refinement_history_, term_names, getattr(model, "feature_names_", None)


def _gamma_panel(a, gamma: np.ndarray) -> None:
    """Gamma per iteration on a log axis, the first and the best value in the title."""
    it = np.arange(gamma.size)
    finite = np.isfinite(gamma)
    a.plot(it[finite], positive(gamma)[finite], "o-", color="C0", ms=3, lw=1.0)
    a.set_yscale("log")
    a.set_ylabel("Gamma")
    best = int(np.argmin(np.where(finite, gamma, np.inf)))
    a.set_title(f"Gamma: {gamma[0]:.3g} -> {gamma[best]:.3g} (best at iteration {best})")


def _coefficient_panel(a, coef: np.ndarray, term_names, states, relative: bool) -> None:
    """One line per coefficient non-zero at some iteration (relative to its first value if ``relative``)."""
    n_iter, n_states, n_features = coef.shape
    term_names = names_or_default(term_names, n_features, "f")
    states = names_or_default(states, n_states, "x")
    active = np.flatnonzero(np.any(coef != 0, axis=0).ravel())
    for j, flat in enumerate(active):
        i, k = divmod(int(flat), n_features)
        values = coef[:, i, k]
        if relative:
            values = values / values[0] if values[0] != 0 else np.full_like(values, np.nan)
        a.plot(
            np.arange(n_iter),
            values,
            "-",
            color=f"C{j % 10}",
            lw=1.2,
            label=f"{states[i]}' : {term_names[k]}",
        )
    a.set_ylabel("xi / xi_SINDy" if relative else "xi")
    a.set_xlabel("iteration")
    if active.size:
        a.legend(loc="best", frameon=False, fontsize="small", ncol=2 if active.size > 6 else 1)


def plot_refinement(model, axes=None, *, relative: bool = True) -> np.ndarray:
    """Gamma per SLSQP iteration and the evolution of the non-zero coefficients (Figures 8b and 8e).

    Parameters
    ----------
    model : fitted ImpulseSINDy (fitted with ``refine=True``), or its ``refinement_history_`` dict
        ``{"score": [...], "coefficients": [...]}`` with one entry per iteration (the score is the fit's
        error measure: the paper's Gamma for short records).
    axes : sequence of 2 Axes, optional
        Gamma panel, coefficient panel.
    relative : bool, default=True
        Draw each coefficient relative to its first (SINDy) value, so that terms of different magnitude
        share the axis; otherwise the values themselves.

    Returns
    -------
    ndarray of 2 Axes
        Gamma per iteration (log axis), then one line per coefficient that is ever non-zero.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sindy_impulse import ImpulseSINDy, damped_oscillator
    >>> from sindy_impulse.plotting import plot_refinement
    >>> ring_down = damped_oscillator(snr_db=30, random_state=0)
    >>> axes = plot_refinement(ImpulseSINDy().fit(ring_down.x, t=ring_down.t))
    >>> len(axes[1].lines)  # the 3 non-zero coefficients
    3
    """
    if isinstance(relative, (bool, np.bool_)) is False:
        raise TypeError(f"relative must be True or False, got {relative!r}")
    history, term_names, states = _refinement_history(model)
    if not {"score", "coefficients"} <= set(history):
        raise ValueError("the refinement history must have the keys 'score' and 'coefficients'")
    if len(history["coefficients"]) == 0:
        raise ValueError(
            "model has no refinement history (fitted with refine=False, or the selected model had no "
            "non-zero coefficient to refine)"
        )
    gamma = check_array(history["score"], "history['score']", ndim=(1,), allow_inf=True)
    coef = check_array(history["coefficients"], "history['coefficients']", ndim=(3,))
    axes = many_axes(axes, 2, name="axes", sharex=True)
    _gamma_panel(axes[0], gamma)
    _coefficient_panel(axes[1], coef, term_names, states, relative)
    return axes

"""One function per kind of figure in the paper. Each takes fitted objects (or their attributes) and an
optional matplotlib ``Axes``, returns the ``Axes`` (or an array of them), and never calls ``plt.show()``.

=================================  ==============================================================
function                           figure of Stender, Oberst & Hoffmann (2019)
=================================  ==============================================================
:func:`plot_alpha_curve`           7a: the alpha-selection criterion over alpha, chosen alpha marked
:func:`plot_filtering`             7b, A1: input against filtered (time-integrated derivative) signal
:func:`plot_sweep`                 6a: Gamma over the threshold sweep, selected candidate marked
:func:`plot_reconstruction`        6b, 8a, 8d: input against the simulated model
:func:`plot_refinement`            8b, 8e: Gamma and coefficients per SLSQP iteration
:func:`plot_embedding`             9: ACF with tau, FNN fraction with m, reconstructed phase space
:func:`plot_complexity_error`      10b: Gamma against number of terms, Pareto front marked
:func:`plot_parameter_dependency`  11: coefficient ratio over the control parameter
:func:`plot_consensus`             12: histograms of the non-zero coefficients, consensus marked
:func:`plot_linear_vs_nonlinear`   13: linear against nonlinear ring-down (and their coefficients)
:func:`plot_feature_space`         14b: 2-D feature space (e.g. PCA of SINDyFeatures) by label
=================================  ==============================================================

matplotlib is imported only when a function is called. Bad input raises ``ValueError`` or ``TypeError``
naming the argument (the array checks are the shared ones of :mod:`sindy_impulse._validation`).
"""

from __future__ import annotations

from collections.abc import Sequence
from numbers import Integral
from typing import TYPE_CHECKING

import numpy as np

from ._validation import check_array, check_signal, check_time, time_vector

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = [
    "plot_alpha_curve",
    "plot_complexity_error",
    "plot_consensus",
    "plot_embedding",
    "plot_feature_space",
    "plot_filtering",
    "plot_linear_vs_nonlinear",
    "plot_parameter_dependency",
    "plot_reconstruction",
    "plot_refinement",
    "plot_sweep",
]

_INPUT_STYLE = {"color": "0.6", "lw": 2.5}
_MODEL_STYLE = {"color": "C3", "lw": 1.2, "ls": "--"}
_MARK_STYLE = {"color": "C3", "ls": ":", "lw": 1.2}


# ----------------------------------------------------------------------------------------------------------
# helpers
# ----------------------------------------------------------------------------------------------------------
def _is_axes(obj) -> bool:
    from matplotlib.axes import Axes

    return isinstance(obj, Axes)


def _one_axes(ax, name: str = "ax", **subplot_kw) -> Axes:
    """``ax`` checked to be one matplotlib Axes, or a new figure's Axes."""
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(6, 3.5), **subplot_kw)
        return ax
    if not _is_axes(ax):
        raise TypeError(f"{name} must be a matplotlib Axes, got {type(ax).__name__}")
    return ax


def _many_axes(ax, n: int, name: str = "ax", ncols: int = 1, sharex: bool = False) -> np.ndarray:
    """``n`` Axes: ``ax`` (one Axes when ``n == 1``, or a sequence/array of exactly ``n``), else new ones."""
    import matplotlib.pyplot as plt

    if ax is None:
        ncols = max(1, min(ncols, n))
        nrows = -(-n // ncols)
        fig, grid = plt.subplots(
            nrows, ncols, sharex=sharex, squeeze=False, figsize=(3.6 * ncols if ncols > 1 else 7, 2.4 * nrows)
        )
        flat = grid.ravel()
        for extra in flat[n:]:
            extra.set_visible(False)
        return flat[:n]
    if _is_axes(ax):
        axes = np.array([ax], dtype=object)
    elif isinstance(ax, (Sequence, np.ndarray)) and not isinstance(ax, str):
        axes = np.asarray(ax, dtype=object).ravel()
    else:
        raise TypeError(f"{name} must be a matplotlib Axes or a sequence of {n}, got {type(ax).__name__}")
    bad = [type(a).__name__ for a in axes if not _is_axes(a)]
    if bad:
        raise TypeError(f"{name} must contain matplotlib Axes only, got {bad[0]}")
    if len(axes) != n:
        raise ValueError(f"{name} has {len(axes)} axes but {n} are needed")
    return axes


def _check_int(value, name: str, low: int, high: int) -> int:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, Integral):
        raise TypeError(f"{name} must be an int, got {value!r}")
    if not low <= int(value) < high:
        raise ValueError(f"{name}={value} is out of range: expected {low} <= {name} < {high}")
    return int(value)


def _check_choice(value, name: str, choices: Sequence[str]) -> str:
    if not isinstance(value, str) or value not in choices:
        raise ValueError(f"{name} must be one of {list(choices)}, got {value!r}")
    return value


def _positive(y: np.ndarray) -> np.ndarray:
    """``y`` with zeros raised to a tiny positive value so that a log axis can show them."""
    y = np.asarray(y, dtype=float)
    pos = y[np.isfinite(y) & (y > 0)]
    floor = pos.min() * 1e-2 if pos.size else 1e-16
    return np.where(np.isfinite(y) & (y <= 0), floor, y)


def _first(value):
    """The first trajectory of a model attribute that is a list for several trajectories."""
    return value[0] if isinstance(value, list) else value


def _fitted_sindy(model, name: str = "model", attrs: Sequence[str] = ("x_filtered_", "t_")):
    """Refuse anything that is not a fitted ImpulseSINDy-like estimator."""
    if model is None or not hasattr(model, "coefficients"):
        raise TypeError(f"{name} must be a fitted ImpulseSINDy, got {type(model).__name__}")
    missing = [a for a in attrs if not hasattr(model, a)]
    if missing:
        raise ValueError(f"{name} is not fitted (no {missing[0]}): call fit first")
    return model


def _state_names(model, n: int, state_names=None) -> list[str]:
    names = state_names if state_names is not None else getattr(model, "feature_names_", None)
    names = [str(s) for s in names] if names is not None else [f"x{i}" for i in range(n)]
    if len(names) != n:
        raise ValueError(f"state_names has {len(names)} names for {n} states")
    return names


# ----------------------------------------------------------------------------------------------------------
# Figure 7a: alpha selection
# ----------------------------------------------------------------------------------------------------------
_CRITERIA = ("error", "gcv", "consistency", "residual", "dof")


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
    est = tvregdiff_or_model
    if hasattr(est, "coefficients") and hasattr(est, "differentiation_method"):  # an ImpulseSINDy
        if not hasattr(est, "differentiation_method_"):
            raise ValueError("tvregdiff_or_model is not fitted (no differentiation_method_): call fit first")
        est = est.differentiation_method_
        if not hasattr(est, "alpha_curve_"):
            raise TypeError(
                f"the model's differentiation method is a {type(est).__name__}, not a TVRegDiff: it has no "
                "alpha curve"
            )
    elif not hasattr(type(est), "_alphas_for") and not hasattr(est, "alpha_curve_"):
        raise TypeError(
            f"tvregdiff_or_model must be a TVRegDiff or an ImpulseSINDy, got {type(est).__name__}"
        )
    if not hasattr(est, "alpha_curve_"):
        raise ValueError("tvregdiff_or_model is not fitted (no alpha_curve_): call fit first")
    column = _check_int(column, "column", 0, len(est.alpha_curve_))
    criterion = _check_choice(criterion, "criterion", _CRITERIA)
    curve = est.alpha_curve_[column]
    alphas = np.asarray(curve["alpha"], dtype=float)
    values = np.asarray(curve[criterion], dtype=float)
    if alphas.size == 0:
        raise ValueError(
            f"column {column} has no alpha curve: alpha was given (not 'auto') or the column is constant"
        )
    chosen = float(np.asarray(est.alpha_)[column])
    ax = _one_axes(ax)
    ax.plot(alphas, values, "o-", color="C0", ms=3, lw=1.2, label=criterion)
    ax.set_xscale("log")
    if np.all(values[np.isfinite(values)] > 0):
        ax.set_yscale("log")
    ax.axvline(chosen, **_MARK_STYLE)
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
    model_t = None
    if hasattr(filtered, "coefficients"):  # ImpulseSINDy
        _fitted_sindy(filtered, "filtered")
        model_t = _first(filtered.t_)
        filtered = _first(filtered.x_filtered_)
    elif hasattr(filtered, "alpha_curve_") or hasattr(type(filtered), "_alphas_for"):  # TVRegDiff
        if not hasattr(filtered, "smoothed_x_"):
            raise ValueError("filtered is an unfitted TVRegDiff (no smoothed_x_): differentiate first")
        filtered = filtered.smoothed_x_
    x = check_signal(x, "x")
    f = check_signal(filtered, "filtered")
    if f.shape != x.shape:
        raise ValueError(f"filtered has shape {f.shape} but x has shape {x.shape}")
    c = None
    if clean is not None:
        c = check_signal(clean, "clean")
        if c.shape != x.shape:
            raise ValueError(f"clean has shape {c.shape} but x has shape {x.shape}")
    n, n_states = x.shape
    if t is None and model_t is not None:
        t = model_t
    time = np.arange(n, dtype=float) if t is None else time_vector(check_time(t, n), n)
    names = _state_names(None, n_states, state_names)
    axes = _many_axes(ax, n_states, sharex=True)
    for i, a in enumerate(axes):
        a.plot(time, x[:, i], color="0.65", lw=1.0, label="input")
        if c is not None:
            a.plot(time, c[:, i], color="k", lw=0.8, label="clean")
        a.plot(time, f[:, i], color="C3", lw=1.3, label="filtered")
        a.set_ylabel(names[i])
    axes[0].legend(loc="upper right", frameon=False)
    axes[-1].set_xlabel("t" if t is not None else "sample")
    return axes


# ----------------------------------------------------------------------------------------------------------
# Figure 6a: threshold sweep
# ----------------------------------------------------------------------------------------------------------
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
    path = model_or_path
    if hasattr(path, "coefficients") and callable(path.coefficients):
        if not hasattr(path, "path_"):
            raise ValueError("model_or_path is not fitted (no path_): call fit first")
        path = path.path_
    if not all(hasattr(path, a) for a in ("threshold", "gamma", "n_terms", "selected")):
        raise TypeError(
            f"model_or_path must be a fitted ImpulseSINDy or a SweepPath, got {type(path).__name__}"
        )
    x = _check_choice(x, "x", ("n_terms", "threshold"))
    gamma = check_array(path.gamma, "path.gamma", ndim=(1,), allow_inf=True, allow_nan=True)
    xs = check_array(getattr(path, x), f"path.{x}", ndim=(1,), allow_nan=(x == "threshold"))
    if xs.shape != gamma.shape:
        raise ValueError(f"path.{x} has {xs.size} entries but path.gamma has {gamma.size}")
    if not np.any(np.isfinite(gamma)):
        raise ValueError("no candidate has a finite Gamma (not simulated, or all diverged): nothing to plot")
    selected = _check_int(path.selected, "path.selected", 0, gamma.size)
    order = np.argsort(xs, kind="stable")
    finite = np.isfinite(gamma[order])
    g = _positive(gamma)
    ax = _one_axes(ax)
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
        positive = xs[np.isfinite(xs) & (xs > 0)]
        if positive.size:
            ax.set_xscale("symlog", linthresh=float(positive.min()))
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
    _fitted_sindy(model, "model", ("x_filtered_", "t_", "n_features_in_"))
    if x is None:
        x = _first(model.x_filtered_)
        if t is None:
            t = _first(model.t_)
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
    names = _state_names(model, n_states, state_names)
    axes = _many_axes(ax, n_states, sharex=True)
    for i, a in enumerate(axes):
        a.plot(time, x[:, i], label="input", **_INPUT_STYLE)
        a.plot(time, recon[:, i], label="reconstruction", **_MODEL_STYLE)
        a.set_ylabel(names[i])
    gamma = getattr(model, "gamma_", np.nan)
    axes[0].set_title(f"Gamma = {gamma:.3g}" if np.isfinite(gamma) else "")
    axes[0].legend(loc="upper right", frameon=False)
    axes[-1].set_xlabel("t")
    return axes


# ----------------------------------------------------------------------------------------------------------
# Figure 8b, 8e: refinement
# ----------------------------------------------------------------------------------------------------------
def plot_refinement(model, axes=None, *, relative: bool = True) -> np.ndarray:
    """Gamma per SLSQP iteration and the evolution of the non-zero coefficients (Figures 8b and 8e).

    Parameters
    ----------
    model : fitted ImpulseSINDy (fitted with ``refine=True``), or its ``refinement_history_`` dict
        ``{"gamma": [...], "coefficients": [...]}`` with one entry per iteration.
    axes : sequence of 2 Axes, optional
        Gamma panel, coefficient panel.
    relative : bool, default=True
        Draw each coefficient relative to its first (SINDy) value, so that terms of different magnitude
        share the axis; otherwise the values themselves.

    Returns
    -------
    ndarray of 2 Axes

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
    if isinstance(model, dict):
        history, term_names, states = model, None, None
    else:
        _fitted_sindy(model, "model", ("refinement_history_",))
        history = model.refinement_history_
        try:
            term_names = list(model.get_feature_names())
        except Exception:  # a plain PySINDy library without names
            term_names = None
        states = getattr(model, "feature_names_", None)
    if not {"gamma", "coefficients"} <= set(history):
        raise ValueError("the refinement history must have the keys 'gamma' and 'coefficients'")
    if len(history["coefficients"]) == 0:
        raise ValueError(
            "model has no refinement history (fitted with refine=False, or the selected model had no "
            "non-zero coefficient to refine)"
        )
    gamma = check_array(history["gamma"], "history['gamma']", ndim=(1,), allow_inf=True)
    coef = check_array(history["coefficients"], "history['coefficients']", ndim=(3,))
    n_iter, n_states, n_features = coef.shape
    term_names = (
        term_names
        if term_names is not None and len(term_names) == n_features
        else [f"f{k}" for k in range(n_features)]
    )
    states = (
        [str(s) for s in states]
        if states is not None and len(states) == n_states
        else [f"x{i}" for i in range(n_states)]
    )
    axes = _many_axes(axes, 2, name="axes", sharex=True)
    it = np.arange(gamma.size)
    finite = np.isfinite(gamma)
    axes[0].plot(it[finite], _positive(gamma)[finite], "o-", color="C0", ms=3, lw=1.0)
    axes[0].set_yscale("log")
    axes[0].set_ylabel("Gamma")
    best = int(np.argmin(np.where(finite, gamma, np.inf)))
    axes[0].set_title(f"Gamma: {gamma[0]:.3g} -> {gamma[best]:.3g} (best at iteration {best})")
    active = np.flatnonzero(np.any(coef != 0, axis=0).ravel())
    for j, flat in enumerate(active):
        i, k = divmod(int(flat), n_features)
        values = coef[:, i, k]
        if relative:
            values = values / values[0] if values[0] != 0 else np.full_like(values, np.nan)
        axes[1].plot(
            np.arange(n_iter),
            values,
            "-",
            color=f"C{j % 10}",
            lw=1.2,
            label=f"{states[i]}' : {term_names[k]}",
        )
    axes[1].set_ylabel("xi / xi_SINDy" if relative else "xi")
    axes[1].set_xlabel("iteration")
    if active.size:
        axes[1].legend(loc="best", frameon=False, fontsize="small", ncol=2 if active.size > 6 else 1)
    return axes


# ----------------------------------------------------------------------------------------------------------
# Figure 9: embedding
# ----------------------------------------------------------------------------------------------------------
def plot_embedding(embedding, signal=None, axes=None) -> np.ndarray:
    """Delay and dimension diagnostics, and the reconstructed phase space (the paper's Figure 9).

    Panels: the autocorrelation (or the auto mutual information) over the lag with ``tau_`` marked; the
    false-nearest-neighbour fraction (or Cao's ``E1``) over the dimension with ``dimension_`` marked;
    with ``signal``, the trajectory in the reconstructed phase space ``(q1, q2)`` (for ``dimension_ = 1``
    the pair ``(s(t - tau), s(t))``).

    Parameters
    ----------
    embedding : fitted DelayEmbedding
    signal : array-like (n_samples,) or (n_samples, 1), optional
        The signal to embed for the phase-space panel.
    axes : sequence of 2 (or 3 with ``signal``) Axes, optional

    Returns
    -------
    ndarray of Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sindy_impulse import DelayEmbedding, damped_oscillator
    >>> from sindy_impulse.plotting import plot_embedding
    >>> s = damped_oscillator().x[:, 0]
    >>> axes = plot_embedding(DelayEmbedding().fit(s), signal=s)
    >>> len(axes)
    3
    """
    if not (hasattr(embedding, "transform") and hasattr(type(embedding), "delay_labels")):
        raise TypeError(f"embedding must be a fitted DelayEmbedding, got {type(embedding).__name__}")
    if not hasattr(embedding, "tau_"):
        raise ValueError("embedding is not fitted (no tau_): call fit first")
    s = None
    if signal is not None:
        s = check_signal(signal, "signal")
        if s.shape[1] != 1:
            raise ValueError(f"signal has {s.shape[1]} columns; pass one signal (1-D or one column)")
        s = s[:, 0]
        if s.size < embedding.tau_ + 1:
            raise ValueError(
                f"signal has {s.size} samples; at least tau + 1 = {embedding.tau_ + 1} are needed"
            )
    tau, m = int(embedding.tau_), int(embedding.dimension_)
    axes = _many_axes(axes, 2 if s is None else 3, name="axes", ncols=3)

    a = axes[0]
    acf = getattr(embedding, "acf_", None)
    mi = getattr(embedding, "mutual_information_", None)
    if acf is not None:
        a.plot(np.arange(acf.size), acf, color="C0", lw=1.2)
        a.axhline(0.0, color="0.5", lw=0.8)
        a.set_ylabel("ACF")
    elif mi is not None:
        a.plot(np.arange(mi.size), mi, color="C0", lw=1.2)
        a.set_ylabel("AMI (nats)")
    else:
        a.text(0.5, 0.5, "tau given, not estimated", transform=a.transAxes, ha="center", va="center")
    a.axvline(tau, **_MARK_STYLE)
    a.set_xlabel("lag (samples)")
    a.set_title(f"tau = {tau}")

    a = axes[1]
    dims = getattr(embedding, "candidate_dimensions_", None)
    fnn = getattr(embedding, "fnn_fraction_", None)
    e1 = getattr(embedding, "cao_e1_", None)
    if dims is not None and fnn is not None:
        a.plot(dims, fnn, "o-", color="C0", ms=4, lw=1.2)
        a.axhline(getattr(embedding, "fnn_fraction_threshold", 0.1), color="0.5", lw=0.8, ls="--")
        a.set_ylabel("FNN fraction")
    elif dims is not None and e1 is not None:
        a.plot(dims, e1, "o-", color="C0", ms=4, lw=1.2)
        a.axhline(getattr(embedding, "cao_threshold", 0.9), color="0.5", lw=0.8, ls="--")
        a.set_ylabel("Cao E1")
    else:
        a.text(0.5, 0.5, "dimension given, not estimated", transform=a.transAxes, ha="center", va="center")
    a.axvline(m, **_MARK_STYLE)
    a.set_xlabel("dimension")
    a.set_title(f"m = {m}")

    if s is not None:
        a = axes[2]
        if m >= 2:
            q = embedding.transform(s)
            a.plot(q[:, 0], q[:, 1], color="C0", lw=1.0)
            a.set_xlabel("q1")
            a.set_ylabel("q2")
        else:
            a.plot(s[:-tau], s[tau:], color="C0", lw=1.0)
            a.set_xlabel("s(t - tau)")
            a.set_ylabel("s(t)")
        a.set_title("reconstructed phase space")
    return axes


# ----------------------------------------------------------------------------------------------------------
# Figure 10: complexity-error plane
# ----------------------------------------------------------------------------------------------------------
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
    color_by = _check_choice(color_by, "color_by", ("estimator", "input"))
    metric = _check_choice(metric, "metric", ("gamma", "gamma_filtered", "gamma_sindy"))
    err = np.asarray(getattr(result, metric), dtype=float)
    terms = np.asarray(result.n_terms)
    labels = np.asarray(getattr(result, f"{color_by}_label"))
    ok = np.asarray(result.succeeded) & np.isfinite(err) & (terms >= 0)
    if not ok.any():
        raise ValueError(f"result has no successful model with a finite {metric}: nothing to plot")
    y = _positive(err)
    ax = _one_axes(ax)
    unique = list(dict.fromkeys(labels.tolist()))
    for j, lab in enumerate(unique):
        sel = ok & np.array([v == lab for v in labels.tolist()])
        ax.scatter(terms[sel], y[sel], s=28, color=f"C{j % 10}", alpha=0.8, label=f"{color_by} {lab}")
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
    quantity = _check_choice(quantity, "quantity", ("ratio", "relative_change"))
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
    ax = _one_axes(ax)
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
    ax.axvline(values[ref], **_MARK_STYLE)
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
    axes = _many_axes(axes, len(keys), name="axes", ncols=3)
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
):
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
        lin = check_array(t.linear_coefficients, "result.linear_coefficients", ndim=(2,))
        non = check_array(t.nonlinear_coefficients, "result.nonlinear_coefficients", ndim=(2,))
        if lin.shape != non.shape:
            raise ValueError(f"result's coefficient matrices differ in shape: {lin.shape} and {non.shape}")
        terms = list(t.feature_names) or [f"f{k}" for k in range(lin.shape[1])]
        ax = _one_axes(ax)
        _coefficient_bars(ax, lin, non, terms, [f"x{i}" for i in range(lin.shape[0])], labels)
        verdict = "nonlinear" if bool(t) else "linear"
        ax.set_title(f"{verdict}: Gamma {t.gamma_linear:.3g} (linear) vs {t.gamma_nonlinear:.3g} (nonlinear)")
        return ax

    if hasattr(t, "coefficients") and callable(t.coefficients):  # two fitted models
        if not (hasattr(x_linear, "coefficients") and callable(x_linear.coefficients)):
            raise TypeError(
                "with a model as first argument, pass the nonlinear model as second argument, got "
                f"{type(x_linear).__name__}"
            )
        if x_nonlinear is not None:
            raise TypeError("with two models, pass no x_nonlinear")
        models = [_fitted_sindy(t, "model_linear"), _fitted_sindy(x_linear, "model_nonlinear")]
        coefs = [np.asarray(m.coefficients(), dtype=float) for m in models]
        term_lists = [list(m.get_feature_names()) for m in models]
        if coefs[0].shape != coefs[1].shape or term_lists[0] != term_lists[1]:
            raise ValueError("the two models have different libraries: their coefficients cannot be compared")
        axes = _many_axes(ax, 2)
        n_states = coefs[0].shape[0]
        column = _check_int(column, "column", 0, n_states)
        states = _state_names(models[0], n_states)
        for j, (m, lab) in enumerate(zip(models, labels)):
            axes[0].plot(
                _first(m.t_), _first(m.x_filtered_)[:, column], color=("C0", "C3")[j], lw=1.2, label=lab
            )
        axes[0].set_xlabel("t")
        axes[0].set_ylabel(states[column])
        axes[0].legend(loc="upper right", frameon=False)
        _coefficient_bars(axes[1], coefs[0], coefs[1], term_lists[0], states, labels)
        return axes

    if x_linear is None or x_nonlinear is None:
        raise TypeError("pass t, x_linear and x_nonlinear (or two fitted models, or a NonlinearityResult)")
    xl = check_signal(x_linear, "x_linear")
    xn = check_signal(x_nonlinear, "x_nonlinear")
    if xl.shape != xn.shape:
        raise ValueError(f"x_nonlinear has shape {xn.shape} but x_linear has shape {xl.shape}")
    n = xl.shape[0]
    time = time_vector(check_time(t, n, "t"), n)
    column = _check_int(column, "column", 0, xl.shape[1])
    ax = _one_axes(ax)
    ax.plot(time, xl[:, column], color="C0", lw=1.2, label=labels[0])
    ax.plot(time, xn[:, column], color="C3", lw=1.2, label=labels[1])
    ax.set_xlabel("t")
    ax.set_ylabel(f"x{column}")
    ax.legend(loc="upper right", frameon=False)
    return ax


# ----------------------------------------------------------------------------------------------------------
# Figure 14: feature space
# ----------------------------------------------------------------------------------------------------------
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
    ax = _one_axes(ax)
    for j, value in enumerate(dict.fromkeys(lab[keep].tolist())):
        sel = keep & np.array([v == value for v in lab.tolist()])
        ax.scatter(
            f[sel, 0],
            f[sel, 1],
            s=22,
            color=f"C{j % 10}",
            alpha=0.85,
            label=None if labels is None else str(value),
        )
    ax.set_xlabel(str(axis_names[0]))
    ax.set_ylabel(str(axis_names[1]))
    if (~keep).any():
        ax.set_title(f"{int((~keep).sum())} row(s) with NaN not shown")
    if labels is not None:
        ax.legend(loc="best", frameon=False)
    return ax

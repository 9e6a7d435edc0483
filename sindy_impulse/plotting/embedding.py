"""Figure of the delay embedding: delay and dimension diagnostics and the reconstructed phase space
(Figure 9)."""

from __future__ import annotations

import numpy as np

from .._utils.validation import check_signal
from ._common import MARK_STYLE, many_axes

__all__ = ["plot_embedding"]


def _delay_curve(embedding):
    """``(lags, values, fmt, ylabel, level)`` of the delay estimate, or None when ``tau`` was given."""
    acf = getattr(embedding, "acf_", None)
    if acf is not None:
        return np.arange(acf.size), acf, "-", "ACF", {"y": 0.0}
    mi = getattr(embedding, "mutual_information_", None)
    if mi is not None:
        return np.arange(mi.size), mi, "-", "AMI (nats)", None
    return None


def _dimension_curve(embedding):
    """``(dimensions, values, fmt, ylabel, level)`` of the dimension estimate, or None when it was given."""
    dims = getattr(embedding, "candidate_dimensions_", None)
    fnn = getattr(embedding, "fnn_fraction_", None)
    e1 = getattr(embedding, "cao_e1_", None)
    if dims is not None and fnn is not None:
        threshold = getattr(embedding, "fnn_fraction_threshold", 0.1)
        return dims, fnn, "o-", "FNN fraction", {"y": threshold, "ls": "--"}
    if dims is not None and e1 is not None:
        return dims, e1, "o-", "Cao E1", {"y": getattr(embedding, "cao_threshold", 0.9), "ls": "--"}
    return None


def _diagnostic_panel(a, curve, mark: int, xlabel: str, title: str, missing: str) -> None:
    """A diagnostic curve with its reference level (or a note that the value was given), ``mark`` marked."""
    if curve is None:
        a.text(0.5, 0.5, missing, transform=a.transAxes, ha="center", va="center")
    else:
        xs, ys, fmt, ylabel, level = curve
        a.plot(xs, ys, fmt, color="C0", ms=4, lw=1.2)
        if level is not None:
            a.axhline(color="0.5", lw=0.8, **level)
        a.set_ylabel(ylabel)
    a.axvline(mark, **MARK_STYLE)
    a.set_xlabel(xlabel)
    a.set_title(title)


def _phase_panel(a, embedding, s: np.ndarray, tau: int, m: int) -> None:
    """The trajectory in the reconstructed phase space (``(s(t - tau), s(t))`` for one dimension)."""
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


def _one_signal(signal, tau: int) -> np.ndarray:
    """``signal`` checked to be one signal of at least ``tau + 1`` samples, as a 1-D array."""
    s = check_signal(signal, "signal")
    if s.shape[1] != 1:
        raise ValueError(f"signal has {s.shape[1]} columns; pass one signal (1-D or one column)")
    s = s[:, 0]
    if s.size < tau + 1:
        raise ValueError(f"signal has {s.size} samples; at least tau + 1 = {tau + 1} are needed")
    return s


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
        The delay panel, the dimension panel and, with ``signal``, the phase-space panel.

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
    s = None if signal is None else _one_signal(signal, embedding.tau_)
    tau, m = int(embedding.tau_), int(embedding.dimension_)
    axes = many_axes(axes, 2 if s is None else 3, name="axes", ncols=3)
    _diagnostic_panel(
        axes[0], _delay_curve(embedding), tau, "lag (samples)", f"tau = {tau}", "tau given, not estimated"
    )
    _diagnostic_panel(
        axes[1], _dimension_curve(embedding), m, "dimension", f"m = {m}", "dimension given, not estimated"
    )
    if s is not None:
        _phase_panel(axes[2], embedding, s, tau, m)
    return axes

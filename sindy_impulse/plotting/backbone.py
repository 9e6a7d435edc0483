"""Backbone curves of data and models overlaid: natural frequency and damping ratio against amplitude.

Reads only the public attributes of
:class:`~sindy_impulse.analysis.Backbone` (``amplitude``, ``frequency_hz``, ``damping_ratio``, ``source``);
matplotlib is imported only when the function is called, and ``plt.show()`` is never called.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ._common import log_ticks

__all__ = ["plot_backbone", "smoothed"]

_STYLE = {
    "data": {"ls": "-", "marker": "o", "ms": 3, "lw": 1.5},
    "model": {"ls": "--", "marker": None, "lw": 1.5},
}


def _two_axes(axes) -> np.ndarray:
    """Two matplotlib Axes: ``axes`` checked, or a new figure's side by side."""
    import matplotlib.pyplot as plt
    from matplotlib.axes import Axes

    if axes is None:
        _, grid = plt.subplots(1, 2, figsize=(9, 3.5), sharex=True, layout="constrained")
        return np.asarray(grid, dtype=object)
    if isinstance(axes, Axes) or not isinstance(axes, (Sequence, np.ndarray)) or isinstance(axes, str):
        raise TypeError(f"axes must be a sequence of two matplotlib Axes, got {type(axes).__name__}")
    flat = np.asarray(axes, dtype=object).ravel()
    if len(flat) != 2 or not all(isinstance(a, Axes) for a in flat):
        raise ValueError(f"axes must hold exactly two matplotlib Axes, got {len(flat)} object(s)")
    return flat


def _labels(backbones, labels) -> list[str]:
    if labels is not None:
        if isinstance(labels, str) or len(labels) != len(backbones):
            raise ValueError(f"labels must be a list of {len(backbones)} string(s), one per backbone")
        return [str(label) for label in labels]
    sources = [str(getattr(b, "source", "backbone")) for b in backbones]
    return [s if sources.count(s) == 1 else f"{s} {sources[:i + 1].count(s)}" for i, s in enumerate(sources)]


#: Fewest points of a data curve that are smoothed (a shorter curve is drawn as it is).
MIN_SMOOTHED = 10


def smoothed(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A data backbone's values (in amplitude order) smoothed, and their local spread: a local straight
    line over two fifths of the points (at least 5; Savitzky-Golay), and the RMS deviation of the points
    from it over the same window. A backbone measured while the mode beats with a neighbour wiggles about
    its trend; the trend is what the amplitude changes, the spread what the beating (and the noise) adds.

    Examples
    --------
    >>> a = np.linspace(0, 1, 41)
    >>> trend, spread = smoothed(10 + a + 0.05 * np.sin(2 * np.pi * 6 * a))
    >>> bool(np.max(np.abs(trend - 10 - a)[5:-5]) < 0.03), bool(0.02 < np.median(spread) < 0.05)
    (True, True)
    """
    from scipy.ndimage import uniform_filter1d
    from scipy.signal import savgol_filter

    values = np.asarray(values, dtype=float)
    window = max(5, (2 * len(values) // 5) | 1)
    if len(values) < window:
        return values, np.zeros_like(values)
    trend = savgol_filter(values, window, 1, mode="interp")
    spread = np.sqrt(uniform_filter1d((values - trend) ** 2, window, mode="nearest"))
    return trend, spread


def _draw(ax, a, values, style, label, spread: bool) -> None:
    """One curve on one axis; a data curve with ``spread``: its points faint, its trend and spread band."""
    ok = np.isfinite(a) & np.isfinite(values)
    a, values = a[ok], values[ok]
    if not (spread and style.get("marker") and len(values) >= MIN_SMOOTHED):
        ax.plot(a, values, label=label, **style)
        return
    trend, width = smoothed(values)
    faint = dict(style, ls="none", alpha=0.35, ms=2.5)
    ax.plot(a, values, label=f"{label} (points)", **faint)
    ax.plot(a, trend, label=f"{label}: trend ± spread", **dict(style, marker=None))
    ax.fill_between(a, trend - width, trend + width, color=style["color"], alpha=0.2, lw=0)


def plot_backbone(*backbones, axes=None, labels=None, log_amplitude: bool = True, spread: bool = True,
                  damping_unit: str = "percent") -> np.ndarray:
    """Overlay backbone curves: frequency against amplitude (left), damping ratio against amplitude (right).

    Data curves (``source="data"``) are drawn as their points with their trend and spread (``spread``),
    model curves dashed.

    Parameters
    ----------
    *backbones : Backbone
        One or more curves from :func:`~sindy_impulse.analysis.hilbert_backbone` or
        :func:`~sindy_impulse.analysis.backbone`.
    axes : sequence of two matplotlib Axes, optional
        Where to draw; default: a new figure.
    labels : list of str, optional
        Legend entries (default: each curve's ``source``, numbered when repeated).
    log_amplitude : bool, default=True
        Logarithmic amplitude axis (its tick labels never crowd).
    spread : bool, default=True
        Draw a data curve of at least 10 points as its points (faint), its trend (a local straight line
        over two fifths of the points) and a band of its local spread (:func:`smoothed`): a mode beating
        with a neighbour makes its backbone wiggle, which is not a change with amplitude. False: the points
        joined by a line.
    damping_unit : {"percent", "fraction"}, default="percent"
        The unit of the damping axis.

    Returns
    -------
    ndarray of two Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np
    >>> from sindy_impulse.analysis import Backbone
    >>> data = Backbone(np.geomspace(0.01, 1, 20), np.linspace(10, 10.3, 20), np.full(20, 0.002), "data")
    >>> model = Backbone(np.geomspace(0.01, 1, 50), np.linspace(10, 10.3, 50), np.full(50, 0.002), "model")
    >>> axes = plot_backbone(data, model)
    >>> [ax.get_ylabel() for ax in axes]
    ['natural frequency (Hz)', 'damping ratio (%)']
    """
    from .._utils.units import DAMPING_UNITS, check_damping_unit

    if not backbones:
        raise ValueError("plot_backbone needs at least one Backbone")
    for i, b in enumerate(backbones):
        if not all(hasattr(b, name) for name in ("amplitude", "frequency_hz", "damping_ratio")):
            raise TypeError(f"backbones[{i}] must be a Backbone, got {type(b).__name__}")
    scale, symbol, _ = DAMPING_UNITS[check_damping_unit(damping_unit)]
    ax_f, ax_z = _two_axes(axes)
    for i, (b, label) in enumerate(zip(backbones, _labels(backbones, labels))):
        style = dict(_STYLE.get(getattr(b, "source", ""), _STYLE["model"]), color=f"C{i % 10}")
        a = np.asarray(b.amplitude, dtype=float)
        _draw(ax_f, a, np.asarray(b.frequency_hz, dtype=float), style, label, spread)
        _draw(ax_z, a, scale * np.asarray(b.damping_ratio, dtype=float), style, label, spread)
    for ax in (ax_f, ax_z):
        ax.set_xlabel("amplitude")
        if log_amplitude:
            ax.set_xscale("log")
            log_ticks(ax, "x")
        ax.grid(True, which="both", alpha=0.3)
    ax_f.set_ylabel("natural frequency (Hz)")
    ax_z.set_ylabel("damping ratio" + (f" ({symbol.strip()})" if symbol else ""))
    ax_f.legend(loc="best", fontsize="small")
    return np.array([ax_f, ax_z], dtype=object)

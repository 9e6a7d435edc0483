"""Backbone curves of data and models overlaid: natural frequency and damping ratio against amplitude.

Reads only the public attributes of
:class:`~sindy_impulse.analysis.Backbone` (``amplitude``, ``frequency_hz``, ``damping_ratio``, ``source``);
matplotlib is imported only when the function is called, and ``plt.show()`` is never called.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["plot_backbone"]

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


def plot_backbone(*backbones, axes=None, labels=None, log_amplitude: bool = True) -> np.ndarray:
    """Overlay backbone curves: frequency against amplitude (left), damping ratio against amplitude (right).

    Data curves (``source="data"``) are drawn as solid lines with markers, model curves dashed.

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
        Logarithmic amplitude axis.

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
    if not backbones:
        raise ValueError("plot_backbone needs at least one Backbone")
    for i, b in enumerate(backbones):
        if not all(hasattr(b, name) for name in ("amplitude", "frequency_hz", "damping_ratio")):
            raise TypeError(f"backbones[{i}] must be a Backbone, got {type(b).__name__}")
    ax_f, ax_z = _two_axes(axes)
    for i, (b, label) in enumerate(zip(backbones, _labels(backbones, labels))):
        style = dict(_STYLE.get(getattr(b, "source", ""), _STYLE["model"]), color=f"C{i % 10}", label=label)
        a = np.asarray(b.amplitude, dtype=float)
        ax_f.plot(a, np.asarray(b.frequency_hz, dtype=float), **style)
        ax_z.plot(a, 100 * np.asarray(b.damping_ratio, dtype=float), **style)
    for ax in (ax_f, ax_z):
        ax.set_xlabel("amplitude")
        if log_amplitude:
            ax.set_xscale("log")
        ax.grid(True, which="both", alpha=0.3)
    ax_f.set_ylabel("natural frequency (Hz)")
    ax_z.set_ylabel("damping ratio (%)")
    ax_f.legend(loc="best", fontsize="small")
    return np.array([ax_f, ax_z], dtype=object)

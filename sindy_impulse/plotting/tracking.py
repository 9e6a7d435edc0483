"""Control charts of a tracked structure (:func:`sindy_impulse.tracking.track`): per mode and quantity the
value of every survey with its ±, the reference's mean and the alarm band of a test of typical ±, the
reference surveys apart from the new ones, and the alarms marked.

matplotlib is imported only when the function is called; ``plt.show()`` is never called.
"""

from __future__ import annotations

import numpy as np

from ._common import many_axes

__all__ = ["plot_tracking"]

_LABELS = {
    "frequency_hz": "frequency [Hz]",
    "damping_ratio": "damping ratio [%]",
    "backbone_frequency_shift_hz": "nonlinear frequency shift [Hz]",
    "backbone_damping_shift": "nonlinear damping shift [%]",
    "backbone_frequency_hz": "backbone frequency [Hz]",
    "backbone_damping_ratio": "backbone damping ratio [%]",
}


def _check(result, quantities, modes):
    if not hasattr(result, "series") or not hasattr(result, "tracks"):
        raise TypeError(f"result must be what track returns, got {type(result).__name__}")
    quantities = [quantities] if isinstance(quantities, str) else list(quantities)
    bad = [q for q in quantities if q not in _LABELS]
    if not quantities or bad:
        raise ValueError(f"quantities must be among {list(_LABELS)}, got {bad or quantities}")
    if not result.tracks:
        raise ValueError("the result has no mode to plot: no survey found one")
    if modes is None:
        modes = [j for j in range(len(result.tracks)) if result.testable[j]] or list(
            range(len(result.tracks))
        )
    modes = [int(j) for j in modes]
    if not modes or any(not 0 <= j < len(result.tracks) for j in modes):
        raise ValueError(f"modes must be indices of the {len(result.tracks)} tracked modes, got {modes}")
    return quantities, modes


def _chart(ax, result, quantity: str, j: int) -> None:
    scale = 100.0 if "damping" in quantity else 1.0
    x = np.arange(len(result.values))
    y = result.series["value"][quantity][:, j] * scale
    e = result.series["std"][quantity][:, j] * scale
    ref = np.zeros(x.size, bool)
    ref[result.reference] = True
    e = np.where(np.isfinite(e), e, 0.0)
    ax.errorbar(x[ref], y[ref], yerr=e[ref], fmt="o", ms=3, color="0.5", lw=0.8, label="reference")
    ax.errorbar(x[~ref], y[~ref], yerr=e[~ref], fmt="o", ms=3, color="C0", lw=0.8, label="new")
    tested = quantity in result.quantities
    band = result.limits(quantity, j) if tested else None
    if band is not None:
        mean, low, high = (v * scale for v in band)
        ax.axhline(mean, color="0.3", lw=0.8)
        ax.axhspan(low, high, color="C2", alpha=0.12, lw=0, label=f"no alarm ({100 * result.alpha:g} %)")
    flagged = result.flags[:, j, result.quantities.index(quantity)] if tested else None
    if flagged is not None and flagged.any():
        ax.plot(x[flagged], y[flagged], "x", color="C3", ms=8, mew=2, label="alarm")
    if result.new.size and result.reference.size:
        ax.axvline(result.reference.max() + 0.5, color="0.6", ls=":", lw=1)
    ax.set_ylabel(_LABELS[quantity])
    ax.set_title(f"{result.tracks[j].label(j)}", fontsize=9)


def plot_tracking(result, quantities=("frequency_hz", "damping_ratio"), modes=None, axes=None):
    """Control charts of a :class:`~sindy_impulse.tracking.TrackResult`.

    Parameters
    ----------
    result : TrackResult
    quantities : str or sequence of str
        Among ``frequency_hz``, ``damping_ratio``, ``backbone_frequency_shift_hz``,
        ``backbone_damping_shift`` (tested, with their alarm band) and ``backbone_frequency_hz``,
        ``backbone_damping_ratio`` (the backbone at the common amplitude).
    modes : sequence of int, optional
        The modes (tracks) to show; default the tested ones.
    axes : array of Axes, optional
        ``len(modes) * len(quantities)`` Axes (row by mode); default a new figure.

    Returns
    -------
    ndarray of Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np
    >>> from sindy_impulse.tracking import ModeValues, SurveyValues, track
    >>> rng = np.random.default_rng(0)
    >>> surveys = [SurveyValues([ModeValues(100 * (1 + 3e-4 * rng.standard_normal()), 1e-3, 0.01, 1e-4, 1.0)])
    ...            for _ in range(25)]
    >>> axes = plot_tracking(track(surveys, reference=20))
    >>> axes.shape, axes[0].get_ylabel()
    ((2,), 'frequency [Hz]')
    """
    quantities, modes = _check(result, quantities, modes)
    axes = many_axes(axes, len(modes) * len(quantities), "axes", ncols=len(quantities), sharex=True)
    for k, ax in enumerate(axes):
        _chart(ax, result, quantities[k % len(quantities)], modes[k // len(quantities)])
    axes[0].legend(fontsize=7, loc="best")
    for ax in axes[-len(quantities) :]:
        ax.set_xlabel("survey")
    return axes

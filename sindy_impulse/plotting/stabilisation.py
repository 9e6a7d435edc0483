"""The stabilisation chart: the poles of a record's free decay over the model order, on its spectrum.

Every physical ESPRIT pole is drawn at its undamped natural frequency and model order: stable poles (those
that recur, :mod:`sindy_impulse.poles.stabilisation`) as filled dots, the others as small grey crosses;
the free decay's power spectral density is drawn on a second axis behind them, and the modes of the
survey as dashed lines. matplotlib is imported only when the function is called.
"""

from __future__ import annotations

from numbers import Integral
from typing import TYPE_CHECKING

import numpy as np

from ._common import one_axes

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["plot_stabilisation"]


def plot_stabilisation(survey, record: int = 0, ax: Axes | None = None) -> Axes:
    """Stabilisation chart of one record of a modal survey, over its spectrum.

    Parameters
    ----------
    survey : ModalSurvey
        What :func:`~sindy_impulse.identify_modes` returned (its ``poles`` are computed if not yet).
    record : int, default=0
        Which hit of a survey of repeated hits.
    ax : matplotlib Axes, optional
        Where to draw (the model order); the spectrum goes on a twin axis. Default: a new figure.

    Returns
    -------
    Axes
        The axes of the poles (model order against frequency).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sindy_impulse import identify_modes, impact_record
    >>> rec = impact_record([120.0, 240.0], [0.005, 0.01], fs=2000, duration=1.0, snr_db=50, random_state=0)
    >>> ax = plot_stabilisation(identify_modes(rec.y, fs=rec.fs))
    >>> ax.get_ylabel()
    'model order'
    """
    if not (hasattr(survey, "poles") and hasattr(survey, "preprocessing") and hasattr(survey, "modes")):
        raise TypeError(f"survey must be what identify_modes returns, got {type(survey).__name__}")
    if not isinstance(record, Integral) or isinstance(record, bool):
        raise TypeError(f"record must be an integer, got {type(record).__name__}")
    if not 0 <= record < len(survey.preprocessing):
        raise ValueError(f"record must be in [0, {len(survey.preprocessing) - 1}], got {record}")
    ax = one_axes(ax)
    table, pre = survey.poles[record], survey.preprocessing[record]
    decay = pre.y[pre.impact.ringdown_index :]
    spectrum = ax.twinx()
    if decay.size >= 8:
        window = np.hanning(decay.size)
        psd = np.abs(np.fft.rfft((decay - decay.mean()) * window)) ** 2
        spectrum.semilogy(np.fft.rfftfreq(decay.size, 1.0 / pre.fs), psd, color="0.75", lw=0.8, zorder=0)
    spectrum.set_ylabel("PSD of the free decay")
    spectrum.set_yticks([])
    ax.set_zorder(spectrum.get_zorder() + 1)
    ax.patch.set_visible(False)
    stable = table.stable
    ax.plot(table.frequency_hz[~stable], table.order[~stable], "+", color="0.5", ms=4, label="pole")
    ax.plot(table.frequency_hz[stable], table.order[stable], "o", color="C0", ms=4, label="stable")
    for k, mode in enumerate(survey.modes):  # with repeated hits: the structure's modes, in every record
        label = f"mode {k}: {mode.frequency_hz:.5g} Hz"
        ax.axvline(mode.frequency_hz, color=f"C{(k + 1) % 10}", ls="--", lw=1.0, label=label)
    ax.set_xlim(0, pre.fs / 2)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("model order")
    ax.legend(loc="upper right", frameon=False, fontsize="small")
    return ax

"""The stabilisation chart: the poles of a record's free decay over the model order, on its spectrum.

Every physical ESPRIT pole is drawn at its undamped natural frequency and model order: stable poles (those
that recur, :mod:`sindy_impulse.poles.stabilisation`) as filled dots, the others as small grey crosses;
the free decay's power spectral density is drawn on its own axis with its ticks (above the chart, or on a
twin axis), and the modes of the survey as dashed lines. matplotlib is imported only when the function is
called.
"""

from __future__ import annotations

from numbers import Integral
from typing import TYPE_CHECKING

import numpy as np

from ._common import one_axes, positive

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["plot_stabilisation"]


def _new_axes():
    """A new figure: the spectrum above the stabilisation chart, sharing the frequency axis."""
    import matplotlib.pyplot as plt

    fig, (top, bottom) = plt.subplots(
        2, 1, figsize=(9, 5), sharex=True, layout="constrained", gridspec_kw={"height_ratios": [1, 1.6]}
    )
    return bottom, top


def _spectrum(ax, pre, twin: bool) -> None:
    """The free decay's power spectral density (Hann window) on ``ax``, on a log axis with its ticks."""
    decay = pre.y[pre.impact.ringdown_index :]
    if decay.size >= 8:
        window = np.hanning(decay.size)
        psd = np.abs(np.fft.rfft((decay - decay.mean()) * window)) ** 2 / (pre.fs * np.sum(window**2))
        ax.semilogy(np.fft.rfftfreq(decay.size, 1.0 / pre.fs), positive(psd), color="0.35", lw=0.8,
                    label="PSD of the free decay")
    ax.set_ylabel("PSD of the free decay" + ("" if twin else "\n[unit²/Hz]"))
    if not twin:
        ax.grid(True, which="major", alpha=0.3)


def _upper_frequency(table, survey, fs: float) -> float:
    """The chart's right edge: a quarter beyond the highest mode or stable pole, at most Nyquist."""
    highs = [m.band_hz[1] for m in survey.modes]
    highs += list(np.asarray(table.frequency_hz)[np.asarray(table.stable)])
    highs += [r.band_hz[1] for r in survey.rejected if r.band_hz is not None]
    return fs / 2 if not highs else min(fs / 2, 1.25 * max(highs))


def plot_stabilisation(
    survey, record: int = 0, ax: Axes | None = None, spectrum_ax: Axes | None = None
) -> Axes:
    """Stabilisation chart of one record of a modal survey, under its spectrum.

    Parameters
    ----------
    survey : ModalSurvey
        What :func:`~sindy_impulse.identify_modes` returned (its ``poles`` are computed if not yet).
    record : int, default=0
        Which hit of a survey of repeated hits.
    ax : matplotlib Axes, optional
        Where to draw the poles (model order against frequency).
    spectrum_ax : matplotlib Axes, optional
        Where to draw the free decay's power spectral density (log axis, with its ticks). Default: with
        ``ax`` given, a twin axis on its right; without, the upper panel of a new figure (the chart below,
        the frequency axis shared).

    Returns
    -------
    Axes
        The axes of the poles (model order against frequency); the frequency axis ends a quarter beyond
        the highest mode, band or stable pole (at most at Nyquist).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sindy_impulse import identify_modes, impact_record
    >>> rec = impact_record([120.0, 240.0], [0.005, 0.01], fs=2000, duration=1.0, snr_db=50, random_state=0)
    >>> ax = plot_stabilisation(identify_modes(rec.y, fs=rec.fs))
    >>> ax.get_ylabel(), len(ax.figure.axes), bool(ax.get_xlim()[1] < 1000)
    ('model order', 2, True)
    """
    if not (hasattr(survey, "poles") and hasattr(survey, "preprocessing") and hasattr(survey, "modes")):
        raise TypeError(f"survey must be what identify_modes returns, got {type(survey).__name__}")
    if not isinstance(record, Integral) or isinstance(record, bool):
        raise TypeError(f"record must be an integer, got {type(record).__name__}")
    if not 0 <= record < len(survey.preprocessing):
        raise ValueError(f"record must be in [0, {len(survey.preprocessing) - 1}], got {record}")
    if ax is None and spectrum_ax is None:
        ax, spectrum_ax = _new_axes()
    ax = one_axes(ax)
    twin = spectrum_ax is None
    spectrum_ax = ax.twinx() if twin else one_axes(spectrum_ax, name="spectrum_ax")
    table, pre = survey.poles[record], survey.preprocessing[record]
    _spectrum(spectrum_ax, pre, twin)
    if twin:  # the poles in front of the spectrum
        ax.set_zorder(spectrum_ax.get_zorder() + 1)
        ax.patch.set_visible(False)
    stable = table.stable
    ax.plot(table.frequency_hz[~stable], table.order[~stable], "+", color="0.5", ms=4, label="pole")
    ax.plot(table.frequency_hz[stable], table.order[stable], "o", color="C0", ms=4, label="stable")
    for k, mode in enumerate(survey.modes):  # with repeated hits: the structure's modes, in every record
        label = f"mode {k}: {mode.frequency_hz:.5g} Hz"
        for target in (ax,) if twin else (ax, spectrum_ax):
            target.axvline(mode.frequency_hz, color=f"C{(k + 1) % 10}", ls="--", lw=1.0,
                           label=label if target is ax else None)
    ax.set_xlim(0, _upper_frequency(table, survey, pre.fs))
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("model order")
    ax.legend(loc="upper right", frameon=False, fontsize="small")
    return ax

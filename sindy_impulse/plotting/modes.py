"""The modal survey: the record's spectrum with the modes marked, and each mode's data against its model."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ._common import INPUT_STYLE, MODEL_STYLE, many_axes

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["plot_modes"]

#: Periods of each mode drawn against its model (from the start of its band signal).
_PERIODS_SHOWN = 12


def _spectrum_panel(ax: Axes, survey) -> None:
    pre = survey.preprocessing[0]
    spectrum = pre.peaks.spectrum
    ax.semilogy(spectrum.frequency_hz, spectrum.psd, color="0.4", lw=0.8, label="ring-down PSD")
    ax.semilogy(spectrum.frequency_hz, spectrum.floor, color="0.7", lw=1.0, ls=":", label="noise floor")
    for k, mode in enumerate(survey.modes):
        ax.axvspan(*mode.band_hz, color=f"C{k % 10}", alpha=0.15, lw=0)
        ax.axvline(
            mode.frequency_hz, color=f"C{k % 10}", lw=1.0, label=f"mode {k}: {mode.frequency_hz:.5g} Hz"
        )
    for r in survey.rejected:
        if r.band_hz is not None:  # a row about a whole record has no band to shade
            ax.axvspan(*r.band_hz, color="k", alpha=0.06, lw=0, hatch="//")
    high = max([m.band_hz[1] for m in survey.modes] + [spectrum.frequency_hz[-1] * 0.5])
    ax.set_xlim(0, min(spectrum.frequency_hz[-1], 1.2 * high))
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("PSD")
    ax.legend(loc="upper right", frameon=False, fontsize="small")


def _mode_panel(ax: Axes, k: int, mode) -> None:
    n = int(min(len(mode.t), round(_PERIODS_SHOWN / (mode.frequency_hz * (mode.t[1] - mode.t[0])))))
    t, y = mode.t[:n], mode.states[:n, 0]
    ax.plot(t, y, label="band signal", **INPUT_STYLE)
    sim = mode.model.simulate(mode.states[0], t)
    ax.plot(t, sim[:, 0], label="model", **MODEL_STYLE)
    ax.set_title(
        f"mode {k}: {mode.frequency_hz:.5g} Hz, damping ratio {mode.damping_ratio:.3g}, "
        f"fit error {mode.fit_error:.2g}",
        fontsize="small",
    )
    ax.set_xlabel("t [s]")
    ax.legend(loc="upper right", frameon=False, fontsize="small")


def plot_modes(survey, axes=None) -> np.ndarray:
    """The spectrum of a hammer-test record with the identified modes, then each mode against its model.

    Parameters
    ----------
    survey : ModalSurvey
        The result of :func:`sindy_impulse.identify_modes`.
    axes : sequence of ``1 + len(survey.modes)`` Axes, optional

    Returns
    -------
    ndarray of Axes
        The spectrum (bands shaded, modes marked, rejected bands hatched), then per mode its band signal and
        the model simulated from the band's first state over the first periods.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sindy_impulse import identify_modes, impact_record
    >>> from sindy_impulse.plotting import plot_modes
    >>> rec = impact_record([120.0], [0.01], fs=2000, duration=1.0, snr_db=50, random_state=0)
    >>> axes = plot_modes(identify_modes(rec.y, fs=rec.fs))
    >>> len(axes), axes[0].get_yscale()
    (2, 'log')
    """
    if not (hasattr(survey, "modes") and hasattr(survey, "preprocessing")):
        raise TypeError(f"survey must be the result of identify_modes, got {type(survey).__name__}")
    axes = many_axes(axes, 1 + len(survey.modes), name="axes")
    _spectrum_panel(axes[0], survey)
    for k, mode in enumerate(survey.modes):
        _mode_panel(axes[k + 1], k, mode)
    return axes

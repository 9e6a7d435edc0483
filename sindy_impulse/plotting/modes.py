"""The modal survey: the record's spectrum with the modes marked, and each mode's data against its model,
over the whole decay (log envelope) and in a zoom on its first periods."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ._common import INPUT_STYLE, MODEL_STYLE, log_ticks, many_axes, positive

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["plot_modes", "plot_mode_decay"]

#: Periods of each mode drawn against its model in the zoom (from the start of its band signal).
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
    ax.set_title("spectrum of the ring-down, bands shaded", fontsize="small")
    ax.legend(loc="upper right", frameon=False, fontsize="small")


def _simulation(mode) -> np.ndarray:
    """The mode's model simulated from the band's first state over the whole band signal (NaN if it
    cannot be simulated)."""
    try:
        sim = np.asarray(mode.model.simulate(mode.states[0], mode.t), dtype=float)
    except (ValueError, RuntimeError, FloatingPointError):
        return np.full(mode.states.shape, np.nan)
    if sim.shape != mode.states.shape:  # a simulation stopped early (diverged): pad with NaN
        sim = np.vstack([sim, np.full((len(mode.t) - len(sim), mode.states.shape[1]), np.nan)])
    return sim


def _envelopes(mode, sim: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The peak envelopes (largest magnitude within one period around each sample) of a mode's band
    signal and of its model's simulation ``sim``: smooth on a log axis, no end effects."""
    from scipy.ndimage import maximum_filter1d

    c = getattr(mode, "coordinate_", 0)
    step = float(np.median(np.diff(mode.t))) if len(mode.t) > 1 else 1.0
    width = max(1, int(round(1.0 / (max(mode.damped_frequency_hz, 1e-300) * step))))
    data, model = mode.states[:, c], sim[:, c]
    envelope = [maximum_filter1d(np.abs(v), size=min(width, len(v)), mode="nearest") for v in (data, model)]
    return envelope[0], envelope[1]


def _record_decay(mode, record):
    """The record's free decay band-passed to the mode's band: ``(t, envelope)`` on the record's clock, from
    the end of the hit to the end of the record (None when it cannot be formed)."""
    from ..preprocessing import bandpass

    start = record.impact.ringdown_index
    y = np.asarray(record.y[start:], dtype=float)
    low, high = mode.band_hz
    if y.size < 8 or not (0 < low < high < record.fs / 2):
        return None
    envelope = np.abs(bandpass(y, record.fs, (low, high), analytic=True))
    return record.t0 + (start + np.arange(y.size)) / record.fs, envelope


def _model_to(mode, end: float):
    """The model's free decay from the band's first state to ``end`` (record clock) at the band's rate, as
    ``(t, peak envelope)``; None if it cannot be simulated."""
    from scipy.ndimage import maximum_filter1d

    fs = mode.fitted_fs
    n = int(np.floor((end - mode.t[0]) * fs)) + 1
    if not (np.isfinite(fs) and n > len(mode.t)):
        return None
    t = mode.t[0] + np.arange(n) / fs
    try:
        sim = np.asarray(mode.model.simulate(mode.states[0], t), dtype=float)
    except (ValueError, RuntimeError, FloatingPointError):
        return None
    sim = sim[:, getattr(mode, "coordinate_", 0)]
    width = max(1, int(round(fs / max(mode.damped_frequency_hz, 1e-300))))
    envelope = maximum_filter1d(np.abs(sim), size=min(width, len(sim)), mode="nearest")
    return t[: len(envelope)], envelope


def _decay_panel(ax: Axes, k, mode, sim: np.ndarray, record=None, damping_unit: str = "percent") -> None:
    """The whole decay: with the ``record``, its free decay band-passed to the mode's band from the hit to
    the end and the model's free decay over the same span, the fitted stretch shaded; the peak envelopes of
    the band signal and of the model on a log axis."""
    from .._utils.units import damping_text

    t = np.asarray(mode.t)
    data, model = _envelopes(mode, sim)
    whole = None if record is None else _record_decay(mode, record)
    if whole is not None:
        ax.semilogy(whole[0], positive(whole[1]), color="0.75", lw=0.8, label="record, band-passed")
        extended = _model_to(mode, whole[0][-1])
        if extended is not None:
            ax.semilogy(extended[0], positive(extended[1]), color="C3", lw=0.8, ls=":",
                        label="model, extended")
        ax.axvspan(t[0], t[-1], color="C0", alpha=0.06, lw=0)
        ax.set_xlim(whole[0][0], whole[0][-1])
        floor = np.percentile(whole[1][whole[1] > 0], 1) if np.any(whole[1] > 0) else None
        if floor is not None and extended is not None:  # the model below the record's noise: not drawn down
            ax.set_ylim(bottom=0.3 * min(floor, float(np.min(positive(data)))))
    ax.semilogy(t, positive(data), label="band signal (fitted)", **INPUT_STYLE)
    ax.semilogy(t, positive(model), label="model", **MODEL_STYLE)
    ax.set_title(
        f"mode {k}: {mode.frequency_hz:.5g} Hz, damping {damping_text(mode.damping_ratio, damping_unit, 3)}, "
        f"fit error {mode.fit_error:.2g}",
        fontsize="small",
    )
    ax.set_xlabel("t [s]")
    ax.set_ylabel("envelope")
    log_ticks(ax, "y")
    ax.legend(loc="best", frameon=False, fontsize="x-small")


def _zoom_panel(ax: Axes, k: int, mode, sim: np.ndarray) -> None:
    """The first periods of the band signal against the model."""
    n = int(min(len(mode.t), round(_PERIODS_SHOWN / (mode.frequency_hz * (mode.t[1] - mode.t[0])))))
    c = getattr(mode, "coordinate_", 0)
    t, y = mode.t[:n], mode.states[:n, c]
    ax.plot(t, y, label="band signal", **INPUT_STYLE)
    ax.plot(t, sim[:n, c], label="model", **MODEL_STYLE)
    from matplotlib.ticker import MaxNLocator

    ax.set_title(f"mode {k}: the first {_PERIODS_SHOWN} periods (band signal grey, model dashed)",
                 fontsize="small")
    ax.set_xlabel("t [s]")
    ax.xaxis.set_major_locator(MaxNLocator(nbins=5))  # a short span: long labels (0.2325), few of them


def _check_mode(mode) -> None:
    if not all(hasattr(mode, name) for name in ("model", "states", "t", "frequency_hz")):
        raise TypeError(f"mode must be a Mode of a ModalSurvey, got {type(mode).__name__}")


def plot_mode_decay(mode, axes=None, label: int | str = 0, record=None,
                    damping_unit: str = "percent") -> np.ndarray:
    """One mode's band signal against its model: the whole decay as log envelopes, and a zoom.

    Parameters
    ----------
    mode : Mode
        A mode of :func:`sindy_impulse.identify_modes`'s survey.
    axes : sequence of two Axes, optional
        Where to draw the decay and the zoom; default: a new figure (constrained layout).
    label : int or str, default=0
        The mode's name in the titles (its index in the table).
    record : Preprocessed, optional
        The record the mode comes from (``survey.preprocessing[mode.record]``): the decay panel then spans
        the whole free decay, from the end of the hit to the end of the record (the band signal the model
        was fitted on is often a stretch of it), with the record band-passed to the mode's band and the
        model's free decay carried on to the end.
    damping_unit : {"percent", "fraction"}, default="percent"
        The damping ratio's unit in the title.

    Returns
    -------
    ndarray of two Axes
        The peak envelopes (largest magnitude within one period) of the band signal and of the model
        simulated from the band's first state over the whole band (and, with ``record``, over the whole
        free decay), on a log axis; then the first 12 periods of both.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sindy_impulse import identify_modes, impact_record
    >>> rec = impact_record([120.0], [0.01], fs=2000, duration=1.0, snr_db=50, random_state=0)
    >>> decay, zoom = plot_mode_decay(identify_modes(rec.y, fs=rec.fs).modes[0])
    >>> decay.get_yscale(), bool(decay.get_xlim()[1] > 0.9), bool(zoom.get_xlim()[1] < 0.3)
    ('log', True, True)
    """
    _check_mode(mode)
    if axes is None:
        import matplotlib.pyplot as plt

        _, axes = plt.subplots(1, 2, figsize=(9, 3), layout="constrained")
    decay, zoom = many_axes(axes, 2, name="axes")
    sim = _simulation(mode)
    _decay_panel(decay, label, mode, sim, record, damping_unit)
    _zoom_panel(zoom, label, mode, sim)
    return np.array([decay, zoom], dtype=object)


def _new_figure(n_modes: int) -> np.ndarray:
    """The spectrum across the top, then one row per mode (decay, zoom), in a constrained layout."""
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(9, 2.8 * (1 + n_modes)), layout="constrained")
    grid = fig.add_gridspec(1 + n_modes, 2)
    axes = [fig.add_subplot(grid[0, :])]
    for k in range(n_modes):
        axes += [fig.add_subplot(grid[k + 1, 0]), fig.add_subplot(grid[k + 1, 1])]
    return np.array(axes, dtype=object)


def plot_modes(survey, axes=None, damping_unit: str = "percent") -> np.ndarray:
    """The spectrum of a hammer-test record with the identified modes, then each mode against its model.

    Parameters
    ----------
    survey : ModalSurvey
        The result of :func:`sindy_impulse.identify_modes`.
    axes : sequence of ``1 + 2 * len(survey.modes)`` Axes, optional
        Default: a new figure in a constrained layout (no text overlaps).
    damping_unit : {"percent", "fraction"}, default="percent"
        The damping ratios' unit in the titles.

    Returns
    -------
    ndarray of Axes
        The spectrum (bands shaded, modes marked, rejected bands hatched), then per mode two panels
        (:func:`plot_mode_decay`): the whole free decay of the record in the mode's band, its band signal
        and its model as log envelopes, and the first 12 periods of both.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from sindy_impulse import identify_modes, impact_record
    >>> from sindy_impulse.plotting import plot_modes
    >>> rec = impact_record([120.0], [0.01], fs=2000, duration=1.0, snr_db=50, random_state=0)
    >>> axes = plot_modes(identify_modes(rec.y, fs=rec.fs))
    >>> len(axes), axes[0].get_yscale(), axes[1].get_yscale()
    (3, 'log', 'log')
    """
    if not (hasattr(survey, "modes") and hasattr(survey, "preprocessing")):
        raise TypeError(f"survey must be the result of identify_modes, got {type(survey).__name__}")
    n = 1 + 2 * len(survey.modes)
    axes = _new_figure(len(survey.modes)) if axes is None else many_axes(axes, n, name="axes")
    _spectrum_panel(axes[0], survey)
    for k, mode in enumerate(survey.modes):
        record = survey.preprocessing[mode.record] if mode.record < len(survey.preprocessing) else None
        plot_mode_decay(mode, axes=axes[1 + 2 * k : 3 + 2 * k], label=k, record=record,
                        damping_unit=damping_unit)
    return axes

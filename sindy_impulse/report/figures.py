"""The figures of a report, drawn by :mod:`sindy_impulse.plotting` on off-screen matplotlib figures and
returned as inline images (``data:image/png;base64,...``): the page needs no other file.

No pyplot: each figure is a :class:`matplotlib.figure.Figure` of its own, so a report neither opens a
window nor touches the user's current figure.
"""

from __future__ import annotations

import base64
import io
import warnings

import numpy as np

__all__ = [
    "png_uri",
    "record_figure",
    "spectrum_figure",
    "decay_figure",
    "backbone_figure",
    "mode_backbones",
    "draw_record",
    "draw_spectrum",
    "draw_decay",
    "draw_backbone",
]

#: Resolution of the inline images (dots per inch).
DPI = 90
#: The smallest relative spans of a backbone's frequency and damping-ratio axes: the changes the test
#: for nonlinearity resolves (0.1 % and 5 %, ``analysis.nonlinearity_test``).
BACKBONE_RESOLUTION = (1e-3, 0.05)
#: Colours of the inline images' palette.
COLORS = 256


def _figure(width: float, height: float):
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height), dpi=DPI, layout="constrained")


def png_uri(fig) -> str:
    """A matplotlib figure as an inline PNG (a ``data:`` URI) of :data:`COLORS` colours (line figures lose
    nothing visible; the file is much smaller than matplotlib's).

    Examples
    --------
    >>> from matplotlib.figure import Figure
    >>> fig = Figure(figsize=(1, 1))
    >>> _ = fig.subplots().plot([0, 1])
    >>> png_uri(fig).startswith("data:image/png;base64,iVBORw0KGgo")
    True
    """
    from PIL import Image  # matplotlib's own dependency

    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=DPI)
    buffer.seek(0)
    method = getattr(getattr(Image, "Quantize", None), "MAXCOVERAGE", 1)  # 1 before Pillow 9.1
    image = Image.open(buffer).convert("RGB").quantize(colors=COLORS, method=method)
    small = io.BytesIO()
    image.save(small, format="PNG", optimize=True)
    return "data:image/png;base64," + base64.b64encode(small.getvalue()).decode("ascii")


def draw_record(pre):
    """The figure of :func:`record_figure`."""
    fig = _figure(9, 2.4)
    ax = fig.subplots()
    t = pre.t0 + np.arange(len(pre.y)) / pre.fs
    ax.plot(t, pre.y, color="0.3", lw=0.6)
    ax.axvline(pre.t0 + pre.impact.onset_index / pre.fs, color="C3", ls=":", lw=1.2, label="hit")
    ax.axvline(pre.t0 + pre.impact.ringdown_index / pre.fs, color="C2", ls="--", lw=1.0, label="free decay")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("record, offset removed")
    ax.legend(loc="upper right", frameon=False, fontsize="small")
    return fig


def record_figure(pre) -> str:
    """One record as preprocessed (offset removed), the hit and the start of the free decay marked.

    Examples
    --------
    >>> from sindy_impulse import identify_modes, impact_record
    >>> rec = impact_record([120.0], [0.01], fs=2000, duration=0.5, snr_db=50, random_state=0)
    >>> survey = identify_modes(rec.y, fs=rec.fs)
    >>> record_figure(survey.preprocessing[0])[:22]
    'data:image/png;base64,'
    """
    return png_uri(draw_record(pre))


def draw_spectrum(survey, record: int = 0):
    """The figure of :func:`spectrum_figure`."""
    from ..plotting import plot_stabilisation

    fig = _figure(9, 5.0)
    top, bottom = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [1, 1.6]})
    ax = plot_stabilisation(survey, record=record, ax=bottom, spectrum_ax=top)
    for target in (top, ax):
        for k, mode in enumerate(survey.modes):
            target.axvspan(*mode.band_hz, color=f"C{(k + 1) % 10}", alpha=0.15, lw=0)
        for r in survey.rejected:
            if r.band_hz is not None and r.record == record:
                target.axvspan(*r.band_hz, color="k", alpha=0.06, lw=0, hatch="//")
    top.set_title("spectrum of the free decay (above) and stabilisation chart (below); bands shaded",
                  fontsize="small")
    if ax.get_legend() is not None:  # one entry per mode: beside the chart, not over its poles
        ax.get_legend().remove()
        handles, labels = ax.get_legend_handles_labels()
        try:
            fig.legend(handles, labels, loc="outside right upper", frameon=False, fontsize="small")
        except ValueError:  # matplotlib before 3.7: no "outside" legends
            ax.legend(handles, labels, loc="upper right", frameon=False, fontsize="small")
    return fig


def spectrum_figure(survey, record: int = 0) -> str:
    """The free decay's spectrum on its own axis (log scale, with its ticks) above the stabilisation chart
    (:func:`plotting.plot_stabilisation`), the frequency axis shared, each mode's band shaded.

    Examples
    --------
    >>> from sindy_impulse import identify_modes, impact_record
    >>> rec = impact_record([120.0], [0.01], fs=2000, duration=0.5, snr_db=50, random_state=0)
    >>> survey = identify_modes(rec.y, fs=rec.fs)
    >>> spectrum_figure(survey)[:22]
    'data:image/png;base64,'
    """
    return png_uri(draw_spectrum(survey, record))


def draw_decay(mode, label, record=None, damping_unit: str = "percent"):
    """The figure of :func:`decay_figure`."""
    from ..plotting import plot_mode_decay

    fig = _figure(9, 3.0)
    plot_mode_decay(mode, axes=fig.subplots(1, 2), label=label, record=record, damping_unit=damping_unit)
    return fig


def decay_figure(mode, label, record=None, damping_unit: str = "percent") -> str:
    """The mode's band signal against its model: the whole free decay (log envelopes; with ``record``, the
    record band-passed to the mode's band from the hit to its end, the fitted stretch shaded) and a zoom
    (:func:`plotting.plot_mode_decay`).

    Examples
    --------
    >>> from sindy_impulse import identify_modes, impact_record
    >>> rec = impact_record([120.0], [0.01], fs=2000, duration=0.5, snr_db=50, random_state=0)
    >>> survey = identify_modes(rec.y, fs=rec.fs)
    >>> decay_figure(survey.modes[0], 0, survey.preprocessing[0])[:22]
    'data:image/png;base64,'
    """
    return png_uri(draw_decay(mode, label, record, damping_unit))


def _model_curve(mode, nonlinearity: bool):
    from ..analysis import backbone

    return mode.backbone if nonlinearity else backbone(mode.model, coordinate=mode.coordinate_)


def _data_curve(mode, nonlinearity: bool):
    from ..analysis import hilbert_backbone

    curve = mode.nonlinearity.backbone_data if nonlinearity else None
    return curve if curve is not None else hilbert_backbone(mode.states[:, mode.coordinate_], mode.t)


def mode_backbones(mode, nonlinearity: bool) -> list:
    """The backbones to show for a mode: the model's (``mode.backbone``, or the model's own when the test
    for nonlinearity is skipped) and the data's (the test's when it has one, else a Hilbert backbone of the
    band signal); those that cannot be computed are left out.

    Examples
    --------
    >>> from sindy_impulse import identify_modes, impact_record
    >>> rec = impact_record([120.0], [0.01], fs=2000, duration=0.5, snr_db=50, random_state=0)
    >>> survey = identify_modes(rec.y, fs=rec.fs)
    >>> [curve.source for curve in mode_backbones(survey.modes[0], nonlinearity=False)]
    ['model', 'data']
    """
    curves = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the survey has already warned about its modes
        for make in (_model_curve, _data_curve):
            try:
                curve = make(mode, nonlinearity)
            except (ValueError, RuntimeError, FloatingPointError):
                continue
            if curve is not None and len(curve) and np.isfinite(curve.frequency_hz).any():
                curves.append(curve)
    return curves


def draw_backbone(curves: list, damping_unit: str = "percent"):
    """The figure of :func:`backbone_figure`."""
    from ..plotting import plot_backbone

    fig = _figure(9, 3.0)
    axes = plot_backbone(*curves, axes=list(fig.subplots(1, 2)), damping_unit=damping_unit)
    for ax, resolution in zip(axes, BACKBONE_RESOLUTION):
        _at_least(ax, resolution)
    return fig


def backbone_figure(curves: list, damping_unit: str = "percent") -> str:
    """Backbones (frequency and damping ratio against amplitude, :func:`plotting.plot_backbone`): the data's
    as its points, its trend and the band of its spread (beating with a neighbouring mode is spread, not
    a change with amplitude), the model's as a line.

    Examples
    --------
    >>> from sindy_impulse import identify_modes, impact_record
    >>> rec = impact_record([120.0], [0.01], fs=2000, duration=0.5, snr_db=50, random_state=0)
    >>> survey = identify_modes(rec.y, fs=rec.fs)
    >>> backbone_figure(mode_backbones(survey.modes[0], nonlinearity=False))[:22]
    'data:image/png;base64,'
    """
    return png_uri(draw_backbone(curves, damping_unit))


def _at_least(ax, resolution: float) -> None:
    """Widen the y axis to ``+-resolution`` (relative) about its middle when the curves span less: a flat
    backbone is drawn flat, not as its last digits under an offset."""
    low, high = ax.get_ylim()
    middle = 0.5 * (low + high)
    if np.isfinite(middle) and middle > 0 and high - low < 2 * resolution * middle:
        ax.set_ylim(middle * (1 - resolution), middle * (1 + resolution))

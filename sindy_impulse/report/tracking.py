"""A tracked structure (:func:`sindy_impulse.tracking.track`) as a section of HTML and as one page: the
settings, the modes with their reference values, the alarms one line each, the term of each changed mode's
equation that carries the change, the trends, the modes missed or appeared, and the control charts.

The page is self-contained like the survey's (:mod:`.html`: the same style sheet, inline images).
"""

from __future__ import annotations

import math
from html import escape

from .figures import _figure, png_uri
from .html import _facts, _img, html_page

__all__ = ["tracking_section", "track_html"]

#: Alarms listed one per line; beyond this many, the count of the others.
MAX_LINES = 200


def _value(x: float, digits: int = 6) -> str:
    return f"{x:.{digits}g}" if math.isfinite(x) else "-"


def _modes_table(result) -> str:
    head = [
        "mode",
        "f_n [Hz]",
        "in reference",
        "tested",
        "reference f_n [Hz] (scatter)",
        "reference damping [%] (scatter)",
        "backbone amplitude",
        "new surveys changed",
        "new surveys without it",
    ]
    rows = []
    changed = result.changed_modes
    for j, tr in enumerate(result.tracks):
        f, fs = result.reference_mean("frequency_hz", j), result.reference_std("frequency_hz", j)
        z, zs = result.reference_mean("damping_ratio", j), result.reference_std("damping_ratio", j)
        cells = [
            str(j),
            _value(tr.frequency_hz),
            "yes" if tr.in_reference else "no",
            "yes" if result.testable[j] else "no",
            f"{_value(f)} ({_value(fs, 2)})",
            f"{_value(100 * z, 4)} ({_value(100 * zs, 2)})",
            _value(result.amplitudes[j], 4),
            str(int(changed[result.new, j].sum())),
            str(int((result.slot[result.new, j] < 0).sum())),
        ]
        rows.append("<tr>" + "".join(f"<td>{escape(c)}</td>" for c in cells) + "</tr>")
    header = "".join(f"<th>{escape(h)}</th>" for h in head)
    return f"<table><tr>{header}</tr>{''.join(rows)}</table>"


def _terms_table(alarm, result) -> str:
    head = [
        "term",
        "status",
        "reference (scatter)",
        "this survey (±)",
        "t",
        "p",
        "frequency shift at the hit [%]",
        "damping shift at the hit [%]",
    ]
    rows = []
    for c in alarm.terms:
        df, dz = 100 * c.relative_frequency_shift, 100 * c.relative_damping_shift
        cells = [
            f"{c.name} ({c.key})",
            c.status + (" *" if c is alarm.term else ""),
            f"{_value(c.reference, 5)} ({_value(c.reference_std, 2)})",
            f"{_value(c.value, 5)} ({_value(c.std, 2)})",
            _value(c.t, 3),
            _value(c.p, 2),
            _value(df, 3),
            _value(dz, 3),
        ]
        rows.append("<tr>" + "".join(f'<td class="text">{escape(x)}</td>' for x in cells) + "</tr>")
    header = "".join(f"<th>{escape(h)}</th>" for h in head)
    return f"<table><tr>{header}</tr>{''.join(rows)}</table>"


def _charts(result) -> str:
    from ..plotting import plot_tracking

    modes = [j for j in range(len(result.tracks)) if result.testable[j]]
    if not modes:
        return "<p>No mode has enough reference surveys to be tested.</p>"
    quantities = ("frequency_hz", "damping_ratio", "backbone_frequency_shift_hz")
    fig = _figure(10, 2.2 * len(modes) + 0.6)
    axes = fig.subplots(len(modes), len(quantities), squeeze=False, sharex=True)
    plot_tracking(result, quantities=quantities, modes=modes, axes=axes.ravel())
    return _img(png_uri(fig), "control charts")


def tracking_section(result, source: str | None = None) -> str:
    """The tracking section of a report (HTML, escaped): settings, modes, alarms with their terms,
    trends, events and control charts."""
    n_new = len(result.new)
    facts = [
        ("surveys", f"{len(result.values)}: {len(result.reference)} reference, {n_new} new"),
        (
            "false-alarm rate",
            f"{100 * result.alpha:g} % per survey (every mode and quantity together), "
            "and per sequence for the trends",
        ),
        ("changed", f"{int(result.changed.sum())} of {n_new} new surveys"),
        ("trends", f"{len(result.trend_alarms)} significant"),
        ("modes vanished or appeared", f"{len(result.event_alarms)} beyond chance"),
    ]
    if source:
        facts.insert(0, ("source", source))
    parts = [
        '<section id="tracking"><h2>Tracking</h2>',
        _facts(facts),
        "<h3>Modes</h3>",
        _modes_table(result),
    ]
    lines = [a.text(result) for a in result.alarms]
    parts.append(f"<h3>Alarms ({len(lines)})</h3>")
    if lines:
        items = "".join(f"<li>{escape(t)}</li>" for t in lines[:MAX_LINES])
        more = (
            f"<p>... and {len(lines) - MAX_LINES} more (in the JSON and CSV outputs).</p>"
            if len(lines) > MAX_LINES
            else ""
        )
        parts.append(f"<ul>{items}</ul>{more}")
    else:
        parts.append("<p>No survey changed beyond the false-alarm rate.</p>")
    first = {}
    for a in result.alarms:
        first.setdefault(a.mode, a)
    for j, a in first.items():
        parts.append(
            f"<h3>Which term: {escape(result.tracks[j].label(j))}, first alarm "
            f"({escape(result.labels[a.survey])})</h3>{_terms_table(a, result)}"
        )
    trends = [t.text(result) for t in result.trend_alarms] or ["No trend over the new surveys."]
    parts.append("<h3>Trends</h3><ul>" + "".join(f"<li>{escape(t)}</li>" for t in trends) + "</ul>")
    events = result.events()
    if events:
        parts.append(
            "<h3>Modes missed or appeared</h3><ul>"
            + "".join(f"<li>{escape(e)}</li>" for e in events)
            + "</ul>"
        )
    notes = result.notes()
    if notes:
        parts.append("<h3>Notes</h3><ul>" + "".join(f"<li>{escape(n)}</li>" for n in notes) + "</ul>")
    parts += ["<h3>Control charts</h3>", _charts(result), "</section>"]
    return "\n".join(parts)


def track_html(result, *, source: str | None = None) -> str:
    """A :class:`~sindy_impulse.tracking.TrackResult` as one self-contained HTML page.

    Examples
    --------
    >>> import numpy as np
    >>> from sindy_impulse.tracking import ModeValues, SurveyValues, track
    >>> rng = np.random.default_rng(0)
    >>> surveys = [SurveyValues([ModeValues(100 * (1 + 3e-4 * rng.standard_normal()), 1e-3, 0.01, 1e-4, 1.0)])
    ...            for _ in range(25)]
    >>> page = track_html(track(surveys, reference=20), source="hits/*.csv")
    >>> page.startswith("<!DOCTYPE html>"), 'id="tracking"' in page, "https://" in page
    (True, True, False)
    """
    if not hasattr(result, "alarms") or not hasattr(result, "tracks"):
        raise TypeError(f"result must be what track returns, got {type(result).__name__}")
    from .._version import __version__

    title = f"Tracking of {source}" if source else "Tracking of repeated tests"
    body = [
        f"<h1>{escape(title)}</h1>",
        tracking_section(result, source),
        f'<p class="muted">Made by sindy-impulse {escape(__version__)}.</p>',
    ]
    return html_page(title, body)

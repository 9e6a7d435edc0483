"""A modal survey as one self-contained HTML page: the record and its source, the modal table with its
uncertainties, the spectrum with the stabilisation chart, and per mode its fit, equation, backbone,
nonlinearity verdict and diagnostics.

Nothing is loaded from elsewhere: the style sheet is inline, the figures are inline PNG images
(:mod:`.figures`), every text is escaped. A few lines of inline script mark the page as loaded (and
count the images that decoded) for a browser test; the page reads the same without them.
"""

from __future__ import annotations

import math
import os
from html import escape

from .._utils.units import DAMPING_UNITS, DEFAULT_DAMPING_UNIT, check_damping_unit, damping_in_words
from .figures import backbone_figure, decay_figure, mode_backbones, record_figure, spectrum_figure
from .summary import FIT_ERROR_MEANING, default_channel_names, mode_account, phase_text
from .text import plus_minus, uncertainty

__all__ = ["html_page", "survey_html", "write_html"]

_STYLE = """
body { font-family: system-ui, sans-serif; max-width: 60rem; margin: 1rem auto; padding: 0 1rem;
       color: #222; line-height: 1.4; }
h1 { font-size: 1.5rem; } h2 { font-size: 1.2rem; border-bottom: 1px solid #ccc; margin-top: 2rem; }
h3 { font-size: 1rem; margin-bottom: 0.3rem; }
table { border-collapse: collapse; font-size: 0.9rem; }
th, td { border: 1px solid #ccc; padding: 0.2rem 0.5rem; text-align: right; }
th { background: #f3f3f3; } td.text { text-align: left; }
img { max-width: 100%; height: auto; display: block; }
pre { background: #f6f6f6; padding: 0.5rem; overflow-x: auto; }
.verdict-ok { color: #1a7f37; } .verdict-bad { color: #b35900; font-weight: bold; }
details { margin-top: 0.3rem; } .muted { color: #666; font-size: 0.9rem; }
"""

_MARKER = """
window.addEventListener("error", function (e) {
  document.body.setAttribute("data-error", String(e.message || (e.target && e.target.tagName)));
}, true);
window.addEventListener("load", function () {
  var ok = 0, images = document.images;
  for (var i = 0; i < images.length; i++) { if (images[i].complete && images[i].naturalWidth > 0) ok++; }
  document.body.setAttribute("data-images", ok + "/" + images.length);
  document.body.setAttribute("data-loaded", "yes");
});
"""


def _img(uri: str, alt: str) -> str:
    return f'<img src="{uri}" alt="{escape(alt)}">'


def _facts(rows: list[tuple[str, str]]) -> str:
    cells = "".join(f'<tr><th>{escape(k)}</th><td class="text">{escape(v)}</td></tr>' for k, v in rows)
    return f"<table>{cells}</table>"


def _offset_text(pre) -> str:
    """The offset removed, how, and its size against the ring-down (the quality check saw it before)."""
    text = f"{pre.offset.value:.4g} ({pre.offset.method.replace('_', ' ')})"
    ratio = getattr(pre.quality, "offset_ratio", float("nan"))
    if "offset" in pre.quality.problems and math.isfinite(ratio):
        text += f"; it was {ratio:.2g} x the ring-down amplitude, removed before the survey"
    return text


def _record_section(survey, source: str | None) -> str:
    parts = ['<section id="record"><h2>The record</h2>']
    parts.append(f"<p>Source: <code>{escape(source or 'data passed to identify_modes')}</code></p>")
    for i, pre in enumerate(survey.preprocessing):
        facts = [
            ("record", f"{i}"),
            ("samples", f"{len(pre.y)} at {pre.fs:.6g} Hz ({len(pre.y) / pre.fs:.4g} s)"),
            (
                "hit",
                f"at {pre.t0 + pre.impact.onset_index / pre.fs:.4g} s (found from the {pre.impact.source})",
            ),
            ("free decay from", f"{pre.t0 + pre.impact.ringdown_index / pre.fs:.4g} s"),
            ("offset removed", _offset_text(pre)),
            ("ring-down", f"SNR {pre.quality.snr_db:.1f} dB, decays {pre.quality.decay_db:.1f} dB"),
        ]
        # the offset is removed by the survey: a problem of the raw record, not of what was analysed
        facts += [("data problem", str(p)) for k, p in pre.quality.problems.items() if k != "offset"]
        parts += [_facts(facts), _img(record_figure(pre), f"record {i}")]
    parts.append("</section>")
    return "\n".join(parts)


def _amplitude_columns(accounts: list, names: list) -> list[tuple[str, object]]:
    """One amplitude column per channel when some mode has a shape; else the reference channel's."""
    if not any(a["channels"] for a in accounts):
        return [("amplitude", lambda a: f"{a['amplitude']:.4g}")]

    def cell(k):
        def text(a):
            if not a["channels"]:  # no shape: only the reference channel's amplitude is known
                return "-"
            c = a["channels"][k]
            phase = "" if c["reference"] else f" ({phase_text(c['phase_deg'], 0)}°)"
            return f"{c['amplitude']:.4g}{phase}"
        return text

    return [(f"amplitude {name} (phase)", cell(k)) for k, name in enumerate(names)]


def _columns(survey, accounts: list, names: list, nonlinearity: bool, unit: str) -> list[tuple[str, object]]:
    """The modal table's columns: ``(header, (mode, account) -> text)``."""
    scale, symbol, _ = DAMPING_UNITS[unit]
    zeta_head = "damping ratio" + (f" [{symbol.strip()}]" if symbol else "")
    cols = [
        ("f_n [Hz]", lambda m, a: plus_minus(m.frequency_hz, uncertainty(m, "frequency_std_hz"))),
        (
            zeta_head,
            lambda m, a: plus_minus(m.damping_ratio, uncertainty(m, "damping_ratio_std"), scale, digits=4),
        ),
        ("f_d [Hz]", lambda m, a: f"{m.damped_frequency_hz:.6g}"),
    ]
    cols += [(h, lambda m, a, f=f: f(a)) for h, f in _amplitude_columns(accounts, names)]
    cols += [
        ("fit error", lambda m, a: f"{m.fit_error:.3g}"),
        ("SNR [dB]", lambda m, a: f"{m.snr_db:.1f}"),
        ("band [Hz]", lambda m, a: f"{m.band_hz[0]:.5g} - {m.band_hz[1]:.5g}"),
    ]
    if any(m.hits for m in survey.modes):
        cols += [
            ("hits", lambda m, a: str(len(m.hits) or 1)),
            ("spread of f_n over hits [Hz]", lambda m, a: f"{m.frequency_spread_hz:.3g}"),
            (f"spread of damping over hits{f' [{symbol.strip()}]' if symbol else ''}",
             lambda m, a: f"{scale * m.damping_ratio_spread:.3g}"),
        ]
    if any(m.residue is not None for m in survey.modes):
        cols.append(("residue", lambda m, a: "-" if m.residue is None else f"{m.residue:.4g}"))
    if nonlinearity:
        cols.append(("nonlinear", lambda m, a: "yes" if a["nonlinear"] else "no"))
    cols.append(("diagnostics", lambda m, a: a["diagnostics"] or "-"))
    return cols


def _table_section(survey, accounts: list, names: list, nonlinearity: bool, unit: str, notes) -> str:
    parts = ['<section id="table"><h2>Modal table</h2>']
    if survey.modes:
        cols = _columns(survey, accounts, names, nonlinearity, unit)
        head = "".join(f"<th>{escape(h)}</th>" for h, _ in [("mode", None)] + cols)
        rows = [
            f'<tr><td><a href="#mode-{k}">{k}</a></td>'
            + "".join(f"<td>{escape(f(m, a))}</td>" for _, f in cols)
            + "</tr>"
            for k, (m, a) in enumerate(zip(survey.modes, accounts))
        ]
        parts.append(f'<table class="modes"><tr>{head}</tr>{"".join(rows)}</table>')
        parts.append(
            '<p class="muted">value ± standard deviation where the identification gives one; the spread '
            f"over repeated hits is their interquartile range; {escape(FIT_ERROR_MEANING)}; the phase of "
            "each channel is relative to the reference channel.</p>"
        )
    else:
        parts.append("<p><strong>No mode found.</strong></p>")
    for r in survey.rejected:
        band = "the whole record" if r.band_hz is None else f"{r.band_hz[0]:.5g} - {r.band_hz[1]:.5g} Hz"
        reason = damping_in_words(str(r.reason), unit)
        parts.append(f"<p>Rejected ({escape(band)}, record {r.record}): {escape(reason)}</p>")
    shown = survey.notes if notes is None else notes  # the caller's notes include the survey's
    parts += [f"<p>Note: {escape(damping_in_words(str(n), unit))}</p>" for n in dict.fromkeys(shown)]
    parts.append("</section>")
    return "\n".join(parts)


def _spectrum_section(survey) -> str:
    images = [
        _img(spectrum_figure(survey, i), f"stabilisation chart, record {i}")
        for i in range(len(survey.preprocessing))
    ]
    return '<section id="spectrum"><h2>Spectrum and stabilisation chart</h2>' + "".join(images) + "</section>"


def _equations(account: dict) -> str:
    lines = [f"({n[:-1]})' = {eq}" for n, eq in account["equations"].items()]
    return f"<pre>{escape(chr(10).join(lines))}</pre>"


def _diagnostics(mode, account: dict) -> str:
    if account["diagnostics"] is None:
        return "<p>No diagnostics.</p>"
    good = account["diagnostics"] == "ok"
    snr = getattr(mode.diagnostics, "snr_db", float("nan"))
    verdict = escape(account["diagnostics"])
    parts = [
        f'<p>Verdict: <span class="verdict-{"ok" if good else "bad"}">{verdict}</span> '
        f"(fit error {mode.fit_error:.3g}" + (f", SNR {snr:.1f} dB" if math.isfinite(snr) else "") + ")</p>"
    ]
    if account["problems"]:
        parts.append("<ul>" + "".join(f"<li>{escape(short)}</li>" for short in account["problems"]) + "</ul>")
    long = [*account["problem_details"].items(), *account["diagnostic_notes"].items()]
    if long:
        items = "".join(f"<li><strong>{escape(str(c))}</strong>: {escape(str(s))}</li>" for c, s in long)
        parts.append(
            f"<details><summary>What each problem means, what to do</summary><ul>{items}</ul></details>"
        )
    return "".join(parts)


def _nonlinearity(account: dict, nonlinearity: bool) -> str:
    if not nonlinearity:
        text = "<p>The test for nonlinearity was skipped.</p>"
    else:
        verdict = "nonlinear" if account["nonlinear"] else "linear"
        text = f"<p>The mode is <strong>{verdict}</strong>: {escape(account['nonlinearity'])}.</p>"
    if account["decision"]:
        text += f'<p class="decision">{escape(account["decision"])}.</p>'
    return text


def _channels(account: dict) -> str:
    """The mode's amplitude and shape per channel (several channels with a shape only)."""
    if not account["channels"]:
        return ""
    rows = "".join(
        f"<tr><td class=\"text\">{escape(str(c['channel']))}{' (reference)' if c['reference'] else ''}</td>"
        f"<td>{c['amplitude']:.4g}</td><td>{c['magnitude']:.4g}</td><td>{phase_text(c['phase_deg'])}</td></tr>"
        for c in account["channels"]
    )
    head = "<tr><th>channel</th><th>amplitude</th><th>shape: magnitude</th><th>shape: phase [°]</th></tr>"
    return f"<h3>Amplitude and shape per channel</h3><table>{head}{rows}</table>"


def _record_of(survey, mode):
    """The preprocessed record a mode comes from (None if the survey does not hold it)."""
    index = getattr(mode, "record", 0)
    return survey.preprocessing[index] if 0 <= index < len(survey.preprocessing) else None


def _mode_section(survey, k: int, mode, account: dict, nonlinearity: bool, unit: str) -> str:
    scale, symbol, _ = DAMPING_UNITS[unit]
    freq = plus_minus(mode.frequency_hz, uncertainty(mode, "frequency_std_hz"))
    zeta = plus_minus(mode.damping_ratio, uncertainty(mode, "damping_ratio_std"), scale, digits=4)
    parts = [
        f'<section class="mode" id="mode-{k}">',
        f"<h2>Mode {k}: {escape(freq)} Hz, damping ratio {escape(zeta)}{escape(symbol)}</h2>",
        "<h3>Band signal against the model</h3>",
        _img(decay_figure(mode, k, _record_of(survey, mode), unit), f"mode {k}: band signal and model"),
        _channels(account),
        "<h3>Equation</h3>",
        _equations(account),
        "<h3>Backbone</h3>",
    ]
    curves = mode_backbones(mode, nonlinearity)
    if curves:
        parts.append(_img(backbone_figure(curves, damping_unit=unit), f"mode {k}: backbone"))
    else:
        parts.append("<p>No backbone: the decay is too short or too noisy for one.</p>")
    parts += ["<h3>Nonlinearity</h3>", _nonlinearity(account, nonlinearity)]
    parts += ["<h3>Diagnostics</h3>", _diagnostics(mode, account), "</section>"]
    return "\n".join(parts)


def _channel_names(survey, channel_names) -> list:
    n = max([1] + [len(m.shape) for m in survey.modes if m.shape is not None])
    if channel_names is not None and len(channel_names) == n:
        return [str(c) for c in channel_names]
    return default_channel_names(n)


def survey_html(survey, *, source: str | None = None, nonlinearity: bool = True,
                damping_unit: str = DEFAULT_DAMPING_UNIT, channel_names=None, notes=None) -> str:
    """A modal survey as one self-contained HTML page.

    Parameters
    ----------
    survey : ModalSurvey
        What :func:`~sindy_impulse.identify_modes` returned.
    source : str, optional
        Where the record came from (a file name), shown at the top.
    nonlinearity : bool, default=True
        Run the test for nonlinearity on each mode (it refits; False: the verdict is left out and the
        backbones are the model's and the band signal's own).
    damping_unit : {"percent", "fraction"}, default="percent"
        The unit of every damping ratio on the page (table, titles, figures).
    channel_names : sequence of str, optional
        The names of the record's channels (default ``ch0``, ``ch1``, ...).
    notes : sequence of str, optional
        The notes to show instead of the survey's own (the command line gives its own with the survey's:
        what it left out, the survey's warnings in its terms).

    Returns
    -------
    str
        The page: the record(s), the modal table (``value ± std`` where the mode has a standard deviation,
        the spread over repeated hits apart), the stabilisation chart over the spectrum with the bands,
        and per mode the band signal against the model (whole decay and zoom), the equation, the backbone,
        the nonlinearity verdict and the diagnostics. Images inline, nothing loaded from elsewhere.

    Examples
    --------
    >>> from sindy_impulse import identify_modes, impact_record
    >>> rec = impact_record([120.0], [0.01], fs=2000, duration=1.0, snr_db=50, random_state=0)
    >>> page = survey_html(identify_modes(rec.y, fs=rec.fs), source="hit.csv", nonlinearity=False)
    >>> page.startswith("<!DOCTYPE html>"), 'id="mode-0"' in page, "hit.csv" in page
    (True, True, True)
    """
    if not all(hasattr(survey, name) for name in ("modes", "rejected", "preprocessing", "notes")):
        raise TypeError(f"survey must be what identify_modes returns, got {type(survey).__name__}")
    from .._version import __version__

    unit = check_damping_unit(damping_unit)
    names = _channel_names(survey, channel_names)
    accounts = [
        mode_account(m, nonlinearity=nonlinearity, damping_unit=unit, channel_names=names)
        for m in survey.modes
    ]
    title = f"Modal survey of {source}" if source else "Modal survey"
    body = [
        f"<h1>{escape(title)}</h1>",
        _record_section(survey, source),
        _table_section(survey, accounts, names, nonlinearity, unit, notes),
        _spectrum_section(survey) if survey.preprocessing else "",
        *(
            _mode_section(survey, k, m, a, nonlinearity, unit)
            for k, (m, a) in enumerate(zip(survey.modes, accounts))
        ),
        f'<p class="muted">Made by sindy-impulse {escape(__version__)}.</p>',
    ]
    return html_page(title, body)


def html_page(title: str, body: list) -> str:
    """A self-contained page: the title, the style sheet, the sections ``body`` (HTML, escaped by their
    makers) and the load marker."""
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        f"<title>{escape(title)}</title><style>{_STYLE}</style></head>\n<body>\n"
        + "\n".join(body)
        + f"\n<script>{_MARKER}</script>\n</body></html>\n"
    )


def write_html(path: str | os.PathLike, page: str, *, overwrite: bool = False) -> str:
    """Write ``page`` to ``path`` (UTF-8) all at once (a temporary file beside it, then renamed); an existing
    file only with ``overwrite=True``. A new file gets the user's usual permissions (umask).

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = write_html(os.path.join(folder, "r.html"), "<p>x</p>")
    ...     try:
    ...         write_html(path, "<p>y</p>")
    ...     except FileExistsError as err:
    ...         print("refused")
    refused
    """
    from ..io._common import atomic_write

    if not isinstance(page, str):
        raise TypeError(f"page must be a str, got {type(page).__name__}")
    path = os.fspath(path)
    if os.path.isdir(path):
        raise IsADirectoryError(f"{path} is a directory, expected an HTML file name")

    def write(tmp: str) -> None:
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(page)

    try:
        atomic_write(path, write, overwrite=overwrite)
    except FileExistsError:
        raise FileExistsError(f"{path} exists; pass overwrite=True to replace it") from None
    return path

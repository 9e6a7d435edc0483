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

from .figures import backbone_figure, decay_figure, mode_backbones, record_figure, spectrum_figure
from .text import nonlinearity_words, plus_minus, problem_lines, uncertainty

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
            ("offset removed", f"{pre.offset.value:.4g} ({pre.offset.method.replace('_', ' ')})"),
            ("ring-down", f"SNR {pre.quality.snr_db:.1f} dB, decays {pre.quality.decay_db:.1f} dB"),
        ]
        facts += [("data problem", str(p)) for p in pre.quality.problems.values()]
        parts += [_facts(facts), _img(record_figure(pre), f"record {i}")]
    parts.append("</section>")
    return "\n".join(parts)


def _columns(survey, nonlinearity: bool) -> list[tuple[str, object]]:
    """The modal table's columns: ``(header, mode -> text)``."""
    cols = [
        ("f_n [Hz]", lambda m: plus_minus(m.frequency_hz, uncertainty(m, "frequency_std_hz"))),
        (
            "damping ratio [%]",
            lambda m: plus_minus(m.damping_ratio, uncertainty(m, "damping_ratio_std"), 100, digits=4),
        ),
        ("f_d [Hz]", lambda m: f"{m.damped_frequency_hz:.6g}"),
        ("amplitude", lambda m: f"{m.amplitude:.4g}"),
        ("fit error", lambda m: f"{m.fit_error:.3g}"),
        ("SNR [dB]", lambda m: f"{m.snr_db:.1f}"),
        ("band [Hz]", lambda m: f"{m.band_hz[0]:.5g} - {m.band_hz[1]:.5g}"),
    ]
    if any(m.hits for m in survey.modes):
        cols += [
            ("hits", lambda m: str(len(m.hits) or 1)),
            ("spread of f_n over hits [Hz]", lambda m: f"{m.frequency_spread_hz:.3g}"),
            ("spread of damping over hits [%]", lambda m: f"{100 * m.damping_ratio_spread:.3g}"),
        ]
    if any(m.residue is not None for m in survey.modes):
        cols.append(("residue", lambda m: "-" if m.residue is None else f"{m.residue:.4g}"))
    if nonlinearity:
        cols.append(("nonlinear", lambda m: "yes" if m.nonlinear else "no"))
    cols.append(("diagnostics", lambda m: getattr(m.diagnostics, "verdict", "-")))
    return cols


def _table_section(survey, nonlinearity: bool) -> str:
    parts = ['<section id="table"><h2>Modal table</h2>']
    if survey.modes:
        cols = _columns(survey, nonlinearity)
        head = "".join(f"<th>{escape(h)}</th>" for h, _ in [("mode", None)] + cols)
        rows = [
            f'<tr><td><a href="#mode-{k}">{k}</a></td>'
            + "".join(f"<td>{escape(f(m))}</td>" for _, f in cols)
            + "</tr>"
            for k, m in enumerate(survey.modes)
        ]
        parts.append(f'<table class="modes"><tr>{head}</tr>{"".join(rows)}</table>')
        parts.append(
            '<p class="muted">value ± standard deviation where the identification gives one; the spread '
            "over repeated hits is their interquartile range.</p>"
        )
    else:
        parts.append("<p><strong>No mode found.</strong></p>")
    for r in survey.rejected:
        band = "the whole record" if r.band_hz is None else f"{r.band_hz[0]:.5g} - {r.band_hz[1]:.5g} Hz"
        parts.append(f"<p>Rejected ({escape(band)}, record {r.record}): {escape(str(r.reason))}</p>")
    parts += [f"<p>Note: {escape(str(n))}</p>" for n in survey.notes]
    parts.append("</section>")
    return "\n".join(parts)


def _spectrum_section(survey) -> str:
    images = [
        _img(spectrum_figure(survey, i), f"stabilisation chart, record {i}")
        for i in range(len(survey.preprocessing))
    ]
    return '<section id="spectrum"><h2>Spectrum and stabilisation chart</h2>' + "".join(images) + "</section>"


def _equations(mode) -> str:
    model = mode.model
    names = list(model.feature_names_)[: getattr(model, "n_states_", len(model.feature_names_))]
    lines = [f"({n})' = {eq}" for n, eq in zip(names, model.equations(4))]
    return f"<pre>{escape(chr(10).join(lines))}</pre>"


def _diagnostics(diag) -> str:
    if diag is None:
        return "<p>No diagnostics.</p>"
    good = diag.verdict == "ok"
    parts = [
        f'<p>Verdict: <span class="verdict-{"ok" if good else "bad"}">{escape(diag.verdict)}</span> '
        f"(fit error {float(max(diag.fit_error)):.3g} of the RMS"
        + (f", SNR {diag.snr_db:.1f} dB" if math.isfinite(diag.snr_db) else "")
        + ")</p>"
    ]
    problems = problem_lines(diag.reasons)
    if problems:
        parts.append("<ul>" + "".join(f"<li>{escape(short)}</li>" for _, short, _ in problems) + "</ul>")
    long = [(c, s) for c, _, s in problems] + [(c, s) for c, s in diag.notes.items()]
    if long:
        items = "".join(f"<li><strong>{escape(str(c))}</strong>: {escape(str(s))}</li>" for c, s in long)
        parts.append(
            f"<details><summary>What each problem means, what to do</summary><ul>{items}</ul></details>"
        )
    return "".join(parts)


def _nonlinearity(mode, nonlinearity: bool) -> str:
    if not nonlinearity:
        return "<p>The test for nonlinearity was skipped.</p>"
    verdict, text = nonlinearity_words(mode.nonlinearity)
    return f"<p>The mode is <strong>{escape(verdict)}</strong>: {escape(text)}.</p>"


def _mode_section(k: int, mode, nonlinearity: bool) -> str:
    freq = plus_minus(mode.frequency_hz, uncertainty(mode, "frequency_std_hz"))
    zeta = plus_minus(mode.damping_ratio, uncertainty(mode, "damping_ratio_std"), 100, digits=4)
    parts = [
        f'<section class="mode" id="mode-{k}">',
        f"<h2>Mode {k}: {escape(freq)} Hz, damping ratio {escape(zeta)} %</h2>",
        "<h3>Band signal against the model</h3>",
        _img(decay_figure(mode, k), f"mode {k}: band signal and model"),
        "<h3>Equation</h3>",
        _equations(mode),
        "<h3>Backbone</h3>",
    ]
    curves = mode_backbones(mode, nonlinearity)
    if curves:
        parts.append(_img(backbone_figure(curves), f"mode {k}: backbone"))
    else:
        parts.append("<p>No backbone: the decay is too short or too noisy for one.</p>")
    parts += ["<h3>Nonlinearity</h3>", _nonlinearity(mode, nonlinearity)]
    parts += ["<h3>Diagnostics</h3>", _diagnostics(mode.diagnostics), "</section>"]
    return "\n".join(parts)


def survey_html(survey, *, source: str | None = None, nonlinearity: bool = True) -> str:
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

    title = f"Modal survey of {source}" if source else "Modal survey"
    body = [
        f"<h1>{escape(title)}</h1>",
        _record_section(survey, source),
        _table_section(survey, nonlinearity),
        _spectrum_section(survey) if survey.preprocessing else "",
        *(_mode_section(k, m, nonlinearity) for k, m in enumerate(survey.modes)),
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
    """Write ``page`` to ``path`` (UTF-8); an existing file only with ``overwrite=True``.

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
    if not isinstance(page, str):
        raise TypeError(f"page must be a str, got {type(page).__name__}")
    path = os.fspath(path)
    if os.path.isdir(path):
        raise IsADirectoryError(f"{path} is a directory, expected an HTML file name")
    mode = "w" if overwrite else "x"
    try:
        with open(path, mode, encoding="utf-8") as fh:
            fh.write(page)
    except FileExistsError:
        raise FileExistsError(f"{path} exists; pass overwrite=True to replace it") from None
    return path

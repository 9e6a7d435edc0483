"""The HTML report of a modal survey (``survey.to_html``, ``sindy-impulse modes --report``) and the
``--plot`` figure: what the page holds, that it is self-contained, that files are not overwritten."""

import base64
import dataclasses
import re
import warnings
from html import escape

import numpy as np
import pytest

from sindy_impulse import identify_modes, impact_record
from sindy_impulse.cli import main
from sindy_impulse.report import survey_html, write_html
from sindy_impulse.report.text import plus_minus, problem_lines


@pytest.fixture(scope="module")
def survey():
    rec = impact_record(
        [120.0, 243.0], [0.005, 0.01], amplitudes=[1.0, 0.5], fs=2000.0, duration=1.0, offset=1.0,
        snr_db=50, random_state=3,
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return identify_modes(rec.y, fs=rec.fs)


@pytest.fixture(scope="module")
def page(survey):
    return survey.to_html(source="bench<1>.csv")


def _modal_table_rows(page: str) -> list[list[str]]:
    table = re.search(r'<table class="modes">(.*?)</table>', page, re.S).group(1)
    rows = re.findall(r"<tr>(.*?)</tr>", table, re.S)
    return [re.findall(r"<t[dh]>(.*?)</t[dh]>", r, re.S) for r in rows]


def test_modal_table_has_one_row_per_mode_with_its_values(survey, page):
    assert len(survey) == 2
    header, *rows = _modal_table_rows(page)
    assert len(rows) == len(survey) and header[:3] == ["mode", "f_n [Hz]", "damping ratio [%]"]
    for row, mode in zip(rows, survey):
        value = lambda cell: float(cell.split(" ± ")[0])  # noqa: E731  (the value before its std)
        assert value(row[1]) == pytest.approx(mode.frequency_hz, rel=1e-5)
        assert value(row[2]) == pytest.approx(100 * mode.damping_ratio, rel=1e-3)
        assert row[header.index("diagnostics")] == mode.diagnostics.verdict
        assert row[header.index("nonlinear")] == ("yes" if mode.nonlinear else "no")


def test_standard_deviations_shown_as_plus_minus_and_hit_spreads_apart(survey):
    mode, other = survey.modes
    names = ("frequency_std_hz", "damping_ratio_std", "hits", "frequency_spread_hz")
    saved = [(m, {n: getattr(m, n) for n in names}) for m in (mode, other)]
    try:
        mode.frequency_std_hz, mode.damping_ratio_std = 0.0123, 0.00042
        mode.hits, mode.frequency_spread_hz = [mode, mode], 0.5
        other.frequency_std_hz = other.damping_ratio_std = float("nan")
        page = survey_html(survey, nonlinearity=False)
    finally:
        for m, values in saved:
            for n, v in values.items():
                setattr(m, n, v)
    header, first, second = _modal_table_rows(page)
    assert first[1] == f"{mode.frequency_hz:.3f} ± 0.012"
    assert first[2] == f"{100 * mode.damping_ratio:.3f} ± 0.042"
    assert "±" not in second[1]  # a mode without a standard deviation: the value alone
    assert first[header.index("spread of f_n over hits [Hz]")] == "0.5"
    assert first[header.index("hits")] == "2"


def test_equations_verdicts_and_source_are_on_the_page(survey, page):
    assert "Modal survey of bench&lt;1&gt;.csv" in page and "bench<1>" not in page  # escaped
    for k, mode in enumerate(survey):
        section = page.split(f'id="mode-{k}"')[1].split("</section>")[0]
        for eq in mode.model.equations(4):
            assert escape(eq) in section
        verdict = "nonlinear" if mode.nonlinear else "linear"
        assert f"The mode is <strong>{verdict}</strong>" in section
        assert f"Verdict: <span class=\"verdict-{'ok' if mode.diagnostics.ok else 'bad'}\">" in section
        assert section.count("<img ") == 2  # the decay and zoom, the backbone


def test_self_contained_no_network_images_inline(survey, page):
    assert "http://" not in page and "https://" not in page
    assert "<link" not in page and "url(" not in page and "@import" not in page
    sources = re.findall(r'<img src="([^"]*)"', page)
    assert len(sources) == 1 + 1 + 2 * len(survey)  # record, stabilisation chart, two per mode
    for src in sources:
        assert src.startswith("data:image/png;base64,")
        assert base64.b64decode(src.split(",", 1)[1])[:8] == b"\x89PNG\r\n\x1a\n"
    assert not re.search(r"<script[^>]+src=", page)


def test_diagnostics_short_lines_and_details_block(survey):
    mode = survey.modes[0]
    original = mode.model.diagnostics_
    reasons = {
        "support": "the data hardly determine the term(s) dy' : y^3: it may be spurious; fit a longer record",
        "fit_error": "the model's simulation misses the data (fit error 0.3 of the RMS): the library lacks",
    }
    mode.model.diagnostics_ = dataclasses.replace(original, verdict="doubtful", reasons=reasons)
    try:
        page = survey_html(survey, nonlinearity=False)
    finally:
        mode.model.diagnostics_ = original
    section = page.split('id="mode-0"')[1].split("</section>")[0]
    assert 'class="verdict-bad">doubtful' in section
    short = re.findall(r"<li>(.*?)</li>", section.split("<details>")[0])
    assert short == [escape("the data hardly determine the term(s) dy' : y^3"),
                     escape("the model's simulation misses the data (fit error 0.3 of the RMS)")]
    details = section.split("<details>")[1]
    assert escape(reasons["support"]) in details and escape(reasons["fit_error"]) in details


def test_plus_minus_and_problem_lines():
    assert plus_minus(1.23456, 0.0123) == "1.235 ± 0.012"
    assert plus_minus(1.23456, float("nan"), digits=3) == "1.23"
    assert plus_minus(0.01, 0.001, scale=100) == "1.00 ± 0.10"
    assert problem_lines({"a": "problem (x: y): do this"}) == [("a", "problem (x", "problem (x: y): do this")]


def test_to_html_refuses_to_overwrite(survey, tmp_path):
    path = tmp_path / "report.html"
    path.write_text("mine")
    with pytest.raises(FileExistsError, match="overwrite=True"):
        survey.to_html(path, nonlinearity=False)
    assert path.read_text() == "mine"
    page = survey.to_html(path, overwrite=True, nonlinearity=False)
    assert path.read_text(encoding="utf-8") == page
    with pytest.raises(TypeError, match="identify_modes"):
        survey_html(object())
    with pytest.raises(IsADirectoryError):
        write_html(tmp_path, page, overwrite=True)


def _csv(tmp_path):
    rec = impact_record(150.0, 0.01, fs=2000.0, duration=0.8, snr_db=50, random_state=1)
    path = tmp_path / "hit.csv"
    np.savetxt(path, rec.y, header="y", comments="", fmt="%.10g")
    return path


def test_cli_report_flag(tmp_path, capsys):
    data, out = _csv(tmp_path), tmp_path / "report.html"
    out.write_text("old")
    command = ["modes", str(data), "--fs", "2000", "--no-nonlinearity", "--report", str(out)]
    assert main(command) != 0 and out.read_text() == "old"  # not replaced without --overwrite
    assert "exists" in capsys.readouterr().err
    assert main([*command, "--overwrite"]) == 0
    assert str(out) in capsys.readouterr().out
    page = out.read_text(encoding="utf-8")
    assert page.startswith("<!DOCTYPE html>") and f"Modal survey of {data}" in page
    assert len(_modal_table_rows(page)) == 2 and "test for nonlinearity was skipped" in page
    assert main(["modes", str(data), "--fs", "2000", "--report", str(data), "--overwrite"]) != 0  # an input
    assert "refusing to overwrite an input" in capsys.readouterr().err


def test_cli_out_dir_holds_the_reports(tmp_path):
    data, folder = _csv(tmp_path), tmp_path / "out"
    command = ["modes", str(data), "--fs", "2000", "--out-dir", str(folder), "--outputs", "html"]
    assert main(command) == 0
    page = (folder / "hit.html").read_text(encoding="utf-8")
    assert "The mode is <strong>" in page  # the test for nonlinearity ran: its verdict is on the page


def _texts(ax) -> list:
    """The texts an Axes draws: title, labels, offset texts, major and minor tick labels in view, legend
    entries."""
    texts = [ax.title, ax.xaxis.label, ax.yaxis.label, ax.xaxis.get_offset_text(), ax.yaxis.get_offset_text()]
    low, high = sorted(ax.get_xlim())
    for minor in (False, True):  # a log axis labels its minor ticks too (2x10^-2, 3x10^-2, ...)
        texts += [t for t in ax.get_xticklabels(minor=minor) if low <= t.get_position()[0] <= high]
    low, high = sorted(ax.get_ylim())
    for minor in (False, True):
        texts += [t for t in ax.get_yticklabels(minor=minor) if low <= t.get_position()[1] <= high]
    if ax.get_legend() is not None:
        texts += ax.get_legend().get_texts()
    return [t for t in texts if t.get_visible() and t.get_text().strip()]


def overlapping_texts(fig) -> list:
    """Pairs of texts of a figure whose boxes overlap (after drawing it)."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    boxes = [(t.get_text(), t.get_window_extent(renderer)) for ax in fig.axes for t in _texts(ax)]
    return [(a, b) for i, (a, box) in enumerate(boxes) for b, other in boxes[i + 1 :] if box.overlaps(other)]


def test_plot_figure_whole_decay_and_no_overlapping_text(survey):
    import matplotlib

    matplotlib.use("Agg")
    axes = survey.plot()
    fig = axes[0].figure
    for k, mode in enumerate(survey):
        decay = axes[1 + 2 * k]
        assert decay.get_yscale() == "log"
        low, high = decay.get_xlim()
        assert low <= mode.t[0] and high >= mode.t[-1]  # the whole band signal, not its first periods
        assert axes[2 + 2 * k].get_xlim()[1] < mode.t[0] + 0.5 * (mode.t[-1] - mode.t[0])  # the zoom
    assert overlapping_texts(fig) == []
    matplotlib.pyplot.close(fig)


def test_a_survey_without_modes_still_reports_why(tmp_path):
    rng = np.random.default_rng(0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        empty = identify_modes(rng.standard_normal(4000) + 2.0, fs=1000.0)
    page = empty.to_html(tmp_path / "empty.html")
    assert len(empty) == 0 and "<strong>No mode found.</strong>" in page
    assert all(escape(note) in page for note in empty.notes) and 'id="mode-0"' not in page
    assert page.count("<img ") == 2  # the record and the stabilisation chart


# -- the report's figures ------------------------------------------------------------------------------------
def _figure_texts(fig) -> list:
    return [t for legend in fig.legends for t in legend.get_texts()]


def overlapping_figure_texts(fig) -> list:
    """:func:`overlapping_texts`, the figure's own legends included (a figure made without pyplot gets a
    canvas to draw on)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    if not hasattr(fig.canvas, "get_renderer"):
        FigureCanvasAgg(fig)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    texts = [t for ax in fig.axes for t in _texts(ax)] + _figure_texts(fig)
    boxes = [(t.get_text(), t.get_window_extent(renderer)) for t in texts]
    return [(a, b) for i, (a, box) in enumerate(boxes) for b, other in boxes[i + 1 :] if box.overlaps(other)]


def test_the_reports_figures_have_no_overlapping_text(survey):
    from sindy_impulse.report.figures import (
        draw_backbone,
        draw_decay,
        draw_record,
        draw_spectrum,
        mode_backbones,
    )

    pre = survey.preprocessing[0]
    figures = [draw_record(pre), draw_spectrum(survey)]
    for k, mode in enumerate(survey):
        figures += [draw_decay(mode, k, pre), draw_backbone(mode_backbones(mode, nonlinearity=True))]
    for fig in figures:
        assert overlapping_figure_texts(fig) == []


def test_backbone_tick_labels_over_one_to_two_decades_do_not_crowd():
    from sindy_impulse.analysis import Backbone
    from sindy_impulse.report.figures import draw_backbone

    rng = np.random.default_rng(0)
    for low, high in [(2.5e-3, 4.5e-2), (6e-3, 8e-2), (0.02, 0.07), (1e-4, 1.0)]:
        a = np.geomspace(low, high, 50)
        noise = rng.standard_normal((2, 50))
        data = Backbone(a, 110 + 0.5 * noise[0], 0.005 + 0.001 * noise[1], "data")
        model = Backbone(a, np.full(50, 110.0), np.full(50, 0.005), "model")
        assert overlapping_figure_texts(draw_backbone([model, data])) == [], (low, high)


def test_the_spectrum_is_on_its_own_axis_with_ticks_and_its_peaks_in_view(survey):
    from sindy_impulse.report.figures import draw_spectrum

    fig = draw_spectrum(survey)
    overlapping_figure_texts(fig)  # drawn
    chart = next(ax for ax in fig.axes if ax.get_ylabel() == "model order")
    spectrum = next(ax for ax in fig.axes if ax is not chart)
    assert spectrum.get_position().y0 >= chart.get_position().y1  # above the chart, not behind its poles
    assert spectrum.get_yscale() == "log" and [t for t in spectrum.get_yticklabels() if t.get_text()]
    (line,) = [line for line in spectrum.get_lines() if len(line.get_xdata()) > 10]
    f, psd = line.get_xdata(), line.get_ydata()
    shown = f <= chart.get_xlim()[1]
    low, high = spectrum.get_ylim()
    assert np.max(psd[shown]) <= high and np.max(psd[shown]) / np.median(psd[shown]) > 1e3  # peaks in view
    for mode in survey:  # every mode's peak is inside the frequency range shown
        assert mode.frequency_hz < chart.get_xlim()[1]


def test_the_whole_decay_panel_spans_the_record_from_the_hit_to_its_end(survey):
    from sindy_impulse.report.figures import draw_decay

    pre = survey.preprocessing[0]
    end = pre.t0 + (len(pre.y) - 1) / pre.fs
    for k, mode in enumerate(survey):
        decay = draw_decay(mode, k, pre).axes[0]
        low, high = decay.get_xlim()
        assert low <= pre.t0 + pre.impact.ringdown_index / pre.fs + 1e-9 and high >= end - 1e-9
        assert low <= mode.t[0] and high >= mode.t[-1]


def test_the_data_backbone_is_drawn_with_its_trend_and_spread(survey):
    from sindy_impulse.report.figures import draw_backbone, mode_backbones

    fig = draw_backbone(mode_backbones(survey[0], nonlinearity=True))
    frequency, damping = fig.axes
    labels = [t.get_text() for t in frequency.get_legend().get_texts()]
    assert "data: trend ± spread" in labels and len(frequency.collections) == 1 == len(damping.collections)
    assert damping.get_ylabel() == "damping ratio (%)"


def test_the_offset_the_survey_removed_is_not_a_data_problem(page):
    record = page.split('id="record"')[1].split("</section>")[0]
    assert "removed before the survey" in record and "remove it (estimate_offset)" not in record


def test_which_verdict_wins_is_said_when_they_seem_to_disagree():
    from types import SimpleNamespace as NS

    from sindy_impulse.report.summary import decision

    model = NS(feature_names_=["y", "dy"], get_feature_names=lambda: ["1", "y", "dy", "y^3", "dy^3"],
               coefficients=lambda: np.array([[0, 0, 1.0, 0, 0], [0, -100.0, -0.5, 0, 0]]))
    diagnostics = NS(verdict="doubtful", missing_terms=["y' : dy^3", "dy' : y^3"], unsupported_terms=[])
    test = NS(nonlinear=False, statistic=0.2, threshold=1.0)
    mode = NS(model=model, diagnostics=diagnostics, nonlinearity=test)
    text = decision(mode, tested=True)
    assert text.startswith("Linear wins") and "y' : dy^3" in text and "statistic 0.2 <= threshold 1" in text
    assert "skipped" in decision(mode, tested=False)
    mode.nonlinearity = NS(nonlinear=True, statistic=3.0, threshold=1.0)
    mode.diagnostics = NS(verdict="ok", missing_terms=[], unsupported_terms=[])
    assert decision(mode, tested=True).startswith("Nonlinear wins: the selected equation is linear")
    mode.nonlinearity = NS(nonlinear=False, statistic=0.1, threshold=1.0)
    assert decision(mode, tested=True) == ""  # they agree: nothing to say
    mode.diagnostics = NS(verdict="doubtful", missing_terms=[], unsupported_terms=[],
                          alternative_terms=[("dy' : dy", "dy' : dy^3")])
    assert decision(mode, tested=True).startswith("Linear wins: the diagnostics find that nonlinear terms")


def test_the_zoom_of_a_high_mode_keeps_its_time_labels_apart():
    from sindy_impulse.report.figures import draw_decay

    rec = impact_record([150.0, 600.0], [0.005, 0.002], fs=4096.0, duration=0.6, snr_db=50, random_state=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        survey = identify_modes(rec.y, fs=rec.fs)
    high = max(survey, key=lambda m: m.frequency_hz)
    assert high.frequency_hz == pytest.approx(600.0, rel=1e-3)
    fig = draw_decay(high, 1, survey.preprocessing[0])  # 12 periods: 0.02 s, labels like 0.2325
    assert overlapping_figure_texts(fig) == []

"""``sindy-impulse modes`` as a newcomer meets it: a CSV file with a time column and two channels, the
README's own command, a record with no mode, the options that choose modes and units, and the terminal,
the JSON and the HTML report saying the same of every mode."""

import io
import json
import re
import warnings
from contextlib import redirect_stderr, redirect_stdout
from html import unescape

import numpy as np
import pytest
from cli_helpers import run_cli as _run

from sindy_impulse import impact_record
from sindy_impulse.cli import main

FS = 2048.0
FREQUENCIES = [60.0, 150.0, 320.0]


@pytest.fixture(scope="module")
def two_channels(tmp_path_factory):
    """A three-mode hammer test, two sensors, written as ``t, ch0, ch1`` (the issue's file)."""
    rec = impact_record(FREQUENCIES, [0.01, 0.005, 0.004], fs=FS, duration=1.0, sensor_dof=[2, 1],
                        snr_db=50, offset=0.2, random_state=0)
    path = tmp_path_factory.mktemp("two") / "hit.csv"
    table = np.column_stack([rec.t, rec.y])
    np.savetxt(path, table, delimiter=",", header="t,ch0,ch1", comments="", fmt="%.9g")
    return rec, str(path)


@pytest.fixture(scope="module")
def surveyed(two_channels, tmp_path_factory):
    """The issue's command: ``modes hit.csv --fs 2048 --json --report --plot``, run once."""
    rec, path = two_channels
    out = tmp_path_factory.mktemp("outputs")
    argv = ["modes", path, "--fs", str(FS), "--json", str(out / "m.json"), "--report", str(out / "r.html"),
            "--plot", str(out / "p.png")]
    stdout, stderr = io.StringIO(), io.StringIO()
    with warnings.catch_warnings(), redirect_stdout(stdout), redirect_stderr(stderr):
        warnings.simplefilter("ignore")
        code = main(argv)
    printed, err = stdout.getvalue(), stderr.getvalue()
    report = json.loads((out / "m.json").read_text())
    page = (out / "r.html").read_text(encoding="utf-8")
    return rec, code, printed, err, report, page


def test_the_time_column_is_the_time_when_fs_is_given_too(surveyed):
    rec, code, printed, _, report, _ = surveyed
    assert code == 0
    assert report["channels"] == ["ch0", "ch1"] and "from ch0, ch1" in printed
    found = [m["frequency_hz"] for m in report["modes"]]
    assert len(found) == 3 and np.allclose(found, FREQUENCIES, rtol=2e-3)


def test_amplitude_and_phase_per_channel_on_the_terminal_and_in_the_json(surveyed):
    rec, _, printed, _, report, page = surveyed
    for k, mode in enumerate(report["modes"]):
        amplitudes = [c["amplitude"] for c in mode["channels"]]
        assert [c["channel"] for c in mode["channels"]] == ["ch0", "ch1"]
        np.testing.assert_allclose(amplitudes, rec.modes.amplitude[k], rtol=0.05)
        truth = np.degrees(rec.modes.phase[k][0] - rec.modes.phase[k][1])  # ch0 relative to ch1
        phase = mode["channels"][0]["phase_deg"]
        assert abs((phase - truth + 180) % 360 - 180) < 5
        reference = next(c["channel"] for c in mode["channels"] if c["reference"])
        assert mode["reference_channel"] == reference
        assert f"ch0: amplitude {amplitudes[0]:.4g}" in printed
        assert f"ch1: amplitude {amplitudes[1]:.4g}" in printed
    assert "Amplitude and shape per channel" in page and "amplitude ch0 (phase)" in page


def _html_table(page: str) -> list[dict]:
    table = re.search(r'<table class="modes">(.*?)</table>', page, re.S).group(1)
    rows = re.findall(r"<tr>(.*?)</tr>", table, re.S)
    header, *rows = [re.findall(r"<t[dh]>(.*?)</t[dh]>", r, re.S) for r in rows]
    return [dict(zip(header, (unescape(re.sub("<[^>]+>", "", c)) for c in row))) for row in rows]


def test_terminal_json_and_report_give_the_same_verdicts_and_damping(surveyed):
    _, _, printed, _, report, page = surveyed
    lines = [line for line in printed.splitlines() if line.startswith("  mode ")]
    rows = _html_table(page)
    assert len(lines) == len(rows) == len(report["modes"]) == 3
    assert report["damping_unit"] == "percent" and "damping ratio [%]" in rows[0]
    for line, row, mode in zip(lines, rows, report["modes"]):
        assert "damping_ratio" not in mode and "damping_ratio_percent" in mode  # the name says the unit
        verdict = "nonlinear" if mode["nonlinear"] else "linear"
        assert f", {verdict}, diagnostics {mode['diagnostics']}" in line
        assert row["diagnostics"] == mode["diagnostics"]
        assert row["nonlinear"] == ("yes" if mode["nonlinear"] else "no")
        zeta = float(re.search(r"damping ([0-9.]+) %", line).group(1))
        assert zeta == pytest.approx(mode["damping_ratio_percent"], rel=1e-3)
        assert float(row["damping ratio [%]"].split(" ± ")[0]) == pytest.approx(zeta, rel=1e-3)
        assert f"fit error {mode['fit_error']:.3g}" in line and row["fit error"] == f"{mode['fit_error']:.3g}"
        for problem in mode["problems"]:
            assert f"problem: {problem}"[:100] in line + printed
            assert problem.replace("'", "&#x27;")[:60] in page
    assert "of the RMS)</p>" not in page  # the diagnostics' own measure is not shown as a second fit error


def test_the_offset_removed_is_not_a_data_problem(surveyed):
    page = surveyed[5]
    record = page.split('id="record"')[1].split("</section>")[0]
    assert "removed before the survey" in record and "remove it (estimate_offset)" not in record


def test_a_rate_that_disagrees_with_the_time_column_is_an_error(two_channels, tmp_path, capsys):
    _, path = two_channels
    out = tmp_path / "m.json"
    code, _, err = _run(["modes", path, "--fs", "5000", "--json", str(out)], capsys)
    assert code == 2 and not out.exists()
    assert "time column 't' has a step of" in err and "5000" in err and err.count("\n") == 1


def test_time_with_fs_a_frequency_range_and_the_damping_unit(two_channels, tmp_path, capsys):
    _, path = two_channels
    out = tmp_path / "m.json"
    argv = ["modes", path, "--time", "t", "--fs", str(FS), "--fmin", "100", "--fmax", "200",
            "--no-nonlinearity", "--damping-unit", "fraction", "--json", str(out)]
    code, printed, _ = _run(argv, capsys)
    report = json.loads(out.read_text())
    assert code == 0 and [round(m["frequency_hz"]) for m in report["modes"]] == [150]
    assert re.search(r"2 mode\(s\) outside 100-200 Hz left out \(--fmin/--fmax\): 60(\.\d+)?, 320(\.\d+)? Hz",
                     " ".join(report["notes"]))
    mode = report["modes"][0]
    assert report["damping_unit"] == "fraction" and mode["damping_ratio"] == pytest.approx(0.005, rel=0.05)
    assert "damping_ratio_percent" not in mode and re.search(r"damping 0\.00\d+,", printed)


def test_max_modes_keeps_the_strongest(two_channels, tmp_path, capsys):
    _, path = two_channels
    code, printed, _ = _run(["modes", path, "--max-modes", "1", "--no-nonlinearity"], capsys)
    assert code == 0 and printed.count("  mode ") == 1
    assert re.search(r"mode 0: 3(19\.9|20)", printed)  # the strongest: 4 x the others in ch1


@pytest.mark.parametrize(
    "options, problem",
    [
        (["--fmin", "300", "--fmax", "100"], "--fmin 300 Hz must be below --fmax 100 Hz"),
        (["--fmin", "-5"], "--fmin must be a frequency of 0 Hz or more"),
        (["--max-modes", "0"], "expected a positive integer"),
        (["--damping-unit", "permille"], "invalid choice"),
    ],
)
def test_bad_selection_options_are_one_line_errors(two_channels, options, problem, capsys):
    code, _, err = _run(["modes", two_channels[1], *options], capsys)
    assert code == 2 and problem in err and err.count("\n") == 1


def test_the_readme_command_runs_as_written(tmp_path, monkeypatch, capsys):
    rec = impact_record([120.0, 240.0], [0.005, 0.01], fs=5000.0, duration=0.6, snr_db=50, random_state=0)
    monkeypatch.chdir(tmp_path)
    np.savetxt("hit.csv", np.column_stack([rec.t, rec.y, rec.force]), delimiter=",", header="t,acc,F",
               comments="", fmt="%.10g")
    code, printed, err = _run("modes hit.csv --fs 5000 --force F --json modes.json".split(), capsys)
    report = json.loads((tmp_path / "modes.json").read_text())
    assert code == 0 and report["channels"] == ["acc"]
    assert [round(m["frequency_hz"]) for m in report["modes"]] == [120, 240]


@pytest.fixture(scope="module")
def noise_only(tmp_path_factory):
    y = np.random.default_rng(0).standard_normal(4096)
    path = tmp_path_factory.mktemp("noise") / "noise.csv"
    np.savetxt(path, np.column_stack([np.arange(4096) / FS, y]), delimiter=",", header="t,ch0", comments="",
               fmt="%.9g")
    return str(path)


def test_no_mode_with_outputs_asked_is_an_error_that_says_why(noise_only, tmp_path, capsys):
    out = tmp_path / "m.json"
    code, printed, err = _run(["modes", noise_only, "--no-nonlinearity", "--json", str(out)], capsys)
    assert code == 2 and not out.exists()
    assert "no mode found" in err and "--allow-empty" in err and "bands=" not in err + printed
    code, printed, err = _run(["modes", noise_only, "--no-nonlinearity", "--json", str(out), "--allow-empty"],
                              capsys)
    assert code == 0 and out.exists() and err == ""
    report = json.loads(out.read_text())
    assert report["modes"] == [] and not any("bands=" in note for note in report["notes"])
    assert any("--fs" in note for note in report["notes"])  # the advice in the command line's terms
    code, printed, _ = _run(["modes", noise_only, "--no-nonlinearity"], capsys)  # nothing asked: no error
    assert code == 0 and "0 mode(s)" in printed


def test_version(capsys):
    from sindy_impulse import __version__

    code, printed, _ = _run(["--version"], capsys)
    assert code == 0 and printed.strip() == f"sindy-impulse {__version__}"


def test_a_wrong_option_points_at_the_commands_help_and_traceback_works_after_the_command(capsys):
    code, _, err = _run(["modes", "hit.csv", "--bogus"], capsys)
    assert code == 2 and err == (
        "sindy-impulse: error: unrecognized arguments: --bogus (see 'sindy-impulse modes --help')\n"
    )
    with pytest.raises(Exception, match="no such file"):  # --traceback after the command's name: raised
        main(["modes", "missing.csv", "--traceback"])
    code, _, err = _run(["modes", "missing.csv"], capsys)
    assert code == 2 and err == "sindy-impulse: error: missing.csv: no such file\n"


def test_every_help_says_what_its_plot_is(capsys):
    for command, words in (("modes", "the spectrum with the modes"), ("fit", "its reconstruction")):
        code, printed, _ = _run([command, "--help"], capsys)
        assert code == 0 and words in " ".join(printed.split())


def test_a_column_named_force_is_the_force_not_a_sensor(tmp_path, capsys):
    """The hammer's force is a pulse 100 times the response: read as a sensor it would be the survey's
    reference channel, and nothing rings there."""
    rec = impact_record([120.0, 252.0], [0.005, 0.01], fs=4000.0, duration=1.0, snr_db=50, random_state=0)
    path = tmp_path / "hit.csv"
    np.savetxt(path, np.column_stack([rec.t, rec.y, rec.force]), delimiter=",", header="t,acc,Force",
               comments="")
    code, out, _ = _run(["modes", str(path), "--json", str(tmp_path / "m.json")], capsys)
    report = json.loads((tmp_path / "m.json").read_text())
    assert code == 0 and report["channels"] == ["acc"] and report["force_column"] == "Force"
    assert "column 'Force', by its name" in out
    assert np.allclose(sorted(m["frequency_hz"] for m in report["modes"]), [120.0, 252.0], rtol=1e-3)
    code, out, _ = _run(["modes", str(path), "--columns", "acc,Force"], capsys)  # a sensor on purpose
    assert "from acc, Force" in out and "by its name" not in out

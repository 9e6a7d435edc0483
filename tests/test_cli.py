import json
import subprocess
import sys

import numpy as np
import pytest

from sindy_impulse.cli import main, read_csv
from sindy_impulse.datasets import damped_oscillator


def test_demo_prints_equations_and_writes_figure(tmp_path, capsys):
    out_png = tmp_path / "demo.png"
    assert main(["demo", "--plot", str(out_png)]) == 0
    out = capsys.readouterr().out
    assert "After refinement (3 terms)" in out
    assert "-64.0000 x1 + -3.2000 x2" in out
    assert out_png.stat().st_size > 1000


def test_demo_with_noise_no_plot(capsys):
    assert main(["demo", "--snr", "30", "--plot", ""]) == 0
    assert "Stiffness k" in capsys.readouterr().out


def test_console_script_usage_error():
    proc = subprocess.run(
        [sys.executable, "-m", "sindy_impulse.cli", "nonsense"], capture_output=True, text=True
    )
    assert proc.returncode != 0
    assert "invalid choice" in proc.stderr
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr


# ----------------------------------------------------------------------------------------------------
# CSV files
# ----------------------------------------------------------------------------------------------------
def _write_ring(path, k=64.0, k_nl=0.0, seed=0, time=True):
    ring = damped_oscillator(k=k, k_nl=k_nl, x0=(1.5, 0.0), snr_db=40, random_state=seed)
    cols, header = [ring.x[:, 0], ring.x[:, 1]], "x,v"
    if time:
        cols, header = [ring.t, *cols], "t," + header
    np.savetxt(path, np.column_stack(cols), delimiter=",", header=header, comments="", fmt="%.10g")
    return path


@pytest.fixture(scope="module")
def rings(tmp_path_factory):
    folder = tmp_path_factory.mktemp("rings")
    paths = [
        _write_ring(folder / "linear.csv"),
        _write_ring(folder / "stiff.csv", k=100.0, seed=1),
        _write_ring(folder / "duffing.csv", k_nl=30.0, seed=2),
    ]
    return folder, paths


def test_read_csv_selects_columns_and_time(rings):
    _, (linear, *_) = rings
    table = read_csv(str(linear))
    assert table.names == ["x", "v"] and table.time_column == "t"
    assert table.data.shape == (401, 2) and table.t[1] == pytest.approx(0.01)
    table = read_csv(str(linear), columns=["v"], dt=0.01)  # the time column is still the time, and agrees
    assert table.names == ["v"] and table.time_column == "t" and table.t[1] == pytest.approx(0.01)
    table = read_csv(str(linear), columns=["t", "v"], dt=0.01)  # named as a state: a state
    assert table.names == ["t", "v"] and table.t == 0.01 and table.time_column is None


def test_read_csv_trailing_delimiter_and_quotes(tmp_path):
    path = tmp_path / "sb.csv"
    path.write_text('"V1","V2",\n0.1,0.2,\n0.3,0.4,\n')
    table = read_csv(str(path), dt=0.5)
    assert table.names == ["V1", "V2"]
    np.testing.assert_array_equal(table.data, [[0.1, 0.2], [0.3, 0.4]])


def test_fit_two_states_json_and_plot(rings, tmp_path, capsys):
    _, (_, _, duffing) = rings
    out_json, out_png = tmp_path / "fit.json", tmp_path / "fit.png"
    code = main(["fit", str(duffing), "--json", str(out_json), "--plot", str(out_png)])
    out = capsys.readouterr().out
    assert code == 0
    assert "(x)' =" in out and "(v)' =" in out
    assert "Nonlinearity test: NONLINEAR" in out
    assert "natural frequency 1.27" in out
    report = json.loads(out_json.read_text())
    assert report["states"] == ["x", "v"] and report["time_column"] == "t"
    assert report["dt"] == pytest.approx(0.01)
    assert set(report["equations"]) == {"x'", "v'"}
    assert report["gamma"] > 0 and report["complexity"] >= 3
    nl = report["nonlinearity"]
    assert nl["nonlinear"] is True and nl["statistic"] > nl["threshold"]
    assert nl["terms"][0]["term"] == "x^3"
    assert nl["terms"][0]["coefficient"] == pytest.approx(-30, rel=0.1)
    (mode,) = report["modes"]
    assert mode["frequency_hz"] == pytest.approx(8 / (2 * np.pi), rel=0.01)
    assert mode["damping_ratio_percent"] == pytest.approx(20.0, rel=0.05) and "damping_ratio" not in mode
    coef = np.array(report["coefficients"])
    assert coef.shape == (2, len(report["library"]))
    assert out_png.read_bytes()[:4] == b"\x89PNG"


def test_fit_embedded_single_column_with_dt(tmp_path, capsys):
    path = _write_ring(tmp_path / "x_only.csv", time=False)
    code = main(["fit", str(path), "--columns", "x", "--dt", "0.01", "--embed", "--dimension", "2"])
    out = capsys.readouterr().out
    assert code == 0
    assert "delay embedding of 'x'" in out and "dt = 0.01" in out
    assert "Nonlinearity test: linear" in out
    frequency = float(out.split("natural frequency ")[1].split()[0])
    assert frequency == pytest.approx(1.2732, rel=0.01)


def test_features_over_a_glob(rings, tmp_path, capsys):
    folder, _ = rings
    out = tmp_path / "features.csv"
    code = main(["features", str(folder / "*.csv"), "--out", str(out), "--n-jobs", "2", "--no-progress"])
    assert code == 0
    assert "3 file(s) x 20 features, 0 failed" in capsys.readouterr().out
    lines = out.read_text().splitlines()
    header = lines[0].split(",")
    assert header[0] == "file" and len(header) == 21 and "v' : x^3" in header
    rows = {line.split(",")[0]: np.array(line.split(",")[1:], dtype=float) for line in lines[1:]}
    assert sorted(rows) == ["duffing.csv", "linear.csv", "stiff.csv"]
    cubic, stiffness = header.index("v' : x^3") - 1, header.index("v' : x") - 1
    assert rows["duffing.csv"][cubic] == pytest.approx(-30, rel=0.1)
    assert rows["linear.csv"][cubic] == 0
    assert rows["stiff.csv"][stiffness] == pytest.approx(-100, rel=0.02)


# ----------------------------------------------------------------------------------------------------
# user errors: one line on stderr, exit code != 0, no traceback
# ----------------------------------------------------------------------------------------------------
def _error(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as stop:  # argparse's usage errors (e.g. --dt abc)
        code = stop.code
    err = capsys.readouterr().err
    assert code != 0
    assert "Traceback" not in err
    lines = [line for line in err.splitlines() if line.startswith("sindy-impulse: error:")]
    assert len(lines) == 1, err
    return lines[0]


def test_error_missing_file(tmp_path, capsys):
    assert "no such file" in _error(["fit", str(tmp_path / "missing.csv")], capsys)


def test_error_no_files_match(tmp_path, capsys):
    message = _error(["features", str(tmp_path / "*.csv"), "--dt", "0.01", "--out", "f.csv"], capsys)
    assert "no files match" in message
    assert "no CSV files" in _error(["features", str(tmp_path), "--dt", "0.01", "--out", "f.csv"], capsys)


def test_error_missing_column(rings, capsys):
    _, (linear, *_) = rings
    message = _error(["fit", str(linear), "--columns", "x,z"], capsys)
    assert "no column 'z'" in message and "columns: t, x, v" in message
    assert "no column 'time'" in _error(["fit", str(linear), "--time", "time"], capsys)


def test_error_non_numeric_cell(tmp_path, capsys):
    path = tmp_path / "bad.csv"
    path.write_text("t,x,v\n0,1,0\n0.01,0.9,abc\n0.02,0.8,-1\n")
    message = _error(["fit", str(path)], capsys)
    assert "column 'v'" in message and "'abc'" in message and "line 3" in message
    path.write_text("t,x,v\n0,1,0\n0.01,,-1\n")
    assert "empty cell" in _error(["fit", str(path)], capsys)
    path.write_text("t,x,v\n0,1,0\n0.01,nan,-1\n")
    assert "non-finite" in _error(["fit", str(path)], capsys)


def test_error_too_few_rows(tmp_path, capsys):
    path = tmp_path / "short.csv"
    path.write_text("t,x,v\n0,1,0\n0.01,0.9,-1\n0.02,0.8,-1\n")
    assert "too few rows" in _error(["fit", str(path)], capsys)
    assert "too few rows" in _error(["fit", str(path), "--columns", "x", "--embed"], capsys)
    assert "too few rows" in _error(["features", str(path), "--out", str(tmp_path / "f.csv")], capsys)
    path.write_text("t,x,v\n")
    assert "no data rows" in _error(["fit", str(path)], capsys)
    path.write_text("")
    assert "is empty" in _error(["fit", str(path)], capsys)


def test_error_bad_dt_and_time(rings, tmp_path, capsys):
    _, (linear, *_) = rings
    assert "--dt must be a positive" in _error(["fit", str(linear), "--dt", "-1"], capsys)
    assert "--dt must be a positive" in _error(["fit", str(linear), "--dt", "nan"], capsys)
    assert "invalid float value" in _error(["fit", str(linear), "--dt", "abc"], capsys)
    assert "has a step of 0.01" in _error(["fit", str(linear), "--dt", "0.1", "--time", "t"], capsys)
    assert "not allowed with" in _error(["fit", str(linear), "--dt", "0.1", "--fs", "10"], capsys)
    no_time = _write_ring(tmp_path / "no_time.csv", time=False)
    assert "no time information" in _error(["fit", str(no_time)], capsys)
    assert "not strictly increasing at line 3" in _error(["fit", str(linear), "--time", "x"], capsys)


def test_error_embed_needs_one_column(rings, capsys):
    _, (linear, *_) = rings
    assert "--embed needs a single measured column" in _error(["fit", str(linear), "--embed"], capsys)


def test_error_one_line_from_a_subprocess(tmp_path):
    proc = subprocess.run(
        [sys.executable, "-m", "sindy_impulse.cli", "fit", str(tmp_path / "missing.csv")],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 2
    assert proc.stderr.startswith("sindy-impulse: error:") and proc.stderr.count("\n") == 1

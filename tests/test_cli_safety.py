"""The command line never loses data: atomic outputs, inputs never overwritten, batches that continue past
bad files, regular files only, strict numbers."""

import math
import os
import signal
import stat
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import sindy_impulse
from sindy_impulse.cli import build_parser, main
from sindy_impulse.cli import files as _io
from sindy_impulse.cli._numbers import NumberError, parse_int, parse_number
from sindy_impulse.cli._options import data_options
from sindy_impulse.cli.files import CLIError, atomic_write, read_csv
from sindy_impulse.datasets import damped_oscillator

OLD = '{"old": "report"}\n'
#: Generous limit for a subprocess that must not hang; no test asserts how long anything takes.
HANG_GUARD = 120


def _write_ring(path, k=64.0, seed=0, n=None):
    ring = damped_oscillator(k=k, x0=(1.5, 0.0), snr_db=40, random_state=seed)
    table = np.column_stack([ring.t, ring.x])[:n]
    np.savetxt(path, table, delimiter=",", header="t,x,v", comments="", fmt="%.10g")
    return path


def _run(argv, capsys):
    """Exit code (also of argparse's usage errors), stdout and stderr of the command line."""
    try:
        code = main([str(a) for a in argv])
    except SystemExit as stop:
        code = stop.code
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    return code, out, err


def _error_line(err):
    (line,) = [line for line in err.splitlines() if line.startswith("sindy-impulse: error:")]
    return line


def _subprocess(code, *args, cwd=None):
    """``python -c code args`` importing this very sindy_impulse."""
    root = os.path.dirname(os.path.dirname(os.path.abspath(sindy_impulse.__file__)))
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([root, os.environ.get("PYTHONPATH", "")]))
    return subprocess.Popen(
        [sys.executable, "-c", textwrap.dedent(code), *map(str, args)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
        cwd=cwd,
    )


@pytest.fixture
def ring(tmp_path):
    return _write_ring(tmp_path / "ring.csv")


# ----------------------------------------------------------------------------------------------------
# atomic writes
# ----------------------------------------------------------------------------------------------------
SLOW_JSON = """
    import json, sys, time
    real_dump = json.dump
    def slow_dump(obj, fh, **kwargs):  # the whole report is written, then the writer stalls
        real_dump(obj, fh, **kwargs)
        print("writing", flush=True)
        time.sleep(600)
    json.dump = slow_dump
    from sindy_impulse.cli import main
    sys.exit(main(sys.argv[1:]))
"""


def test_sigkill_during_a_write_leaves_the_old_file_and_no_temp_file(ring, tmp_path):
    out = tmp_path / "fit.json"
    out.write_text(OLD)
    proc = _subprocess(SLOW_JSON, "fit", ring, "--json", out)
    try:
        for line in proc.stdout:  # the fit's report, then the writer's signal
            if line.strip() == "writing":
                break
        else:
            pytest.fail(f"the writer never started: {proc.stderr.read()}")
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=HANG_GUARD)
    finally:
        proc.kill()
        proc.stdout.close()
        proc.stderr.close()
    assert proc.returncode == -signal.SIGKILL
    assert out.read_text() == OLD
    assert sorted(os.listdir(tmp_path)) == ["fit.json", "ring.csv"]


def test_a_failure_after_a_partial_write_keeps_the_old_file(tmp_path, monkeypatch):
    out = tmp_path / "table.csv"
    out.write_text(OLD)

    def broken_fsync(fd):
        assert os.fstat(fd).st_size > 0  # the temporary file holds (part of) the new content
        raise OSError(5, "Input/output error")

    monkeypatch.setattr(_io.os, "fsync", broken_fsync)
    with pytest.raises(CLIError, match=r"cannot write .*table.csv: Input/output error"):
        atomic_write(str(out), lambda fh: fh.write("new,content\n" * 1000))
    assert out.read_text() == OLD
    assert os.listdir(tmp_path) == ["table.csv"]


def test_an_error_while_rendering_leaves_no_trace(tmp_path):
    out = tmp_path / "new.json"

    def render(fh):
        fh.write("partial")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        atomic_write(str(out), render)
    assert os.listdir(tmp_path) == []


def test_atomic_write_keeps_permissions_and_follows_links(tmp_path):
    target = tmp_path / "report.json"
    target.write_text(OLD)
    target.chmod(0o640)
    link = tmp_path / "latest.json"
    link.symlink_to(target.name)
    atomic_write(str(link), lambda fh: fh.write("new"))
    assert link.is_symlink() and target.read_text() == "new"
    assert stat.S_IMODE(target.stat().st_mode) == 0o640
    fresh = tmp_path / "fresh.json"
    atomic_write(str(fresh), lambda fh: fh.write("x"))
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE(fresh.stat().st_mode) == 0o666 & ~umask


# ----------------------------------------------------------------------------------------------------
# inputs are never overwritten; outputs are checked before any work
# ----------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("flag", ["--json", "--plot"])
def test_fit_refuses_to_overwrite_its_input(ring, flag, capsys):
    before = ring.read_bytes()
    code, _, err = _run(["fit", ring, flag, ring], capsys)
    assert code == 2
    assert f"{flag} {ring} is the input file {ring}; refusing to overwrite an input" in _error_line(err)
    assert ring.read_bytes() == before


def test_a_link_to_the_input_is_the_input(ring, tmp_path, capsys):
    (tmp_path / "fit.png").symlink_to(ring)
    code, _, err = _run(["fit", ring, "--plot", tmp_path / "fit.png"], capsys)
    assert code == 2 and "refusing to overwrite an input" in _error_line(err)


@pytest.mark.parametrize(
    "outputs, message",
    [
        (["--json", "{d}/same", "--plot", "{d}/same"], "--json and --plot name the same file"),
        (["--json", "{d}/missing/fit.json"], "no such directory"),
        (["--json", "{d}"], "it is a directory, not a regular file"),
        (["--plot", "{d}/fit.xyz"], "cannot write .xyz figures"),
    ],
)
def test_bad_outputs_are_refused_before_the_fit(ring, tmp_path, outputs, message, capsys):
    code, out, err = _run(["fit", ring, *(o.format(d=tmp_path) for o in outputs)], capsys)
    assert code == 2 and message in _error_line(err)
    assert out == ""  # nothing was fitted


def test_features_refuses_to_overwrite_an_input(tmp_path, capsys):
    data = _write_ring(tmp_path / "data.csv")
    before = data.read_bytes()
    for pattern in (data, tmp_path, tmp_path / "*.csv"):
        code, _, err = _run(["features", pattern, "--out", data, "--no-progress"], capsys)
        assert code == 2 and "refusing to overwrite an input" in _error_line(err)
    assert data.read_bytes() == before


# ----------------------------------------------------------------------------------------------------
# batches continue past bad files
# ----------------------------------------------------------------------------------------------------
def test_a_batch_processes_the_good_files_and_reports_the_bad_ones(tmp_path, capsys):
    runs = tmp_path / "runs"
    runs.mkdir()
    _write_ring(runs / "a_linear.csv")
    (runs / "b_broken.csv").write_text("t,x,v\n0,1,0\n0.01,0.9,abc\n")
    _write_ring(runs / "c_short.csv", n=10)
    _write_ring(runs / "d_stiff.csv", k=100.0, seed=1)
    out = runs / "features.csv"
    out.write_text("file,x' : 1\nold.csv,1\n")  # an earlier run's table among the inputs: not read
    code, stdout, err = _run(["features", runs, "--out", out, "--n-jobs", "1"], capsys)
    assert code == 1
    assert f"{out}: 4 file(s) x 20 features, 0 failed, 2 skipped" in stdout
    skipped = [line for line in err.splitlines() if line.startswith("sindy-impulse: skipped:")]
    assert len(skipped) == 2
    assert "b_broken.csv: column 'v' has a non-numeric cell 'abc' at line 3" in skipped[0]
    assert "c_short.csv has too few rows: 10 data rows" in skipped[1]
    assert err.splitlines()[-1].startswith("sindy-impulse: error: 2 of 4 file(s) skipped")
    assert "SINDy fits" in err  # the progress bar (tqdm is installed in the test environment)
    lines = out.read_text().splitlines()
    rows = {line.split(",")[0]: np.array(line.split(",")[1:], dtype=float) for line in lines[1:]}
    assert list(rows) == ["a_linear.csv", "b_broken.csv", "c_short.csv", "d_stiff.csv"]
    assert np.isnan(rows["b_broken.csv"]).all() and np.isnan(rows["c_short.csv"]).all()
    stiffness = lines[0].split(",").index("v' : x") - 1
    assert rows["a_linear.csv"][stiffness] == pytest.approx(-64, rel=0.02)
    assert rows["d_stiff.csv"][stiffness] == pytest.approx(-100, rel=0.02)


def test_a_batch_without_a_usable_file_writes_nothing(tmp_path, capsys):
    (tmp_path / "a.csv").write_text("t,x\n0,1\n0.01,nan\n")
    (tmp_path / "b.csv").write_text("t,x\n0,1\n0.01,1e400\n")
    out = tmp_path / "features.csv"
    out.write_text("file,x' : 1\nold.csv,1\n")
    code, _, err = _run(["features", tmp_path, "--out", out, "--no-progress"], capsys)
    assert code == 2
    assert "none of the 2 files could be used" in _error_line(err)
    assert err.count("sindy-impulse: skipped:") == 2
    assert out.read_text() == "file,x' : 1\nold.csv,1\n"


def test_progress_bar_only_when_wanted_and_available(monkeypatch):
    from sindy_impulse.cli.features_command import _progress_bar

    args = build_parser().parse_args(["features", "x", "--out", "y"])
    assert _progress_bar(args) is True
    monkeypatch.setitem(sys.modules, "tqdm", None)  # not installed: silently no bar
    assert _progress_bar(args) is False
    args = build_parser().parse_args(["features", "x", "--out", "y", "--no-progress"])
    assert _progress_bar(args) is False


# ----------------------------------------------------------------------------------------------------
# regular files only
# ----------------------------------------------------------------------------------------------------
def test_a_fifo_input_is_refused_without_hanging(tmp_path):
    fifo = tmp_path / "live.csv"
    os.mkfifo(fifo)
    proc = _subprocess(
        "import sys; from sindy_impulse.cli import main; sys.exit(main(sys.argv[1:]))", "fit", fifo
    )
    try:
        _, err = proc.communicate(timeout=HANG_GUARD)
    finally:
        proc.kill()
    assert proc.returncode == 2
    assert err == f"sindy-impulse: error: {fifo} is a FIFO (named pipe), expected a regular CSV file\n"


@pytest.mark.parametrize(
    "path, message", [("/dev/null", "is a character device"), (".", "is a directory, expected a CSV file")]
)
def test_other_non_regular_inputs_are_refused(path, message, capsys):
    code, _, err = _run(["fit", path], capsys)
    assert code == 2 and message in _error_line(err)


def test_a_fifo_in_a_batch_is_a_bad_file(tmp_path, capsys):
    os.mkfifo(tmp_path / "live.csv")
    (tmp_path / "short.csv").write_text("t,x\n0,1\n")
    code, _, err = _run(["features", tmp_path, "--out", tmp_path / "f.csv", "--no-progress"], capsys)
    assert code == 2
    assert "live.csv is a FIFO (named pipe)" in err


# ----------------------------------------------------------------------------------------------------
# strict numbers
# ----------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "text, reason",
    [
        ("1_0", "underscore"),
        (" 1", "spaces around the number"),
        ("1 ", "spaces around the number"),
        ("0x10", "hexadecimal"),
        ("1e400", "too large for a float"),
        ("-1e400", "too large for a float"),
        ("nan", "not finite"),
        ("-inf", "not finite"),
        ("infinity", "not finite"),
        ("\u0661", "not a number"),  # an Arabic-Indic digit one, which float() accepts
        ("", "empty"),
        ("1,5", "not a number"),
    ],
)
def test_parse_number_refuses(text, reason):
    with pytest.raises(NumberError, match=reason):
        parse_number(text)


def test_parse_number_and_int_accept_plain_decimals():
    assert [parse_number(s) for s in ("1", "-2.5", ".5", "5.", "+1e-3", "1E3")] == [
        1,
        -2.5,
        0.5,
        5,
        1e-3,
        1e3,
    ]
    assert math.isnan(parse_number("NaN", finite=False))
    assert parse_int("-12") == -12
    for text in ("1.0", "1_0", " 1", "0x1"):
        with pytest.raises(NumberError):
            parse_int(text)


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--dt", "1_0"], "argument --dt: invalid number '1_0': an underscore digit separator"),
        (["--dt", " 1"], "argument --dt: invalid number ' 1': spaces around the number"),
        (["--dt", "0x10"], "argument --dt: invalid number '0x10': hexadecimal notation"),
        (["--dt", "1e400"], "argument --dt: invalid number '1e400': too large for a float"),
        (["--fs", "nan"], "--fs must be a positive sampling frequency"),
        (["--fs", "0"], "--fs must be a positive sampling frequency"),
        (["--degree", "1_0"], "argument --degree: invalid number '1_0'"),
        (["--degree", "2.5"], "argument --degree: expected a positive integer, got '2.5'"),
        (["--dimension", "two"], "argument --dimension: expected a positive integer or 'auto', got 'two'"),
        (["--tau", " 3"], "argument --tau: invalid number ' 3': spaces around the number"),
        (["--fs", "100", "--dt", "0.01"], "not allowed with argument"),
    ],
)
def test_options_are_parsed_strictly(ring, argv, message, capsys):
    code, _, err = _run(["fit", ring, *argv], capsys)
    assert code == 2 and message in _error_line(err)


def test_other_commands_parse_numbers_strictly(capsys):
    assert "too large for a float" in _error_line(_run(["demo", "--snr", "1e400"], capsys)[2])
    assert "invalid number '1_0'" in _error_line(_run(["demo", "--seed", "1_0"], capsys)[2])
    assert "invalid int value: 'x'" in _error_line(
        _run(["features", "d", "--out", "o", "--n-jobs", "x"], capsys)[2]
    )


@pytest.mark.parametrize(
    "cell, problem",
    [
        ("1_0", "an invalid number '1_0' at line 3 (an underscore digit separator)"),
        (" 1", "an invalid number ' 1' at line 3 (spaces around the number)"),
        ("0x10", "an invalid number '0x10' at line 3 (hexadecimal notation)"),
        ("1e400", "an invalid number '1e400' at line 3 (too large for a float)"),
        ("nan", "a non-finite value 'nan' at line 3"),
        ("inf", "a non-finite value 'inf' at line 3"),
    ],
)
def test_csv_cells_are_parsed_strictly_and_located(tmp_path, cell, problem):
    path = tmp_path / "cells.csv"
    path.write_text(f"t,x,v\n0,1,0\n0.01,{cell},-1\n")
    with pytest.raises(CLIError) as err:
        read_csv(str(path))
    assert str(err.value) == f"{path}: column 'x' has {problem}"


def test_spaces_after_every_delimiter_are_the_file_format(tmp_path):
    path = tmp_path / "spaced.csv"
    path.write_text("t, x, v\n0, 1, 0\n0.5, 0.9, -1\n")
    table = read_csv(str(path))
    assert table.names == ["x", "v"]
    np.testing.assert_array_equal(table.data, [[1, 0], [0.9, -1]])


# ----------------------------------------------------------------------------------------------------
# the data options are ready for more commands
# ----------------------------------------------------------------------------------------------------
def test_fs_is_the_sampling_frequency(tmp_path):
    path = tmp_path / "x_only.csv"
    path.write_text("x,force\n" + "".join(f"{np.cos(i / 5):.6f},{i % 2}\n" for i in range(8)))
    args = build_parser().parse_args(["fit", str(path), "--fs", "100", "--columns", "x"])
    options = data_options(args)
    assert options == {"columns": ["x"], "time": None, "dt": 0.01}
    table = read_csv(str(path), **{**options, "columns": None}, extra=["force"])
    assert table.names == ["x"] and table.t == 0.01  # the extra column is not a state
    assert table.extra["force"].tolist() == [0, 1] * 4


def test_an_interruption_is_one_line_and_status_130(ring, monkeypatch, capsys):
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr("sindy_impulse.cli.fit_command.read_csv", interrupted)
    code, _, err = _run(["fit", ring], capsys)
    assert code == 130 and err == "sindy-impulse: interrupted\n"

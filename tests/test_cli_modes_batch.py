"""``sindy-impulse modes FILE [FILE ...]``: several inputs, --out-dir naming, no overwriting, short output."""

import json
import re

import numpy as np
import pytest
from cli_helpers import run_cli as _run

from sindy_impulse import impact_record

FS = 5000.0


def _write(path, seed, f=(120.0, 240.0)):
    rec = impact_record(list(f), [0.005, 0.01], fs=FS, duration=0.6, snr_db=50, random_state=seed)
    np.savetxt(path, np.column_stack([rec.t, rec.y]), delimiter=",", header="t,acc", comments="", fmt="%.12g")
    return str(path)


@pytest.fixture(scope="module")
def hits(tmp_path_factory):
    folder = tmp_path_factory.mktemp("hits")
    return [_write(folder / "hit1.csv", 0), _write(folder / "hit2.csv", 1, (150.0, 330.0))]


def test_out_dir_writes_each_kind_per_input_named_after_it(hits, tmp_path, capsys):
    out = tmp_path / "results"  # created when missing
    argv = ["modes", *hits, "--no-nonlinearity", "--out-dir", str(out), "--outputs", "json,unv,uff58,png"]
    code, printed, err = _run(argv, capsys)
    assert code == 0 and err == ""
    names = sorted(p.name for p in out.iterdir())
    assert names == sorted(f"hit{i}{s}" for i in (1, 2) for s in (".json", ".unv", "_signals.unv", ".png"))
    for i, frequencies in ((1, [120, 240]), (2, [150, 330])):
        report = json.loads((out / f"hit{i}.json").read_text())
        assert report["file"] == hits[i - 1]
        assert [round(m["frequency_hz"]) for m in report["modes"]] == frequencies
        assert all(set(m["equations"]) == {"y'", "dy'"} for m in report["modes"])
    assert (out / "hit1.png").read_bytes()[:4] == b"\x89PNG"
    pyuff = pytest.importorskip("pyuff")
    sets = pyuff.UFF(str(out / "hit2_signals.unv")).read_sets()
    assert [s["id1"] for s in sets][::2] == ["mode 1 150 Hz band signal", "mode 2 330 Hz band signal"]
    assert "written to" in printed and "2 of 2 file(s) done, 4 mode(s)" in printed


def test_the_terminal_gets_one_line_per_mode_and_no_equations(hits, capsys):
    code, printed, _ = _run(["modes", hits[0], "--no-nonlinearity"], capsys)
    assert code == 0
    lines = printed.splitlines()
    assert lines[0] == f"{hits[0]}: 2 mode(s) from acc"
    assert len(lines) == 3
    assert all(re.fullmatch(r"  mode \d: [\d.]+ Hz, damping [\d.]+ %, amplitude .*, diagnostics \w+", x)
               for x in lines[1:])
    assert "' =" not in printed and "note" not in printed


def test_each_problem_is_one_line_and_its_details_go_to_the_json(tmp_path, capsys):
    noise = tmp_path / "noise.csv"
    rng = np.random.default_rng(0)
    t = np.arange(3000) / FS
    np.savetxt(noise, np.column_stack([t, rng.standard_normal(t.size)]), delimiter=",", header="t,acc",
               comments="")
    out = tmp_path / "noise.json"
    code, printed, _ = _run(["modes", str(noise), "--json", str(out), "--allow-empty"], capsys)
    assert code == 0
    lines = printed.splitlines()
    warned = [x for x in lines if x.startswith("  warning: ")]
    assert lines[0].endswith("0 mode(s) from acc") and warned
    assert all(len(x) <= 160 for x in lines)
    notes = json.loads(out.read_text())["notes"]
    assert len(notes) == len(warned)
    for note, line in zip(notes, warned):  # the whole note, or its start cut at the line's length
        text = line[len("  warning: "):]
        assert text == note or (text.endswith("...") and note.startswith(text[:-3]))


def test_no_output_is_replaced_without_overwrite(hits, tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    (out / "hit2.json").write_text("mine")
    code, _, err = _run(["modes", *hits, "--no-nonlinearity", "--out-dir", str(out)], capsys)
    assert code == 2 and "hit2.json exists; add --overwrite" in err
    assert sorted(p.name for p in out.iterdir()) == ["hit2.json"]  # refused before any work
    assert (out / "hit2.json").read_text() == "mine"
    single = tmp_path / "table.json"
    single.write_text("mine")
    code, _, err = _run(["modes", hits[0], "--json", str(single)], capsys)
    assert code == 2 and "table.json exists; add --overwrite" in err and single.read_text() == "mine"
    code, _, _ = _run(["modes", *hits, "--no-nonlinearity", "--out-dir", str(out), "--overwrite"], capsys)
    assert code == 0 and json.loads((out / "hit2.json").read_text())["file"] == hits[1]


@pytest.mark.parametrize(
    "extra, message",
    [
        (["--json", "a.json"], "--json names one output file but 2 inputs were given; use --out-dir DIR"),
        (["--plot", "a.png"], "--plot names one output file but 2 inputs"),
        (["--uff58", "a.unv"], "--uff58 names one output file but 2 inputs"),
        (["--outputs", "json,png"], "--outputs chooses what --out-dir holds; give --out-dir DIR"),
        (["--out-dir", "{tmp}", "--outputs", "json,xls"], "--outputs takes a comma-separated list of json"),
        (["--out-dir", "{tmp}", "--json", "a.json"], "--json and --out-dir: choose one"),
    ],
)
def test_options_that_do_not_fit_several_inputs_are_refused(hits, tmp_path, capsys, extra, message):
    extra = [x.replace("{tmp}", str(tmp_path)) for x in extra]
    code, printed, err = _run(["modes", *hits, *extra], capsys)
    assert code == 2 and message in err and printed == ""


def test_inputs_with_the_same_name_would_clash_in_the_out_dir(hits, tmp_path, capsys):
    other = tmp_path / "elsewhere"
    other.mkdir()
    twin = _write(other / "hit1.csv", 3)
    code, _, err = _run(["modes", hits[0], twin, "--out-dir", str(tmp_path / "out")], capsys)
    assert code == 2 and "would both write hit1.* in --out-dir" in err
    code, _, err = _run(["modes", hits[0], hits[0], "--out-dir", str(tmp_path / "out")], capsys)
    assert code == 2 and "is given twice" in err


def test_a_bad_input_is_skipped_and_the_batch_goes_on(hits, tmp_path, capsys):
    bad = tmp_path / "short.csv"
    bad.write_text("t,acc\n0,1\n0.001,2\n")
    out = tmp_path / "out"
    argv = ["modes", str(bad), hits[1], "--no-nonlinearity", "--out-dir", str(out)]
    code, printed, err = _run(argv, capsys)
    assert code == 1
    assert err.splitlines() == [f"sindy-impulse: skipped: {bad} has 2 data rows; a hammer-test record needs "
                                "at least 64"]
    assert sorted(p.name for p in out.iterdir()) == ["hit2.json"]
    assert "1 of 2 file(s) done, 2 mode(s)" in printed


def test_uff58_of_one_input(hits, tmp_path, capsys):
    pyuff = pytest.importorskip("pyuff")
    path = tmp_path / "signals.unv"
    code, printed, _ = _run(["modes", hits[0], "--no-nonlinearity", "--uff58", str(path)], capsys)
    assert code == 0 and f"written: {path}" in printed
    assert len(pyuff.UFF(str(path)).read_sets()) == 4


@pytest.mark.slow  # two worker processes
def test_two_jobs_write_the_serial_json(hits, tmp_path, capsys):
    for jobs, folder in (("1", "serial"), ("2", "parallel")):
        code, _, _ = _run(["modes", *hits, "--n-jobs", jobs, "--out-dir", str(tmp_path / folder)], capsys)
        assert code == 0
    for name in ("hit1.json", "hit2.json"):
        assert (tmp_path / "serial" / name).read_text() == (tmp_path / "parallel" / name).read_text()

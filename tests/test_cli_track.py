"""``sindy-impulse track REF ... --against FILE ...``: one line per alarm, JSON, CSV, HTML, exit codes."""

import csv
import json

import numpy as np
import pytest
from cli_helpers import run_cli as _run

from sindy_impulse import impact_record

FS = 2000.0


def _write(path, seed, f):
    rec = impact_record([f], [0.01], fs=FS, duration=0.5, snr_db=50, random_state=seed)
    np.savetxt(path, np.column_stack([rec.t, rec.y]), delimiter=",", header="t,acc", comments="", fmt="%.12g")
    return str(path)


@pytest.fixture(scope="module")
def hits(tmp_path_factory):
    """Five reference hits of a 150 Hz mode scattering 0.03 %, then one like them and one 1 % lower."""
    folder = tmp_path_factory.mktemp("hits")
    rng = np.random.default_rng(0)
    ref = [_write(folder / f"ref{i}.csv", i, 150.0 * (1 + 3e-4 * rng.standard_normal())) for i in range(5)]
    same = _write(folder / "new0.csv", 10, 150.0 * (1 + 3e-4 * rng.standard_normal()))
    lower = _write(folder / "new1.csv", 11, 150.0 * 0.99)
    return ref, [same, lower]


def test_one_line_per_alarm_and_every_output(hits, tmp_path, capsys):
    ref, new = hits
    out = {k: str(tmp_path / f"track.{k}") for k in ("json", "csv", "html", "png")}
    code, text, _ = _run(
        [
            "track",
            *ref,
            "--against",
            *new,
            "--json",
            out["json"],
            "--csv",
            out["csv"],
            "--report",
            out["html"],
            "--plot",
            out["png"],
            "--no-progress",
        ],
        capsys,
    )
    assert code == 0
    alarms = [line for line in text.splitlines() if " changed: " in line]
    assert len(alarms) == 1 and alarms[0].strip().startswith(new[1]) and "linear stiffness" in alarms[0]
    assert "1 of 2 new surveys changed" in text
    data = json.loads(open(out["json"]).read())
    assert data["files"] == ref + new and [a["label"] for a in data["alarms"]] == [new[1]]
    rows = list(csv.DictReader(open(out["csv"])))
    assert len(rows) == 7 and rows[-1]["changed"] == "True" and rows[-1]["term"] == "linear stiffness"
    assert 'id="tracking"' in open(out["html"]).read()


def test_fail_on_change_and_no_overwriting(hits, tmp_path, capsys):
    ref, new = hits
    code, _, _ = _run(["track", *ref, "--against", *new, "--fail-on-change", "--no-progress"], capsys)
    assert code == 3
    code, _, _ = _run(["track", *ref, "--against", new[0], "--fail-on-change", "--no-progress"], capsys)
    assert code == 0
    existing = tmp_path / "out.json"
    existing.write_text("{}")
    code, _, err = _run(["track", *ref, "--against", *new, "--json", str(existing)], capsys)
    assert code == 2 and "--overwrite" in err and existing.read_text() == "{}"


def test_too_few_reference_files_and_a_bad_rate(hits, tmp_path, capsys):
    ref, new = hits
    code, _, err = _run(["track", ref[0], "--against", *new, "--no-progress"], capsys)
    assert code == 2 and "at least 2" in err
    code, _, err = _run(["track", *ref, "--against", *new, "--alpha", "0.7"], capsys)
    assert code == 2 and "--alpha" in err
    missing = str(tmp_path / "nope.csv")
    code, text, err = _run(["track", *ref, "--against", new[0], missing, "--no-progress"], capsys)
    assert code == 1 and "skipped" in err and "1 new surveys" in text
    assert "note: the reference has 5 surveys" in text

"""The benchmarks package: one runner lists every benchmark, each a ``main(argv=None)``; no benchmark
edits ``sys.path`` or imports another module's private names; results are saved as plain JSON."""

from __future__ import annotations

import ast
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from benchmark_helpers import PACKAGE, helper

from sindy_impulse import impact_record

ROOT = PACKAGE.parent
FILES = sorted(p for p in PACKAGE.rglob("*.py") if "results" not in p.parts)
GROUPS = ("accuracy", "real_records", "robustness", "speed", "pysindy_suite", "tracking")


def _tree(path: Path) -> ast.Module:
    return ast.parse(path.read_text(), filename=str(path))


def _main(path: Path) -> ast.FunctionDef | None:
    return next((n for n in _tree(path).body if isinstance(n, ast.FunctionDef) and n.name == "main"), None)


BENCHMARKS = {p.stem: p for p in FILES if p.parent != PACKAGE and _main(p) is not None}


def _runner(*args: str) -> subprocess.CompletedProcess:
    """``python -m benchmarks ARGS`` from the repository root, as a user types it."""
    return subprocess.run([sys.executable, "-m", "benchmarks", *args], cwd=ROOT, capture_output=True,
                          text=True, timeout=600)


def test_the_groups_are_packages_and_every_module_is_in_one():
    for group in GROUPS:
        assert (PACKAGE / group / "__init__.py").is_file(), group
    loose = [p.name for p in FILES if p.parent == PACKAGE]
    assert sorted(loose) == ["__init__.py", "__main__.py"]
    assert all(p.parent.parent == PACKAGE and p.parent.name in GROUPS for p in FILES if p.parent != PACKAGE)


def test_the_list_names_every_benchmark_once_with_a_summary():
    done = _runner("--list")
    assert done.returncode == 0, done.stderr
    listed = {}
    for line in done.stdout.splitlines():
        if line.startswith("  "):
            name, rest = line.split(maxsplit=1)
            listed[name] = rest
    assert set(listed) == set(BENCHMARKS) and len(BENCHMARKS) >= 30
    assert all(len(summary) > 20 for summary in listed.values())


def test_every_benchmark_has_main_argv_none():
    for name, path in BENCHMARKS.items():
        args = _main(path).args
        assert [a.arg for a in args.args] == ["argv"], name
        assert len(args.defaults) == 1 and ast.literal_eval(args.defaults[0]) is None, name


def test_benchmark_names_are_unique():
    stems = [p.stem for p in FILES if p.parent != PACKAGE and p.name != "__init__.py"]
    assert len(stems) == len(set(stems))


def test_every_module_imports_and_each_main_checks():
    done = _runner("--check")
    assert done.returncode == 0, done.stdout + done.stderr
    assert "every main(argv=None)" in done.stdout


@pytest.mark.parametrize("path", FILES, ids=[str(p.relative_to(PACKAGE)) for p in FILES])
def test_no_sys_path_edits_and_no_private_imports(path):
    text = path.read_text()
    assert "sys.path" not in text, f"{path.name} edits sys.path: import benchmarks.<group>.<module>"
    for node in ast.walk(_tree(path)):
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("benchmarks"):
            private = [a.name for a in node.names if a.name.startswith("_")]
            assert not private, f"{path.name} imports private names {private} of {node.module}"
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            modules = [a.name for a in node.names] if isinstance(node, ast.Import) else [node.module or ""]
            assert not any(m.split(".")[0] in ("tests", "conftest") or m.startswith("test_") for m in modules)


def test_an_unknown_name_is_refused_with_the_list_command():
    done = _runner("no_such_benchmark")
    assert done.returncode == 2 and "python -m benchmarks --list" in done.stderr


def test_results_are_plain_json():
    plain = helper("__main__").plain
    value = {"a": (np.float64(1.5), np.int64(2)), "b": np.array([[1.0, np.nan]]), 3: {np.inf, -np.inf},
             "p": Path("x"), "ok": np.bool_(True)}
    out = plain(value)
    assert out["a"] == [1.5, 2] and out["b"] == [[1.0, "nan"]] and sorted(out["3"]) == ["-inf", "inf"]
    assert out["p"] == "x" and out["ok"] is True
    text = json.dumps(out, allow_nan=False)
    assert json.loads(text) == out and not any(isinstance(v, float) and math.isnan(v) for v in out["b"][0])


def test_results_are_ignored_by_git_but_their_readme_is_not():
    ignore = (ROOT / ".gitignore").read_text()
    assert "benchmarks/results/*.json" in ignore and (PACKAGE / "results" / "README.md").is_file()


def test_the_calibration_of_a_family_is_tabled_by_the_source_of_the_values():
    """``uncertainty --family X``: a modes-benchmark family's records (the generator's refusals left out),
    their modes' error over std by where the values come from; an unknown family is refused."""
    done = _runner("--no-save", "uncertainty", "--family", "a", "--n", "2", "--seed", "0")
    assert done.returncode == 0, done.stderr
    assert "2 records of family a, seed 0" in done.stdout
    assert "family a, by the source of the mode's values" in done.stdout
    rows = [line.split() for line in done.stdout.splitlines() if line.startswith(("poles", "equation"))]
    assert rows and all(row[1] in ("frequency", "damping") and int(row[2]) >= 1 for row in rows)
    # the pole-valued modes again, by whether their record had a mode found nonlinear (a linear family:
    # none had), each group only where it has modes
    poles = {int(row[2]) for row in rows if row[0] == "poles"}
    alone = {int(row[2]) for row in rows if row[0] == "poles:nothing-nonlinear"}
    assert poles and alone == poles and not any(row[0] == "poles:beside-nonlinear" for row in rows)
    refused = _runner("--no-save", "uncertainty", "--family", "z")
    assert refused.returncode != 0 and "invalid choice" in refused.stderr


def test_a_lone_mode_record_is_that_mode_of_the_same_structure_with_the_same_noise():
    """``families.lone_mode_record``: the hit excites one mode of the record's own structure; without the
    element the lone modes add up to the record (superposition), with it a lone mode holds no other mode."""
    families = helper("accuracy.families")
    linear = {"frequencies_hz": [40.0, 90.0], "damping_ratios": [0.01, 0.002], "amplitudes": [0.5, 1.0],
              "fs": 1000.0, "duration": 2.0, "sensor": "displacement", "snr_db": 50.0, "random_state": 1}
    rec = impact_record(**linear)
    noise = rec.y - rec.y_clean
    lone = [families.lone_mode_record(linear, i) for i in (0, 1)]
    np.testing.assert_allclose(lone[0] + lone[1] - noise, rec.y, atol=1e-9 * np.abs(rec.y_clean).max())
    assert np.std(lone[0] - noise) > 0.1 * np.std(rec.y_clean)  # each holds its mode
    config = dict(linear, cubic_stiffness=4e3 / families.element_shares(linear).sum() ** 2)
    nonlinear = impact_record(**config)
    alone = families.lone_mode_record(config, 0) - (nonlinear.y - nonlinear.y_clean)
    start = rec.free_decay_index
    spectrum = np.abs(np.fft.rfft(alone[start:]))
    both = np.abs(np.fft.rfft(nonlinear.y_clean[start:]))
    f = np.fft.rfftfreq(alone.size - start, 1 / linear["fs"])
    near = np.abs(f - 90) < 2  # the other mode: only what the element passes it from the lone one
    assert spectrum[near].max() < 0.02 * both[near].max()
    made = families.element_variants(config, 0)
    assert set(made) == {"alone", "alone, element as strong", "no element"}
    np.testing.assert_allclose(made["no element"][0], rec.y)
    np.testing.assert_allclose(made["alone"][0], families.lone_mode_record(config, 0))
    assert not np.allclose(made["alone, element as strong"][0], made["alone"][0])
    for bad in (2, -1, 0.5):
        with pytest.raises(ValueError, match="mode must be an index of the record's 2 mode"):
            families.element_variants(config, bad)
        with pytest.raises(ValueError, match="mode must be an index"):
            families.lone_mode_record(config, bad)


def test_the_coupling_study_runs_on_family_g():
    done = _runner("--no-save", "coupling_misses", "--n", "2", "--seed", "0")
    assert done.returncode == 0, done.stderr
    assert "family g, seed 0: 2 records" in done.stdout


@pytest.mark.slow
def test_the_failures_list_numbers_records_as_the_progress_lines_do():
    """``modes --show-failures`` names a failing record by its draw's index, as its progress line does,
    also after a record the generator refused (family g, seed 197: record 8 is refused)."""
    done = _runner("--no-save", "modes", "--family", "g", "--n", "12", "--seed", "197", "--show-failures")
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert any(line.startswith("  [g #8] left out") for line in lines)
    at = next(i for i, line in enumerate(lines) if line.startswith("failures of family g"))
    wrong = {line.split("]")[0] for line in lines[:at] if "survey WRONG" in line}
    listed = {line.split("]")[0] for line in lines[at + 1:] if line.startswith("  [g #")}
    assert wrong == listed


def test_the_coupling_stage_benchmark_scores_each_record_before_and_after_the_stage():
    """``coupling_stage``: a family's records scored with the survey's values before its last stage and
    after it."""
    done = _runner("--no-save", "coupling_stage", "--seed", "131", "--n", "3")
    assert done.returncode == 0, done.stderr
    assert "family g, seed 131: 3 records," in done.stdout and "right before it" in done.stdout
    refused = _runner("--no-save", "coupling_stage", "--family", "z")
    assert refused.returncode != 0 and "invalid choice" in refused.stderr


def test_the_efficiency_study_tables_both_baselines_with_an_interval():
    """``efficiency``: median errors of the survey and of both baselines on the modes both found, their ratio
    with a bootstrap interval, and each over the Cramer-Rao bound."""
    done = _runner("--no-save", "efficiency", "--family", "a", "--n", "3", "--seed", "0")
    assert done.returncode == 0, done.stderr
    rows = [line for line in done.stdout.splitlines() if line.startswith(("| esprit |", "| stabilised |"))]
    assert len(rows) == 2
    for row in rows:
        cells = [c.strip() for c in row.strip("|").split("|")]
        assert int(cells[1]) >= 3  # at least one mode a record
        ratio, interval = cells[3].split(" ", 1)
        low, high = (float(v) for v in interval.strip("()").split("-"))
        assert low <= float(ratio) <= high
    refused = _runner("--no-save", "efficiency", "--family", "g")
    assert refused.returncode != 0 and "invalid choice" in refused.stderr

"""The documentation's page writers (docs/_ext): the results pages from the benchmark runner's JSON, and the
API pages from the package's public names. The site's build runs them; these tests check what they write
without building it."""

import importlib.util
import json
from pathlib import Path
from types import SimpleNamespace

import pytest

DOCS = Path(__file__).resolve().parent.parent / "docs"


def _load(name):
    spec = importlib.util.spec_from_file_location(name, DOCS / "_ext" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


results_pages = _load("results_pages")
api_pages = _load("api_pages")


@pytest.fixture
def tree(tmp_path):
    """A repository with a benchmarks package of two groups: a benchmark run, one never run, a helper."""
    (tmp_path / "docs").mkdir()
    accuracy = tmp_path / "benchmarks" / "accuracy"
    accuracy.mkdir(parents=True)
    (tmp_path / "benchmarks" / "results").mkdir()
    (accuracy / "ran.py").write_text('"""A benchmark that ran."""\n\ndef main(argv=None):\n    return {}\n')
    (accuracy / "never.py").write_text('"""Never run."""\n\ndef main(argv=None):\n    return {}\n')
    (accuracy / "helper.py").write_text('"""Shared code, no main."""\n\ndef cases():\n    return []\n')
    run = {"name": "ran", "command": "python -m benchmarks ran", "date": "2026-11-28T12:00:00Z",
           "git_commit": "0" * 40, "load_average": [1.0, 0.5, 0.2], "output": "table | 1\n",
           "result": {"ok": True, "median_error": 0.000123456, "rows": [{"snr": 30, "right": 19},
                                                                       {"snr": 40, "right": 20, "note": "x"}],
                      "timing": {"fit_s": 0.1}}}
    (tmp_path / "benchmarks" / "results" / "ran.json").write_text(json.dumps(run))
    return tmp_path


def test_a_page_per_group_and_not_run_yet_where_nothing_was_saved(tree):
    results_pages.write_pages(SimpleNamespace(srcdir=str(tree / "docs")))
    page = (tree / "docs" / "results" / "accuracy.rst").read_text()
    assert "ran\n---" in page and "never\n-----" in page and "helper" not in page
    never = page[page.index("never\n-----"):]
    assert "**Not run yet**" in never and "**Not run yet**" not in page[: page.index("never\n-----")]
    assert "0.0001235" in page and "   * - snr\n     - right\n     - note" in page  # the rows' table
    assert "fit_s" in page and "    table | 1" in page  # a nested mapping, the printed output
    # every group the site lists has its page, even with no benchmark in this checkout
    speed = (tree / "docs" / "results" / "speed.rst").read_text()
    assert "**Not run yet**" in speed
    index = (tree / "docs" / "results" / "index.rst").read_text()
    assert "   accuracy" in index and "   speed" in index


def test_a_quick_run_is_shown_and_said_to_be_quick(tree):
    saved = tree / "benchmarks" / "results"
    (saved / "ran.json").rename(saved / "ran.quick.json")
    results_pages.write_pages(SimpleNamespace(srcdir=str(tree / "docs")))
    assert "A ``--quick`` run" in (tree / "docs" / "results" / "accuracy.rst").read_text()


def test_cells_stay_on_one_line_and_cannot_start_a_list():
    assert results_pages.fmt("a\nb  c") == "a b c"
    assert results_pages.fmt(float("nan")) == "nan" and results_pages.fmt(12345) == "12,345"
    assert results_pages.table([["- x", "1"]], ["h", "v"])[-3] == "   * - \\- x"


def test_api_pages_cover_the_public_names_once(tmp_path):
    api_pages.write_pages(SimpleNamespace(srcdir=str(tmp_path)))
    index = (tmp_path / "api" / "index.rst").read_text()
    import sindy_impulse

    for name in sindy_impulse._PUBLIC:
        assert f".{name}`" in index or f"~sindy_impulse.{name}`" in index, name
    analysis = (tmp_path / "api" / "sindy_impulse.analysis.rst").read_text()
    assert "   nonlinearity_test" in analysis
    # esprit is defined under poles and re-exported by analysis: documented once, linked from analysis
    assert "   esprit\n" not in analysis and "sindy_impulse.poles.esprit" in analysis

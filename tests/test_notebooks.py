"""Every notebook in notebooks/ runs top to bottom (the issue asks for under 2 minutes each).

Running them takes 5-30 s each: they are in the second step of ``.ci/run`` (``pytest -m slow``), not in
the contributor's default run."""

from pathlib import Path

import pytest

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")

NOTEBOOKS = sorted((Path(__file__).resolve().parent.parent / "notebooks").glob("*.ipynb"))


@pytest.mark.slow
@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.name for p in NOTEBOOKS])
def test_notebook_runs(path, tmp_path, monkeypatch):
    monkeypatch.setenv("MPLBACKEND", "Agg")
    nb = nbformat.read(path, as_version=4)
    assert all(
        cell.get("outputs", []) == [] for cell in nb.cells if cell.cell_type == "code"
    ), f"{path.name}: outputs must be stripped in git"
    client = nbclient.NotebookClient(
        nb, timeout=180, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}
    )
    client.execute()


def test_one_notebook_per_results_section():
    names = {p.stem for p in NOTEBOOKS}
    for section in ("3.1", "3.2", "3.3", "3.4", "appendix_A", "real_data"):
        assert any(name.startswith(section) for name in names), f"no notebook for {section}"

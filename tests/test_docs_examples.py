"""Every example in the README and in the site's narrative pages runs as written.

A page's ```python blocks run in order in one namespace, in a fresh temporary folder, and its ```console
blocks' ``$ `` lines run there too, in the shell, at their place between the Python blocks (the
README writes ``hit.csv`` in Python, then surveys it with ``sindy-impulse``); a command must exit with 0.
Blocks fenced as ``bash`` or ``text`` are shown, not run (the set-up commands, a cluster's address). The
pages in ``SLOW`` run with the slow checks (``pytest -m slow``). The gallery's examples run when the site is
built (sphinx-gallery), the docstrings' examples as doctests.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
#: The pages whose examples a user copies: the README, the site's front page, getting started, the guide.
PAGES = [ROOT / "README.md", DOCS / "index.md", DOCS / "getting-started.md", *sorted(DOCS.glob("guide/*.md"))]
#: Pages whose examples take half a minute of CPU or more (several command-line processes; a dask cluster):
#: they run with the slow checks (`pytest -m slow`, CI's second step), so the default run stays short.
SLOW = {DOCS / "guide" / "cli.md", DOCS / "guide" / "batches.md"}
#: Pages of prose only (an index, the method): nothing to run.
NO_EXAMPLES = {DOCS / "guide" / "index.md", DOCS / "guide" / "method.md"}
FENCE = re.compile(r"^```([\w-]*)[^\n]*\n(.*?)^```[ \t]*$", re.MULTILINE | re.DOTALL)
RUN = {"python", "console"}
MAX_README_LINES = 200


def fenced(text: str) -> list[tuple[str, str, int]]:
    """The fenced blocks of a Markdown text that run: (language, code, line of the fence)."""
    found = []
    for match in FENCE.finditer(text):
        if match.group(1) in RUN:
            found.append((match.group(1), match.group(2), text.count("\n", 0, match.start()) + 1))
    return found


def commands(console: str) -> list[str]:
    """The ``$ `` lines of a console block (the other lines are the output shown)."""
    return [line[2:] for line in console.splitlines() if line.startswith("$ ")]


def _shell(command: str, folder: Path, where: str) -> None:
    env = dict(os.environ, MPLBACKEND="Agg")
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    proc = subprocess.run(
        command, shell=True, cwd=folder, env=env, capture_output=True, text=True, timeout=600
    )
    assert proc.returncode == 0, f"{where}: $ {command}\n{proc.stdout[-2000:]}\n{proc.stderr[-2000:]}"


def _params():
    for page in PAGES:
        marks = [pytest.mark.slow] if page in SLOW else []
        yield pytest.param(page, marks=marks, id=str(page.relative_to(ROOT)))


@pytest.mark.parametrize("page", list(_params()))
def test_page_examples_run(page, tmp_path, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    found = fenced(page.read_text())
    if page in NO_EXAMPLES:
        assert not found, f"{page.name} has examples now: take it out of NO_EXAMPLES"
        return
    assert found, f"{page.name}: no python or console block found (the extraction or the page is wrong)"
    monkeypatch.chdir(tmp_path)
    namespace: dict = {"__name__": "__docs_example__"}
    try:
        for language, code, line in found:
            where = f"{page.relative_to(ROOT)}:{line}"
            if language == "python":
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")  # the examples' warnings are part of what they show
                    exec(compile(code, where, "exec"), namespace)  # noqa: S102 - the page's own example
            else:
                assert commands(code), f"{where}: a console block without a '$ ' line"
                for command in commands(code):
                    _shell(command, tmp_path, where)
    finally:
        plt.close("all")


def test_readme_is_short_and_its_links_resolve():
    text = (ROOT / "README.md").read_text()
    assert len(text.splitlines()) <= MAX_README_LINES
    for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", text):
        if "://" not in target:
            assert (ROOT / target).exists(), f"README links to {target}, which is not in the repository"
    # what the README must not hold (issue 37): history, commit hashes, results tables
    assert not re.search(r"\b[0-9a-f]{7,40}\b", text), "a commit hash in the README"
    assert "this stop" not in text.lower()


def test_extraction_sees_blocks_and_commands():
    """The extractor on a page written here: a python block, a console block, a bash block left alone."""
    page = "text\n```python\nx = 1\n```\n\n```console\n$ echo hi\nhi\n```\n\n```bash\nrm -rf /\n```\n"
    found = [(lang, line) for lang, _, line in fenced(page)]
    assert found == [("python", 2), ("console", 6)]
    assert commands("$ echo hi\nhi\n$ ls\n") == ["echo hi", "ls"]


"""Write the benchmark results pages at build time from the runner's saved JSON.

``python -m benchmarks NAME [--quick]`` runs ``benchmarks/<group>/NAME.py`` and saves
``benchmarks/results/NAME.json`` (``NAME.quick.json`` for a quick run): the command, the date, the commit,
the machine's load, the printed output and ``result``, what the benchmark's ``main`` returned. Here every
group gets a page (``results/<group>.rst``) with one section per benchmark of the group (a module defining
``main``, the runner's own rule, read without importing it): its docstring's first paragraph, the command
that reruns it, the run's facts, ``result`` as tables and the printed output. A benchmark without a saved
result says "not run yet" instead of failing the build; a full run's file is preferred to a quick one's.
``result`` is rendered by shape, so a benchmark needs no page code of its own:

- a mapping of scalars is a two-column table (quantity, value);
- a list of mappings is a table with one row per mapping (the union of their keys as columns);
- a mapping inside a mapping is a subsection named by its key; a list of scalars is one line.
"""

from __future__ import annotations

import ast
import json
import math
import re
from pathlib import Path

#: The groups in the order the site lists them, with what each measures; others found are appended.
GROUPS = {
    "accuracy": "Accuracy on synthetic records with a known truth: the paper's cases, the modal table "
    "against ESPRIT, uncertainties, backbones, the test for nonlinearity.",
    "real_records": "Measured records (hammer tests and free decays) against the values their sources "
    "publish.",
    "robustness": "Bad inputs, soaks and work bounds: what happens on data that should be refused or "
    "warned about.",
    "speed": "Speed, each figure beside a baseline measured in the same run (ratios, not absolute times).",
    "pysindy_suite": "PySINDy's own test suite run against ImpulseSINDy in PySINDy's plain mode.",
    "tracking": "Tracking modes over many tests.",
}
HEADER = ".. Written by docs/_ext/results_pages.py at build time from benchmarks/results/*.json.\n\n"
MAX_ROWS = 200


def fmt(value) -> str:
    """One table cell: numbers to 4 significant digits, everything on one line."""
    if isinstance(value, bool) or value is None:
        return str(value)
    if isinstance(value, int):
        return f"{value:,}" if abs(value) >= 10_000 else str(value)
    if isinstance(value, float):
        if math.isnan(value) or math.isinf(value):
            return str(value)
        return f"{value:.4g}"
    if isinstance(value, list | tuple) and all(not isinstance(v, dict | list) for v in value):
        return ", ".join(fmt(v) for v in value)
    if isinstance(value, dict):
        return "; ".join(f"{k}: {fmt(v)}" for k, v in value.items())[:300]
    if isinstance(value, list):
        return json.dumps(value, separators=(", ", ": "))[:300]
    text = " ".join(str(value).split())
    return text.replace("|", "/") or "-"


def _cell(text: str) -> str:
    # a cell that starts like a reST list or field would change the table's structure
    return ("\\" + text) if text[:1] in "-*+:#|" else text


def table(rows: list[list[str]], header: list[str]) -> list[str]:
    out = [".. list-table::", "   :header-rows: 1", ""]
    for row in [header, *rows]:
        out.append(f"   * - {_cell(row[0])}")
        out += [f"     - {_cell(c)}" for c in row[1:]]
    return out + [""]


def heading(text: str, level: int) -> list[str]:
    marks = "=-~^\"'"
    text = " ".join(str(text).split()) or "-"
    return [text, marks[min(level, len(marks) - 1)] * len(text), ""]


def render(value, level: int) -> list[str]:
    """The reST of one JSON value (see the module's docstring for the shapes)."""
    if isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
        keys: list[str] = []
        for row in value:
            keys += [k for k in row if k not in keys]
        rows = [[fmt(row.get(k, "")) for k in keys] for row in value[:MAX_ROWS]]
        more = [f"({len(value) - MAX_ROWS} more rows in the JSON file)", ""] if len(value) > MAX_ROWS else []
        return table(rows, [fmt(k) for k in keys]) + more
    if not isinstance(value, dict):
        return [fmt(value), ""]
    scalars = [(k, v) for k, v in value.items() if not isinstance(v, dict) and not _is_table(v)]
    out = table([[fmt(k), fmt(v)] for k, v in scalars], ["quantity", "value"]) if scalars else []
    for key, sub in value.items():
        if isinstance(sub, dict) or _is_table(sub):
            out += heading(key, level) + render(sub, level + 1)
    return out


def _is_table(value) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)


def docstring_summary(path: Path) -> str:
    """The module docstring's first paragraph, on one line, safe as reST text (``name_`` is not a link)."""
    try:
        doc = ast.get_docstring(ast.parse(path.read_text()))
    except (SyntaxError, UnicodeDecodeError):
        doc = None
    text = " ".join((doc or "").split("\n\n")[0].split())
    parts = re.split(r"(``.+?``)", text)  # literals stay as they are
    return "".join(p if p.startswith("``") else re.sub(r"(?<=\w)_(?=\W|$)", r"\\_", p) for p in parts)


def is_benchmark(path: Path) -> bool:
    """A module that defines ``main`` at its top level (the runner's rule; helpers define none)."""
    try:
        tree = ast.parse(path.read_text())
    except (SyntaxError, UnicodeDecodeError):
        return False
    return any(isinstance(node, ast.FunctionDef) and node.name == "main" for node in tree.body)


def benchmarks(root: Path) -> dict[str, list[Path]]:
    """Each group folder of ``benchmarks/`` and its benchmark modules."""
    found: dict[str, list[Path]] = {group: [] for group in GROUPS}
    for folder in sorted(p for p in (root / "benchmarks").glob("*/") if p.is_dir()):
        if folder.name.startswith(("_", ".")) or folder.name == "results":
            continue
        found.setdefault(folder.name, [])
        modules = [p for p in folder.glob("*.py") if not p.name.startswith("_") and is_benchmark(p)]
        found[folder.name] += sorted(modules)
    return found


#: The facts of a run the runner saves beside its result, as the page names them.
FACTS = {"command": "command", "date": "date (UTC)", "seconds": "wall time (s)", "git_commit": "commit",
         "git_dirty": "uncommitted changes", "load_average": "load average before / after (1, 5, 15 min)",
         "cpu_count": "cores", "python": "Python", "platform": "platform"}


def saved_run(data) -> list[str]:
    """A saved run: its facts, its result as tables, its printed output (a plain result is shown as is)."""
    if not (isinstance(data, dict) and "result" in data):
        return render(data, 2)
    facts = [[label, fmt(data[key])] for key, label in FACTS.items() if key in data]
    out = table(facts, ["run", "value"]) if facts else []
    out += heading("result", 2) + render(data["result"], 3)
    printed = str(data.get("output") or "").rstrip()
    if printed:
        out += heading("printed output", 2) + ["::", ""]
        out += ["    " + line for line in printed.splitlines()] + [""]
    return out


def section(module: Path, results: Path) -> list[str]:
    name = module.stem
    out = heading(name, 1)
    summary = docstring_summary(module)
    if summary:
        out += [summary, ""]
    quick = " (``--quick`` for a smaller run)" if '"--quick"' in module.read_text() else ""
    out += [f"Rerun: ``python -m benchmarks {name}``{quick}.", ""]
    saved = next((p for p in (results / f"{name}.json", results / f"{name}.quick.json") if p.exists()), None)
    if saved is None:
        return out + ["**Not run yet**: no saved result in ``benchmarks/results``.", ""]
    try:
        data = json.loads(saved.read_text())
    except (OSError, ValueError) as err:
        return out + [f"**Not readable**: ``benchmarks/results/{saved.name}`` ({fmt(err)}).", ""]
    if saved.name.endswith(".quick.json"):
        out += ["A ``--quick`` run (smaller inputs): a full run's figures may differ.", ""]
    return out + saved_run(data)


def group_page(group: str, modules: list[Path], results: Path) -> str:
    title = group.replace("_", " ").capitalize()
    out = [HEADER] + heading(title, 0)
    out += [GROUPS.get(group, ""), ""]
    if not modules:
        out += [f"**Not run yet**: no benchmark in ``benchmarks/{group}/`` in this checkout.", ""]
    for module in modules:
        out += section(module, results)
    return "\n".join(out) + "\n"


def index_page(groups: list[str]) -> str:
    out = [HEADER] + heading("Results", 0)
    out += [
        "Every figure on these pages comes from a script in ``benchmarks/`` that anyone can rerun: "
        "``python -m benchmarks NAME [--quick]`` writes ``benchmarks/results/NAME.json``, and the site's "
        "build turns each saved file into the tables below (a benchmark never run says so). Timings are "
        "ratios against a baseline measured in the same run, on the 2-core machine the project is built on.",
        "",
        ".. toctree::",
        "   :maxdepth: 2",
        "",
        *[f"   {g}" for g in groups],
        "",
    ]
    return "\n".join(out)


def _write(path: Path, text: str) -> None:
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


def write_pages(app) -> None:
    root = Path(app.srcdir).parent
    folder = Path(app.srcdir) / "results"
    folder.mkdir(exist_ok=True)
    found = benchmarks(root)
    for group, modules in found.items():
        _write(folder / f"{group}.rst", group_page(group, modules, root / "benchmarks" / "results"))
    _write(folder / "index.rst", index_page(list(found)))


def setup(app):
    app.connect("config-inited", lambda app, config: write_pages(app))
    return {"parallel_read_safe": True, "parallel_write_safe": True}

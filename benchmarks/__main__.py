"""The one runner of the benchmarks: ``python -m benchmarks NAME [--quick] [ARGS]`` (see the package).

``--list`` prints every benchmark with its docstring's first line; ``--check`` imports every module of the
package and checks each benchmark's ``main(argv=None)``. A run prints what the benchmark prints and saves
``benchmarks/results/NAME.json`` (``NAME.quick.json`` when ``--quick`` is among the benchmark's arguments):

``name``, ``module``, ``command`` (as typed), ``argv``, ``date`` (UTC, ISO 8601), ``seconds`` (wall time),
``git_commit`` and ``git_dirty`` (uncommitted changes to tracked files), ``load_average`` (1, 5 and 15
minutes, before and after the run), ``cpu_count`` and ``cpus_usable`` (this process's share), ``python``,
``platform``, ``output`` (the printed text) and ``result`` (what ``main`` returned; numpy values as plain
numbers, non-finite ones as the strings ``"nan"``, ``"inf"`` and ``"-inf"``).
"""

from __future__ import annotations

import argparse
import ast
import contextlib
import datetime
import importlib
import inspect
import io
import json
import math
import os
import platform
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

PACKAGE = Path(__file__).resolve().parent
ROOT = PACKAGE.parent
RESULTS = PACKAGE / "results"
#: The order of the groups in ``--list``.
GROUPS = ("accuracy", "real_records", "robustness", "speed", "pysindy_suite", "tracking")


@dataclass(frozen=True)
class Entry:
    """One module of the package: its dotted name, file, first docstring line, whether it is a benchmark
    (defines ``main``) and whether it takes ``--quick``."""

    name: str
    module: str
    path: Path
    summary: str
    benchmark: bool
    quick: bool


def _summary(tree: ast.Module, width: int = 90) -> str:
    """The docstring's first sentence (its first paragraph when shorter), cut to ``width`` characters."""
    paragraph = " ".join((ast.get_docstring(tree) or "").strip().split("\n\n")[0].split())
    sentence = paragraph.split(". ")[0].rstrip(".")
    return sentence if len(sentence) <= width else sentence[: width - 3].rstrip() + "..."


def modules() -> list[Entry]:
    """Every module of the package's groups, read without importing it (the group order, then by name)."""
    out = []
    for group in GROUPS:
        for path in sorted((PACKAGE / group).glob("*.py")):
            if path.name == "__init__.py":
                continue
            tree = ast.parse(path.read_text(), filename=str(path))
            benchmark = any(isinstance(n, ast.FunctionDef) and n.name == "main" for n in tree.body)
            quick = any(isinstance(n, ast.Constant) and n.value == "--quick" for n in ast.walk(tree))
            out.append(Entry(path.stem, f"benchmarks.{group}.{path.stem}", path, _summary(tree), benchmark,
                             quick))
    return out


def benchmarks() -> dict[str, Entry]:
    """The benchmarks by name (a module's file name, unique across the groups)."""
    found = {}
    for entry in modules():
        if entry.benchmark:
            if entry.name in found:
                other = found[entry.name].module
                raise SystemExit(f"two benchmarks named {entry.name}: {other}, {entry.module}")
            found[entry.name] = entry
    return found


def print_list() -> None:
    """One line per benchmark, by group ("quick": it takes ``--quick``)."""
    group = None
    for entry in benchmarks().values():
        here = entry.module.split(".")[1]
        if here != group:
            group = here
            print(f"\n{group}/")
        print(f"  {entry.name:22s} {'quick' if entry.quick else '':5s}  {entry.summary}")


def check() -> list[str]:
    """Import every module of the package; the problems found (a module that does not import, a
    benchmark whose ``main`` is not ``main(argv=None)``)."""
    problems = []
    for entry in modules():
        try:
            module = importlib.import_module(entry.module)
        except Exception as exc:  # noqa: BLE001 - every problem is listed
            problems.append(f"{entry.module} does not import: {type(exc).__name__}: {exc}")
            continue
        if not entry.benchmark:
            continue
        params = list(inspect.signature(module.main).parameters.values())
        if len(params) != 1 or params[0].name != "argv" or params[0].default is not None:
            problems.append(f"{entry.module}.main{inspect.signature(module.main)} is not main(argv=None)")
    return problems


def plain(value):
    """``value`` with every numpy value, tuple, set and path as JSON's own types; non-finite floats as
    strings."""
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, set, frozenset)):
        return [plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return plain(value.tolist())
    if isinstance(value, np.generic):
        return plain(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    return str(value)


def _git(*args: str) -> str | None:
    try:
        done = subprocess.run(["git", *args], cwd=ROOT, capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.SubprocessError):
        return None
    return done.stdout.strip() if done.returncode == 0 else None


def machine() -> dict:
    """The commit, the load and the cores: what the figures of a run depend on."""
    commit = _git("rev-parse", "HEAD")
    dirty = _git("status", "--porcelain", "--untracked-files=no")
    usable = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return {"git_commit": commit, "git_dirty": None if dirty is None else bool(dirty),
            "cpu_count": os.cpu_count(), "cpus_usable": usable, "python": platform.python_version(),
            "platform": platform.platform()}


class _Tee(io.TextIOBase):
    """Writes to the terminal and keeps a copy."""

    def __init__(self, stream):
        self.stream, self.parts = stream, []

    def write(self, text: str) -> int:
        self.parts.append(text)
        return self.stream.write(text)

    def flush(self) -> None:
        self.stream.flush()


def run(entry: Entry, argv: list[str]) -> dict:
    """Run one benchmark; the record the runner saves."""
    module = importlib.import_module(entry.module)
    command = " ".join(["python -m benchmarks", entry.name, *argv])
    record = {"name": entry.name, "module": entry.module, "command": command, "argv": argv,
              "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
              **machine(), "load_average": {"before": list(os.getloadavg())}}
    tee, saved_argv = _Tee(sys.stdout), sys.argv
    sys.argv = [f"python -m benchmarks {entry.name}", *argv]  # argparse's prog: the command to type
    start = time.perf_counter()
    try:
        with contextlib.redirect_stdout(tee):
            result = module.main(argv)
    finally:
        sys.argv = saved_argv
    if not isinstance(result, dict):
        raise TypeError(f"{entry.module}.main returned {type(result).__name__}, not a dict")
    record["seconds"] = time.perf_counter() - start
    record["load_average"]["after"] = list(os.getloadavg())
    record["output"] = "".join(tee.parts)
    record["result"] = result
    return plain(record)


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="python -m benchmarks", description=__doc__.splitlines()[0],
        epilog="Options after NAME go to the benchmark: python -m benchmarks NAME --help lists them.")
    parser.add_argument("--list", action="store_true", help="list the benchmarks, one line each")
    parser.add_argument("--check", action="store_true",
                        help="import every module and check each benchmark's main(argv=None)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--out", type=Path, help="save the result here (default benchmarks/results/NAME.json)")
    where.add_argument("--no-save", action="store_true", help="print only")
    parser.add_argument("name", nargs="?", metavar="NAME", help="the benchmark (see --list)")
    parser.add_argument("args", nargs=argparse.REMAINDER, metavar="ARGS", help="the benchmark's own options")
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = _parser()
    args = parser.parse_args(argv)
    if args.list:
        print_list()
        return 0
    if args.check:
        problems = check()
        print("\n".join(problems) if problems else f"{len(modules())} modules import; every main(argv=None)")
        return 1 if problems else 0
    if args.name is None:
        parser.error("give a benchmark's NAME (python -m benchmarks --list shows them)")
    found = benchmarks()
    name = args.name.removesuffix(".py").replace("/", ".").split(".")[-1]
    if name not in found:
        parser.error(f"no benchmark named {args.name!r}; python -m benchmarks --list shows them")
    record = run(found[name], args.args)
    if not args.no_save:
        out = args.out or RESULTS / f"{name}{'.quick' if '--quick' in args.args else ''}.json"
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text(json.dumps(record, indent=1) + "\n")
        print(f"\nsaved {out}")
    return 1 if record["result"].get("ok") is False else 0


if __name__ == "__main__":
    sys.exit(main())

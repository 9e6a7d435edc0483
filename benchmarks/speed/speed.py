"""Speed where users feel it: the one entry point of the performance figures.

Run from the repository root::

    python -m benchmarks speed                 # every figure (a few minutes on 2 cores)
    python -m benchmarks speed --quick         # the same figures on smaller inputs, fewer repetitions
    python -m benchmarks speed --write-readme  # and write the table into README.md (perf markers)

Each figure is printed with a baseline measured in the same run (PySINDy's ``simulate``, a minimal numba
RK4 written for the model, a plain Python loop, one numpy pass over the record, one worker instead of
two, the package without its background build) and their ratio, so a busy machine shifts both; the
1-minute load average before and after each section says how busy it was. No figure is a test: nothing
asserts a time.
"""

from __future__ import annotations

import argparse
import os
import platform
import time
from pathlib import Path

from benchmarks.speed import batch, dask_features, figures
from benchmarks.speed.cases import load
from benchmarks.speed.cold_start import cold_start

ROOT = Path(__file__).resolve().parents[2]

START, END = "<!-- perf:start -->", "<!-- perf:end -->"


def _cold_rows(quick: bool) -> list:
    package = ROOT / "sindy_impulse"
    base = cold_start(package, "no warm-up")
    rows = [
        ("import sindy_impulse (fresh install)", base["import"], float("nan"), float("nan"), "(info)"),
        ("import of ImpulseSINDy (PySINDy, scikit-learn, numba)", base["import_estimator"], float("nan"),
         float("nan"), "(info)"),
    ]
    for variant in ("pip install", "warm-up") + (() if quick else ("read-only package",)):
        run = cold_start(package, variant)
        rows.append((f"first fit after install, {variant} vs compiling at first call", run["first_fit"],
                     base["first_fit"], base["first_fit"] / run["first_fit"], "(info)"))
        rows.append((f"imports and first fit after install minus the dependencies' bare import, {variant} "
                     "vs compiling at first call", run["beyond_dependencies"], base["beyond_dependencies"],
                     base["beyond_dependencies"] / run["beyond_dependencies"], "<= 1 s"))
        second = run["second_process"]["first_fit"]
        rows.append((f"first fit of a later process ({variant}) vs the process after install", second,
                     run["first_fit"], run["first_fit"] / second, "(info)"))
    return rows


def _sections(quick: bool):
    return [
        ("cold start", _cold_rows),
        ("simulation", figures.simulation),
        ("paper's oscillator", figures.paper_fit),
        ("many states", figures.many_states),
        ("long records", figures.long_records),
        ("modal survey", figures.modal_survey),
        ("survey speed", figures.survey_speed),
        ("feature study", figures.feature_study_rows),
        ("dask", dask_features.dask_rows),
        ("batch", batch.batch_rows),
    ]


def _format(value: float) -> str:
    if value != value:  # NaN
        return "-"
    if abs(value) >= 1.0:
        return f"{value:.2f} s"
    if abs(value) >= 1e-3:
        return f"{value * 1e3:.1f} ms"
    return f"{value * 1e6:.1f} us"


def _table(rows: list, loads: list, quick: bool) -> str:
    lines = [
        f"Measured by `python -m benchmarks speed{' --quick' if quick else ''}` on {os.cpu_count()} cores "
        f"({platform.processor() or platform.machine()}, Python {platform.python_version()}); 1-minute "
        f"load average during the sections {min(loads):.1f}-{max(loads):.1f} (0 = idle machine).",
        "",
        "| figure | ours | baseline, same run | ratio | goal |",
        "|---|---|---|---|---|",
    ]
    for name, ours, base, ratio, goal in rows:
        ratio_text = "-" if ratio != ratio else f"{ratio:.2f}"
        lines.append(f"| {name} | {_format(ours)} | {_format(base)} | {ratio_text} | {goal} |")
    return "\n".join(lines)


def write_readme(table: str, readme: Path = ROOT / "README.md") -> None:
    """Replace the text between the perf markers of the README by ``table``."""
    text = readme.read_text()
    if START not in text or END not in text:
        raise SystemExit(f"{readme} has no {START} ... {END} markers")
    head, rest = text.split(START, 1)
    _, tail = rest.split(END, 1)
    readme.write_text(f"{head}{START}\n{table}\n{END}{tail}")


def main(argv=None) -> dict:
    formatter = argparse.RawDescriptionHelpFormatter
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=formatter)
    parser.add_argument("--quick", action="store_true", help="smaller inputs, fewer repetitions")
    parser.add_argument("--write-readme", action="store_true", help="write the table into README.md")
    parser.add_argument("--only", nargs="*", help="run only these sections (names as printed)")
    args = parser.parse_args(argv)
    rows, loads = [], []
    for name, section in _sections(args.quick):
        if args.only and name not in args.only:
            continue
        loads.append(load())
        start = time.perf_counter()
        new = section(args.quick)
        loads.append(load())
        print(f"\n== {name} ({time.perf_counter() - start:.0f} s, load {loads[-2]:.1f} -> {loads[-1]:.1f})")
        for row in new:
            print(f"  {row[0]}: ours {_format(row[1])}, baseline {_format(row[2])}, ratio {row[3]:.3g} "
                  f"(goal {row[4]})")
        rows += new
    table = _table(rows, loads, args.quick)
    print("\n" + table)
    if args.write_readme:
        write_readme(table)
    return {"quick": args.quick, "load_averages": loads,
            "rows": [dict(zip(("figure", "ours", "baseline", "ratio", "goal"), row)) for row in rows]}


if __name__ == "__main__":
    main()

"""``sindy-impulse track REF_FILE ... --against FILE ...``: many tests of one structure, which changed.

Every file is surveyed (``identify_modes``, in parallel with ``--n-jobs``), the reference files define the
state to compare with and the ``--against`` files are tested in the order given
(:func:`sindy_impulse.tracking.track`). The terminal shows one line per alarm (the survey, the mode, what
changed, the term of its equation that carries it), per trend and per mode missed or appeared; ``--json``,
``--csv`` (one row per survey and mode) and ``--report`` (a self-contained HTML page with control charts)
write the details. A file that cannot be read or surveyed gets a ``sindy-impulse: skipped:`` line and the
exit status 1; ``--fail-on-change`` makes any alarm or trend exit with status 3 (for scripts that watch a
structure).
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
import warnings

from ._options import add_input_options, integer, real
from .files import CLIError, atomic_write, check_outputs, write_figure, write_json

__all__ = ["add_parser", "run"]

SUMMARY = "which of many tests of one structure changed: mode, quantity, term of its equation"
DESCRIPTION = (
    "Survey every record (as 'modes' does), take the REF_FILEs as the state to compare with and test each "
    "--against file in order: a mode's frequency, damping ratio and backbone against the reference's "
    "scatter at a false-alarm rate (--alpha, default 1 % per survey), a trend over the new files, and for "
    "each changed mode the term of its equation that carries the change."
)


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("track", help=SUMMARY, description=DESCRIPTION)
    p.add_argument("reference", nargs="+", metavar="REF_FILE", help="the reference tests (at least 2)")
    p.add_argument(
        "--against",
        nargs="+",
        metavar="FILE",
        required=True,
        help="the new tests, in their order (a trend is looked for in this order)",
    )
    add_input_options(p)
    p.add_argument("--force", metavar="NAME", help="column of the hammer's force (onset, double hits)")
    p.add_argument(
        "--alpha",
        type=real,
        default=0.01,
        help="false-alarm rate per survey and for the trends (default 0.01)",
    )
    p.add_argument(
        "--amplitude",
        type=real,
        default=None,
        help="amplitude (sensor units) at which backbones are compared (default: per mode the "
        "median of the reference hits)",
    )
    p.add_argument("--json", metavar="OUT.json", help="also write the result as JSON")
    p.add_argument("--csv", metavar="OUT.csv", help="also write one row per survey and mode as CSV")
    p.add_argument("--report", metavar="OUT.html", help="also write a self-contained HTML report")
    p.add_argument("--plot", metavar="OUT.png", help="also write the control charts")
    p.add_argument("--overwrite", action="store_true", help="replace output files that exist")
    p.add_argument(
        "--fail-on-change",
        action="store_true",
        help="exit with status 3 when a survey changed or a trend was found",
    )
    p.add_argument("--n-jobs", type=integer, default=None, help="parallel jobs (-1: all cores; default 1)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar (shown on a terminal)")
    p.set_defaults(func=run)
    return p


def _outputs(args) -> dict:
    outputs = {"--json": args.json, "--csv": args.csv, "--report": args.report, "--plot": args.plot}
    check_outputs(outputs, args.reference + args.against, figures=["--plot"], overwrite=args.overwrite)
    return outputs


def _surveys(paths: list, args) -> list:
    """``(path, survey)`` of every file that could be read and surveyed (skipped lines for the others)."""
    from ..modes.batch import FailedRecord, run_surveys
    from .modes_command import read_input

    tables = []
    for path in paths:
        try:
            tables.append(read_input(path, args))
        except CLIError as err:
            print(f"sindy-impulse: skipped: {' '.join(str(err).split())}", file=sys.stderr)
    results = (
        run_surveys(
            [tab.data if tab.data.shape[1] > 1 else tab.data[:, 0] for tab in tables],
            t=[tab.t for tab in tables],
            force=[(tab.extra or {}).get("force") for tab in tables],
            names=[tab.path for tab in tables],
            n_jobs=args.n_jobs,
            progress=False if args.no_progress else None,
        )
        if tables
        else []
    )
    out = []
    for table, (_, survey, _) in zip(tables, results):
        if isinstance(survey, FailedRecord):
            print(f"sindy-impulse: skipped: {survey}", file=sys.stderr)
        else:
            out.append((table.path, survey))
    return out


def _write_csv(path: str, rows: list) -> None:
    columns = list(dict.fromkeys(k for r in rows for k in r))

    def render(fh):
        writer = csv.DictWriter(fh, fieldnames=columns)
        writer.writeheader()
        for r in rows:
            writer.writerow(
                {k: ("" if isinstance(v, float) and not math.isfinite(v) else v) for k, v in r.items()}
            )

    atomic_write(path, render)


def _write(result, outputs: dict, files: list) -> list:
    from ..tracking.export import frame_rows

    written = []
    if outputs["--json"]:
        write_json(outputs["--json"], {"files": files, **result.to_dict()})
        written.append(outputs["--json"])
    if outputs["--csv"]:
        _write_csv(outputs["--csv"], frame_rows(result))
        written.append(outputs["--csv"])
    if outputs["--report"]:
        page = result.to_html(source=f"{len(result.reference)} reference and {len(result.new)} new files")
        atomic_write(outputs["--report"], lambda fh: fh.write(page))
        written.append(outputs["--report"])
    if outputs["--plot"]:
        write_figure(outputs["--plot"], lambda: result.plot()[0].figure)
        written.append(outputs["--plot"])
    return written


def run(args) -> int:
    from ..tracking import track

    if not (0 < args.alpha < 0.5):
        raise CLIError(f"--alpha must be a false-alarm rate in (0, 0.5), got {args.alpha!r}")
    outputs = _outputs(args)
    reference, new = _surveys(args.reference, args), _surveys(args.against, args)
    skipped = len(args.reference) + len(args.against) - len(reference) - len(new)
    if len(reference) < 2:
        raise CLIError(f"{len(reference)} reference file(s) could be surveyed; at least 2 are needed")
    files = [p for p, _ in reference + new]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = track([s for _, s in reference + new], reference=len(reference), alpha=args.alpha,
                       labels=files, amplitude=args.amplitude)
    n_modes = sum(tr.in_reference for tr in result.tracks)
    print(
        f"tracking: {len(reference)} reference and {len(new)} new surveys, {n_modes} mode(s) in the reference"
    )
    for line in result.lines():
        print("  " + line)
    for note in [str(w.message) for w in caught] + result.notes():
        print("  note: " + " ".join(note.split()))
    print(
        f"{int(result.changed.sum())} of {len(new)} new surveys changed, "
        f"{len(result.trend_alarms)} trend(s), {len(result.event_alarms)} mode(s) vanished or appeared, "
        f"at a {100 * args.alpha:g} % false-alarm rate"
    )
    written = _write(result, outputs, files)
    if written:
        print(f"written: {', '.join(written)}")
    if args.fail_on_change and (result.changed.any() or result.trend_alarms or result.event_alarms):
        return 3
    return 1 if skipped else 0

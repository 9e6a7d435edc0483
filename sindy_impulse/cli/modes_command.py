"""``sindy-impulse modes FILE [FILE ...]``: the modal table of hammer-test records (``identify_modes`` on
each, in parallel with ``--n-jobs``: ``survey_many``), one line per mode and one per problem on the
terminal; the details (equations, notes) in ``--json``.

One input: ``--json``, ``--plot``, ``--uff`` (UFF 55 table), ``--uff58`` (band signals and free decays),
``--report`` (a self-contained HTML report) name the files. Several inputs: ``--out-dir DIR`` writes, per
input, ``DIR/<stem><suffix>`` for each kind of :data:`OUT_DIR_KINDS` chosen with ``--outputs`` (default
``json``). No existing file is replaced without ``--overwrite``. In a batch, an input that cannot be read
or surveyed gets a ``sindy-impulse: skipped:`` line on stderr and the exit status 1; the others are
processed.
"""

from __future__ import annotations

import argparse
import math
import sys

from ._options import add_input_options, add_report_options, data_options, integer
from .files import (
    CLIError,
    atomic_write,
    check_outputs,
    outputs_in_folder,
    read_measurement,
    write_figure,
    write_json,
)

__all__ = ["OUT_DIR_KINDS", "add_parser", "run"]

_SENSORS = ("displacement", "velocity", "acceleration")

#: What ``--out-dir`` holds per input: kind -> (suffix after the input's stem, the one-input option that
#: writes the same file). A new output is one entry here and one writer in :data:`_WRITERS`.
OUT_DIR_KINDS = {
    "json": (".json", "--json"),
    "unv": (".unv", "--uff"),
    "uff58": ("_signals.unv", "--uff58"),
    "png": (".png", "--plot"),
    "html": (".html", "--report"),
}

#: The one-line help and the description of the command.
SUMMARY = "modal tables of hammer-test records (CSV, UFF 58, LabVIEW, TDMS, MAT, NPZ)"
DESCRIPTION = (
    "Find the modes of hammer-test (impact) records: onset, offset, spectral peaks, one band-passed signal "
    "per mode, one identified equation per mode. Prints one line per mode (frequency, damping ratio, "
    "amplitude, fit error, the verdict of the test for nonlinearity) and one per problem; the equations "
    "and notes go to --json. Several files: one survey each (--n-jobs in parallel), outputs in --out-dir."
)


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("modes", help=SUMMARY, description=DESCRIPTION)
    p.add_argument(
        "files",
        nargs="+",
        metavar="FILE",
        help="the records: CSV with a header row, or UFF 58 (.uff/.unv), LabVIEW .lvm, TDMS, .mat, .npz "
        '(sampling rate, channel names and force channel from the file; pip install "sindy-impulse[io]")',
    )
    add_input_options(p)
    p.add_argument("--force", metavar="NAME", help="column of the hammer's force (onset, double hits)")
    p.add_argument("--sensor", choices=_SENSORS, help="kind of sensor (residues with --force)")
    p.add_argument("--no-nonlinearity", action="store_true", help="skip the test for nonlinearity (faster)")
    add_report_options(p)
    p.add_argument(
        "--uff",
        metavar="OUT.unv",
        help="also write the modal table as UFF 55 (frequency, damping ratio, shape per channel; nodes 1..n "
        'in +Z; needs pip install "sindy-impulse[io]")',
    )
    p.add_argument(
        "--uff58",
        metavar="OUT.unv",
        help="also write each mode's band signal and its model's free decay as UFF 58 time records",
    )
    p.add_argument(
        "--report",
        metavar="OUT.html",
        help="also write a self-contained HTML report: the record, the modal table, the stabilisation chart, "
        "and per mode its fit, equation, backbone, nonlinearity verdict and diagnostics",
    )
    p.add_argument(
        "--out-dir",
        metavar="DIR",
        help="write the outputs of each input to DIR, named after it: DIR/<stem>.json, <stem>.unv, "
        "<stem>_signals.unv, <stem>.png, <stem>.html (see --outputs); created when missing",
    )
    p.add_argument(
        "--outputs",
        metavar="KINDS",
        default="json",
        help=f"what --out-dir holds, comma-separated among {', '.join(OUT_DIR_KINDS)} (default: json)",
    )
    p.add_argument("--overwrite", action="store_true", help="replace output files that exist")
    p.add_argument("--n-jobs", type=integer, default=None, help="parallel jobs (-1: all cores; default 1)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar (shown on a terminal)")
    p.set_defaults(func=run)
    return p


# ----------------------------------------------------------------------------------------------------
# what to write where
# ----------------------------------------------------------------------------------------------------
def _single_flags(args) -> dict:
    """{kind: path} of the one-input options given."""
    return {k: getattr(args, flag.lstrip("-").replace("-", "_")) for k, (_, flag) in OUT_DIR_KINDS.items()
            if getattr(args, flag.lstrip("-").replace("-", "_"), None)}


def _out_dir_kinds(text: str) -> list[str]:
    kinds = [k.strip() for k in text.split(",") if k.strip()]
    unknown = [k for k in kinds if k not in OUT_DIR_KINDS]
    if not kinds or unknown:
        raise CLIError(f"--outputs takes a comma-separated list of {', '.join(OUT_DIR_KINDS)}, got {text!r}")
    return list(dict.fromkeys(kinds))


def plan_outputs(args) -> list[dict]:
    """Per input, ``{kind: path}`` of the files to write, every one checked before any work."""
    single = _single_flags(args)
    if args.out_dir is None:
        if args.outputs != "json":
            raise CLIError("--outputs chooses what --out-dir holds; give --out-dir DIR")
        if single and len(args.files) > 1:
            flag = OUT_DIR_KINDS[next(iter(single))][1]
            raise CLIError(
                f"{flag} names one output file but {len(args.files)} inputs were given; use --out-dir DIR "
                "(one set of outputs per input, named after it)"
            )
        check_outputs({OUT_DIR_KINDS[k][1]: p for k, p in single.items()}, args.files, figures=["--plot"],
                      overwrite=args.overwrite)
        return [single]
    if single:
        flags = ", ".join(OUT_DIR_KINDS[k][1] for k in single)
        raise CLIError(f"{flags} and --out-dir: choose one (--outputs says what --out-dir holds)")
    kinds = _out_dir_kinds(args.outputs)
    plan = outputs_in_folder(args.files, args.out_dir, {k: OUT_DIR_KINDS[k][0] for k in kinds})
    for paths in plan:
        for path in paths.values():
            check_outputs({"--out-dir": path}, args.files, overwrite=args.overwrite)
    return plan


def _write_uff55(survey, report, path):
    survey.to_uff(path, overwrite=True)  # checked before any work, as every output


def _write_uff58(survey, report, path):
    survey.to_uff58(path, overwrite=True)


def _write_html(survey, report, path):
    nonlinearity = all("nonlinear" in m for m in report["modes"])  # the test was run (no --no-nonlinearity)
    page = survey.to_html(source=report["file"], nonlinearity=nonlinearity)
    atomic_write(path, lambda fh: fh.write(page))


#: kind -> writer(survey, report, path).
_WRITERS = {
    "json": lambda survey, report, path: write_json(path, report),
    "unv": _write_uff55,
    "uff58": _write_uff58,
    "png": lambda survey, report, path: write_figure(path, lambda: survey.plot()[0].figure),
    "html": _write_html,
}


def write_outputs(survey, report, paths: dict) -> list[str]:
    """Write every output of one input; returns the paths written (CLIError naming a failed one)."""
    written = []
    for kind, path in paths.items():
        try:
            _WRITERS[kind](survey, report, path)
        except (ImportError, ValueError, OSError) as err:
            raise CLIError(f"cannot write {path}: {' '.join(str(err).split())}") from None
        written.append(path)
    return written


# ----------------------------------------------------------------------------------------------------
# reading, surveying, reporting
# ----------------------------------------------------------------------------------------------------
def read_input(path: str, args):
    """One input as a Table with its force (if any) under ``extra["force"]``."""
    table = read_measurement(path, **data_options(args), extra=[args.force] if args.force else ())
    if args.force:
        table.extra["force"] = table.extra.pop(args.force)
    if table.data.shape[0] < 64:
        raise CLIError(f"{path} has {table.data.shape[0]} data rows; a hammer-test record needs at least 64")
    return table


def _finite(value):
    value = float(value)
    return value if math.isfinite(value) else None


def _coefficients_std(mode) -> dict:
    """Per equation, the standard deviation of each of its terms' coefficients (terms the model has)."""
    if mode.coefficients_std is None:
        return {}
    terms = mode.model.get_feature_names()
    return {
        f"{n}'": {term: float(std) for term, std in zip(terms, row) if math.isfinite(std)}
        for n, row in zip(mode.model.feature_names_, mode.coefficients_std)
    }


def survey_report(table, survey, caught, nonlinear: bool) -> dict:
    """The JSON-ready report of one input's survey (``caught``: its warnings as (category, message))."""
    rows = survey.table(nonlinear=nonlinear)
    return {
        "file": table.path,
        "channels": table.names,
        "modes": [
            {
                **{k: (_finite(v) if isinstance(v, float) else v) for k, v in row.items()},
                "equations": {f"{n}'": eq for n, eq in zip(m.model.feature_names_, m.model.equations(4))},
                "coefficients_std": _coefficients_std(m),
            }
            for row, m in zip(rows, survey.modes)
        ],
        "rejected": [
            {"band_hz": r.band_hz and list(r.band_hz), "reason": r.reason, "record": r.record}
            for r in survey.rejected
        ],
        "notes": list(dict.fromkeys(message for _, message in caught)),
    }


#: Longest problem line printed, indent included (the full text is in --json).
_LINE = 160


def _one_line(text: str) -> str:
    text = " ".join(str(text).split())
    return text if len(text) <= _LINE - 2 else text[: _LINE - 5] + "..."


def print_report(report: dict) -> None:
    """One line for the file, one per mode, one per problem (a rejected band, a warning)."""
    modes = report["modes"]
    print(f"{report['file']}: {len(modes)} mode(s) from {', '.join(report['channels'])}")
    for i, m in enumerate(modes):
        verdict = {True: ", nonlinear", False: ", linear"}.get(m.get("nonlinear"), "")
        print(
            f"  mode {i}: {m['frequency_hz']:.6g} Hz, damping ratio {m['damping_ratio']:.4g}, "
            f"amplitude {m['amplitude']:.4g}, fit error {m['fit_error']:.3g}{verdict}"
        )
    for r in report["rejected"]:
        band = "record" if r["band_hz"] is None else f"{r['band_hz'][0]:.4g}-{r['band_hz'][1]:.4g} Hz"
        print("  " + _one_line(f"rejected {band}: {r['reason']}"))
    for note in report["notes"]:
        print("  " + _one_line(f"warning: {note}"))


def _survey_all(tables: list, args) -> list:
    """``(name, survey or FailedRecord, warnings)`` per table, in parallel with ``--n-jobs``."""
    from ..modes.batch import run_surveys

    return run_surveys(
        [tab.data if tab.data.shape[1] > 1 else tab.data[:, 0] for tab in tables],
        t=[tab.t for tab in tables],
        force=[(tab.extra or {}).get("force") for tab in tables],
        names=[tab.path for tab in tables],
        sensor=args.sensor,
        nonlinearity=not args.no_nonlinearity,
        n_jobs=args.n_jobs,
        progress=False if args.no_progress else None,
    )


def _skip(problems: list, message: str, single: bool) -> None:
    """A problem with one input: the error of a one-input run, a skipped line in a batch."""
    if single:
        raise CLIError(message)
    problems.append(message)
    print(f"sindy-impulse: skipped: {_one_line(message)}", file=sys.stderr)


def run(args) -> int:
    from ..modes.batch import FailedRecord

    plan = plan_outputs(args)
    single, problems, tables, targets = len(args.files) == 1, [], [], []
    for path, paths in zip(args.files, plan):
        try:
            tables.append(read_input(path, args))
            targets.append(paths)
        except CLIError as err:
            _skip(problems, str(err), single)
    written, n_modes = [], 0
    results = _survey_all(tables, args) if tables else []
    for table, paths, (_, survey, caught) in zip(tables, targets, results):
        if isinstance(survey, FailedRecord):  # identify_modes refused the record
            _skip(problems, survey.message if survey.error == "ValueError" else str(survey), single)
            continue
        report = survey_report(table, survey, caught, nonlinear=not args.no_nonlinearity)
        print_report(report)
        n_modes += len(survey.modes)
        try:
            written += write_outputs(survey, report, paths)
        except CLIError as err:
            _skip(problems, str(err), single)
    if written:
        print(f"written to {args.out_dir}: {len(written)} file(s)" if args.out_dir else
              f"written: {', '.join(written)}")
    if not single:
        print(f"{len(args.files) - len(problems)} of {len(args.files)} file(s) done, {n_modes} mode(s)")
    return 1 if problems else 0

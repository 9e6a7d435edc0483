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
import re
import sys

from .._utils.units import DAMPING_UNITS, DEFAULT_DAMPING_UNIT, damping_in_words, damping_text
from ._options import (
    add_damping_option,
    add_input_options,
    add_report_options,
    data_options,
    integer,
    positive_int,
    real,
)
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
    "amplitude and shape per channel, fit error, the verdicts of the test for nonlinearity and of the "
    "diagnostics) and one per problem; the equations and notes go to --json. A CSV file's time column (t "
    "or time) is the time; --fs or --dt must agree with it. Several files: one survey each (--n-jobs in "
    "parallel), outputs in --out-dir. A record with no mode, when outputs are asked for, is an error (exit "
    "2, or a skipped file and exit 1 in a batch) unless --allow-empty."
)


def _add_selection_options(p) -> None:
    """Which modes, in which unit, and whether a record with none is an error."""
    p.add_argument("--fmin", type=real, metavar="HZ", help="report only modes at or above this frequency")
    p.add_argument("--fmax", type=real, metavar="HZ", help="report only modes at or below this frequency")
    p.add_argument(
        "--max-modes",
        type=positive_int,
        metavar="N",
        help="at most N modes, the strongest (largest amplitude; with --fmin/--fmax, in that range); the "
        "survey looks at the N strongest spectral peaks",
    )
    add_damping_option(p)
    p.add_argument(
        "--allow-empty",
        action="store_true",
        help="a record in which no mode is found is not an error: write its outputs and exit 0",
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
    add_input_options(
        p, "sensor columns of a CSV file, or channels of another format (default: all but the time and the "
        "force)"
    )
    p.add_argument(
        "--force", metavar="NAME", help="column (or channel) of the hammer's force (onset, double hits; "
        "default: a column named force, hammer or excitation, or the file's force channel)"
    )
    p.add_argument("--sensor", choices=_SENSORS, help="kind of sensor (residues with --force)")
    p.add_argument("--no-nonlinearity", action="store_true", help="skip the test for nonlinearity (faster)")
    _add_selection_options(p)
    add_report_options(p, "the spectrum with the modes and each mode's decay against its model")
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
    page = survey.to_html(
        source=report["file"],
        nonlinearity=report["nonlinearity_tested"],
        damping_unit=report["damping_unit"],
        channel_names=report["channels"],
        notes=report["notes"],
    )
    atomic_write(path, lambda fh: fh.write(page))


#: kind -> writer(survey, report, path).
_WRITERS = {
    "json": lambda survey, report, path: write_json(path, report),
    "unv": _write_uff55,
    "uff58": _write_uff58,
    "png": lambda survey, report, path: write_figure(
        path, lambda: survey.plot(damping_unit=report["damping_unit"])[0].figure
    ),
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
    table = read_measurement(path, **data_options(args), extra=[args.force] if args.force else (),
                             find_force=True)
    if args.force:
        table.extra["force"] = table.extra.pop(args.force)
    if table.data.shape[0] < 64:
        raise CLIError(f"{path} has {table.data.shape[0]} data rows; a hammer-test record needs at least 64")
    return table


#: Advice of the Python interface, as the command line offers it: (what the library says, what to say).
_ADVICE = (
    ("check the sensor, the sampling rate fs, or give bands=",
     "check the sensor and the sampling rate (--fs, --dt or the file's time column)"),
    ("the sampling rate fs", "the sampling rate (--fs, --dt or the file's time column)"),
    ("pass force_channel=", "name the force column with --force"),
    ("pass fs=", "give --fs"),
    ("n_modes=", "--max-modes "),
    ("samples per period at fs", "samples per period at the sampling rate"),
)
#: A sentence that advises an option the command line does not have (``bands=``): left out.
_NOT_OFFERED = re.compile(r"[,;]? *(or )?(give|pass|use) bands=[^;)]*")


def for_the_command_line(text: str) -> str:
    """A message of the library with its advice in the command line's terms (``fs`` -> ``--fs``) and
    advice the command line cannot follow (``bands=``) left out.

    Examples
    --------
    >>> for_the_command_line("no ring-down (check the sensor, the sampling rate fs, or give bands=)")
    "no ring-down (check the sensor and the sampling rate (--fs, --dt or the file's time column))"
    """
    for library, command in _ADVICE:
        text = text.replace(library, command)
    return _NOT_OFFERED.sub("", text)


def survey_report(table, survey, caught, nonlinear: bool, damping_unit: str = DEFAULT_DAMPING_UNIT,
                  notes=()) -> dict:
    """The JSON-ready report of one input's survey (``caught``: its warnings as (category, message);
    ``notes``: what the command itself did, e.g. the modes it left out of the frequency range): the
    account of every mode (:func:`sindy_impulse.report.summary.survey_account`, what the terminal and the
    HTML report say too)."""
    from ..report.summary import survey_account

    account = survey_account(
        survey, nonlinearity=nonlinear, damping_unit=damping_unit, channel_names=table.names
    )
    for r in account["rejected"]:
        r["reason"] = for_the_command_line(str(r["reason"]))
    warned = [damping_in_words(message, damping_unit) for _, message in caught]
    messages = [*notes, *warned, *account.pop("notes")]  # the survey's notes are mostly warned too: once
    return {
        "file": table.path,
        "channels": table.names,
        "force_column": table.force_column,
        "nonlinearity_tested": nonlinear,
        **account,
        "notes": list(dict.fromkeys(for_the_command_line(m) for m in messages)),
    }


#: Longest problem line printed, indent included (the full text is in --json).
_LINE = 160


def _one_line(text: str) -> str:
    text = " ".join(str(text).split())
    return text if len(text) <= _LINE - 2 else text[: _LINE - 5] + "..."


def _channel_line(channels: list) -> str:
    from ..report.summary import phase_text

    return " | ".join(
        f"{c['channel']}: amplitude {c['amplitude']:.4g}, phase "
        + ("0 deg (reference)" if c["reference"] else f"{phase_text(c['phase_deg'])} deg")
        for c in channels
    )


def _mode_lines(i: int, m: dict, unit: str) -> list[str]:
    verdict = {True: ", nonlinear", False: ", linear"}.get(m.get("nonlinear"), "")
    zeta = m["damping_ratio" + DAMPING_UNITS[unit][2]]
    amplitude = "" if m["channels"] else f", amplitude {m['amplitude']:.4g}"
    lines = [
        f"  mode {i}: {m['frequency_hz']:.6g} Hz, damping {damping_text(zeta / DAMPING_UNITS[unit][0], unit)}"
        f"{amplitude}, fit error {m['fit_error']:.3g}{verdict}, diagnostics {m['diagnostics']}"
    ]
    if m["channels"]:
        lines.append("    " + _one_line(_channel_line(m["channels"])))
    lines += ["    " + _one_line(f"problem: {p}") for p in m["problems"]]
    if m["decision"]:
        lines.append("    " + _one_line(m["decision"]))
    return lines


def print_report(report: dict) -> None:
    """One line for the file, one or more per mode (values; amplitude and phase per channel; the
    diagnostics' problems; which verdict decides when they seem to disagree), one per problem (a rejected
    band, a warning)."""
    modes = report["modes"]
    force = report.get("force_column")
    force = f" (the force: column {force!r}, by its name; --force to choose)" if force else ""
    print(f"{report['file']}: {len(modes)} mode(s) from {', '.join(report['channels'])}{force}")
    for i, m in enumerate(modes):
        for line in _mode_lines(i, m, report["damping_unit"]):
            print(line)
    for r in report["rejected"]:
        band = "record" if r["band_hz"] is None else f"{r['band_hz'][0]:.4g}-{r['band_hz'][1]:.4g} Hz"
        print("  " + _one_line(f"rejected {band}: {r['reason']}"))
    for note in report["notes"]:
        print("  " + _one_line(f"warning: {note}"))


def frequency_range(args) -> tuple[float, float] | None:
    """``(--fmin, --fmax)`` checked (None when neither is given; a missing end is 0 or infinity)."""
    low, high = args.fmin, args.fmax
    if low is None and high is None:
        return None
    low = 0.0 if low is None else low
    high = math.inf if high is None else high
    if not (math.isfinite(low) and low >= 0):
        raise CLIError(f"--fmin must be a frequency of 0 Hz or more, got {args.fmin!r}")
    if not (high > 0 and not math.isnan(high)) or (args.fmax is not None and not math.isfinite(high)):
        raise CLIError(f"--fmax must be a positive frequency, got {args.fmax!r}")
    if low >= high:
        raise CLIError(f"--fmin {low:g} Hz must be below --fmax {high:g} Hz")
    return low, high


def _band_text(low: float, high: float) -> str:
    return f"{low:g}-{high:g} Hz" if math.isfinite(high) else f"above {low:g} Hz"


def select_modes(survey, band, max_modes):
    """The survey with only the modes in ``band`` (``(low, high)`` Hz, or None: all) and at most
    ``max_modes`` of them, the strongest (largest amplitude); returns ``(survey, notes)``, the notes
    saying what was left out. ``identify_modes`` fits every band it finds (``n_modes`` limits the spectral
    peaks, not the modes its stabilisation diagram adds), so both are applied to its result."""
    import dataclasses

    if band is None and max_modes is None:
        return survey, []
    low, high = (0.0, math.inf) if band is None else band
    inside = [m for m in survey.modes if low <= m.frequency_hz <= high]
    notes = []
    if len(inside) < len(survey.modes):
        found = ", ".join(f"{m.frequency_hz:.5g}" for m in survey.modes if m not in inside)
        notes.append(
            f"{len(survey.modes) - len(inside)} mode(s) outside {_band_text(low, high)} left out "
            f"(--fmin/--fmax): {found} Hz"
        )
    if max_modes is not None and len(inside) > max_modes:
        strongest = sorted(inside, key=lambda m: -m.amplitude)[:max_modes]
        dropped = ", ".join(f"{m.frequency_hz:.5g}" for m in inside if m not in strongest)
        notes.append(
            f"{len(inside) - max_modes} weaker mode(s) left out (--max-modes {max_modes}): {dropped} Hz"
        )
        inside = [m for m in inside if m in strongest]
    rejected = [
        r for r in survey.rejected if r.band_hz is None or (r.band_hz[1] >= low and r.band_hz[0] <= high)
    ]
    kept = dataclasses.replace(survey, modes=inside, rejected=rejected)
    if "poles" in survey.__dict__:  # the stabilisation diagram does not depend on the selection
        kept.__dict__["poles"] = survey.__dict__["poles"]
    return kept, notes


def _survey_all(tables: list, args) -> list:
    """``(name, survey or FailedRecord, warnings)`` per table, in parallel with ``--n-jobs``."""
    from ..modes.batch import run_surveys

    return run_surveys(
        [tab.data if tab.data.shape[1] > 1 else tab.data[:, 0] for tab in tables],
        t=[tab.t for tab in tables],
        force=[(tab.extra or {}).get("force") for tab in tables],
        names=[tab.path for tab in tables],
        sensor=args.sensor,
        n_modes=args.max_modes if frequency_range(args) is None else None,
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


def _empty_problem(path: str, survey, notes: list, band) -> str:
    """Why a record gave no mode and what to try, as one message."""
    if band is not None and notes:
        why = f"no mode in {_band_text(*band)}; " + "; ".join(notes)
        hint = "widen --fmin/--fmax"
    else:
        reasons = [for_the_command_line(str(r.reason)) for r in survey.rejected[:2]]
        reasons += [for_the_command_line(str(n)) for n in survey.notes[-1:]]
        why = "no mode found" + (f" ({'; '.join(reasons)})" if reasons else "")
        hint = (
            "check the sensor, the sampling rate (--fs, --dt or the time column) and the trigger, or hit "
            "harder"
        )
    return f"{path}: {why}; {hint}; no output written (--allow-empty writes them anyway)"


def run(args) -> int:
    from ..modes.batch import FailedRecord

    plan = plan_outputs(args)
    band = frequency_range(args)
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
            message = survey.message if survey.error == "ValueError" else str(survey)
            _skip(problems, for_the_command_line(message), single)
            continue
        survey, notes = select_modes(survey, band, args.max_modes)
        report = survey_report(table, survey, caught, nonlinear=not args.no_nonlinearity,
                               damping_unit=args.damping_unit, notes=notes)
        print_report(report)
        n_modes += len(survey.modes)
        if not survey.modes and paths and not args.allow_empty:
            _skip(problems, _empty_problem(table.path, survey, notes, band), single)
            continue
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

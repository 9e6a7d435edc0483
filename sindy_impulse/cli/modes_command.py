"""``sindy-impulse modes FILE.csv``: the modal table of a hammer-test record (``identify_modes``), one
equation per mode (``--json`` the same as JSON, ``--plot`` the spectrum and each mode against its model)."""

from __future__ import annotations

import argparse
import math

from ._options import add_input_options, add_report_options, data_options
from .files import CLIError, check_outputs, read_measurement, write_figure, write_json

__all__ = ["add_parser", "run"]

_SENSORS = ("displacement", "velocity", "acceleration")


#: The command's one-line help and its description.
SUMMARY = "modal table of a hammer-test record stored as CSV"
DESCRIPTION = (
    "Find the modes of a hammer-test (impact) record: onset, offset, spectral peaks, one band-passed signal "
    "per mode, one identified equation per mode; prints frequency, damping ratio, amplitude, fit error and "
    "the verdict of the test for nonlinearity."
)


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("modes", help=SUMMARY, description=DESCRIPTION)
    p.add_argument(
        "file",
        metavar="FILE",
        help="the record: CSV with a header row, or UFF 58 (.uff/.unv), LabVIEW .lvm, TDMS, .mat, .npz "
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
    p.set_defaults(func=run)
    return p


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


def survey_report(table, args):
    """Run identify_modes on the table: ``(survey, report)`` with a JSON-ready report."""
    import warnings

    from ..modes import identify_modes

    extra = table.extra or {}
    y = table.data if table.data.shape[1] > 1 else table.data[:, 0]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        survey = identify_modes(y, table.t, force=extra.get("force"), sensor=args.sensor)
        rows = survey.table(nonlinear=not args.no_nonlinearity)
    report = {
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
        "notes": list(dict.fromkeys(str(w.message) for w in caught)),
    }
    return survey, report


def print_report(report: dict) -> None:
    modes = report["modes"]
    print(f"{report['file']}: {len(modes)} mode(s) from channel(s) {', '.join(report['channels'])}")
    if modes:
        print("  #  f_n [Hz]     f_d [Hz]     damping ratio  amplitude    fit error  nonlinear")
    for i, m in enumerate(modes):
        nl = {True: "yes", False: "no"}.get(m.get("nonlinear"), "-")
        print(
            f"  {i:<2d} {m['frequency_hz']:<12.6g} {m['damped_frequency_hz']:<12.6g} "
            f"{m['damping_ratio']:<14.4g} {m['amplitude']:<12.4g} {m['fit_error']:<10.3g} {nl}"
        )
        for lhs, eq in m["equations"].items():
            print(f"       ({lhs[:-1]})' = {eq}")
    for r in report["rejected"]:
        band = "record" if r["band_hz"] is None else f"{r['band_hz'][0]:.4g}-{r['band_hz'][1]:.4g} Hz"
        print(f"  rejected {band}: {r['reason']}")
    for note in report["notes"]:
        print(f"note: {note}")


def run(args) -> int:
    outputs = {"--json": args.json, "--plot": args.plot, "--uff": args.uff}
    check_outputs(outputs, [args.file], figures=["--plot"])
    table = read_measurement(args.file, **data_options(args), extra=[args.force] if args.force else ())
    if args.force:
        table.extra["force"] = table.extra.pop(args.force)
    if table.data.shape[0] < 64:
        raise CLIError(
            f"{args.file} has {table.data.shape[0]} data rows; a hammer-test record needs at least 64"
        )
    survey, report = survey_report(table, args)
    print_report(report)
    if args.json:
        write_json(args.json, report)
        print(f"JSON report written to {args.json}")
    if args.plot:
        write_figure(args.plot, lambda: survey.plot()[0].figure)
        print(f"Figure of the spectrum and the modes written to {args.plot}")
    if args.uff:
        try:  # the file was checked above, as --json is: a named output is replaced
            survey.to_uff(args.uff, overwrite=True)
        except ImportError as err:
            raise CLIError(str(err)) from None
        print(f"UFF 55 modal table written to {args.uff}")
    return 0

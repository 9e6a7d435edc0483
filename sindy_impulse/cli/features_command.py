"""``sindy-impulse features DIR_OR_GLOB --out OUT.csv``: SINDy coefficient features of many CSV files,
one row per file (paper section 3.4).

A bad file does not stop the batch: it gets a row of NaN in the table and a ``sindy-impulse: skipped:``
line (its name and what is wrong) on stderr, the other files are processed, and the command ends with a
summary line and exit status 1. The batch never reads its own ``--out`` file (a features table left by an
earlier run) and never overwrites one of its inputs.
"""

from __future__ import annotations

import argparse
import csv
import os
import sys

from ._options import (
    add_input_options,
    add_model_options,
    data_options,
    integer,
    make_embedding,
    make_estimator,
    required_rows,
)
from .files import CLIError, Table, atomic_write, check_outputs, list_inputs, open_input, read_csv

__all__ = ["add_parser", "run"]

#: Relative spread of the time steps above which a time column is not uniformly sampled.
_STEP_TOL = 1e-6


def add_parser(sub) -> argparse.ArgumentParser:
    feats = sub.add_parser(
        "features",
        help="SINDy coefficient features of many CSV files, one row per file",
        description="Reconstruct every file (in parallel) and write its coefficients, one row per file "
        "(SINDyFeatures, paper section 3.4). A file that cannot be used gets a row of NaN and a message; "
        "the others are processed and the exit status is 1.",
    )
    feats.add_argument("pattern", metavar="DIR_OR_GLOB", help="a directory (its *.csv) or a quoted glob")
    add_input_options(feats)
    add_model_options(feats)
    feats.add_argument("--out", required=True, metavar="OUT.csv", help="the features table to write")
    feats.add_argument(
        "--n-jobs", type=integer, default=None, help="parallel jobs (-1: all cores; default 1)"
    )
    feats.add_argument("--no-progress", action="store_true", help="no progress bar")
    feats.set_defaults(func=run)
    return feats


def _read_all(files: list[str], options: dict) -> tuple[list, dict]:
    """One Table per file (None for a file that cannot be read) and ``{index: message}`` of those."""
    tables, errors = [], {}
    for i, path in enumerate(files):
        try:
            tables.append(read_csv(path, **options))
        except CLIError as err:
            tables.append(None)
            errors[i] = str(err)
    return tables, errors


def _reject(tables: list, errors: dict, i: int, message: str) -> None:
    tables[i] = None
    errors[i] = message


def _same_columns(tables: list, errors: dict) -> list[str]:
    """The state columns of the first usable file; files with other columns are rejected."""
    first = next(tab for tab in tables if tab is not None)
    for i, tab in enumerate(tables):
        if tab is not None and tab.names != first.names:
            _reject(
                tables,
                errors,
                i,
                f"{tab.path} has state columns {', '.join(tab.names)} but {first.path} has "
                f"{', '.join(first.names)}; choose the same ones with --columns",
            )
    return first.names


def _step(tab: Table) -> float:
    """The uniform sampling step of a table's time column."""
    import numpy as np

    d = np.diff(tab.t)
    if d.size and np.ptp(d) > _STEP_TOL * np.median(d):
        raise CLIError(f"{tab.path}: the time column is not uniformly sampled; resample it or use --dt")
    return float(np.median(d)) if d.size else float("nan")


def _common_step(tables: list, errors: dict) -> float | None:
    """The sampling step common to the files' time columns (files off it are rejected)."""
    dt, first = None, None
    for i, tab in enumerate(tables):
        if tab is None:
            continue
        try:
            step = _step(tab)
        except CLIError as err:
            _reject(tables, errors, i, str(err))
            continue
        if dt is None:
            dt, first = step, tab
        elif not abs(step - dt) <= _STEP_TOL * dt:
            _reject(
                tables,
                errors,
                i,
                f"{tab.path} is sampled every {step:g} but {first.path} every {dt:g}; "
                "the features need one sampling step",
            )
    return dt


def _enough_rows(tables: list, errors: dict, need: int) -> None:
    for i, tab in enumerate(tables):
        if tab is not None and tab.data.shape[0] < need:
            _reject(
                tables,
                errors,
                i,
                f"{tab.path} has too few rows: {tab.data.shape[0]} data rows, at least {need} are needed",
            )


def _usable(tables: list, errors: dict, files: list[str]) -> list[int]:
    """Indices of the usable files; when none is left, the batch stops with the reason."""
    good = [i for i, tab in enumerate(tables) if tab is not None]
    if not good:
        if len(files) == 1:
            raise CLIError(errors[0])
        _report_skipped(errors)
        raise CLIError(f"none of the {len(files)} files could be used")
    return good


def _report_skipped(errors: dict) -> None:
    for i in sorted(errors):
        print(f"sindy-impulse: skipped: {' '.join(errors[i].split())}", file=sys.stderr)


def _progress_bar(args) -> bool:
    if args.no_progress:
        return False
    try:
        import tqdm  # noqa: F401
    except ImportError:
        return False
    return True


def _features(args, tables: list, errors: dict, files: list[str], dt: float | None):
    """Fit the usable files: ``(features matrix with NaN rows for the rejected files, transformer)``."""
    import numpy as np

    from ..features import SINDyFeatures

    names = _same_columns(tables, errors)
    if args.embed and len(names) != 1:
        raise CLIError(
            f"--embed needs a single measured column, got {', '.join(names)}; choose one with --columns"
        )
    dt = _common_step(tables, errors) if dt is None else dt
    estimator = make_estimator(args.degree)
    _enough_rows(tables, errors, required_rows(estimator, 2 if args.embed else len(names)))
    features = SINDyFeatures(
        estimator=estimator,
        dt=dt,
        embed=make_embedding(args),
        n_jobs=args.n_jobs,
        progress=_progress_bar(args),
    )
    good = _usable(tables, errors, files)
    series = [tables[i].data[:, 0] if len(names) == 1 else tables[i].data for i in good]
    features.fit(series)
    if features.embedding_ is not None:  # the common embedding is known only now
        _enough_rows(tables, errors, features.embedding_.offset_ + features.min_samples_)
        good = _usable(tables, errors, files)
        series = [tables[i].data[:, 0] for i in good]
    X = np.full((len(files), len(features.get_feature_names_out())), np.nan)
    X[good] = features.transform(series)
    header = features.get_feature_names_out(None if features.embedding_ is not None else names)
    failures = {good[i]: message for i, message in features.failures_.items()}
    return X, list(header), failures


def _is_features_table(path: str) -> bool:
    """Whether ``path`` is a table this command wrote (its header starts with ``file``): a batch leaves
    it out of its inputs and may replace it, while any other file among the inputs is never overwritten."""
    if not os.path.isfile(path):
        return False
    with open_input(path) as fh:
        first = next(csv.reader([fh.readline()]), [""])
    return bool(first) and first[0].strip() == "file"


def _labels(files: list[str]) -> list[str]:
    """File names for the first column: the base names when they are unique, else the paths."""
    base = [os.path.basename(f) for f in files]
    return base if len(set(base)) == len(base) else files


def run(args) -> int:
    if args.n_jobs is not None and args.n_jobs == 0:
        raise CLIError("--n-jobs must not be 0 (use a positive number, or -1 for all cores)")
    options = data_options(args)
    files = list_inputs(args.pattern, exclude=[args.out] if _is_features_table(args.out) else [])
    check_outputs({"--out": args.out}, files)
    tables, errors = _read_all(files, options)
    _usable(tables, errors, files)
    X, header, failures = _features(args, tables, errors, files, options["dt"])

    def write(fh):
        out = csv.writer(fh)
        out.writerow(["file", *header])
        for label, row in zip(_labels(files), X):
            out.writerow([label, *(format(v, ".10g") for v in row)])

    atomic_write(args.out, write)
    skipped = f", {len(errors)} skipped" if errors else ""
    print(f"{args.out}: {len(files)} file(s) x {X.shape[1]} features, {len(failures)} failed{skipped}")
    for i, message in sorted(failures.items()):
        print(f"sindy-impulse: warning: {files[i]}: reconstruction failed ({message})", file=sys.stderr)
    if not errors:
        return 0
    _report_skipped(errors)
    print(
        f"sindy-impulse: error: {len(errors)} of {len(files)} file(s) skipped (rows of NaN in {args.out}): "
        + ", ".join(files[i] for i in sorted(errors)),
        file=sys.stderr,
    )
    return 1

"""Command line: ``sindy-impulse demo | fit | features``.

``demo`` runs the paper's oscillator case end to end. ``fit`` reconstructs the equations of one measured
ring-down stored as a CSV file and reports Gamma, the nonlinearity test and the modal parameters. ``features``
turns many CSV files into one table of SINDy coefficient features (paper section 3.4).

CSV files are read with the standard library (no pandas): a header row of column names, then one row of
numbers per sample. Every mistake a user can make with the files or the options ends in a one-line
``sindy-impulse: error: ...`` on stderr and exit code 2 (``--traceback`` shows the full traceback instead).
"""

from __future__ import annotations

import argparse
import csv
import glob
import json
import math
import os
import sys
from dataclasses import dataclass

#: Names recognised as the time column when neither ``--time`` nor ``--dt`` is given.
_TIME_NAMES = ("t", "time")
#: Samples beyond the library's number of terms a fit needs (the differentiation trims the ends).
_SAMPLE_MARGIN = 16


class CLIError(Exception):
    """A user error: reported as one line, without a traceback."""


class _Parser(argparse.ArgumentParser):
    """argparse with one-line error messages (``sindy-impulse: error: ...``) and exit code 2."""

    def error(self, message):
        hint = f" (see '{self.prog} --help')"
        self.exit(2, f"sindy-impulse: error: {message}{hint}\n")


# ----------------------------------------------------------------------------------------------------
# reading CSV files
# ----------------------------------------------------------------------------------------------------
@dataclass
class Table:
    """The selected columns of a CSV file."""

    path: str
    names: list  # state columns
    data: object  # ndarray (n_samples, n_columns)
    t: object  # float (time step) or ndarray (n_samples,)
    time_column: str | None


def _parse_float(text: str):
    try:
        return float(text)
    except ValueError:
        return None


def _split_names(text: str | None) -> list[str] | None:
    if text is None:
        return None
    names = [n.strip() for n in text.split(",")]
    if not names or any(not n for n in names):
        raise CLIError(f"--columns must be a comma-separated list of column names, got {text!r}")
    if len(set(names)) != len(names):
        raise CLIError(f"--columns names a column twice: {text!r}")
    return names


def read_csv(path: str, columns: list[str] | None = None, time: str | None = None, dt: float | None = None):
    """Read the state columns (and the time column) of a CSV file with a header row.

    Parameters
    ----------
    path : str
        The file.
    columns : list of str, optional
        State columns, by name. Default: every numeric column except the time column.
    time : str, optional
        Name of the time column. Default: a column named ``t`` or ``time`` when ``dt`` is not given.
    dt : float, optional
        Sampling step (then no column is the time).

    Returns
    -------
    Table

    Raises
    ------
    CLIError
        Missing or empty file, unknown column, a non-numeric or non-finite cell (with its column and
        line), no time information.
    """
    import numpy as np

    from ._validation import check_time

    if not os.path.exists(path):
        raise CLIError(f"{path}: no such file")
    if os.path.isdir(path):
        raise CLIError(f"{path} is a directory, expected a CSV file")
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:
            sample = fh.read(4096)
            fh.seek(0)
            try:
                dialect = csv.Sniffer().sniff(sample, delimiters=",;\t")
            except csv.Error:
                dialect = csv.excel
            reader = csv.reader(fh, dialect)
            header = next((row for row in reader if any(cell.strip() for cell in row)), None)
            if header is None:
                raise CLIError(f"{path} is empty; expected a header row of column names and rows of numbers")
            header = [h.strip() for h in header]
            rows, lines = [], []
            for row in reader:
                if not any(cell.strip() for cell in row):
                    continue
                rows.append([cell.strip() for cell in row])
                lines.append(reader.line_num)
    except UnicodeDecodeError as err:
        raise CLIError(f"{path} is not a text (UTF-8) CSV file ({err.reason})") from None
    except csv.Error as err:
        raise CLIError(f"{path}: malformed CSV ({err})") from None
    except OSError as err:
        raise CLIError(f"{path}: cannot read ({err.strerror})") from None

    # A trailing delimiter makes an unnamed, empty last column (e.g. 'V1,V2,'): drop it.
    named = [i for i, h in enumerate(header) if h or any(i < len(r) and r[i] for r in rows)]
    for i in named:
        if not header[i]:
            raise CLIError(f"{path}: column {i + 1} has no name in the header row")
    dupes = sorted({header[i] for i in named if [header[j] for j in named].count(header[i]) > 1})
    if dupes:
        raise CLIError(f"{path}: duplicate column name(s) in the header: {', '.join(dupes)}")
    index = {header[i]: i for i in named}
    available = ", ".join(header[i] for i in named)

    def column(name):
        """The numbers of one column, or CLIError naming the first bad cell."""
        i = index[name]
        values = np.empty(len(rows))
        for k, (row, line) in enumerate(zip(rows, lines)):
            cell = row[i] if i < len(row) else ""
            value = _parse_float(cell) if cell else None
            if value is None:
                what = "an empty cell" if not cell else f"a non-numeric cell {cell!r}"
                raise CLIError(f"{path}: column {name!r} has {what} at line {line}")
            if not math.isfinite(value):
                raise CLIError(f"{path}: column {name!r} has a non-finite value {cell!r} at line {line}")
            values[k] = value
        return values

    def numeric(name):
        i = index[name]
        return any(_parse_float(r[i]) is not None for r in rows if i < len(r) and r[i])

    if not rows:
        raise CLIError(f"{path} has a header but no data rows")
    for name in ([time] if time else []) + (columns or []):
        if name not in index:
            raise CLIError(f"{path}: no column {name!r} (columns: {available})")
    if time is None and dt is None:
        time = next((n for n in index if n.lower() in _TIME_NAMES), None)
        if time is None:
            raise CLIError(
                f"{path}: no time information; give the sampling step with --dt or the time column "
                "with --time"
            )
    if columns is None:
        columns = [n for n in index if n != time and numeric(n)]
        if not columns:
            raise CLIError(f"{path}: no numeric column besides the time (columns: {available})")
    elif time in columns:
        raise CLIError(f"{path}: column {time!r} is the time column and cannot also be a state")
    data = np.column_stack([column(n) for n in columns])
    if time is not None:
        t = column(time)
        steps = np.diff(t)
        if np.any(steps <= 0):
            k = int(np.argmax(steps <= 0)) + 1
            raise CLIError(
                f"{path}: the time column {time!r} is not strictly increasing at line {lines[k]} "
                f"({rows[k][index[time]]} after {rows[k - 1][index[time]]})"
            )
        t = check_time(t, len(rows), f"time column {time!r}")
    else:
        t = dt
    return Table(path, columns, data, t, time)


# ----------------------------------------------------------------------------------------------------
# shared options
# ----------------------------------------------------------------------------------------------------
def _check_dt(dt):
    if dt is None:
        return None
    if not (math.isfinite(dt) and dt > 0):
        raise CLIError(f"--dt must be a positive number of time units per sample, got {dt!r}")
    return dt


def _auto_int(text: str):
    if text == "auto":
        return "auto"
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer or 'auto', got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer or 'auto', got {text!r}")
    return value


def _positive_int(text: str):
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}")
    return value


def _fmt(value) -> str:
    """A number of the report (None: not finite)."""
    return "inf" if value is None else f"{value:.4g}"


def _n_terms(n_states: int, degree: int) -> int:
    return math.comb(n_states + degree, degree)


def _min_rows(n_states: int, degree: int) -> int:
    return _n_terms(n_states, degree) + _SAMPLE_MARGIN


def _add_data_options(p):
    p.add_argument("--columns", help="comma-separated state columns (default: all numeric columns but time)")
    when = p.add_mutually_exclusive_group()
    when.add_argument("--time", metavar="NAME", help="the time column (default: a column named t or time)")
    when.add_argument(
        "--dt", type=float, help="sampling step (time units per sample), instead of a time column"
    )
    p.add_argument(
        "--embed", action="store_true", help="delay-embed a single measured column (DelayEmbedding)"
    )
    p.add_argument("--tau", type=_auto_int, default="auto", help="embedding delay in samples (default: auto)")
    p.add_argument("--dimension", type=_auto_int, default="auto", help="embedding dimension (default: auto)")
    p.add_argument("--degree", type=_positive_int, default=3, help="PolynomialLibrary degree (default: 3)")


def _estimator(degree: int):
    import pysindy as ps

    from .estimator import ImpulseSINDy

    return ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=degree))


# ----------------------------------------------------------------------------------------------------
# demo
# ----------------------------------------------------------------------------------------------------
def _demo(args) -> int:
    import numpy as np

    from .datasets import damped_oscillator
    from .estimator import ImpulseSINDy

    print("sindy-impulse demo: the paper's case 3.1.2 (Stender, Oberst & Hoffmann 2019)")
    print("  x1' = x2, x2' = -64 x1 - 3.2 x2, x(0) = (1, 0), t in [0, 4], dt = 0.01; states only,")
    print(f"  derivatives by TVRegDiff, polynomial library of degree 3, SNR = {args.snr or 'no noise'}")
    t, x, _ = damped_oscillator(snr_db=args.snr, random_state=args.seed)
    model = ImpulseSINDy().fit(x, t=t, feature_names=["x1", "x2"])
    path = model.path_
    print(f"\nThreshold sweep: {len(path)} distinct models from {path.n_terms[0]} terms to none.")
    print(
        f"Selected before refinement ({path.n_terms[path.selected]} terms), Gamma = {model.gamma_sindy_:.4f}:"
    )
    names = model.get_feature_names()
    for lhs, row in zip(model.feature_names_, path.coefficients[path.selected]):
        terms = " + ".join(f"{c: .4f} {n}" for c, n in zip(row, names) if c != 0) or "0"
        print(f"  ({lhs})' = {terms}")
    print(f"After refinement ({model.complexity} terms), Gamma = {model.gamma_:.3g} (the paper: 2.345):")
    model.print(precision=4, lhs=[f"  ({n})'" for n in model.feature_names_])
    coef = model.coefficients()
    k, c = -coef[1, names.index("x1")], -coef[1, names.index("x2")]
    print(f"\nStiffness k = {k:.4f} (true 64), damping c = {c:.4f} (true 3.2)")
    print(f"Natural frequency {np.sqrt(k) / (2 * np.pi):.4f} Hz, damping ratio {c / (2 * np.sqrt(k)):.4f}")
    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        from .plotting import plot_reconstruction

        axes = plot_reconstruction(model)
        axes[0].figure.savefig(args.plot, dpi=120, bbox_inches="tight")
        print(f"Figure of input vs reconstruction written to {args.plot}")
    return 0


# ----------------------------------------------------------------------------------------------------
# fit
# ----------------------------------------------------------------------------------------------------
def _states(table: Table, args):
    """The states to fit, their names, times and the embedding (or None)."""
    import numpy as np

    from ._validation import time_vector
    from .embedding import DelayEmbedding

    x, names, n = table.data, list(table.names), table.data.shape[0]
    t = time_vector(table.t, n)
    embedding = None
    if n < _min_rows(max(2, x.shape[1]) if args.embed else x.shape[1], args.degree):
        need = _min_rows(max(2, x.shape[1]) if args.embed else x.shape[1], args.degree)
        raise CLIError(
            f"{table.path} has too few rows: {n} data rows, at least {need} are needed for "
            f"{'an embedded signal' if args.embed else f'{x.shape[1]} state(s)'} and a "
            f"degree-{args.degree} library"
        )
    if args.embed:
        if x.shape[1] != 1:
            raise CLIError(
                f"{table.path}: --embed needs a single measured column, got {len(names)} "
                f"({', '.join(names)}); choose one with --columns"
            )
        try:
            embedding = DelayEmbedding(tau=args.tau, dimension=args.dimension).fit(x[:, 0])
        except ValueError as err:
            raise CLIError(f"{table.path}: cannot embed column {names[0]!r}: {err}") from None
        states = embedding.transform(x[:, 0])
        t = embedding.transform_time(t)
        names = embedding.delay_labels(name=names[0])
        names = [n.replace("(t)", "") if n.endswith("(t)") else n for n in names]
        names = [n.replace("(t-", "_lag").replace(")", "") for n in names]
    else:
        states = x
    need = _min_rows(states.shape[1], args.degree)
    offset = embedding.offset_ if embedding is not None else 0
    if states.shape[0] < need:
        raise CLIError(
            f"{table.path} has too few rows: {n} data rows, at least {need + offset} are needed for "
            f"{states.shape[1]} state(s) and a degree-{args.degree} library"
        )
    return np.asarray(states), names, t, embedding


def _finite(value):
    """A JSON-safe float (None for inf/NaN)."""
    value = float(value)
    return value if math.isfinite(value) else None


def _fit_report(table: Table, args):
    import warnings

    from .analysis import modal_parameters, nonlinearity_test

    states, names, t, embedding = _states(table, args)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = _estimator(args.degree).fit(states, t=t, feature_names=names)
        test = nonlinearity_test(model, states, t)
    modes = modal_parameters(model)
    notes = list(dict.fromkeys(str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)))
    report = {
        "file": table.path,
        "n_samples": int(states.shape[0]),
        "states": names,
        "columns": table.names,
        "time_column": table.time_column,
        "dt": _finite(t[1] - t[0]) if len(t) > 1 else None,
        "embedding": (
            {"tau": embedding.tau_, "dimension": embedding.dimension_} if embedding is not None else None
        ),
        "degree": args.degree,
        "equations": {f"{n}'": eq for n, eq in zip(names, model.equations(args.precision))},
        "library": list(model.get_feature_names()),
        "coefficients": model.coefficients().tolist(),
        "complexity": model.complexity,
        "gamma": _finite(model.gamma_),
        "gamma_before_refinement": _finite(model.gamma_sindy_),
        "nonlinearity": {
            "nonlinear": bool(test.nonlinear),
            "statistic": _finite(test.statistic),
            "threshold": _finite(test.threshold),
            "gamma_linear": _finite(test.gamma_linear),
            "gamma_nonlinear": _finite(test.gamma_nonlinear),
            "noise_gamma": _finite(test.noise_gamma),
            "source": test.source,
            "terms": [
                {"equation": s.equation, "term": s.term, "coefficient": s.coefficient, "share": s.share}
                for s in test.terms
            ],
        },
        "modes": [
            {"frequency_hz": _finite(f), "damping_ratio": _finite(z)}
            for f, z in zip(modes.frequencies_hz, modes.damping_ratios)
        ],
        "warnings": notes,
    }
    return model, report


def _print_report(r: dict, precision: int) -> None:
    emb = r["embedding"]
    how = (
        f"delay embedding of {r['columns'][0]!r} (tau = {emb['tau']} samples, dimension {emb['dimension']})"
        if emb
        else "states " + ", ".join(r["states"])
    )
    timing = f"time column {r['time_column']!r}" if r["time_column"] else f"dt = {r['dt']:g}"
    print(f"{r['file']}: {r['n_samples']} samples, {how}; {timing}")
    print(
        f"Model ({r['complexity']} terms, PolynomialLibrary degree {r['degree']}), "
        f"Gamma = {_fmt(r['gamma'])}:"
    )
    for lhs, eq in r["equations"].items():
        print(f"  ({lhs[:-1]})' = {eq}")
    nl = r["nonlinearity"]
    verdict = "NONLINEAR" if nl["nonlinear"] else "linear"
    cmp = ">" if nl["nonlinear"] else "<="
    print(
        f"Nonlinearity test: {verdict} (Gamma grows by {_fmt(nl['statistic'])} without nonlinear terms "
        f"{cmp} threshold {_fmt(nl['threshold'])}; Gamma linear {_fmt(nl['gamma_linear'])}, "
        f"nonlinear {_fmt(nl['gamma_nonlinear'])})"
    )
    if nl["terms"] and not nl["nonlinear"]:
        print("  best nonlinear alternative (not significant):")
    for term in nl["terms"]:
        print(
            f"  {term['equation']} {term['coefficient']:+.{precision}g} {term['term']} "
            f"({term['share']:.1%} of its equation)"
        )
    if r["modes"]:
        print("Modal parameters (linear part at the origin):")
        for i, m in enumerate(r["modes"], 1):
            print(
                f"  mode {i}: natural frequency {m['frequency_hz']:.4g} Hz, "
                f"damping ratio {m['damping_ratio']:.4g}"
            )
    else:
        print("Modal parameters: no oscillatory mode in the linear part")
    for note in r["warnings"]:
        print(f"note: {note}")


def _fit(args) -> int:
    dt = _check_dt(args.dt)
    table = read_csv(args.file, _split_names(args.columns), args.time, dt)
    if table.data.shape[1] == 1 and not args.embed:
        print(
            "sindy-impulse: note: a single state; to reconstruct an oscillator from one measured signal, "
            "use --embed",
            file=sys.stderr,
        )
    model, report = _fit_report(table, args)
    _print_report(report, args.precision)
    if args.json:
        _write(args.json, lambda fh: json.dump(report, fh, indent=2))
        print(f"JSON report written to {args.json}")
    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from .plotting import plot_reconstruction

        axes = plot_reconstruction(model)
        _write(args.plot, lambda fh: axes[0].figure.savefig(fh, dpi=120, bbox_inches="tight"), mode="wb")
        plt.close(axes[0].figure)
        print(f"Figure of input vs reconstruction written to {args.plot}")
    return 0


def _write(path, write, mode="w"):
    try:
        with open(path, mode, **({"newline": "", "encoding": "utf-8"} if mode == "w" else {})) as fh:
            write(fh)
    except OSError as err:
        raise CLIError(f"cannot write {path}: {err.strerror}") from None


# ----------------------------------------------------------------------------------------------------
# features
# ----------------------------------------------------------------------------------------------------
def _files(pattern: str) -> list[str]:
    if os.path.isdir(pattern):
        files = sorted(glob.glob(os.path.join(glob.escape(pattern), "*.csv")))
        if not files:
            raise CLIError(f"no CSV files (*.csv) in directory {pattern}")
        return files
    files = sorted(f for f in glob.glob(pattern) if os.path.isfile(f))
    if not files:
        if not glob.has_magic(pattern):
            raise CLIError(f"{pattern}: no such file or directory")
        raise CLIError(f"no files match {pattern!r}")
    return files


def _labels(files: list[str]) -> list[str]:
    """File names for the first column: the base names when they are unique, else the paths."""
    base = [os.path.basename(f) for f in files]
    return base if len(set(base)) == len(base) else files


def _features(args) -> int:
    import numpy as np

    from ._validation import time_vector
    from .embedding import DelayEmbedding
    from .features import SINDyFeatures

    dt = _check_dt(args.dt)
    if args.n_jobs is not None and args.n_jobs == 0:
        raise CLIError("--n-jobs must not be 0 (use a positive number, or -1 for all cores)")
    columns = _split_names(args.columns)
    files = _files(args.pattern)
    tables = [read_csv(f, columns, args.time, dt) for f in files]
    names = tables[0].names
    for tab in tables[1:]:
        if tab.names != names:
            raise CLIError(
                f"{tab.path} has state columns {', '.join(tab.names)} but {tables[0].path} has "
                f"{', '.join(names)}; choose the same ones with --columns"
            )
    if args.embed and len(names) != 1:
        raise CLIError(
            f"--embed needs a single measured column, got {', '.join(names)}; choose one with --columns"
        )
    if dt is None:  # one common step from the time columns
        steps = []
        for tab in tables:
            t = time_vector(tab.t, tab.data.shape[0])
            d = np.diff(t)
            if d.size and np.ptp(d) > 1e-6 * np.median(d):
                raise CLIError(
                    f"{tab.path}: the time column is not uniformly sampled; resample it or use --dt"
                )
            steps.append(float(np.median(d)) if d.size else np.nan)
        dt = steps[0]
        for tab, step in zip(tables, steps):
            if not abs(step - dt) <= 1e-6 * dt:
                raise CLIError(
                    f"{tab.path} is sampled every {step:g} but {tables[0].path} every {dt:g}; "
                    "the features need one sampling step"
                )
    n_states = 1 if args.embed else len(names)
    need = _min_rows(2 if args.embed else n_states, args.degree)
    for tab in tables:
        if tab.data.shape[0] < need:
            raise CLIError(
                f"{tab.path} has too few rows: {tab.data.shape[0]} data rows, at least {need} are needed"
            )
    series = [tab.data[:, 0] if n_states == 1 else tab.data for tab in tables]
    embed = DelayEmbedding(tau=args.tau, dimension=args.dimension) if args.embed else False
    try:
        import tqdm  # noqa: F401

        progress = not args.no_progress
    except ImportError:
        progress = False
    features = SINDyFeatures(
        estimator=_estimator(args.degree), dt=dt, embed=embed, n_jobs=args.n_jobs, progress=progress
    )
    X = features.fit_transform(series)
    header = list(features.get_feature_names_out())
    if features.embedding_ is None:  # name the states after the columns
        import pysindy as ps
        from pysindy.utils import AxesArray

        library = ps.PolynomialLibrary(degree=args.degree)
        probe = np.linspace(0.5, 1.5, 4 * len(names)).reshape(4, len(names))
        library.fit([AxesArray(probe, {"ax_time": 0, "ax_coord": 1})])
        terms = library.get_feature_names(input_features=names)
        header = [f"{s}' : {term}" for s in names for term in terms]

    def write(fh):
        out = csv.writer(fh)
        out.writerow(["file", *header])
        for label, row in zip(_labels(files), X):
            out.writerow([label, *(format(v, ".10g") for v in row)])

    _write(args.out, write)
    print(f"{args.out}: {len(files)} file(s) x {X.shape[1]} features, {features.n_failed_} failed")
    for i, message in sorted(features.failures_.items()):
        print(f"sindy-impulse: warning: {files[i]}: reconstruction failed ({message})", file=sys.stderr)
    return 0


# ----------------------------------------------------------------------------------------------------
# the parser
# ----------------------------------------------------------------------------------------------------
def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="sindy-impulse",
        description="Recover differential equations from impulse-response (ring-down) measurements.",
        epilog="CSV files: a header row of column names, then one row of numbers per sample.",
    )
    parser.add_argument("--traceback", action="store_true", help="show the full traceback on errors")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    demo = sub.add_parser("demo", help="run the paper's oscillator case 3.1.2 end to end")
    demo.add_argument("--snr", type=float, default=None, help="add noise at this SNR in dB")
    demo.add_argument("--seed", type=int, default=0, help="noise seed")
    demo.add_argument("--plot", default="sindy_impulse_demo.png", help="figure file ('' for none)")
    demo.set_defaults(func=_demo)

    fit = sub.add_parser(
        "fit",
        help="reconstruct the equations of one ring-down stored as CSV",
        description="Reconstruct the equations of one ring-down (ImpulseSINDy) and report Gamma, the test "
        "for nonlinearity and the modal parameters.",
    )
    fit.add_argument("file", metavar="FILE.csv", help="CSV file with a header row")
    _add_data_options(fit)
    fit.add_argument("--precision", type=_positive_int, default=4, help="digits of the coefficients")
    fit.add_argument("--json", metavar="OUT.json", help="also write the results as JSON")
    fit.add_argument("--plot", metavar="OUT.png", help="write the input vs reconstruction figure")
    fit.set_defaults(func=_fit)

    feats = sub.add_parser(
        "features",
        help="SINDy coefficient features of many CSV files, one row per file",
        description="Reconstruct every file (in parallel) and write its coefficients, one row per file "
        "(SINDyFeatures, paper section 3.4).",
    )
    feats.add_argument("pattern", metavar="DIR_OR_GLOB", help="a directory (its *.csv) or a quoted glob")
    _add_data_options(feats)
    feats.add_argument("--out", required=True, metavar="OUT.csv", help="the features table to write")
    feats.add_argument("--n-jobs", type=int, default=None, help="parallel jobs (-1: all cores; default 1)")
    feats.add_argument("--no-progress", action="store_true", help="no progress bar")
    feats.set_defaults(func=_features)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)  # a usage error exits (code 2) after its one-line message
    try:
        return args.func(args)
    except Exception as err:  # noqa: BLE001 - the command line reports, it does not crash
        if args.traceback:
            raise
        message = str(err) if isinstance(err, (CLIError, ValueError)) else f"{type(err).__name__}: {err}"
        message = " ".join(message.split())  # one line
        print(f"sindy-impulse: error: {message}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

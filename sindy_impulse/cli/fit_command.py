"""``sindy-impulse fit FILE.csv``: the equations of one measured ring-down, Gamma, the test for
nonlinearity and the modal parameters (``--json`` the same as JSON, ``--plot`` the reconstruction)."""

from __future__ import annotations

import argparse
import math
import sys

from .._utils.units import DAMPING_UNITS, DEFAULT_DAMPING_UNIT, damping_key, damping_text
from ._options import (
    add_damping_option,
    add_input_options,
    add_model_options,
    add_report_options,
    data_options,
    make_embedding,
    make_estimator,
    positive_int,
    required_rows,
)
from .files import CLIError, Table, check_outputs, read_csv, write_figure, write_json

__all__ = ["add_parser", "run"]


def add_parser(sub) -> argparse.ArgumentParser:
    fit = sub.add_parser(
        "fit",
        help="reconstruct the equations of one ring-down stored as CSV",
        description="Reconstruct the equations of one ring-down (ImpulseSINDy) and report Gamma, the test "
        "for nonlinearity and the modal parameters.",
    )
    fit.add_argument("file", metavar="FILE.csv", help="CSV file with a header row")
    add_input_options(fit)
    add_model_options(fit)
    add_damping_option(fit)
    fit.add_argument("--precision", type=positive_int, default=4, help="digits of the coefficients")
    add_report_options(fit)
    fit.set_defaults(func=run)
    return fit


def _too_few(table: Table, need: int, what: str, degree: int) -> CLIError:
    return CLIError(
        f"{table.path} has too few rows: {table.data.shape[0]} data rows, at least {need} are needed for "
        f"{what} and a degree-{degree} library"
    )


def _states(table: Table, args, estimator):
    """The states to fit, their names, times and the embedding (or None)."""
    import numpy as np

    from .._utils.validation import time_vector

    x, names, n = table.data, list(table.names), table.data.shape[0]
    t = time_vector(table.t, n)
    need = required_rows(estimator, max(2, x.shape[1]) if args.embed else x.shape[1])
    if n < need:
        what = "an embedded signal" if args.embed else f"{x.shape[1]} state(s)"
        raise _too_few(table, need, what, args.degree)
    if not args.embed:
        return np.asarray(x), names, t, None
    if x.shape[1] != 1:
        raise CLIError(
            f"{table.path}: --embed needs a single measured column, got {len(names)} "
            f"({', '.join(names)}); choose one with --columns"
        )
    try:
        embedding = make_embedding(args).fit(x[:, 0])
    except ValueError as err:
        raise CLIError(f"{table.path}: cannot embed column {names[0]!r}: {err}") from None
    states = embedding.transform(x[:, 0])
    need = required_rows(estimator, states.shape[1]) + embedding.offset_
    if n < need:
        raise _too_few(table, need, f"{states.shape[1]} state(s)", args.degree)
    labels = embedding.delay_labels(name=names[0])
    labels = [n.replace("(t)", "") if n.endswith("(t)") else n for n in labels]
    labels = [n.replace("(t-", "_lag").replace(")", "") for n in labels]
    return np.asarray(states), labels, embedding.transform_time(t), embedding


def _finite(value):
    """A JSON-safe float (None for inf/NaN)."""
    value = float(value)
    return value if math.isfinite(value) else None


def _nonlinearity(test) -> dict:
    return {
        "nonlinear": bool(test.nonlinear),
        "statistic": _finite(test.statistic),
        "threshold": _finite(test.threshold),
        "significance": _finite(test.significance),
        "amplitude_dependence": _finite(test.amplitude_dependence),
        "frequency_shift": _finite(test.frequency_shift),
        "damping_ratio_shift": _finite(test.damping_ratio_shift),
        "gamma_linear": _finite(test.gamma_linear),
        "gamma_nonlinear": _finite(test.gamma_nonlinear),
        "noise_gamma": _finite(test.noise_gamma),
        "source": test.source,
        "terms": [
            {"equation": s.equation, "term": s.term, "coefficient": s.coefficient, "share": s.share}
            for s in test.terms
        ],
    }


def fit_report(table: Table, args):
    """Fit the model to the table's states and report it as a JSON-ready dict: ``(model, report)``."""
    import warnings

    from ..analysis import modal_parameters, nonlinearity_test

    estimator = make_estimator(args.degree)
    states, names, t, embedding = _states(table, args, estimator)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = estimator.fit(states, t=t, feature_names=names)
        test = nonlinearity_test(model, states, t)
    modes = modal_parameters(model)
    scale = DAMPING_UNITS[args.damping_unit][0]
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
        "nonlinearity": _nonlinearity(test),
        "damping_unit": args.damping_unit,
        "modes": [
            {"frequency_hz": _finite(f), damping_key("damping_ratio", args.damping_unit): _finite(scale * z)}
            for f, z in zip(modes.frequencies_hz, modes.damping_ratios)
        ],
        "warnings": notes,
    }
    return model, report


def _fmt(value) -> str:
    """A number of the report (None: not finite)."""
    return "inf" if value is None else f"{value:.4g}"


def _print_nonlinearity(nl: dict, precision: int) -> None:
    verdict = "NONLINEAR" if nl["nonlinear"] else "linear"
    cmp = ">" if nl["nonlinear"] else "<="
    print(
        f"Nonlinearity test: {verdict} (statistic {_fmt(nl['statistic'])} {cmp} threshold "
        f"{_fmt(nl['threshold'])}: significance {_fmt(nl['significance'])}, amplitude dependence "
        f"{_fmt(nl['amplitude_dependence'])}; Gamma linear {_fmt(nl['gamma_linear'])}, "
        f"nonlinear {_fmt(nl['gamma_nonlinear'])})"
    )
    if nl["terms"] and not nl["nonlinear"]:
        print("  best nonlinear alternative (not significant):")
    for term in nl["terms"]:
        print(
            f"  {term['equation']} {term['coefficient']:+.{precision}g} {term['term']} "
            f"({term['share']:.1%} of its equation)"
        )


def print_modes(modes: list, unit: str = DEFAULT_DAMPING_UNIT) -> None:
    """The modal parameters of a report, one line per mode (damping in ``unit``)."""
    if not modes:
        print("Modal parameters: no oscillatory mode in the linear part")
        return
    print("Modal parameters (linear part at the origin):")
    scale = DAMPING_UNITS[unit][0]
    for i, m in enumerate(modes, 1):
        zeta = m[damping_key("damping_ratio", unit)]
        zeta = "inf" if zeta is None else damping_text(zeta / scale, unit)
        print(f"  mode {i}: natural frequency {_fmt(m['frequency_hz'])} Hz, damping ratio {zeta}")


def print_report(r: dict, precision: int) -> None:
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
    _print_nonlinearity(r["nonlinearity"], precision)
    print_modes(r["modes"], r["damping_unit"])
    for note in r["warnings"]:
        print(f"note: {note}")


def run(args) -> int:
    check_outputs({"--json": args.json, "--plot": args.plot}, [args.file], figures=["--plot"])
    table = read_csv(args.file, **data_options(args))
    if table.data.shape[1] == 1 and not args.embed:
        print(
            "sindy-impulse: note: a single state; to reconstruct an oscillator from one measured signal, "
            "use --embed",
            file=sys.stderr,
        )
    model, report = fit_report(table, args)
    print_report(report, args.precision)
    if args.json:
        write_json(args.json, report)
        print(f"JSON report written to {args.json}")
    if args.plot:
        from ..plotting import plot_reconstruction

        write_figure(args.plot, lambda: plot_reconstruction(model)[0].figure)
        print(f"Figure of input vs reconstruction written to {args.plot}")
    return 0

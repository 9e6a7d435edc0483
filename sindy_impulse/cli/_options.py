"""Options shared by the commands, their strict parsing, and the objects they stand for.

Groups a command adds with one call each: :func:`add_input_options` (which columns of a CSV file, and
its time: ``--time NAME``, ``--dt S | --fs HZ``), :func:`add_model_options` (``--embed``, ``--tau``,
``--dimension``, ``--degree``), :func:`add_report_options` (``--json``, ``--plot``) and
:func:`add_damping_option` (``--damping-unit``). The parsed options become reading arguments with
:func:`data_options` and models with :func:`make_estimator`.
"""

from __future__ import annotations

import argparse
import math

from ._numbers import NumberError, parse_int, parse_number
from .files import CLIError

__all__ = [
    "Parser",
    "add_damping_option",
    "add_input_options",
    "add_model_options",
    "add_report_options",
    "data_options",
    "make_embedding",
    "make_estimator",
    "required_rows",
]


class Parser(argparse.ArgumentParser):
    """argparse with one-line error messages (``sindy-impulse: error: ...``) and exit code 2."""

    def error(self, message):
        hint = f" (see '{self.prog} --help')"
        self.exit(2, f"sindy-impulse: error: {message}{hint}\n")


# ----------------------------------------------------------------------------------------------------
# strict option types (argparse reports their errors as "argument --dt: ...")
# ----------------------------------------------------------------------------------------------------
def _refused(text: str, err: NumberError, kind: str) -> argparse.ArgumentTypeError:
    if err.reason in ("not a number", "empty"):
        return argparse.ArgumentTypeError(f"invalid {kind} value: {text!r}")
    return argparse.ArgumentTypeError(str(err))


def real(text: str) -> float:
    """A number in plain decimal notation; ``nan``/``inf`` pass (the range check of the option decides)."""
    try:
        return parse_number(text, finite=False)
    except NumberError as err:
        raise _refused(text, err, "float") from None


def integer(text: str) -> int:
    """An integer in plain decimal notation."""
    try:
        return parse_int(text)
    except NumberError as err:
        raise _refused(text, err, "int") from None


def _positive(text: str, expected: str) -> int:
    try:
        value = parse_int(text)
    except NumberError as err:
        if err.reason in ("not a number", "empty", "not a whole number"):
            raise argparse.ArgumentTypeError(f"expected {expected}, got {text!r}") from None
        raise argparse.ArgumentTypeError(str(err)) from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected {expected}, got {text!r}")
    return value


def positive_int(text: str) -> int:
    return _positive(text, "a positive integer")


def auto_int(text: str):
    return "auto" if text == "auto" else _positive(text, "a positive integer or 'auto'")


# ----------------------------------------------------------------------------------------------------
# option groups
# ----------------------------------------------------------------------------------------------------
def add_input_options(
    p: argparse.ArgumentParser, columns: str = "state columns (default: all numeric columns but the time)"
) -> None:
    """``--columns`` (``columns``: what they are) and the time of the samples: ``--time NAME`` and/or
    ``--dt S`` or ``--fs HZ`` (a time column and a rate given together must agree)."""
    p.add_argument("--columns", metavar="NAMES", help=f"comma-separated {columns}")
    p.add_argument(
        "--time", metavar="NAME", help="the time column (default: a column named t or time, if there is one)"
    )
    step = p.add_mutually_exclusive_group()
    step.add_argument(
        "--dt", type=real, help="sampling step (time units per sample); with a time column, it must agree"
    )
    step.add_argument(
        "--fs", type=real, metavar="HZ", help="sampling frequency; with a time column, it must agree"
    )


def add_model_options(p: argparse.ArgumentParser) -> None:
    """The states and library of the model: ``--embed``, ``--tau``, ``--dimension``, ``--degree``."""
    p.add_argument(
        "--embed", action="store_true", help="delay-embed a single measured column (DelayEmbedding)"
    )
    p.add_argument("--tau", type=auto_int, default="auto", help="embedding delay in samples (default: auto)")
    p.add_argument("--dimension", type=auto_int, default="auto", help="embedding dimension (default: auto)")
    p.add_argument("--degree", type=positive_int, default=3, help="PolynomialLibrary degree (default: 3)")


def add_damping_option(p: argparse.ArgumentParser) -> None:
    """``--damping-unit {percent,fraction}``: the unit of every damping ratio the command shows or writes."""
    from .._utils.units import DAMPING_UNITS, DEFAULT_DAMPING_UNIT

    p.add_argument(
        "--damping-unit",
        choices=tuple(DAMPING_UNITS),
        default=DEFAULT_DAMPING_UNIT,
        help="unit of the damping ratios on the terminal and in the JSON, whose names say it "
        "(damping_ratio_percent; fraction: damping_ratio) (default: percent)",
    )


def add_report_options(
    p: argparse.ArgumentParser, figure: str = "the input against its reconstruction"
) -> None:
    """``--json OUT.json`` and ``--plot OUT.png`` (``figure``: what the figure shows)."""
    p.add_argument("--json", metavar="OUT.json", help="also write the results as JSON")
    p.add_argument(
        "--plot", metavar="OUT.png", help=f"also write a figure of {figure} (any format matplotlib writes)"
    )


# ----------------------------------------------------------------------------------------------------
# from options to arguments and objects
# ----------------------------------------------------------------------------------------------------
def split_names(text: str | None) -> list[str] | None:
    """``--columns a,b`` as a list of names (None when not given)."""
    if text is None:
        return None
    names = [n.strip() for n in text.split(",")]
    if not names or any(not n for n in names):
        raise CLIError(f"--columns must be a comma-separated list of column names, got {text!r}")
    if len(set(names)) != len(names):
        raise CLIError(f"--columns names a column twice: {text!r}")
    return names


def sampling_step(args: argparse.Namespace) -> float | None:
    """The sampling step from ``--dt`` or ``--fs`` (None: the time comes from a column)."""
    dt, fs = getattr(args, "dt", None), getattr(args, "fs", None)
    if dt is not None and not (math.isfinite(dt) and dt > 0):
        raise CLIError(f"--dt must be a positive number of time units per sample, got {dt!r}")
    if fs is None:
        return dt
    if not (math.isfinite(fs) and fs > 0 and math.isfinite(1.0 / fs)):
        raise CLIError(f"--fs must be a positive sampling frequency (samples per time unit), got {fs!r}")
    return 1.0 / fs


def data_options(args: argparse.Namespace) -> dict:
    """The keyword arguments of :func:`~sindy_impulse.cli.files.read_csv` the input options ask for."""
    return {"columns": split_names(args.columns), "time": args.time, "dt": sampling_step(args)}


def make_estimator(degree: int):
    """The model every command fits: ImpulseSINDy with a polynomial library of ``degree``."""
    import pysindy as ps

    from ..identification.estimator import ImpulseSINDy

    return ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=degree))


def make_embedding(args: argparse.Namespace):
    """The DelayEmbedding of ``--embed --tau --dimension`` (False without ``--embed``)."""
    from ..embedding import DelayEmbedding

    return DelayEmbedding(tau=args.tau, dimension=args.dimension) if args.embed else False


def required_rows(estimator, n_states: int) -> int:
    """Fewest samples a reconstruction of ``n_states`` states needs: the library's own rule
    (``SINDyFeatures.min_samples_``: its terms plus the samples the differentiation trims)."""
    import numpy as np

    from ..features import SINDyFeatures

    layout = SINDyFeatures(estimator=estimator, embed=False).fit(np.zeros((1, 1, n_states)))
    return int(layout.min_samples_)

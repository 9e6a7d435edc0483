"""Command line: ``sindy-impulse demo | fit | modes | features | track``.

``demo`` runs the paper's oscillator case end to end. ``fit`` reconstructs the equations of one measured
ring-down stored as a CSV file and reports Gamma, the nonlinearity test and the modal parameters. ``modes``
finds the modes of raw hammer-test records (a modal table per record, one equation per mode). ``features``
turns many CSV files into one table of SINDy coefficient features (paper section 3.4). ``track`` tests many
records of one structure against reference ones: which mode, quantity and term of its equation changed.

One module per command (:mod:`.demo`, :mod:`.fit`, :mod:`.features`: each ``add_parser(sub)`` and
``run(args)``; a new command is one more module in :data:`COMMANDS`). The options they share are in
:mod:`._options`, numbers are parsed strictly by :mod:`._numbers`, and every file they read or write goes
through :mod:`._io` (regular files only, atomic outputs that never overwrite an input).

CSV files are read with the standard library (no pandas): a header row of column names, then one row of
numbers per sample. Every mistake a user can make with the files or the options ends in a one-line
``sindy-impulse: error: ...`` on stderr and exit code 2 (``--traceback`` shows the full traceback instead).
"""

from __future__ import annotations

import argparse
import sys

from . import demo_command as demo
from . import features_command as features
from . import fit_command as fit
from . import modes_command as modes
from . import track_command as track
from ._options import Parser
from .files import CLIError, Table, read_csv

__all__ = ["CLIError", "Table", "build_parser", "main", "read_csv"]

#: The commands, in the order of ``--help``.
COMMANDS = (demo, fit, modes, features, track)


def build_parser() -> argparse.ArgumentParser:
    """The ``sindy-impulse`` parser with one sub-command per module of :data:`COMMANDS`."""
    parser = Parser(
        prog="sindy-impulse",
        description="Recover differential equations from impulse-response (ring-down) measurements.",
        epilog="CSV files: a header row of column names, then one row of numbers per sample.",
    )
    parser.add_argument("--traceback", action="store_true", help="show the full traceback on errors")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    for command in COMMANDS:
        command.add_parser(sub)
    return parser


def main(argv=None) -> int:
    """Run the command line; returns the exit status (0 success, 1 a batch with skipped files, 2 error)."""
    parser = build_parser()
    args = parser.parse_args(argv)  # a usage error exits (code 2) after its one-line message
    try:
        return args.func(args)
    except KeyboardInterrupt:
        if args.traceback:
            raise
        print("sindy-impulse: interrupted", file=sys.stderr)
        return 130
    except Exception as err:  # noqa: BLE001 - the command line reports, it does not crash
        if args.traceback:
            raise
        message = str(err) if isinstance(err, (CLIError, ValueError)) else f"{type(err).__name__}: {err}"
        message = " ".join(message.split())  # one line
        print(f"sindy-impulse: error: {message}", file=sys.stderr)
        return 2

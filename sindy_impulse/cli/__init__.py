"""Command line: ``sindy-impulse demo | fit | modes | features | track``.

``demo`` runs the paper's oscillator case end to end. ``fit`` reconstructs the equations of one measured
ring-down stored as a CSV file and reports Gamma, the nonlinearity test and the modal parameters. ``modes``
finds the modes of raw hammer-test records (a modal table per record, one equation per mode). ``features``
turns many CSV files into one table of SINDy coefficient features (paper section 3.4). ``track`` tests many
records of one structure against reference ones: which mode, quantity and term of its equation changed.

One module per command (:mod:`.demo_command`, :mod:`.fit_command`, :mod:`.modes_command`,
:mod:`.features_command`: each ``add_parser(sub)`` and
``run(args)``; a new command is one more module in :data:`COMMANDS`). The options they share are in
:mod:`._options`, numbers are parsed strictly by :mod:`._numbers`, and every file they read or write goes
through :mod:`.files` (regular files only, atomic outputs that never overwrite an input).

CSV files are read with the standard library (no pandas): a header row of column names, then one row of
numbers per sample. Every mistake a user can make with the files or the options ends in a one-line
``sindy-impulse: error: ...`` on stderr and exit code 2 (``--traceback`` shows the full traceback instead).
"""

from __future__ import annotations

import argparse
import sys

from .._version import __version__
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
        epilog="CSV files: a header row of column names, then one row of numbers per sample; a column "
        "named t or time is the time (--fs or --dt, if given, must agree with it). Exit status: 0 done, 1 a "
        "batch in which some files were skipped, 2 an error.",
    )
    parser.add_argument("--version", action="version", version=f"sindy-impulse {__version__}")
    parser.add_argument("--traceback", action="store_true", help="show the full traceback on errors")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    parser.commands = {}
    for command in COMMANDS:
        p = command.add_parser(sub)
        # also after the command's name; SUPPRESS: not given there, the value before it stands
        p.add_argument("--traceback", action="store_true", default=argparse.SUPPRESS,
                       help="show the full traceback on errors")
        parser.commands[p.prog.split()[-1]] = p
    return parser


def main(argv=None) -> int:
    """Run the command line; returns the exit status (0 success, 1 a batch with skipped files, 2 error)."""
    parser = build_parser()
    args, unknown = parser.parse_known_args(argv)  # a usage error exits (code 2) after its one-line message
    if unknown:  # said by the command's parser, so that its help is the one pointed at
        parser.commands.get(args.command, parser).error(f"unrecognized arguments: {' '.join(unknown)}")
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

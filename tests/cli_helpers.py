"""The command line run in-process as the tests run it: the exit code and what it printed."""

import warnings

from sindy_impulse.cli import main


def run_cli(argv, capsys):
    """``(exit code, stdout, stderr)`` of ``sindy-impulse ARGV`` (the library's warnings silenced: the
    command line reports them itself)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            code = main(argv)
        except SystemExit as stop:
            code = stop.code
    out = capsys.readouterr()
    return code, out.out, out.err

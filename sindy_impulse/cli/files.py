"""Every file the command line touches: CSV input, the listing of a batch's inputs, safe outputs.

Inputs are opened only when they are regular files (a FIFO, a directory or a device is refused before it
is opened, so nothing hangs); their numbers are parsed strictly (:mod:`._numbers`, with the file, column
and line of a bad cell). Outputs are written atomically (rendered in memory, written to a temporary file
next to the target, flushed, fsynced, then renamed over it), so an interrupted write leaves the old file
intact and never a partial one; an output that is one of the inputs is refused before any work.
"""

from __future__ import annotations

import contextlib
import csv
import glob
import io
import os
import stat
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

from ._numbers import NumberError, parse_number

__all__ = [
    "CLIError",
    "Table",
    "atomic_write",
    "check_outputs",
    "list_inputs",
    "open_input",
    "outputs_in_folder",
    "read_csv",
    "read_measurement",
    "write_figure",
    "write_json",
]

#: Names recognised as the time column when neither ``--time`` nor a sampling step is given.
TIME_NAMES = ("t", "time")
#: Names recognised as the hammer's force column (by the ``modes`` command) when ``--force`` is not given.
FORCE_NAMES = ("force", "hammer", "excitation")


class CLIError(Exception):
    """A user error: reported as one line, without a traceback."""


# ----------------------------------------------------------------------------------------------------
# inputs
# ----------------------------------------------------------------------------------------------------
_KINDS = (
    (stat.S_ISDIR, "a directory"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


def _kind(mode: int) -> str | None:
    """What a non-regular file is (None for a regular file)."""
    if stat.S_ISREG(mode):
        return None
    return next((name for test, name in _KINDS if test(mode)), "not a regular file")


def open_input(path: str):
    """Open a regular file for reading text, refusing anything else before it is opened."""
    try:
        before = os.stat(path)
    except FileNotFoundError:
        raise CLIError(f"{path}: no such file") from None
    except OSError as err:
        raise CLIError(f"{path}: cannot read ({err.strerror})") from None
    kind = _kind(before.st_mode)
    if kind == "a directory":
        raise CLIError(f"{path} is a directory, expected a CSV file")
    if kind is not None:
        raise CLIError(f"{path} is {kind}, expected a regular CSV file")
    try:  # O_NONBLOCK: should the path have become a FIFO since the stat, opening it does not block
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0))
    except OSError as err:
        raise CLIError(f"{path}: cannot read ({err.strerror})") from None
    now = os.fstat(fd)
    if _kind(now.st_mode) is not None or (now.st_dev, now.st_ino) != (before.st_dev, before.st_ino):
        os.close(fd)
        raise CLIError(f"{path} changed while being opened; expected a regular CSV file")
    return os.fdopen(fd, "r", newline="", encoding="utf-8-sig")


def _same_file(a: str, b: str) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:  # one of them does not exist (yet)
        return os.path.realpath(a) == os.path.realpath(b)


def list_inputs(pattern: str, exclude: Iterable[str] = ()) -> list[str]:
    """The files of a directory (its ``*.csv``) or of a glob, sorted, without the ``exclude`` files.

    Directories matching a glob are left out; other non-regular files are kept (reading them reports
    them). ``exclude`` is for the command's own outputs: a batch never reads the file it writes.
    """
    exclude = [e for e in exclude if e]
    if os.path.isdir(pattern):
        found = glob.glob(os.path.join(glob.escape(pattern), "*.csv"))
        files = sorted(f for f in found if not any(_same_file(f, e) for e in exclude))
        if not files:
            raise CLIError(f"no CSV files (*.csv) in directory {pattern}")
        return files
    found = (f for f in glob.glob(pattern) if not os.path.isdir(f))
    files = sorted(f for f in found if not any(_same_file(f, e) for e in exclude))
    if not files and not glob.has_magic(pattern):
        if os.path.lexists(pattern):
            raise CLIError(f"{pattern} is the output file itself, not an input")
        raise CLIError(f"{pattern}: no such file or directory")
    if not files:
        raise CLIError(f"no files match {pattern!r}")
    return files


# ----------------------------------------------------------------------------------------------------
# CSV files
# ----------------------------------------------------------------------------------------------------
@dataclass
class Table:
    """The selected columns of a CSV file."""

    path: str
    names: list  # state columns
    data: object  # ndarray (n_samples, n_columns)
    t: object  # float (time step) or ndarray (n_samples,)
    time_column: str | None
    extra: dict = field(default_factory=dict)  # further requested columns: name -> ndarray (n_samples,)
    force_column: str | None = None  # the column found to be the force by its name (``find_force``)


def _read_rows(path: str):
    """The header (stripped names) and the non-blank rows (cells as written) with their line numbers."""
    try:
        with open_input(path) as fh:
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
            rows, lines = [], []
            for row in reader:
                if any(cell.strip() for cell in row):
                    rows.append(row)
                    lines.append(reader.line_num)
    except UnicodeDecodeError as err:
        raise CLIError(f"{path} is not a text (UTF-8) CSV file ({err.reason})") from None
    except csv.Error as err:
        raise CLIError(f"{path}: malformed CSV ({err})") from None
    except OSError as err:
        raise CLIError(f"{path}: cannot read ({err.strerror})") from None
    return [h.strip() for h in header], rows, lines


def _column_index(path: str, header: list, rows: list) -> dict:
    """Column name -> index, without the unnamed empty column a trailing delimiter makes."""
    named = [i for i, h in enumerate(header) if h or any(i < len(r) and r[i].strip() for r in rows)]
    for i in named:
        if not header[i]:
            raise CLIError(f"{path}: column {i + 1} has no name in the header row")
    names = [header[i] for i in named]
    dupes = sorted({n for n in names if names.count(n) > 1})
    if dupes:
        raise CLIError(f"{path}: duplicate column name(s) in the header: {', '.join(dupes)}")
    return {header[i]: i for i in named}


_CELL_PROBLEM = {"not a number": "a non-numeric cell", "not finite": "a non-finite value"}


def _column(path: str, name: str, i: int, rows: list, lines: list):
    """The numbers of column ``i``, or CLIError naming the file, the column and the line of a bad cell."""
    import numpy as np

    values = np.empty(len(rows))
    for k, row in enumerate(rows):
        cell = row[i] if i < len(row) else ""
        try:
            values[k] = parse_number(cell)
        except NumberError as err:
            if err.reason == "empty":
                raise CLIError(f"{path}: column {name!r} has an empty cell at line {lines[k]}") from None
            what = _CELL_PROBLEM.get(err.reason, "an invalid number")
            why = "" if err.reason in _CELL_PROBLEM else f" ({err.reason})"
            raise CLIError(f"{path}: column {name!r} has {what} {cell!r} at line {lines[k]}{why}") from None
    return values


def _numeric(i: int, rows: list) -> bool:
    """Whether some cell of column ``i`` looks like a number to Python (lenient on purpose: a column of
    numbers with one badly written cell is a state column, and reading it reports that cell)."""
    for row in rows:
        try:
            float(row[i] if i < len(row) else "")
            return True
        except ValueError:
            continue
    return False


def _select(path, index, rows, columns, time, dt, extra):
    """The state columns and the time column to read.

    A column named ``t`` or ``time`` is the time whether or not a sampling step is given (the caller
    checks that they agree), unless ``columns`` names it as a state; ``time`` names another column."""
    available = ", ".join(index)
    if not rows:
        raise CLIError(f"{path} has a header but no data rows")
    for name in ([time] if time else []) + list(columns or []) + list(extra):
        if name not in index:
            raise CLIError(f"{path}: no column {name!r} (columns: {available})")
    if time is None:
        chosen = set(columns or ()) | set(extra)
        time = next((n for n in index if n.lower() in TIME_NAMES and n not in chosen), None)
        if time is None and dt is None:
            raise CLIError(
                f"{path}: no time information; give the sampling step with --dt or --fs, or the time "
                "column with --time"
            )
    if columns is None:
        columns = [n for n in index if n != time and n not in extra and _numeric(index[n], rows)]
        if not columns:
            raise CLIError(f"{path}: no numeric column besides the time (columns: {available})")
    elif time in columns:
        raise CLIError(f"{path}: column {time!r} is the time column and cannot also be a state")
    return list(columns), time


def _check_step(path: str, time: str, t, dt: float) -> None:
    """A sampling step given as an option must be the time column's: evenly spaced, and off by less than
    half a sample over the record."""
    import numpy as np

    n = t.size
    step = (t[-1] - t[0]) / (n - 1)
    uneven = float(np.max(np.abs(t - (t[0] + step * np.arange(n)))))
    if uneven > 0.01 * step:
        raise CLIError(
            f"{path}: the time column {time!r} is not evenly spaced, so no sampling rate (--fs, --dt) "
            "describes it; leave the option out to use the column's times"
        )
    if abs(step - dt) * (n - 1) > 0.5 * dt:
        raise CLIError(
            f"{path}: the time column {time!r} has a step of {step:.6g} ({1 / step:.6g} samples per time "
            f"unit) but the option gives {dt:.6g} ({1 / dt:.6g} per time unit); leave --fs/--dt out to use "
            f"the column, or list {time!r} in --columns if it is a measured channel, not the time"
        )


def read_csv(path: str, columns=None, time=None, dt=None, extra=(), find_force: bool = False) -> Table:
    """Read the state columns (and the time column) of a CSV file with a header row.

    Parameters
    ----------
    path : str
        The file (a regular file; a FIFO, directory or device is refused without being opened).
    columns : list of str, optional
        State columns, by name. Default: every numeric column except the time and ``extra`` columns.
    time : str, optional
        Name of the time column. Default: a column named ``t`` or ``time`` (unless ``columns`` names it
        as a state).
    dt : float, optional
        Sampling step: needed when the file has no time column; with one, it must agree with it (evenly
        spaced, off by less than half a sample over the record) and the column's times are used.
    extra : sequence of str
        Further columns to read (e.g. a measured force), returned in ``Table.extra``.
    find_force : bool
        Without ``columns`` and ``extra``: a column named as :data:`FORCE_NAMES` lists (any case) is the
        force, returned as ``Table.extra["force"]``, not a sensor.

    Returns
    -------
    Table

    Raises
    ------
    CLIError
        Missing, empty or non-regular file, unknown column, a cell that is not a finite number in plain
        decimal notation (with its file, column and line), no time information, a sampling step that
        disagrees with the time column.

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = os.path.join(folder, "hit.csv")
    ...     with open(path, "w") as fh:
    ...         _ = fh.write("t,ch0,ch1\\n0,1,2\\n0.5,3,4\\n1.0,5,6\\n")
    ...     table = read_csv(path, dt=0.5)  # the time column is the time, and agrees with dt
    ...     try:
    ...         read_csv(path, dt=0.1)
    ...     except CLIError as err:
    ...         problem = "step of 0.5" in str(err)
    >>> table.names, table.time_column, problem
    (['ch0', 'ch1'], 't', True)
    """
    import numpy as np

    from .._utils.validation import check_time

    header, rows, lines = _read_rows(path)
    index = _column_index(path, header, rows)
    named = next((n for n in index if n.lower() in FORCE_NAMES), None)
    found = find_force and not extra and not columns and named is not None
    extra = (named,) if found else tuple(extra)
    columns, time = _select(path, index, rows, columns, time, dt, extra)
    data = np.column_stack([_column(path, n, index[n], rows, lines) for n in columns])
    extras = {("force" if found else n): _column(path, n, index[n], rows, lines) for n in extra}
    force = named if found else None
    if time is None:
        return Table(path, columns, data, dt, None, extras, force)
    t = _column(path, time, index[time], rows, lines)
    steps = np.diff(t)
    if np.any(steps <= 0):
        k = int(np.argmax(steps <= 0)) + 1
        raise CLIError(
            f"{path}: the time column {time!r} is not strictly increasing at line {lines[k]} "
            f"({rows[k][index[time]]} after {rows[k - 1][index[time]]})"
        )
    if dt is not None and t.size > 1:
        _check_step(path, time, t, dt)
    return Table(path, columns, data, check_time(t, len(rows), f"time column {time!r}"), time, extras, force)


# ----------------------------------------------------------------------------------------------------
# outputs
# ----------------------------------------------------------------------------------------------------
def check_outputs(
    outputs: dict, inputs: Iterable[str] = (), figures: Iterable[str] = (), overwrite: bool = True
) -> None:
    """Refuse, before any work, outputs that cannot be written or would overwrite an input.

    ``outputs`` maps an option (``"--json"``) to its path (empty or None: not written); the options
    in ``figures`` are figures, whose extension must be a format matplotlib writes. With
    ``overwrite=False`` an existing file is refused too (the ``modes`` command without ``--overwrite``).
    """
    inputs = list(inputs)
    seen = {}
    for flag, path in outputs.items():
        if not path:
            continue
        target = os.path.realpath(path)
        folder = os.path.dirname(target)
        if not os.path.isdir(folder):
            raise CLIError(f"cannot write {path}: no such directory {os.path.dirname(path) or '.'}")
        if os.path.exists(target):
            kind = _kind(os.stat(target).st_mode)
            if kind is not None:
                raise CLIError(f"cannot write {path}: it is {kind}, not a regular file")
            if not os.access(target, os.W_OK):
                raise CLIError(f"cannot write {path}: the file is read-only")
            if not overwrite:
                raise CLIError(f"{flag} {path} exists; add --overwrite to replace it")
        elif not os.access(folder, os.W_OK | os.X_OK):
            raise CLIError(f"cannot write {path}: permission denied in {os.path.dirname(path) or '.'}")
        for source in inputs:
            if os.path.exists(target) and _same_file(target, source):
                raise CLIError(f"{flag} {path} is the input file {source}; refusing to overwrite an input")
        if target in seen:
            raise CLIError(f"{seen[target]} and {flag} name the same file {path}")
        seen[target] = flag
        if flag in figures:
            _check_figure_format(flag, path)


def outputs_in_folder(inputs: list[str], folder: str, suffixes: dict) -> list[dict]:
    """Per input, ``{kind: folder/<stem><suffix>}`` (``stem``: the input's file name without its
    extension), for ``suffixes`` ``{kind: suffix}``; the folder is created when missing.

    Two inputs with the same stem (``a/hit.csv`` and ``b/hit.csv``, or ``hit.csv`` and ``hit.uff``)
    would write the same outputs: refused, naming both (as is a file given twice).

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as out:
    ...     plan = outputs_in_folder(["data/hit1.csv", "hit2.uff"], out, {"json": ".json"})
    ...     [os.path.relpath(p["json"], out) for p in plan]
    ['hit1.json', 'hit2.json']
    """
    if os.path.exists(folder) and not os.path.isdir(folder):
        raise CLIError(f"--out-dir {folder} is a file, not a directory")
    stems = {}
    for path in inputs:
        stem = os.path.splitext(os.path.basename(path))[0]
        if stem in stems:
            if _same_file(stems[stem], path):
                raise CLIError(f"{path} is given twice")
            raise CLIError(
                f"{stems[stem]} and {path} would both write {stem}.* in --out-dir {folder}; rename one"
            )
        stems[stem] = path
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as err:
        raise CLIError(f"cannot create --out-dir {folder}: {err.strerror}") from None
    return [
        {kind: os.path.join(folder, os.path.splitext(os.path.basename(path))[0] + suffix)
         for kind, suffix in suffixes.items()}
        for path in inputs
    ]


def _check_figure_format(flag: str, path: str) -> None:
    from matplotlib.backend_bases import FigureCanvasBase

    ext, supported = _extension(path), FigureCanvasBase.get_supported_filetypes()
    if ext not in supported:
        formats = ", ".join(sorted(supported))
        raise CLIError(f"{flag} {path}: cannot write .{ext} figures (formats: {formats})")


def atomic_write(path: str, render: Callable, binary: bool = False) -> None:
    """Write ``path`` all at once or not at all.

    ``render(fh)`` writes the content to an in-memory file (text, ``newline=""``, or bytes); only then is
    a temporary file created next to the target (a symbolic link's target), written, flushed, fsynced
    and renamed over the target (``os.replace``). An error or an interruption (even SIGKILL) while
    rendering leaves no trace; one while writing removes the temporary file; the old file stays intact
    until the rename. A new file gets the usual permissions (umask), an existing one keeps its own.
    """
    buffer = io.BytesIO() if binary else io.StringIO(newline="")
    render(buffer)
    content = buffer.getvalue() if binary else buffer.getvalue().encode("utf-8")
    target = os.path.realpath(path)
    folder, base = os.path.split(target)
    try:
        mode = stat.S_IMODE(os.stat(target).st_mode) if os.path.exists(target) else None
        temp, fd = _create_temp(folder, base)
    except OSError as err:
        raise CLIError(f"cannot write {path}: {err.strerror}") from None
    try:
        with os.fdopen(fd, "wb") as fh:
            if mode is not None and hasattr(os, "fchmod"):
                os.fchmod(fh.fileno(), mode)
            fh.write(content)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(temp, target)
    except BaseException as err:
        with contextlib.suppress(OSError):
            os.unlink(temp)
        if isinstance(err, OSError):
            raise CLIError(f"cannot write {path}: {err.strerror or err}") from None
        raise
    _sync_directory(folder)


def _extension(path: str) -> str:
    """The figure format of a file name (PNG without an extension)."""
    return os.path.splitext(path)[1].lstrip(".").lower() or "png"


def _create_temp(folder: str, base: str):
    """A new hidden file ``.<base>.<random>.tmp`` in ``folder`` (created exclusively, umask applies)."""
    from ..io._common import temporary_beside

    return temporary_beside(folder, base)


def _sync_directory(folder: str) -> None:
    """Make the rename durable (best effort: not every system can fsync a directory)."""
    with contextlib.suppress(OSError):
        fd = os.open(folder, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


def write_json(path: str, obj) -> None:
    """``obj`` as indented JSON, atomically."""
    import json

    atomic_write(path, lambda fh: json.dump(obj, fh, indent=2))


def write_figure(path: str, draw: Callable) -> None:
    """The matplotlib figure ``draw()`` returns, atomically, in the format of the file's extension (PNG
    without one), drawn off screen (Agg) and closed afterwards."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ext = _extension(path)
    figure = draw()
    try:
        atomic_write(
            path, lambda fh: figure.savefig(fh, format=ext, dpi=120, bbox_inches="tight"), binary=True
        )
    finally:
        plt.close(figure)


def read_measurement(path: str, columns=None, time=None, dt=None, extra=(),
                     find_force: bool = False) -> Table:
    """A CSV file (:func:`read_csv`) or a modal-testing file read by :func:`sindy_impulse.io.read_record`
    (UFF 58, LabVIEW ``.lvm``, TDMS, ``.mat``, ``.npz``), as the same :class:`Table`.

    From a modal-testing file the sampling rate and the channel names come from the file; ``columns``
    selects response channels by name (default: every channel but the force), ``extra`` names further
    channels (e.g. ``force``; the file's own force channel is taken when it marks one and ``extra`` is
    empty), ``dt`` must agree with the file's rate and ``time`` does not apply; ``find_force``: a CSV
    column named as a force is the force (:func:`read_csv`).
    """
    from ..io import FORMATS, read_record

    suffix = os.path.splitext(path)[1].lower()
    if suffix not in FORMATS or suffix == ".csv":
        return read_csv(path, columns=columns, time=time, dt=dt, extra=extra, find_force=find_force)
    if time is not None:
        raise CLIError(f"--time names a CSV column; {path} holds its sampling rate itself")
    try:
        record = read_record(path, fs=None if dt is None else 1.0 / dt)
    except ImportError as err:
        raise CLIError(str(err)) from None
    except (OSError, ValueError) as err:  # the Python argument fs= is the option --fs here
        message = str(err).replace("pass fs=", "give --fs").replace(" fs=", " --fs ")
        raise CLIError(f"cannot read {path}: {message}") from None
    names = list(record.channel_names)
    for name in [*(columns or []), *extra]:
        if name not in names:
            raise CLIError(f"{path} has no channel {name!r}; its channels: {', '.join(names)}")
    found = {name: record.data[:, names.index(name)] for name in extra}
    if not extra and record.force is not None:
        found["force"] = record.force
    default = [n for k, n in enumerate(names) if k != record.force_channel and n not in extra]
    chosen = list(columns) if columns else default
    if not chosen:
        raise CLIError(f"{path} holds no response channel besides the force")
    data = record.data[:, [names.index(n) for n in chosen]]
    return Table(str(path), chosen, data, record.t, None, found)

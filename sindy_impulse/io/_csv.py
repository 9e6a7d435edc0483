"""CSV files with one header row: ``time [s], acc1 [m/s^2], hammer [N], ...``.

Read from the file: channel names and units from the header (``name [unit]`` or ``name (unit)``), the
sampling rate and ``t0`` from a ``time`` / ``t`` column (seconds, or ``ms`` / ``us`` when its unit says
so; it must be evenly spaced), else from the ``fs=`` argument (then required); the force channel is the
one named force / hammer / excitation / F, or else in force units (N, lbf). CSV holds no nodes or
directions. Separators ``,``, ``;`` or tab; lines starting with ``#`` are skipped; the decimal point is
``.``. The writer puts a time column first and 17 significant digits, so a record reads back exactly.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np

from ._common import check_fs_argument, fs_from_time, join_unit, split_unit
from ._record import Record, assemble

__all__ = ["read_csv", "write_csv"]

_TIME_NAMES = ("time", "t")
_TIME_SCALE = {"": 1.0, "s": 1.0, "sec": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6}


def read_csv(path: str | Path, *, fs: float | None = None, force_channel: int | str | None = None) -> Record:
    """Read a CSV file with a header row as a Record.

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = os.path.join(folder, "tap.csv")
    ...     with open(path, "w") as fh:
    ...         _ = fh.write("t [s],acc [m/s^2],hammer [N]\\n0,0.5,0\\n0.001,0.25,1\\n0.002,0.125,0\\n")
    ...     rec = read_csv(path)
    >>> rec.fs, rec.channel_names, rec.units, rec.force_channel
    (1000.0, ('acc', 'hammer'), ('m/s^2', 'N'), 1)
    """
    what = str(path)
    with open(path, encoding="utf-8-sig", newline="") as fh:
        lines = [line for line in fh if line.strip() and not line.lstrip().startswith("#")]
    if len(lines) < 2:
        raise ValueError(f"{what}: a CSV record needs a header row and at least one row of numbers")
    delimiter = max((",", ";", "\t"), key=lines[0].count)
    header = next(csv.reader([lines[0]], delimiter=delimiter))
    try:
        table = np.loadtxt(io.StringIO("".join(lines[1:])), delimiter=delimiter, ndmin=2)
    except ValueError as err:
        raise ValueError(f"{what}: rows of unequal length or non-numeric values ({err})") from err
    if table.shape[1] != len(header):
        raise ValueError(f"{what}: {len(header)} header names for {table.shape[1]} columns")
    parsed = [split_unit(h) for h in header]
    time_cols = [j for j, (name, _) in enumerate(parsed) if name.lower() in _TIME_NAMES]
    fs_file, t0 = None, 0.0
    if time_cols:
        j = time_cols[0]
        unit = parsed[j][1].lower()
        if unit not in _TIME_SCALE:
            raise ValueError(f"{what}: time column unit {parsed[j][1]!r} is not s, ms or us")
        fs_file, t0 = fs_from_time(table[:, j] * _TIME_SCALE[unit], what)
    keep = [j for j in range(len(header)) if j not in time_cols[:1]]
    return assemble(
        [table[:, j] for j in keep],
        [parsed[j][0] for j in keep],
        fs=check_fs_argument(fs_file, fs, what),
        t0=t0,
        units=[parsed[j][1] for j in keep],
        force_argument=force_channel,
        source=what,
        meta={"format": "csv", "delimiter": delimiter},
    )


def write_csv(record: Record, tmp_path: str) -> None:
    """Write the record as CSV: a ``time [s]`` column, then one ``name [unit]`` column per channel."""
    header = ["time [s]"]
    for name, unit in zip(record.channel_names, record.units):
        if split_unit(name)[0].lower() in _TIME_NAMES:
            raise ValueError(f"a CSV channel cannot be called {name!r}: the reader takes it as the time")
        if any(c in name + unit for c in "\r\n"):
            raise ValueError(f"CSV names and units cannot hold line breaks: {name!r} [{unit!r}]")
        text = join_unit(name, unit)
        header.append(text if unit or split_unit(text) == (name, "") else f"{name} []")
    with open(tmp_path, "w", encoding="utf-8", newline="") as fh:
        csv.writer(fh, lineterminator="\n").writerow(header)
        np.savetxt(fh, np.column_stack([record.t, record.data]), fmt="%.17g", delimiter=",")

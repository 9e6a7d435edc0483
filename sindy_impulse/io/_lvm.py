"""LabVIEW measurement files (``.lvm``, text): read with lvm-read, written here in the same layout.

Read from the file: channel names (the ``X_Value`` header row), units (``Y_Unit_Label``), sampling rate
(``Delta_X``, else the X column), ``t0`` (``X0``). LVM has no node or direction fields: this package's
writer puts them, with the exact ``fs`` and the force channel, as JSON in the file header's
``Description`` field (``sindy-impulse {...}``), which the reader takes when present. Otherwise the
force channel is the one named force / hammer / excitation / F, or else in force units (N, lbf).

Only the first segment of a multi-segment file is read (with a DataWarning). Values are written with 17
significant digits, so a record reads back exactly.
"""

from __future__ import annotations

import math
import warnings
from datetime import datetime
from pathlib import Path

import numpy as np

from ..exceptions import DataWarning
from ._common import check_fs_argument, decode_tag, encode_tag, fs_from_time, json_meta, require, snap_fs
from ._record import Record, assemble

__all__ = ["read_lvm", "write_lvm"]

_SKIP = ("X_Value", "Comment")


def read_lvm(path: str | Path, *, fs: float | None = None, force_channel: int | str | None = None) -> Record:
    """Read the first segment of a LabVIEW measurement file as a Record.

    Examples
    --------
    >>> rec = read_lvm("hammer_test.lvm")  # doctest: +SKIP
    """
    lvm_read = require("lvm_read", "reading LabVIEW .lvm files")
    what = str(path)
    try:
        lvm = lvm_read.read(str(path), read_from_pickle=False, dump_file=False)
    except (ValueError, SyntaxError, KeyError, IndexError) as err:
        raise ValueError(f"{what}: not a readable LabVIEW measurement file ({err})") from err
    if lvm.get("Segments", 0) > 1:
        warnings.warn(f"{what}: {lvm['Segments']} segments, reading the first", DataWarning, stacklevel=3)
    seg = lvm[0]
    names = list(seg.get("Channel names", []))
    block = np.atleast_2d(np.asarray(seg["data"], dtype=float))
    keep = [j for j, name in enumerate(names) if name not in _SKIP]
    n = len(keep)

    def per_channel(key: str, default):
        values = list(seg.get(key, []))
        return [values[k] if k < len(values) and values[k] not in ("", None) else default for k in range(n)]

    samples = [int(s) if _finite(s) else block.shape[0] for s in per_channel("Samples", math.nan)]
    columns = [block[: samples[k], j] for k, j in enumerate(keep)]
    tag = decode_tag(lvm.get("Description")) or {}
    fs_file, t0 = _timing(seg, block, names, n, what)
    if tag.get("fs") is not None and fs_file and abs(float(tag["fs"]) - fs_file) <= 1e-6 * fs_file:
        fs_file, t0 = float(tag["fs"]), float(tag.get("t0", t0))
    force = tag.get("force_channel", -3)
    nodes, directions = tag.get("nodes", ()), tag.get("directions", ())
    return assemble(
        columns,
        [names[j] for j in keep],
        fs=check_fs_argument(fs_file, fs, what),
        t0=t0,
        units=[str(u) for u in per_channel("Y_Unit_Label", "")],
        nodes=nodes if len(nodes) == n else (),
        directions=directions if len(directions) == n else (),
        force_from_file=None if force == -3 else (-2 if force is None else int(force)),
        force_argument=force_channel,
        source=what,
        meta={**tag.get("meta", {}), "format": "lvm", "header": _header(lvm)},
    )


def _rounded_spacing(fs: float, delta: float, x: np.ndarray, what: str) -> float:
    """The X column's sampling rate where ``Delta_X`` is that column's spacing rounded to fewer digits than
    the column resolves over the record (LabVIEW writes 0.000605 s for 31 / 51200 s: 1/Delta_X is then
    0.08 % off); else ``fs``."""
    try:
        fs_x, _ = fs_from_time(x, what)
    except ValueError:
        return fs
    digits = next((d for d in range(1, 16) if float(f"{1.0 / fs_x:.{d}g}") == delta), None)
    if digits is None:
        return fs
    span = float(x[-1] - x[0])
    off = float(np.max(np.abs(x - (x[0] + np.arange(x.size) * span / (x.size - 1)))))
    return fs_x if max(off, 1e-15 * span) / span < 0.5 * 10.0 ** (1 - digits) / 10 else fs


def _finite(value) -> bool:
    try:
        return math.isfinite(float(value))
    except (TypeError, ValueError):
        return False


def _timing(seg: dict, block: np.ndarray, names: list, n: int, what: str) -> tuple[float | None, float]:
    deltas = [float(d) for d in seg.get("Delta_X", [])[:n] if _finite(d)]
    x0 = [float(x) for x in seg.get("X0", [])[:n] if _finite(x)]
    t0 = x0[0] if x0 else 0.0
    if deltas:
        if max(deltas) - min(deltas) > 1e-9 * max(deltas):
            raise ValueError(f"{what}: unequal sampling across channels (Delta_X {deltas})")
        if deltas[0] <= 0:
            raise ValueError(f"{what}: Delta_X {deltas[0]!r} is not positive")
        fs = snap_fs(1.0 / deltas[0], 1e-6)
        if "X_Value" in names:
            fs = _rounded_spacing(fs, deltas[0], block[:, names.index("X_Value")], what)
        return fs, t0
    if "X_Value" in names:
        return fs_from_time(block[:, names.index("X_Value")], what)
    return None, t0


def _header(lvm: dict) -> dict:
    return {k: v for k, v in lvm.items() if isinstance(k, str) and isinstance(v, str) and k != "Description"}


def _text(value: str, what: str) -> str:
    if any(c in value for c in "\t\r\n"):
        raise ValueError(f"LVM {what} cannot hold tabs or line breaks: {value!r}")
    return value


def write_lvm(record: Record, tmp_path: str) -> None:
    """Write the record as a one-segment LabVIEW measurement file (tab separated, one X column)."""
    n = record.n_channels
    now = datetime.now()
    date, clock = now.strftime("%Y/%m/%d"), now.strftime("%H:%M:%S.%f")
    tag = encode_tag(
        {
            "fs": record.fs,
            "t0": record.t0,
            "nodes": list(record.nodes),
            "directions": list(record.directions),
            "force_channel": record.force_channel,
        }
    )
    tag = tag[:-1] + ',"meta":' + json_meta(record.meta) + "}"

    def row(key: str, values) -> str:
        return key + "\t" + "\t".join(str(v) for v in values)

    header = [
        "LabVIEW Measurement\t",
        "Writer_Version\t2",
        "Reader_Version\t2",
        "Separator\tTab",
        "Decimal_Separator\t.",
        "Multi_Headings\tNo",
        "X_Columns\tOne",
        "Time_Pref\tRelative",
        "Operator\tsindy-impulse",
        "Description\t" + _text(tag, "description"),
        f"Date\t{date}",
        f"Time\t{clock}",
        "***End_of_Header***\t",
        "\t",
        "Channels\t" + str(n) + "\t" * (n - 1),
        row("Samples", [record.n_samples] * n),
        row("Date", [date] * n),
        row("Time", [clock] * n),
        row("Y_Unit_Label", [_text(u, "units") for u in record.units]),
        row("X_Dimension", ["Time"] * n),
        row("X0", [repr(float(record.t0))] * n),
        row("Delta_X", [repr(1.0 / record.fs)] * n),
        "***End_of_Header***" + "\t" * n,
        row("X_Value", [_text(c, "channel names") for c in record.channel_names] + ["Comment"]),
    ]
    table = np.column_stack([record.t, record.data])
    with open(tmp_path, "w", encoding="utf-8", newline="\n") as fh:
        fh.write("\n".join(header) + "\n")
        np.savetxt(fh, table, fmt="%.17g", delimiter="\t")

"""Universal File Format data set 58 (function at nodal DOF): time records, ASCII or binary, via pyuff.

One data set per channel, function type 1 (time response), even abscissa. What is read from each set:

========================  =======================================================================
Record field              UFF 58 field
========================  =======================================================================
``channel_names``         ID line 1 (else ``"<node><+X|...>"`` from the response node and direction)
``units``                 ordinate axis units label (record 9)
``nodes``, ``directions``  response node and direction (record 6; node 0 is read as unknown, -1)
``fs``, ``t0``            abscissa increment and minimum (record 7)
``force_channel``         the set whose ordinate specific data type is 13 (excitation force)
========================  =======================================================================

The abscissa fields hold 6 significant digits; the writer also puts the exact ``fs`` and ``t0`` in ID
line 2 (``sindy-impulse {"fs": ..., "t0": ...}``), which the reader prefers when it agrees with them.
The ordinates are written in double precision (ASCII: 12 significant digits, ``%20.11e``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ._common import decode_tag, encode_tag, fs_from_spacing, fs_from_time, require
from ._record import Record, assemble

__all__ = ["read_uff58", "write_uff58"]

#: UFF specific data types (record 9, field 1) by unit label (lower case).
_SPEC_BY_UNIT = {
    **dict.fromkeys(["m/s^2", "m/s2", "m/s**2", "mm/s^2", "g", "g0", "in/s^2", "ft/s^2"], 12),
    **dict.fromkeys(["m/s", "mm/s", "in/s", "ft/s"], 11),
    **dict.fromkeys(["m", "mm", "um", "µm", "in", "ft"], 8),
    **dict.fromkeys(["pa", "kpa", "bar", "psi"], 15),
}
_FORCE_SPEC = 13
_DIR_LABELS = {1: "+X", 2: "+Y", 3: "+Z", 4: "+RX", 5: "+RY", 6: "+RZ"}


def _label(node: int, direction: int, index: int) -> str:
    if node <= 0:
        return f"ch{index + 1}"
    if direction == 0:
        return str(node)
    return f"{node}{_DIR_LABELS[abs(direction)].replace('+', '-' if direction < 0 else '+')}"


def read_uff58(
    path: str | Path, *, fs: float | None = None, force_channel: int | str | None = None
) -> Record:
    """Read the time-response data sets 58 of a UFF file (ASCII or binary) as one Record.

    Data sets of other types, and sets 58 that are not real time functions (FRFs, spectra), are skipped.
    See the module docstring for what is read from where.

    Examples
    --------
    >>> rec = read_uff58("hammer_test.uff")  # doctest: +SKIP
    """
    pyuff = require("pyuff", "reading UFF files")
    what = str(path)
    try:
        uff = pyuff.UFF(str(path))
        wanted = [int(i) for i in np.flatnonzero(np.asarray(uff.get_set_types()) == 58)]
        sets = uff.read_sets(wanted) if wanted else []
    except Exception as err:  # pyuff raises bare Exceptions
        raise ValueError(f"{what}: not a readable UFF file ({err})") from err
    sets = [sets] if isinstance(sets, dict) else list(sets)
    timed = [
        s
        for s in sets
        if not np.iscomplexobj(s["data"])
        and (s.get("func_type") in (0, 1) or s.get("abscissa_spec_data_type") == 17)
    ]
    if not timed:
        found = sorted({int(s.get("func_type", -1)) for s in sets})
        raise ValueError(
            f"{what}: no time-response data set 58 (function type 1) in the file; "
            f"data set types {sorted(set(np.asarray(uff.get_set_types()).tolist()))}, "
            f"58 function types {found}"
        )
    return _record_from_sets(timed, what, fs, force_channel)


def _set_timing(s: dict, what: str) -> tuple[float, float]:
    tag = decode_tag(s.get("id2"))
    if s.get("abscissa_spacing", 1) == 0:
        fs_i, t0_i = fs_from_time(np.asarray(s["x"], dtype=float), what)
    else:
        fs_i, t0_i = fs_from_spacing(float(s["abscissa_inc"]), rtol=1e-5, what=what), float(s["abscissa_min"])
    if tag and "fs" in tag and abs(float(tag["fs"]) - fs_i) <= 1e-5 * fs_i:
        fs_i, t0_i = float(tag["fs"]), float(tag.get("t0", t0_i))
    return fs_i, t0_i


def _record_from_sets(sets: list[dict], what: str, fs: float | None, force_argument) -> Record:
    from ._common import check_fs_argument

    timing = [_set_timing(s, what) for s in sets]
    nodes = [int(s.get("rsp_node", 0)) if int(s.get("rsp_node", 0)) > 0 else -1 for s in sets]
    directions = [int(s.get("rsp_dir", 0)) for s in sets]
    names = [str(s.get("id1", "")).strip() for s in sets]
    if any(n in ("", "NONE") for n in names) or len(set(names)) < len(names):
        names = [_label(n, d, i) for i, (n, d) in enumerate(zip(nodes, directions))]
        names = names if len(set(names)) == len(names) else [f"ch{i + 1}" for i in range(len(sets))]
    fss = [f for f, _ in timing]
    if max(fss) - min(fss) > 1e-9 * max(fss):
        listing = ", ".join(f"{n!r}: {f:g} Hz" for n, f in zip(names, fss))
        raise ValueError(f"{what}: unequal sampling across channels ({listing})")
    t0s = [t for _, t in timing]
    if max(t0s) - min(t0s) > 0.5 / fss[0]:
        raise ValueError(f"{what}: the channels start at different times ({min(t0s)!r} to {max(t0s)!r} s)")
    units = [str(s.get("ordinate_axis_units_lab", "")).strip() for s in sets]
    units = ["" if u == "NONE" else u for u in units]
    spec = [int(s.get("ordinate_spec_data_type", 0)) for s in sets]
    marked = [i for i, k in enumerate(spec) if k == _FORCE_SPEC]
    ours = any(decode_tag(s.get("id2")) for s in sets)
    force_from_file = marked[0] if len(marked) == 1 else (-2 if ours and not marked else None)
    return assemble(
        [s["data"] for s in sets],
        names,
        fs=check_fs_argument(fss[0], fs, what),
        t0=t0s[0],
        units=units,
        nodes=nodes,
        directions=directions,
        force_from_file=force_from_file,
        force_argument=force_argument,
        source=what,
        meta={
            "format": "uff58",
            "binary": [bool(s.get("binary", 0)) for s in sets],
            "function_types": [int(s.get("func_type", 0)) for s in sets],
            "ordinate_spec_data_types": spec,
            "reference_nodes": [int(s.get("ref_node", 0)) for s in sets],
            "reference_directions": [int(s.get("ref_dir", 0)) for s in sets],
        },
    )


def _check_text(value: str, width: int, what: str) -> str:
    if "\n" in value or "\r" in value or len(value) > width:
        raise ValueError(f"UFF 58 holds {what} of at most {width} characters on one line, not {value!r}")
    return value


def uff58_sets(record: Record, *, binary: bool = False) -> list[dict]:
    """The pyuff data-set dicts (type 58) of a record, one per channel."""
    pyuff = require("pyuff", "writing UFF files")
    t = record.t
    f = record.force_channel
    ref_node = max(record.nodes[f], 0) if f is not None else 0
    ref_dir = record.directions[f] if f is not None else 0
    out = []
    for i, name in enumerate(record.channel_names):
        unit = _check_text(record.units[i], 20, "unit labels")
        spec = _FORCE_SPEC if i == f else _SPEC_BY_UNIT.get(unit.strip().lower(), 0)
        tag = encode_tag({"fs": record.fs, "t0": record.t0})
        dset = pyuff.prepare_58(
            binary=int(bool(binary)),
            id1=_check_text(name, 80, "channel names") or "NONE",
            id2=tag,
            func_type=1,
            rsp_node=max(record.nodes[i], 0),
            rsp_dir=record.directions[i],
            ref_node=ref_node,
            ref_dir=ref_dir,
            data=np.array(record.data[:, i], dtype=float),
            x=t,
            abscissa_spacing=1,
            abscissa_min=float(record.t0),
            abscissa_inc=1.0 / record.fs,
            abscissa_spec_data_type=17,
            abscissa_axis_units_lab="s",
            ordinate_spec_data_type=spec,
            ordinate_axis_units_lab=unit or "NONE",
            orddenom_spec_data_type=0,
            z_axis_spec_data_type=0,
        )
        dset["abscissa_axis_lab"] = "Time"
        dset["ordinate_axis_lab"] = name if 0 < len(name) <= 20 else "NONE"
        out.append(dset)
    return out


def write_uff58(record: Record | list[Record], tmp_path: str, *, binary: bool = False) -> None:
    """Write the record's channels (of each record of a list, in order) as data sets 58 to ``tmp_path``
    (used by :func:`write_record`)."""
    pyuff = require("pyuff", "writing UFF files")
    records = record if isinstance(record, list) else [record]
    sets = [s for r in records for s in uff58_sets(r, binary=binary)]
    try:
        # "add" to the empty temporary file: pyuff's "overwrite" truncates the file at a binary set
        pyuff.UFF(tmp_path).write_sets(sets, mode="add")
    except Exception as err:  # pyuff raises bare Exceptions
        raise ValueError(f"pyuff could not write the UFF 58 sets: {err}") from err

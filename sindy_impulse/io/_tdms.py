"""NI TDMS files (``.tdms``) via npTDMS.

Read from the file: every numeric channel of every group (named ``channel``, or ``group/channel`` when
the names repeat across groups), units from the ``unit_string`` (or ``NI_UnitDescription``) property,
sampling rate and ``t0`` from ``wf_increment`` and ``wf_start_offset`` (else a channel named ``time`` /
``t``, else the ``fs=`` argument), node and direction from the ``node`` and ``direction`` properties
(this package's writer sets them), the force channel from the root property ``sindy_impulse_force``
(written here) or else a channel named force / hammer / excitation / F or in force units.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ._common import check_fs_argument, fs_from_time, json_meta, require, snap_fs
from ._record import Record, assemble

__all__ = ["read_tdms", "write_tdms"]

_GROUP = "record"


def read_tdms(path: str | Path, *, fs: float | None = None, force_channel: int | str | None = None) -> Record:
    """Read the numeric channels of a TDMS file as a Record.

    Examples
    --------
    >>> rec = read_tdms("hammer_test.tdms")  # doctest: +SKIP
    """
    nptdms = require("nptdms", "reading TDMS files")
    what = str(path)
    try:
        tdms = nptdms.TdmsFile.read(str(path))
    except Exception as err:  # npTDMS raises ValueError, KeyError, struct.error... on a broken file
        raise ValueError(f"{what}: not a readable TDMS file ({err})") from err
    chans = [
        c for g in tdms.groups() for c in g.channels() if len(c) and np.asarray(c[:1]).dtype.kind in "fiu"
    ]
    time = [
        c for c in chans if c.name.strip().lower() in ("time", "t") and "wf_increment" not in c.properties
    ]
    chans = [c for c in chans if c not in time]
    short = [c.name for c in chans]
    names = short if len(set(short)) == len(short) else [f"{c.group_name}/{c.name}" for c in chans]
    props = [c.properties for c in chans]
    fs_file, t0 = _timing(props, names, time, what)
    root = tdms.properties
    marked = root.get("sindy_impulse_force")
    stored = json.loads(root.get("sindy_impulse_meta", "{}"))
    return assemble(
        [np.asarray(c[:], dtype=float) for c in chans],
        names,
        fs=check_fs_argument(fs_file, fs, what),
        t0=t0,
        units=[str(p.get("unit_string", p.get("NI_UnitDescription", ""))) for p in props],
        nodes=[int(p["node"]) for p in props] if all("node" in p for p in props) else (),
        directions=[int(p["direction"]) for p in props] if all("direction" in p for p in props) else (),
        force_from_file=None if marked is None else (-2 if int(marked) < 0 else int(marked)),
        force_argument=force_channel,
        source=what,
        meta={**stored, "format": "tdms", "root_properties": {k: str(v) for k, v in root.items()}},
    )


def _timing(props: list, names: list, time: list, what: str) -> tuple[float | None, float]:
    incs = [float(p["wf_increment"]) for p in props if "wf_increment" in p]
    if incs:
        if len(incs) < len(props) or max(incs) - min(incs) > 1e-12 * max(incs):
            listing = {n: p.get("wf_increment") for n, p in zip(names, props)}
            raise ValueError(f"{what}: unequal sampling across channels (wf_increment {listing})")
        starts = {float(p.get("wf_start_offset", 0.0)) for p in props}
        if max(starts) - min(starts) > 0.5 * incs[0]:
            raise ValueError(f"{what}: the channels start at different times ({sorted(starts)})")
        exact = props[0].get("sindy_impulse_fs")
        fs = snap_fs(1.0 / incs[0], 1e-12)
        if exact is not None and abs(float(exact) - fs) <= 1e-9 * fs:
            fs = float(exact)
        return fs, min(starts)
    if time:
        return fs_from_time(np.asarray(time[0][:], dtype=float), what)
    return None, 0.0


def write_tdms(record: Record, tmp_path: str) -> None:
    """Write the record as one TDMS group ``record`` with waveform properties per channel."""
    nptdms = require("nptdms", "writing TDMS files")
    force = -1 if record.force_channel is None else record.force_channel
    root = nptdms.RootObject(
        properties={"sindy_impulse_force": force, "sindy_impulse_meta": json_meta(record.meta)}
    )
    group = nptdms.GroupObject(_GROUP)
    channels = []
    for i, name in enumerate(record.channel_names):
        properties = {
            "wf_increment": 1.0 / record.fs,
            "wf_start_offset": float(record.t0),
            "wf_samples": record.n_samples,
            "unit_string": record.units[i],
            "node": int(record.nodes[i]),
            "direction": int(record.directions[i]),
            "sindy_impulse_fs": float(record.fs),
        }
        channels.append(
            nptdms.ChannelObject(_GROUP, name, np.ascontiguousarray(record.data[:, i]), properties=properties)
        )
    with nptdms.TdmsWriter(tmp_path) as writer:
        writer.write_segment([root, group, *channels])

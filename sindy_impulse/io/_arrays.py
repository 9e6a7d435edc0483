"""NumPy ``.npz`` and MATLAB ``.mat`` files: named arrays.

The writer's layout (both formats): ``data`` (n_samples, n_channels), ``fs``, ``t0``, ``channel_names``,
``units`` (string arrays; cell arrays in MATLAB), ``nodes``, ``directions``, ``force_channel`` and
``meta_json``. ``force_channel`` is 0-based in ``.npz`` (-1: none) and 1-based in ``.mat`` (0: none), as
each language counts.

A file in another layout is read as well: a ``data`` array (or the one 2-D array, samples along its
longer side) with optional ``channel_names`` / ``names`` and ``units``, or else every 1-D numeric array
of the common length as a channel named by its key. The sampling rate is ``fs`` (or ``Fs``,
``sampling_rate``, ``sample_rate``, ``fs_hz``), else a ``t`` / ``time`` array, else the ``fs=``
argument; the force channel is ``force_channel`` or the one named force / hammer / excitation / F.
MATLAB v7.3 (HDF5) files need h5py.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from ._common import check_fs_argument, fs_from_time, json_meta, require
from ._record import Record, assemble

__all__ = ["read_npz", "write_npz", "read_mat", "write_mat"]

_FS_KEYS = ("fs", "Fs", "FS", "sampling_rate", "sample_rate", "samplerate", "fs_hz")
_TIME_KEYS = ("t", "time", "Time", "T")
_OURS = {"data", "fs", "t0", "channel_names", "names", "units", "nodes", "directions", "force_channel"}


def _strings(value, n: int) -> list[str] | None:
    """A list of n strings from a string array, a cell array or one string; None if not that."""
    if value is None:
        return None
    items = [value] if isinstance(value, str) else list(np.asarray(value, dtype=object).ravel())
    out = []
    for item in items:
        if isinstance(item, np.ndarray):
            item = "".join(str(x) for x in item.ravel()) if item.size else ""
        out.append(str(item).strip())
    return out if len(out) == n else None


def _ints(value, n: int) -> list[int]:
    arr = np.atleast_1d(np.asarray(value)).ravel() if value is not None else np.array([])
    return [int(v) for v in arr] if arr.size == n else []


def _numeric(value) -> bool:
    return isinstance(value, np.ndarray) and value.dtype.kind in "fiu" and value.size > 1


def _channels(arrays: Mapping, what: str) -> tuple[np.ndarray, list[str] | None]:
    if "data" in arrays:
        data = np.asarray(arrays["data"], dtype=float)
        return (data[:, None] if data.ndim == 1 else data), None
    two_d = [k for k, v in arrays.items() if _numeric(v) and np.squeeze(v).ndim == 2]
    if len(two_d) == 1:
        data = np.asarray(arrays[two_d[0]], dtype=float)
        return (data if data.shape[0] >= data.shape[1] else data.T), None
    skip = set(_TIME_KEYS) | set(_FS_KEYS)
    columns = {
        k: np.ravel(v) for k, v in arrays.items() if k not in skip and _numeric(v) and np.squeeze(v).ndim == 1
    }
    if not columns:
        raise ValueError(f"{what}: no data array found (expected 'data' or 1-D channel arrays)")
    lengths = {k: c.size for k, c in columns.items()}
    if len(set(lengths.values())) > 1:
        raise ValueError(f"{what}: unequal channel lengths {lengths}")
    return np.column_stack(list(columns.values())), list(columns)


def record_from_arrays(
    arrays: Mapping, what: str, fs: float | None, force_channel, *, fmt: str, one_based: bool
) -> Record:
    """A Record from the named arrays of an ``.npz`` or ``.mat`` file (see the module docstring)."""
    data, names = _channels(arrays, what)
    n = data.shape[1]
    names = names or _strings(arrays.get("channel_names", arrays.get("names")), n)
    fs_file, t0 = None, float(np.ravel(arrays.get("t0", [0.0]))[0])
    for key in _FS_KEYS:
        if key in arrays and np.size(arrays[key]) == 1:
            fs_file = float(np.ravel(arrays[key])[0])
            break
    else:
        for key in _TIME_KEYS:
            if key in arrays and np.size(arrays[key]) == data.shape[0]:
                fs_file, t0 = fs_from_time(np.ravel(arrays[key]), what)
                break
    marked = None
    if "force_channel" in arrays:
        marked = int(np.ravel(arrays["force_channel"])[0]) - (1 if one_based else 0)
        marked = -2 if marked < 0 else marked
    meta = {}
    if "meta_json" in arrays:
        meta = json.loads(str(np.ravel(arrays["meta_json"])[0]) if np.size(arrays["meta_json"]) else "{}")
    return assemble(
        list(data.T),
        names or [f"ch{i + 1}" for i in range(n)],
        fs=check_fs_argument(fs_file, fs, what),
        t0=t0,
        units=_strings(arrays.get("units"), n) or (),
        nodes=_ints(arrays.get("nodes"), n),
        directions=_ints(arrays.get("directions"), n),
        force_from_file=marked,
        force_argument=force_channel,
        source=what,
        meta={**meta, "format": fmt, "variables": sorted(k for k in arrays if not k.startswith("__"))},
    )


def _layout(record: Record, one_based: bool) -> dict:
    force = record.force_channel
    return {
        "data": np.asarray(record.data),
        "fs": np.float64(record.fs),
        "t0": np.float64(record.t0),
        "nodes": np.asarray(record.nodes, dtype=np.int64),
        "directions": np.asarray(record.directions, dtype=np.int64),
        "force_channel": np.int64((-1 if force is None else force) + (1 if one_based else 0)),
        "meta_json": json_meta(record.meta),
    }


def read_npz(path: str | Path, *, fs: float | None = None, force_channel: int | str | None = None) -> Record:
    """Read a ``.npz`` file (no pickles) as a Record."""
    with np.load(path, allow_pickle=False) as npz:
        arrays = {k: npz[k] for k in npz.files}
    arrays = {k: (str(v) if v.dtype.kind == "U" and v.ndim == 0 else v) for k, v in arrays.items()}
    return record_from_arrays(arrays, str(path), fs, force_channel, fmt="npz", one_based=False)


def write_npz(record: Record, tmp_path: str) -> None:
    """Write the record's arrays to a ``.npz`` file."""
    arrays = _layout(record, one_based=False)
    arrays["channel_names"] = np.asarray(record.channel_names, dtype=str)
    arrays["units"] = np.asarray(record.units, dtype=str)
    with open(tmp_path, "wb") as fh:
        np.savez(fh, **arrays)


def read_mat(path: str | Path, *, fs: float | None = None, force_channel: int | str | None = None) -> Record:
    """Read a MATLAB ``.mat`` file (v4-v7 with scipy; v7.3 with h5py) as a Record."""
    from scipy.io import loadmat

    try:
        arrays = loadmat(str(path), simplify_cells=True)
    except NotImplementedError:  # v7.3: HDF5
        arrays = _read_mat73(path)
    except ValueError as err:
        raise ValueError(f"{path}: not a readable MATLAB file ({err})") from err
    arrays = {k: (np.asarray(v) if isinstance(v, (int, float)) else v) for k, v in arrays.items()}
    return record_from_arrays(arrays, str(path), fs, force_channel, fmt="mat", one_based=True)


def write_mat(record: Record, tmp_path: str) -> None:
    """Write the record's arrays to a MATLAB v5 ``.mat`` file (names and units as cell arrays)."""
    from scipy.io import savemat

    arrays = _layout(record, one_based=True)
    arrays["channel_names"] = np.asarray(list(record.channel_names), dtype=object)
    arrays["units"] = np.asarray(list(record.units), dtype=object)
    savemat(tmp_path, arrays, oned_as="column")


def _read_mat73(path: str | Path) -> dict:
    h5py = require("h5py", "reading MATLAB v7.3 (HDF5) files")
    out = {}
    with h5py.File(path, "r") as f:
        for key, item in f.items():
            if isinstance(item, h5py.Dataset) and not key.startswith("#"):
                out[key] = _mat73_value(f, item)
    return out


def _mat73_value(f, ds):
    cls = ds.attrs.get("MATLAB_class", b"double")
    cls = cls.decode() if isinstance(cls, bytes) else str(cls)
    if "MATLAB_empty" in ds.attrs and ds.attrs["MATLAB_empty"]:
        return "" if cls == "char" else np.array([])
    value = ds[()]
    if cls == "char":
        return "".join(chr(c) for c in np.asarray(value).T.ravel())
    if cls == "cell":
        return np.array([_mat73_value(f, f[ref]) for ref in np.asarray(value).T.ravel()], dtype=object)
    arr = np.asarray(value).T  # MATLAB is column-major
    return arr.reshape(-1) if 1 in arr.shape and arr.ndim == 2 and arr.size > 1 else np.squeeze(arr)

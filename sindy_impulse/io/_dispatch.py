"""``read_record`` and ``write_record``: one entry point for every format, chosen by the file suffix."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from pathlib import Path

from ._arrays import read_mat, read_npz, write_mat, write_npz
from ._common import atomic_write, check_readable
from ._csv import read_csv, write_csv
from ._lvm import read_lvm, write_lvm
from ._record import Record
from ._tdms import read_tdms, write_tdms
from ._uff58 import read_uff58, write_uff58

__all__ = ["FORMATS", "read_record", "write_record"]

#: File suffix -> format name.
FORMATS = {
    ".uff": "uff",
    ".unv": "uff",
    ".lvm": "lvm",
    ".tdms": "tdms",
    ".mat": "mat",
    ".npz": "npz",
    ".csv": "csv",
}
_READERS: dict[str, Callable[..., Record]] = {
    "uff": read_uff58,
    "lvm": read_lvm,
    "tdms": read_tdms,
    "mat": read_mat,
    "npz": read_npz,
    "csv": read_csv,
}
_WRITERS: dict[str, Callable[[Record, str], None]] = {
    "lvm": write_lvm,
    "tdms": write_tdms,
    "mat": write_mat,
    "npz": write_npz,
    "csv": write_csv,
}


def _format_of(path: Path, format: str | None) -> str:
    if format is not None:
        name = str(format).lower().lstrip(".")
        name = FORMATS.get("." + name, name)
        if name not in _READERS:
            raise ValueError(f"unknown format {format!r}; known: {sorted(_READERS)}")
        return name
    suffix = path.suffix.lower()
    if suffix not in FORMATS:
        raise ValueError(
            f"cannot tell the format of {str(path)!r} from its suffix {suffix!r}; known suffixes: "
            f"{', '.join(FORMATS)} (or pass format=)"
        )
    return FORMATS[suffix]


def read_record(
    path: str | os.PathLike,
    *,
    format: str | None = None,
    fs: float | None = None,
    force_channel: int | str | None = None,
) -> Record:
    """Read a measurement file as a :class:`Record`.

    Parameters
    ----------
    path : str or path-like
        The file. Its suffix gives the format: ``.uff`` / ``.unv`` (UFF 58, ASCII or binary; pyuff),
        ``.lvm`` (LabVIEW; lvm-read), ``.tdms`` (npTDMS), ``.mat`` (scipy; v7.3 with h5py), ``.npz``,
        ``.csv`` (a header row).
    format : str, optional
        ``"uff"``, ``"lvm"``, ``"tdms"``, ``"mat"``, ``"npz"`` or ``"csv"``, to override the suffix.
    fs : float, optional
        Sampling rate (Hz), for a file that does not hold it (a CSV without a time column, arrays
        without ``fs``). A file that holds one must agree with it (ValueError otherwise).
    force_channel : int or str, optional
        Column index or name of the force channel; default: what the file marks as the force, else the
        channel named force / hammer / excitation / F, else the one in force units (N, lbf), else none.

    Returns
    -------
    Record
        With ``source`` the path and ``meta["format"]`` the format read. What each format gives (names,
        units, nodes and directions, sampling rate, force) is listed in :mod:`sindy_impulse.io`.

    Raises
    ------
    FileNotFoundError
        No such file.
    ValueError
        Unknown suffix or format, a file that cannot be parsed, channels of unequal length or sampling,
        no sampling rate (pass ``fs=``), an ``fs=`` that contradicts the file.
    ImportError
        The format's optional package is missing (``pip install "sindy-impulse[io]"``).

    Examples
    --------
    >>> import os, tempfile
    >>> import numpy as np
    >>> rec = Record(np.eye(3), fs=100.0, channel_names=("hammer", "a1", "a2"), units=("N", "g", "g"),
    ...              force_channel=0)
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = write_record(rec, os.path.join(folder, "tap.npz"))
    ...     back = read_record(path)
    ...     also = read_record(path, force_channel="a2")  # the argument wins over the file
    >>> back.fs, back.channel_names, back.force_channel, np.array_equal(back.data, rec.data)
    (100.0, ('hammer', 'a1', 'a2'), 0, True)
    >>> also.force_channel
    2
    """
    p = Path(path)
    name = _format_of(p, format)
    check_readable(p)
    return _READERS[name](p, fs=fs, force_channel=force_channel)


def write_record(
    record: Record | Sequence[Record],
    path: str | os.PathLike,
    *,
    format: str | None = None,
    overwrite: bool = False,
    binary: bool = False,
) -> Path:
    """Write a :class:`Record` to a file in the format of its suffix (or ``format``).

    Parameters
    ----------
    record : Record or sequence of Record
        What to write. A UFF file may hold several records (their channels one after the other, each
        with its own sampling rate and start time: e.g. a survey's band signals,
        :meth:`~sindy_impulse.modes.ModalSurvey.to_uff58`); :func:`read_record` reads back only files whose
        channels share one sampling rate.
    path : str or path-like
        The file: ``.uff`` / ``.unv`` (one UFF 58 time-response set per channel), ``.lvm``, ``.tdms``,
        ``.mat`` (v5), ``.npz`` or ``.csv``.
    format : str, optional
        Overrides the suffix (same names as :func:`read_record`).
    overwrite : bool
        Replace an existing file; without it an existing file raises FileExistsError.
    binary : bool
        UFF only: binary data sets 58 (``58b``) instead of ASCII.

    Returns
    -------
    Path
        The file written. It is written to a temporary file in the same folder and moved into place, so
        a failed write leaves neither a partial file nor a changed old one.

    Examples
    --------
    >>> import os, tempfile
    >>> import numpy as np
    >>> rec = Record(np.ones((3, 1)), fs=10.0)
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = write_record(rec, os.path.join(folder, "r.csv"))
    ...     try:
    ...         write_record(rec, path)
    ...     except FileExistsError:
    ...         print("refused")
    refused
    """
    p = Path(path)
    name = _format_of(p, format)
    record = _records_to_write(record, name)
    if binary and name != "uff":
        raise ValueError(f"binary=True applies to UFF files only, not {name!r}")
    if name == "uff":

        def write(tmp: str) -> None:
            write_uff58(record, tmp, binary=binary)

    else:

        def write(tmp: str) -> None:
            _WRITERS[name](record, tmp)

    return atomic_write(p, write, overwrite=overwrite)


def _records_to_write(record, name: str):
    """The Record (or, for UFF, the list of Records) to write; TypeError for anything else."""
    if isinstance(record, Record):
        return record
    many = isinstance(record, (list, tuple)) and len(record) > 0
    if many and all(isinstance(r, Record) for r in record):
        if name != "uff":
            raise TypeError(f"only a UFF file holds several records; write one Record to a {name!r} file")
        return list(record)
    raise TypeError(f"record must be a sindy_impulse.io.Record, not {type(record).__name__}")

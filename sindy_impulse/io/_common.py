"""Shared helpers of the file formats: optional imports, atomic writes, force detection, sampling rates."""

from __future__ import annotations

import importlib
import json
import math
import os
import re
import secrets
import stat
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path
from types import ModuleType

import numpy as np

from ..exceptions import DataWarning

#: What a user types to get every optional reader and writer.
INSTALL_HINT = 'pip install "sindy-impulse[io]"'
#: Tag of the machine-readable metadata this package writes into free-text header fields.
TAG = "sindy-impulse"

_PIP_NAMES = {"pyuff": "pyuff", "nptdms": "npTDMS", "lvm_read": "lvm-read", "h5py": "h5py"}
_FORCE_NAME = re.compile(r"force|hammer|excitation|^\s*f\s*$", re.IGNORECASE)
_FORCE_UNITS = {"n", "kn", "lbf", "kgf", "mn"}


def require(module: str, purpose: str) -> ModuleType:
    """Import an optional dependency, or raise an ImportError naming the ``io`` extra.

    Examples
    --------
    >>> require("json", "testing").__name__
    'json'
    """
    try:
        return importlib.import_module(module)
    except ImportError as err:
        pip_name = _PIP_NAMES.get(module, module)
        raise ImportError(
            f"{purpose} needs the optional package {pip_name!r}, which is not installed: {INSTALL_HINT}"
        ) from err


def check_readable(path: str | os.PathLike) -> Path:
    """The path as a Path, or FileNotFoundError / IsADirectoryError."""
    p = Path(path)
    if not p.exists():
        raise FileNotFoundError(f"no such file: {str(p)!r}")
    if p.is_dir():
        raise IsADirectoryError(f"{str(p)!r} is a folder, not a record file")
    return p


def temporary_beside(folder: str | os.PathLike, name: str, suffix: str = "") -> tuple[str, int]:
    """A new hidden file ``.<name>.<random>.tmp<suffix>`` in ``folder``, created exclusively with the
    permissions any new file of the user gets (``0o666`` less the umask, as ``open`` gives), and its open
    descriptor (write only).

    Examples
    --------
    >>> import stat, tempfile
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path, fd = temporary_beside(folder, "modes.json")
    ...     os.close(fd)
    ...     mask = os.umask(0); _ = os.umask(mask)
    ...     stat.S_IMODE(os.stat(path).st_mode) == 0o666 & ~mask
    True
    """
    for _ in range(100):
        path = os.path.join(os.fspath(folder), f".{name}.{secrets.token_hex(4)}.tmp{suffix}")
        try:
            return path, os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
        except FileExistsError:
            continue
    raise FileExistsError(f"no free temporary name for {name} in {os.fspath(folder)}")


def atomic_write(path: str | os.PathLike, write: Callable[[str], None], *, overwrite: bool) -> Path:
    """Call ``write(tmp_path)`` on a temporary file beside ``path``, then move it into place.

    Without ``overwrite`` an existing file is never replaced (FileExistsError), even one that appears while
    writing: the finished file is hard-linked to its name, which fails if the name is taken. A failed write
    leaves no temporary file behind. A new file gets the user's usual permissions (the umask applies), a
    replaced one keeps its own.
    """
    target = Path(path)
    if target.is_dir():
        raise IsADirectoryError(f"{str(target)!r} is a folder")
    if not overwrite and target.exists():
        raise FileExistsError(f"{str(target)!r} exists; pass overwrite=True to replace it")
    folder = target.parent if str(target.parent) else Path(".")
    if not folder.is_dir():
        raise FileNotFoundError(f"folder {str(folder)!r} does not exist")
    tmp, fd = temporary_beside(folder, target.name, target.suffix)
    try:
        mode = stat.S_IMODE(os.fstat(fd).st_mode)
        if overwrite and target.exists():
            mode = stat.S_IMODE(target.stat().st_mode)
    finally:
        os.close(fd)
    try:
        write(tmp)
        os.chmod(tmp, mode)  # a writer may have made the file anew
        if overwrite:
            os.replace(tmp, target)
        else:
            _place_new(tmp, target)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    return target


def _place_new(tmp: str, target: Path) -> None:
    try:
        os.link(tmp, target)
    except FileExistsError:
        raise FileExistsError(f"{str(target)!r} exists; pass overwrite=True to replace it") from None
    except OSError:  # no hard links on this file system: check, then rename
        if target.exists():
            raise FileExistsError(f"{str(target)!r} exists; pass overwrite=True to replace it") from None
        os.replace(tmp, target)


def snap_fs(fs: float, rtol: float) -> float:
    """The value with the fewest decimals (0 to 6) within ``rtol`` of ``fs``: undoes rounded spacings.

    Examples
    --------
    >>> snap_fs(1 / 4.88281e-04, 1e-5)
    2048.0
    >>> snap_fs(12.8000001, 1e-6)
    12.8
    """
    for decimals in range(7):
        candidate = round(fs, decimals)
        if candidate > 0 and abs(candidate - fs) <= rtol * fs:
            return float(candidate)
    return float(fs)


def fs_from_spacing(dt: float, *, rtol: float, what: str) -> float:
    """Sampling rate from a sample spacing held to relative precision ``rtol``."""
    if not (math.isfinite(dt) and dt > 0):
        raise ValueError(f"{what}: sample spacing {dt!r} is not a positive number")
    return snap_fs(1.0 / dt, rtol)


def fs_from_time(t: np.ndarray, what: str) -> tuple[float, float]:
    """``(fs, t0)`` of a time column; ValueError if it is not evenly spaced (to 1 % of a sample)."""
    t = np.asarray(t, dtype=float)
    if t.size < 2:
        raise ValueError(f"{what}: a time column needs at least 2 samples to give the sampling rate")
    dt = (t[-1] - t[0]) / (t.size - 1)
    if not (np.isfinite(dt) and dt > 0):
        raise ValueError(f"{what}: the time column does not increase")
    off = np.abs(t - (t[0] + dt * np.arange(t.size)))
    worst = int(np.argmax(off))
    if off[worst] > 0.01 * dt:
        raise ValueError(
            f"{what}: unequal sampling: time {t[worst]!r} at sample {worst} is {off[worst] / dt:.3g} "
            "samples off an even grid"
        )
    # the end points are printed to some precision: snap within what that precision allows
    rtol = max(1e-9, 4 * np.finfo(float).eps * max(abs(t[0]), abs(t[-1])) / (t[-1] - t[0]))
    rtol = max(rtol, float(np.max(off)) / (t[-1] - t[0]))
    return snap_fs(1.0 / dt, rtol), float(t[0])


def check_fs_argument(fs_file: float | None, fs_arg: float | None, what: str) -> float:
    """The sampling rate: the file's, the argument's, or a ValueError when neither or they disagree."""
    if fs_arg is not None:
        fs_arg = float(fs_arg)
        if not (math.isfinite(fs_arg) and fs_arg > 0):
            raise ValueError(f"fs={fs_arg!r} is not a positive number")
    if fs_file is None:
        if fs_arg is None:
            raise ValueError(f"{what} holds no sampling rate (no time column or spacing): pass fs=")
        return fs_arg
    if fs_arg is not None and abs(fs_arg - fs_file) > 1e-6 * fs_file:
        raise ValueError(f"{what} says fs = {fs_file!r} Hz but fs={fs_arg!r} was given")
    return float(fs_file)


def find_force(names: Sequence[str], units: Sequence[str] = ()) -> int | None:
    """Index of the force channel from names (force, hammer, excitation, F) or else force units (N, lbf).

    None when no channel or several channels look like a force (several: with a DataWarning).

    Examples
    --------
    >>> find_force(["acc1", "Hammer", "acc2"])
    1
    >>> find_force(["a", "b"], ["m/s^2", "N"])
    1
    """
    for candidates, how in (
        ([i for i, n in enumerate(names) if _FORCE_NAME.search(str(n))], "named"),
        ([i for i, u in enumerate(units) if str(u).strip().lower() in _FORCE_UNITS], "in force units"),
    ):
        if len(candidates) == 1:
            return candidates[0]
        if len(candidates) > 1:
            picked = [names[i] for i in candidates]
            warnings.warn(
                f"several channels look like the force ({how}: {picked}); none taken as the force: "
                "pass force_channel=",
                DataWarning,
                stacklevel=4,
            )
            return None
    return None


def resolve_force(
    argument: int | str | None, from_file: int | None, names: Sequence[str], units: Sequence[str] = ()
) -> int | None:
    """The force channel: ``argument`` (index or name) if given, else the file's mark, else a guess.

    ``from_file`` is -2 when the file says explicitly that there is none.
    """
    if argument is not None:
        if isinstance(argument, str):
            if argument not in names:
                raise ValueError(f"force_channel={argument!r} is not a channel name; channels: {list(names)}")
            return list(names).index(argument)
        index = int(argument)
        if not -len(names) <= index < len(names):
            raise ValueError(f"force_channel={argument!r} is out of range for {len(names)} channels")
        return index % len(names)
    if from_file is not None:
        return None if from_file == -2 else from_file
    return find_force(names, units)


def encode_tag(values: dict) -> str:
    """``"sindy-impulse {json}"``: the metadata this package writes into free-text header fields."""
    return f"{TAG} " + json.dumps(values, separators=(",", ":"), default=str)


def decode_tag(text: object) -> dict | None:
    """The dict of :func:`encode_tag`, or None when ``text`` is not such a field."""
    if not isinstance(text, str) or not text.strip().startswith(TAG + " "):
        return None
    try:
        out = json.loads(text.strip()[len(TAG) + 1 :])
    except ValueError:
        return None
    return out if isinstance(out, dict) else None


def json_meta(meta: dict) -> str:
    """The record's ``meta`` as JSON (values that are not JSON become their ``str``)."""
    return json.dumps(meta, default=str)


def split_unit(header: str) -> tuple[str, str]:
    """``"acc1 [m/s^2]"`` or ``"acc1 (m/s^2)"`` -> ``("acc1", "m/s^2")``; no unit -> ``(header, "")``.

    Examples
    --------
    >>> split_unit("hammer [N]")
    ('hammer', 'N')
    >>> split_unit("acc1")
    ('acc1', '')
    """
    match = re.fullmatch(r"\s*(.*?)\s*[\[(]([^\])]*)[\])]\s*", header)
    if match and match.group(1):
        return match.group(1), match.group(2).strip()
    return header.strip(), ""


def join_unit(name: str, unit: str) -> str:
    """Inverse of :func:`split_unit`."""
    return f"{name} [{unit}]" if unit else name

"""The :class:`Record`: a multi-channel, evenly sampled measurement with its channel descriptions."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Record"]


@dataclass(frozen=True, eq=False)
class Record:
    """An evenly sampled multi-channel record (a hammer test: responses and, often, the force).

    Every field but ``data`` and ``fs`` has a default; the per-channel tuples default to ``"ch1"``,
    ``"ch2"``... (names), ``""`` (units), ``-1`` (node unknown) and ``0`` (direction unknown). The arrays
    and tuples are normalised in ``__post_init__``: ``data`` becomes a read-only float64 array of shape
    (n_samples, n_channels) (a 1-D array is one channel).

    Attributes
    ----------
    data : ndarray (n_samples, n_channels)
        The samples, one column per channel, all finite.
    fs : float
        Sampling rate (Hz), positive and finite.
    t0 : float
        Time of the first sample (s).
    channel_names : tuple of str
        One distinct name per channel.
    units : tuple of str
        One unit label per channel (``""`` when unknown), e.g. ``"m/s^2"``, ``"N"``.
    nodes : tuple of int
        Measurement node of each channel (``-1``: unknown).
    directions : tuple of int
        Measurement direction of each channel, UFF convention: 1, 2, 3 = +X, +Y, +Z, 4, 5, 6 = rotations
        about them, negative values the opposite sense, 0 unknown.
    force_channel : int or None
        Column of the excitation force (hammer), or None.
    source : str
        Where the record comes from (a path or a description).
    meta : dict
        Anything else (the reader puts the format and the file's header fields here).

    Examples
    --------
    >>> import numpy as np
    >>> rec = Record(np.zeros((4, 2)), fs=1000.0, channel_names=("hammer", "acc"), units=("N", "m/s^2"),
    ...              force_channel=0)
    >>> rec.n_channels, rec.n_samples, float(rec.t[-1])
    (2, 4, 0.003)
    >>> rec.response.shape, rec.force.shape, rec.nodes, rec.directions
    ((4, 1), (4,), (-1, -1), (0, 0))
    >>> Record(np.zeros((4, 2)), fs=1000.0, channel_names=("a",))
    Traceback (most recent call last):
    ...
    ValueError: channel_names has 1 entries for 2 channels
    """

    data: np.ndarray
    fs: float
    t0: float = 0.0
    channel_names: tuple[str, ...] = ()
    units: tuple[str, ...] = ()
    nodes: tuple[int, ...] = ()
    directions: tuple[int, ...] = ()
    force_channel: int | None = None
    source: str = ""
    meta: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        data = _as_matrix(self.data)
        n = data.shape[1]
        fs = _finite_float(self.fs, "fs")
        if fs <= 0:
            raise ValueError(f"fs must be positive, not {fs!r}")
        names = _per_channel(self.channel_names, n, "channel_names", [f"ch{i + 1}" for i in range(n)], str)
        if len(set(names)) != n:
            twice = sorted({x for x in names if names.count(x) > 1})
            raise ValueError(f"channel names must be distinct; repeated: {twice}")
        directions = _per_channel(self.directions, n, "directions", [0] * n, _int)
        bad = [d for d in directions if not -6 <= d <= 6]
        if bad:
            raise ValueError(f"directions must be in -6..6 (UFF: 1=+X, 2=+Y, 3=+Z, 0 unknown), got {bad}")
        force = self.force_channel
        if force is not None:
            force = _int(force)
            if not 0 <= force < n:
                raise ValueError(f"force_channel {force} is not a column of {n} channels")
        for name, value in (
            ("data", data),
            ("fs", fs),
            ("t0", _finite_float(self.t0, "t0")),
            ("channel_names", names),
            ("units", _per_channel(self.units, n, "units", [""] * n, str)),
            ("nodes", _per_channel(self.nodes, n, "nodes", [-1] * n, _int)),
            ("directions", directions),
            ("force_channel", force),
            ("source", str(self.source)),
            ("meta", dict(self.meta)),
        ):
            object.__setattr__(self, name, value)

    @property
    def n_channels(self) -> int:
        """Number of channels (columns of ``data``)."""
        return self.data.shape[1]

    @property
    def n_samples(self) -> int:
        """Number of samples (rows of ``data``)."""
        return self.data.shape[0]

    @property
    def t(self) -> np.ndarray:
        """Time of each sample (s): ``t0 + arange(n_samples) / fs``."""
        return self.t0 + np.arange(self.n_samples) / self.fs

    @property
    def response(self) -> np.ndarray:
        """The data without the force channel, shape (n_samples, n_channels - 1) or all of it."""
        if self.force_channel is None:
            return self.data
        return np.delete(self.data, self.force_channel, axis=1)

    @property
    def force(self) -> np.ndarray | None:
        """The force channel, shape (n_samples,), or None."""
        return None if self.force_channel is None else self.data[:, self.force_channel]

    def __repr__(self) -> str:
        force = "" if self.force_channel is None else f", force={self.channel_names[self.force_channel]!r}"
        return (
            f"Record({self.n_samples} samples x {self.n_channels} channels at {self.fs:g} Hz, "
            f"channels={list(self.channel_names)}{force}, source={self.source!r})"
        )


def _as_matrix(data) -> np.ndarray:
    if isinstance(data, Sequence) and len(data) > 0:
        lengths = [np.size(row) for row in data]
        if len(set(lengths)) > 1:
            raise ValueError(f"ragged data: rows of lengths {sorted(set(lengths))}; all must be equal")
    try:
        arr = np.array(data, dtype=float)
    except (TypeError, ValueError) as err:
        raise ValueError(f"data must be a numeric array (n_samples, n_channels): {err}") from None
    if arr.ndim == 1:
        arr = arr[:, None]
    if arr.ndim != 2 or arr.shape[0] < 1 or arr.shape[1] < 1:
        raise ValueError(f"data must have shape (n_samples, n_channels) with both >= 1, not {arr.shape}")
    finite = np.isfinite(arr)
    if not finite.all():
        row, col = np.argwhere(~finite)[0]
        raise ValueError(f"data holds non-finite values (first at sample {row}, channel {col})")
    arr.setflags(write=False)
    return arr


def _finite_float(value, what: str) -> float:
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{what} must be a number, not {value!r}") from None
    if not math.isfinite(out):
        raise ValueError(f"{what} must be finite, not {out!r}")
    return out


def _int(value) -> int:
    if isinstance(value, (bool, np.bool_)) or int(value) != value:
        raise ValueError(f"{value!r} is not an integer")
    return int(value)


def _per_channel(values, n: int, what: str, default: list, convert) -> tuple:
    if values is None or (not isinstance(values, str) and len(values) == 0):
        return tuple(default)
    if isinstance(values, str):
        values = (values,)
    values = list(values)
    if len(values) != n:
        raise ValueError(f"{what} has {len(values)} entries for {n} channels")
    try:
        return tuple(convert(v) for v in values)
    except (TypeError, ValueError) as err:
        raise ValueError(f"{what}: {err}") from None


def assemble(
    columns: Sequence[np.ndarray],
    names: Sequence[str],
    *,
    fs: float,
    t0: float = 0.0,
    units: Sequence[str] = (),
    nodes: Sequence[int] = (),
    directions: Sequence[int] = (),
    force_from_file: int | None = None,
    force_argument: int | str | None = None,
    source: str = "",
    meta: dict | None = None,
) -> Record:
    """A Record from per-channel columns read from a file (checks the lengths, finds the force)."""
    from ._common import resolve_force

    if not columns:
        raise ValueError(f"{source}: no data channels found")
    lengths = [np.size(c) for c in columns]
    if len(set(lengths)) > 1:
        listing = ", ".join(f"{n!r}: {k}" for n, k in zip(names, lengths))
        raise ValueError(f"{source}: unequal channel lengths ({listing})")
    names = [str(n) for n in names]
    force = resolve_force(force_argument, force_from_file, names, units)
    return Record(
        np.column_stack([np.asarray(c, dtype=float).ravel() for c in columns]),
        fs=fs,
        t0=t0,
        channel_names=tuple(names),
        units=tuple(units),
        nodes=tuple(nodes),
        directions=tuple(directions),
        force_channel=force,
        source=source,
        meta=meta or {},
    )

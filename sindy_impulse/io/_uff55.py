"""Universal File Format data set 55 (data at nodes): a modal table as complex mode shapes, via pyuff.

Each mode is one data set 55 of analysis type 3 (complex eigenvalue, first order), data characteristic
2 (3-DOF translation vector), complex data, with the eigenvalue ``lambda = -zeta w + i w sqrt(1 - zeta^2)``
(``w = 2 pi f``). UFF 55 holds 6 significant digits (``E13.5``) for the eigenvalue and the shape; the
writer also puts the exact frequency and damping ratio in ID line 4
(``sindy-impulse {"f": ..., "zeta": ...}``), which :func:`read_uff55` prefers when it agrees with the
eigenvalue.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Mapping, Sequence
from datetime import datetime
from pathlib import Path

import numpy as np

from ._common import atomic_write, check_readable, decode_tag, encode_tag, require

__all__ = ["write_uff55", "read_uff55"]


def _get(mode, key: str, default=None):
    if isinstance(mode, Mapping):
        return mode.get(key, default)
    return getattr(mode, key, default)


def _mode_layout(mode, k: int, nodes, directions) -> tuple[float, float, np.ndarray, list[int], list[int]]:
    f = float(_get(mode, "frequency_hz"))
    zeta = float(_get(mode, "damping_ratio"))
    if not (math.isfinite(f) and f > 0):
        raise ValueError(f"mode {k}: frequency_hz must be positive and finite, not {f!r}")
    if not (math.isfinite(zeta) and 0 <= zeta < 1):
        raise ValueError(f"mode {k}: damping_ratio must be in [0, 1), not {zeta!r}")
    shape = _get(mode, "shape")
    single = shape is None  # a single-node shape 1 + 0j at the first node and direction
    shape = np.array([1.0 + 0.0j]) if single else np.atleast_1d(np.asarray(shape, dtype=complex))
    n = shape.size
    own_nodes, own_dirs = _get(mode, "nodes", nodes), _get(mode, "directions", directions)
    node_list = list(range(1, n + 1)) if own_nodes is None else [int(x) for x in np.ravel(own_nodes)]
    dir_list = [3] * n if own_dirs is None else [int(x) for x in np.ravel(own_dirs)]
    if single:
        node_list, dir_list = node_list[:1], dir_list[:1]
    if len(node_list) != n or len(dir_list) != n:
        raise ValueError(f"mode {k}: {n} shape values but {len(node_list)} nodes, {len(dir_list)} directions")
    if any(d not in (1, 2, 3, -1, -2, -3) for d in dir_list):
        raise ValueError(
            f"mode {k}: UFF 55 complex shapes hold directions +-1, +-2, +-3 only, got {dir_list}"
        )
    if any(nd <= 0 for nd in node_list):
        raise ValueError(f"mode {k}: node numbers must be positive, got {node_list}")
    pairs = list(zip(node_list, [abs(d) for d in dir_list]))
    if len(set(pairs)) != n:
        raise ValueError(f"mode {k}: a node and direction appear twice in {pairs}")
    return f, zeta, shape, node_list, dir_list


def _mode_set(pyuff, k: int, mode, nodes, directions, stamp: str) -> dict:
    f, zeta, shape, node_list, dir_list = _mode_layout(mode, k, nodes, directions)
    order = list(dict.fromkeys(node_list))
    r = np.zeros((3, len(order)), dtype=complex)
    for value, node, d in zip(shape, node_list, dir_list):
        r[abs(d) - 1, order.index(node)] = value if d > 0 else -value
    w = 2 * math.pi * f
    return pyuff.prepare_55(
        id1="sindy-impulse modal table",
        id2=f"mode {k}: {f:.6g} Hz, damping ratio {zeta:.4g}",
        id3=stamp,
        id4=encode_tag({"f": f, "zeta": zeta}),
        id5="NONE",
        model_type=1,
        analysis_type=3,
        data_ch=2,
        spec_data_type=8,
        data_type=5,
        n_data_per_node=3,
        r1=r[0],
        r2=r[1],
        r3=r[2],
        load_case=1,
        mode_n=k,
        eig=complex(-zeta * w, w * math.sqrt(1 - zeta**2)),
        modal_a=0j,
        modal_b=0j,
        node_nums=np.asarray(order, dtype=np.int64),
    )


def write_uff55(
    path: str | os.PathLike,
    modes: Iterable,
    *,
    nodes: Sequence[int] | None = None,
    directions: Sequence[int] | None = None,
    overwrite: bool = False,
) -> Path:
    """Write a modal table as UFF data sets 55 (one complex mode per set).

    Parameters
    ----------
    path : str or path-like
        The file to write (``.uff`` / ``.unv``); an existing one only with ``overwrite=True``.
    modes : iterable of dict or object
        Each with ``frequency_hz`` (undamped natural frequency, Hz), ``damping_ratio`` (in [0, 1)) and
        ``shape`` (complex, one value per channel; None: a single-node shape ``1 + 0j``), and optionally
        its own ``nodes`` and ``directions`` per channel. A :class:`~sindy_impulse.modes.ModalSurvey` or a
        list of its :class:`~sindy_impulse.modes.Mode` objects will do.
    nodes, directions : sequence of int, optional
        Node and direction (UFF: 1, 2, 3 = +X, +Y, +Z; negative: the opposite sense) of each channel, for
        the modes that do not carry their own. Default: nodes 1..n (channel numbers) in +Z (3).
    overwrite : bool
        Replace an existing file.

    Returns
    -------
    Path
        The file written (atomically: a temporary file in the same folder, then renamed).

    Notes
    -----
    A channel in a negative direction is stored in its axis's component with the opposite sign, so it
    reads back as the positive direction. Rotations (4-6) cannot be stored in complex UFF 55 shapes.

    Examples
    --------
    >>> import os, tempfile
    >>> modes = [{"frequency_hz": 120.0, "damping_ratio": 0.01, "shape": [1.0, 0.5 - 0.1j]},
    ...          {"frequency_hz": 310.0, "damping_ratio": 0.02, "shape": None}]
    >>> with tempfile.TemporaryDirectory() as folder:  # doctest: +SKIP
    ...     path = write_uff55(os.path.join(folder, "modes.uff"), modes)
    ...     [(m["frequency_hz"], m["damping_ratio"]) for m in read_uff55(path)]
    [(120.0, 0.01), (310.0, 0.02)]
    """
    pyuff = require("pyuff", "writing UFF files")
    stamp = datetime.now().strftime("%d-%b-%y %H:%M:%S")
    sets = [_mode_set(pyuff, k, m, nodes, directions, stamp) for k, m in enumerate(modes, start=1)]
    if not sets:
        raise ValueError("no modes to write")

    def write(tmp: str) -> None:
        try:
            # "add" to the empty temporary file: pyuff's "overwrite" truncates the file at a binary set
            pyuff.UFF(tmp).write_sets(sets, mode="add")
        except Exception as err:  # pyuff raises bare Exceptions
            raise ValueError(f"pyuff could not write the UFF 55 sets: {err}") from err

    return atomic_write(path, write, overwrite=overwrite)


def read_uff55(path: str | os.PathLike) -> list[dict]:
    """Read the modes (data sets 55, complex eigenvalue or normal mode) of a UFF file.

    Returns
    -------
    list of dict
        One per mode, in file order: ``frequency_hz`` and ``damping_ratio`` (from the exact values this
        package writes, else the eigenvalue: ``|lambda| / 2 pi`` and ``-Re lambda / |lambda|``; for a
        normal mode, the frequency and viscous damping ratio fields), ``shape`` (complex ndarray),
        ``nodes`` and ``directions`` (per shape value: for each node of the set, each direction 1-3 that
        is non-zero at that node in some mode of the file, else 3), ``mode_number``.
    """
    pyuff = require("pyuff", "reading UFF files")
    what = str(check_readable(path))
    try:
        uff = pyuff.UFF(what)
        wanted = [int(i) for i in np.flatnonzero(np.asarray(uff.get_set_types()) == 55)]
        sets = uff.read_sets(wanted) if wanted else []
    except Exception as err:  # pyuff raises bare Exceptions
        raise ValueError(f"{what}: not a readable UFF file ({err})") from err
    sets = [sets] if isinstance(sets, dict) else list(sets)
    sets = [s for s in sets if s.get("analysis_type") in (2, 3, 7)]
    if not sets:
        raise ValueError(f"{what}: no mode data set 55 (normal or complex eigenvalue analysis) in the file")
    used: dict[int, set[int]] = {}
    for s in sets:
        for j, node in enumerate(np.ravel(s["node_nums"])):
            used.setdefault(int(node), set()).update(d for d in (1, 2, 3) if s[f"r{d}"][j] != 0)
    return [_mode_from_set(s, used) for s in sets]


def _mode_from_set(s: dict, used: dict[int, set[int]]) -> dict:
    if s["analysis_type"] == 2:
        f, zeta = float(s["freq"]), float(s.get("modal_damp_vis", 0.0))
    else:
        lam = complex(s["eig"])
        f, zeta = abs(lam) / (2 * math.pi), (-lam.real / abs(lam) if lam else 0.0)
    tag = decode_tag(s.get("id4")) or {}
    if "f" in tag and abs(float(tag["f"]) - f) <= 1e-4 * f and abs(float(tag["zeta"]) - zeta) <= 1e-4:
        f, zeta = float(tag["f"]), float(tag["zeta"])
    shape, node_out, dir_out = [], [], []
    for j, node in enumerate(np.ravel(s["node_nums"])):
        for d in sorted(used[int(node)]) or [3]:
            shape.append(complex(s[f"r{d}"][j]))
            node_out.append(int(node))
            dir_out.append(d)
    return {
        "frequency_hz": f,
        "damping_ratio": zeta,
        "shape": np.asarray(shape, dtype=complex),
        "nodes": node_out,
        "directions": dir_out,
        "mode_number": int(s.get("mode_n", 0)),
    }

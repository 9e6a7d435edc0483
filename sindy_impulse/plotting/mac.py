"""The Modal Assurance Criterion as a picture: one cell per pair of modes, dark where the shapes agree.

Reads a MAC matrix, a :class:`~sindy_impulse.analysis.MacResult` or mode shapes (computed with
:func:`sindy_impulse.analysis.mac_result`); matplotlib is imported only when the function is called, and
``plt.show()`` is never called.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ._common import one_axes

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["plot_mac"]

#: Cells darker than this MAC get white annotations.
_WHITE_TEXT_ABOVE = 0.6
#: How far outside [0, 1] a given matrix may stray by rounding.
_TOLERANCE = 1e-9
_AXIS = {"labels_a": "row", "labels_b": "column"}


def _holds_modes(obj) -> bool:
    """Whether ``obj`` is (or holds) mode objects or ``None`` entries: shapes, not a MAC matrix."""
    if hasattr(obj, "frequency_hz") or (hasattr(obj, "modes") and not isinstance(obj, np.ndarray)):
        return True
    if isinstance(obj, (list, tuple)) and any(e is None or hasattr(e, "frequency_hz") for e in obj):
        return True
    try:
        return bool(np.iscomplexobj(np.asarray(obj)))  # complex shapes: a MAC matrix is real
    except (TypeError, ValueError):
        return False


def _as_matrix(value) -> tuple[np.ndarray, list[str], list[str]]:
    """A given MAC matrix, checked, with index labels."""
    try:
        m = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(
            f"matrix_or_shapes_a must be a MAC matrix, a MacResult or mode shapes, got {type(value).__name__}"
        ) from None
    if m.ndim != 2 or 0 in m.shape:
        raise ValueError(f"a MAC matrix must be 2-D and non-empty, got shape {m.shape}")
    if not np.all(np.isfinite(m)) or m.min() < -_TOLERANCE or m.max() > 1 + _TOLERANCE:
        raise ValueError(
            "a MAC matrix holds values in [0, 1]; for the auto-MAC of real mode shapes pass "
            "plot_mac(shapes, shapes) or plot_mac(mac_result(shapes))"
        )
    return np.clip(m, 0.0, 1.0), [str(i) for i in range(m.shape[0])], [str(j) for j in range(m.shape[1])]


def _resolve(matrix_or_shapes_a, shapes_b):
    """The matrix, its row and column labels, and whether it is an auto-MAC."""
    from ..analysis.mac import MacResult, mac_result

    value = matrix_or_shapes_a
    if isinstance(value, MacResult):
        if shapes_b is not None:
            raise TypeError("shapes_b must be None when a MacResult is given")
        return value.matrix, list(value.labels_a), list(value.labels_b), value.auto
    if shapes_b is not None or _holds_modes(value):
        res = mac_result(value, shapes_b)
        return res.matrix, list(res.labels_a), list(res.labels_b), res.auto
    m, rows, cols = _as_matrix(value)
    return m, rows, cols, False


def _check_labels(labels, n: int, name: str, default: list[str]) -> list[str]:
    if labels is None:
        return default
    if isinstance(labels, str) or len(labels) != n:
        got = "a string" if isinstance(labels, str) else f"{len(labels)} labels"
        raise ValueError(f"{name} must hold {n} labels, one per {_AXIS[name]}, got {got}")
    return [str(s) for s in labels]


def plot_mac(
    matrix_or_shapes_a,
    shapes_b=None,
    *,
    labels_a=None,
    labels_b=None,
    ax=None,
    annotate: bool = True,
) -> Axes:
    """A MAC matrix as an image: one cell per pair of modes, from white (0) to dark blue (1).

    Parameters
    ----------
    matrix_or_shapes_a : ndarray (n_a, n_b), MacResult or mode shapes
        A MAC matrix (real, in [0, 1]), a :class:`~sindy_impulse.analysis.MacResult`, or the first set of
        mode shapes in any form :func:`~sindy_impulse.analysis.mac` takes (an array, a sequence of shapes,
        ``None`` entries or :class:`~sindy_impulse.modes.Mode` objects, a ModalSurvey). A real 2-D array
        without ``shapes_b`` is read as a MAC matrix; complex shapes, sequences of modes and anything with
        ``shapes_b`` are read as shapes. For the auto-MAC of real shapes pass them twice or a MacResult.
    shapes_b : mode shapes, optional
        The second set (columns); the MAC of the two sets is drawn.
    labels_a, labels_b : sequence of str, optional
        Row and column labels. Default: ``"k: 120.3 Hz"`` for mode objects (``k`` their index in the
        input), else the index.
    ax : matplotlib Axes, optional
        Where to draw (default: a new figure).
    annotate : bool, default=True
        Write each cell's value in it.

    Returns
    -------
    Axes
        The image (``ax.images[0]``, its array the MAC matrix), with a colorbar labelled "MAC"; rows are
        the first set (y axis), columns the second (x axis).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np
    >>> from sindy_impulse.plotting import plot_mac
    >>> shapes = np.array([[1.0, 1.0, 0.0], [1.0, -1.0, 0.2], [0.0, 0.3, 1.0]]) * (1 + 0.5j)
    >>> ax = plot_mac(shapes)
    >>> ax.images[0].get_array().shape, len(ax.texts), ax.get_title()
    ((3, 3), 9, 'auto-MAC')
    """
    if not isinstance(annotate, (bool, np.bool_)):
        raise TypeError(f"annotate must be True or False, got {annotate!r}")
    matrix, rows, cols, auto = _resolve(matrix_or_shapes_a, shapes_b)
    rows = _check_labels(labels_a, matrix.shape[0], "labels_a", rows)
    cols = _check_labels(labels_b, matrix.shape[1], "labels_b", cols)
    ax = one_axes(ax)
    image = ax.imshow(matrix, cmap="Blues", vmin=0.0, vmax=1.0, interpolation="nearest", aspect="equal")
    slanted = any(len(c) > 3 for c in cols)
    ax.set_xticks(
        np.arange(matrix.shape[1]), cols, rotation=30 if slanted else 0, ha="right" if slanted else "center"
    )
    ax.set_yticks(np.arange(matrix.shape[0]), rows)
    ax.set_xlabel("mode" if auto else "modes B")
    ax.set_ylabel("mode" if auto else "modes A")
    ax.set_title("auto-MAC" if auto else "MAC")
    if annotate:
        for (i, j), v in np.ndenumerate(matrix):
            color = "white" if v > _WHITE_TEXT_ABOVE else "black"
            ax.text(j, i, f"{v:.2f}", ha="center", va="center", color=color, fontsize="small")
    ax.figure.colorbar(image, ax=ax, label="MAC")
    return ax

"""The Modal Assurance Criterion (MAC): how alike two sets of mode shapes are.

For mode shapes ``a_i`` and ``b_j`` (complex or real, one value per channel)

    MAC[i, j] = |a_i^H b_j|**2 / ((a_i^H a_i) (b_j^H b_j)),

the squared cosine of the angle between them: 1 for shapes equal up to a complex factor, 0 for orthogonal
ones, independent of how each shape is scaled or rotated in phase. The auto-MAC (a set against itself) is
symmetric with ones on its diagonal; off-diagonal values near 1 mean two modes the sensors cannot tell apart
by their shapes.

Reference: R. J. Allemang and D. L. Brown, "A correlation coefficient for modal vector analysis", Proc. 1st
International Modal Analysis Conference (IMAC), 1982; R. J. Allemang, "The modal assurance criterion -
twenty years of use and abuse", Sound and Vibration 37(8), 2003.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..exceptions import DataWarning
from ..poles.stabilisation import mac_matrix

__all__ = ["MacResult", "mac", "mac_result"]


@dataclass(frozen=True)
class MacResult:
    """A MAC matrix and which of the given modes it is made of (see :func:`mac_result`).

    Attributes
    ----------
    matrix : ndarray (len(rows), len(columns))
        ``MAC[i, j]`` between the kept shapes ``rows[i]`` of ``shapes_a`` and ``columns[j]`` of ``shapes_b``,
        in [0, 1].
    rows, columns : ndarray of int
        Indices (into ``shapes_a`` and ``shapes_b``) of the modes kept: those with a mode shape.
    dropped_a, dropped_b : tuple of int
        Indices of the modes left out because they have no shape (``None``, or a mode whose ``shape`` is
        None).
    labels_a, labels_b : list of str
        One label per kept mode: ``"k: 120.3 Hz"`` for a mode object (``k`` its index in the input), else
        ``"k"``.
    auto : bool
        True for an auto-MAC (``shapes_b`` not given): then ``columns``, ``dropped_b`` and ``labels_b`` are
        those of ``shapes_a``.
    """

    matrix: np.ndarray
    rows: np.ndarray
    columns: np.ndarray
    dropped_a: tuple
    dropped_b: tuple
    labels_a: list
    labels_b: list
    auto: bool = False

    @property
    def shape(self) -> tuple:
        """The shape of :attr:`matrix`."""
        return self.matrix.shape


def _is_mode(obj) -> bool:
    """A mode object (like :class:`sindy_impulse.modes.Mode`): its ``shape`` attribute is the mode shape.

    Arrays also have a ``.shape`` (their dimensions); modes are told apart by their ``frequency_hz``.
    """
    return not isinstance(obj, np.ndarray) and hasattr(obj, "frequency_hz") and hasattr(obj, "shape")


def _entries(shapes, name: str) -> list:
    """The entries of ``shapes``: one per mode (a 1-D array-like, a mode object or None)."""
    if shapes is None:
        raise TypeError(f"{name} must be mode shapes (an array or a sequence), got None")
    if _is_mode(shapes):
        return [shapes]
    if not isinstance(shapes, (np.ndarray, list, tuple)) and hasattr(shapes, "modes"):
        return list(shapes.modes)  # a ModalSurvey
    if isinstance(shapes, (str, bytes, dict)):
        raise TypeError(f"{name} must be mode shapes (an array or a sequence), got {type(shapes).__name__}")
    if isinstance(shapes, np.ndarray) and shapes.dtype != object:
        if shapes.ndim not in (1, 2):
            raise ValueError(
                f"{name} must be 2-D (n_modes, n_channels) or one 1-D shape, got {shapes.ndim}-D"
            )
        return list(np.atleast_2d(shapes))
    try:
        entries = list(shapes)
    except TypeError:
        raise TypeError(
            f"{name} must be mode shapes (an array or a sequence), got {type(shapes).__name__}"
        ) from None
    if entries and all(np.ndim(e) == 0 and e is not None and not _is_mode(e) for e in entries):
        return [np.asarray(entries)]  # a flat list of numbers: one shape
    return entries


def _vector(entry, label: str) -> np.ndarray:
    try:
        v = np.asarray(entry, dtype=complex)
    except (TypeError, ValueError):
        raise TypeError(f"{label} must be a numeric 1-D mode shape, got {type(entry).__name__}") from None
    if v.ndim != 1 or v.size == 0:
        raise ValueError(f"{label} must be a non-empty 1-D mode shape, got shape {v.shape}")
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{label} has non-finite values (NaN or inf)")
    if not np.any(v):
        raise ValueError(f"{label} is zero: a mode shape needs a non-zero norm")
    return v


def _label(index: int, entry) -> str:
    if _is_mode(entry):
        try:
            return f"{index}: {float(entry.frequency_hz):.4g} Hz"
        except (TypeError, ValueError):
            pass
    return str(index)


def _collect(shapes, name: str):
    """Unit-norm shapes (n_kept, n_channels), the kept indices, the dropped ones and the labels."""
    entries = _entries(shapes, name)
    if not entries:
        raise ValueError(f"{name} holds no mode shape")
    kept, dropped, vectors, labels = [], [], [], []
    for i, entry in enumerate(entries):
        shape = entry.shape if _is_mode(entry) else entry
        if shape is None:
            dropped.append(i)
            continue
        v = _vector(shape, f"{name}[{i}]")
        if vectors and v.size != vectors[0].size:
            raise ValueError(
                f"{name}[{i}] has {v.size} channels but {name}[{kept[0]}] has {vectors[0].size}: "
                "all shapes of a set need the same channels"
            )
        kept.append(i)
        # MAC is scale-free: an exact power-of-two scaling keeps the squared norms from over/underflowing
        e = -np.frexp(np.abs(v).max())[1]
        vectors.append(np.ldexp(v.real, e) + 1j * np.ldexp(v.imag, e))
        labels.append(_label(i, entry))
    if not kept:
        raise ValueError(f"{name}: none of its {len(entries)} modes has a mode shape")
    if dropped:
        named = ", ".join(
            f"{name}[{i}] ({_label(i, entries[i])})" if _is_mode(entries[i]) else f"{name}[{i}]"
            for i in dropped
        )
        # stack: _collect, _mac_result, mac or mac_result, the caller
        warnings.warn(
            f"mac: {len(dropped)} mode(s) without a mode shape left out: {named}", DataWarning, stacklevel=4
        )
    return np.array(vectors), np.array(kept, dtype=int), tuple(dropped), labels



def mac_result(shapes_a, shapes_b=None) -> MacResult:
    """The MAC matrix with the indices and labels of the modes it is made of.

    The same as :func:`mac` (see there for the arguments), but returns a :class:`MacResult`: ``matrix``,
    ``rows`` and ``columns`` (the indices of the kept modes, those with a shape), ``dropped_a`` and
    ``dropped_b`` (the ones left out) and ``labels_a`` and ``labels_b`` (for plots).

    Examples
    --------
    >>> import warnings
    >>> import numpy as np
    >>> from sindy_impulse.analysis import mac_result
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")  # the DataWarning naming shapes_a[1]
    ...     res = mac_result([[1.0, 1.0], None, [1.0, -1.0]], [[1.0, 1.0]])
    >>> res.rows.tolist(), res.columns.tolist(), res.dropped_a, res.matrix.round(12).tolist()
    ([0, 2], [0], (1,), [[1.0], [0.0]])
    """
    return _mac_result(shapes_a, shapes_b)


def _mac_result(shapes_a, shapes_b) -> MacResult:
    A, rows, dropped_a, labels_a = _collect(shapes_a, "shapes_a")
    if shapes_b is None:
        gram = mac_matrix(A, A)
        matrix = np.triu(gram) + np.triu(gram, 1).T  # exactly symmetric
        return MacResult(matrix, rows, rows.copy(), dropped_a, dropped_a, labels_a, list(labels_a), True)
    B, columns, dropped_b, labels_b = _collect(shapes_b, "shapes_b")
    if A.shape[1] != B.shape[1]:
        raise ValueError(
            f"shapes_a has {A.shape[1]} channels but shapes_b has {B.shape[1]}: MAC compares shapes measured "
            "on the same channels"
        )
    matrix = mac_matrix(A, B)
    return MacResult(matrix, rows, columns, dropped_a, dropped_b, labels_a, labels_b)


def mac(shapes_a, shapes_b=None) -> np.ndarray:
    """Modal Assurance Criterion matrix ``|a_i^H b_j|**2 / ((a_i^H a_i) (b_j^H b_j))`` of two sets of shapes.

    Parameters
    ----------
    shapes_a : array-like (n_modes, n_channels), or sequence
        The mode shapes, complex or real: a 2-D array with one shape per row (a 1-D array is one shape), or
        a sequence with one entry per mode, each a 1-D array-like, ``None`` (a mode without a shape) or a
        mode object such as :class:`sindy_impulse.modes.Mode` whose ``shape`` attribute is its complex
        shape per channel or None (told apart from arrays, which also have ``.shape``, by a
        ``frequency_hz`` attribute). A :class:`~sindy_impulse.modes.ModalSurvey` stands for its modes.
    shapes_b : same as ``shapes_a``, optional
        The second set; None: the auto-MAC of ``shapes_a`` (symmetric, ones on the diagonal).

    Returns
    -------
    ndarray (n_kept_a, n_kept_b)
        ``MAC[i, j]`` in [0, 1] between the i-th and j-th modes that have a shape. Modes without one are
        left out with a :class:`~sindy_impulse.exceptions.DataWarning` naming them; :func:`mac_result`
        returns the same matrix with the indices of the rows and columns kept.

    Raises
    ------
    ValueError
        The two sets (or two shapes of one set) have different channel counts; a shape is zero, empty or
        not finite; a set has no shape at all.
    TypeError
        A shape is not numeric.

    Notes
    -----
    MAC is invariant to a complex factor on each shape (``mac(a, c * a) == 1``) and symmetric in its sets
    (``mac(b, a) == mac(a, b).T``). It says how alike the shapes are, not that they are right: a few
    channels make unrelated shapes look alike.

    Examples
    --------
    Two orthogonal shapes measured on two channels:

    >>> import numpy as np
    >>> from sindy_impulse.analysis.mac import mac  # also ``from sindy_impulse.analysis import mac``
    >>> phi = np.array([[1.0, 1.0], [1.0, -1.0]])
    >>> mac(phi).round(12).tolist()
    [[1.0, 0.0], [0.0, 1.0]]
    >>> float(mac([1.0, 2.0, 3.0], [2j, 4j, 6j])[0, 0]), float(mac([1.0, 0.0], [1.0, 1.0])[0, 0])
    (1.0, 0.5)
    """
    return _mac_result(shapes_a, shapes_b).matrix

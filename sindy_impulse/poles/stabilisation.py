"""The stabilisation diagram of a free decay: ESPRIT poles over a range of model orders, and which are stable.

A physical mode's pole stays put when the model order grows; noise and computational poles wander. The
experimental modal analysis tools (LSCF, SSI, ERA) show every pole on a chart of order against frequency
and keep the ones that recur: here a pole is **stable** when, at :data:`MIN_ORDERS` or more orders of the
range (its own included), some physical pole lies within :data:`FREQUENCY_TOL` (relative) of its
undamped natural frequency and :data:`DAMPING_TOL` (relative) of its damping ratio (and, with several
channels, whose mode shape has a MAC of at least :data:`MAC_TOL` with its own). Each order's poles are
:func:`~sindy_impulse.poles.esprit`'s physical ones (oscillatory, decaying, above the noise in their band,
not a split of a stronger pole), all from one Hankel decomposition (:class:`~.esprit.SignalSpace`).

:meth:`PoleTable.modes` gathers the stable poles into one mode per cluster of frequencies: the medians of
its poles' frequencies and damping ratios, and the number of orders that found it.
"""

from __future__ import annotations

from dataclasses import dataclass
from numbers import Integral, Real

import numpy as np

from .._utils.params import Interval, check_param
from .._utils.threads import one_thread
from .._utils.validation import check_signal
from .esprit import MAX_ROWS, SignalSpace, _sampling_step

__all__ = [
    "stabilisation", "PoleTable", "StableMode", "ORDERS", "FREQUENCY_TOL", "DAMPING_TOL", "MAC_TOL",
    "MIN_ORDERS", "mac_matrix",
]

#: Model orders of the diagram (complex exponentials fitted: two per mode).
ORDERS = tuple(range(10, 61, 2))
#: A pole recurs at another order within this relative difference of its natural frequency ...
FREQUENCY_TOL = 0.005
#: ... and this relative difference of its damping ratio ...
DAMPING_TOL = 0.1
#: ... and, with several channels, this modal assurance criterion between the two poles' mode shapes ...
MAC_TOL = 0.9
#: ... at this many orders (its own included) to be stable.
MIN_ORDERS = 5


@dataclass(frozen=True)
class StableMode:
    """One cluster of stable poles: a mode the diagram finds.

    Attributes
    ----------
    frequency_hz, damping_ratio : float
        Medians over the cluster's poles (undamped natural frequency, damping ratio).
    n_orders : int
        Orders with a pole in the cluster.
    frequency_spread_hz, damping_ratio_spread : float
        How far its poles scatter about the medians (1.4826 times their median absolute deviation; 0 for
        one pole): a floor under the medians' standard deviations (the orders read the same samples, so
        their scatter is the model order's share of the error, not the noise's).
    """

    frequency_hz: float
    damping_ratio: float
    n_orders: int
    frequency_spread_hz: float = 0.0
    damping_ratio_spread: float = 0.0


@dataclass(frozen=True)
class PoleTable:
    """Every physical pole of the diagram, one row per pole and order.

    Attributes
    ----------
    frequency_hz, damping_ratio : ndarray (n_poles,)
        Undamped natural frequency and damping ratio.
    order : ndarray of int (n_poles,)
        The model order the pole was found at.
    stable : ndarray of bool (n_poles,)
        Whether it recurs (see the module).
    orders : tuple of int
        The orders of the diagram.
    mode_shape : ndarray of complex (n_poles, n_channels) or None
        Each pole's complex amplitude in every channel (None for a table without them).
    """

    frequency_hz: np.ndarray
    damping_ratio: np.ndarray
    order: np.ndarray
    stable: np.ndarray
    orders: tuple
    mode_shape: np.ndarray | None = None

    def __len__(self) -> int:
        return int(self.order.size)

    def modes(self) -> list[StableMode]:
        """The stable poles gathered into modes, by frequency: neighbours (sorted by frequency) closer
        than :data:`FREQUENCY_TOL` belong to one cluster.

        Examples
        --------
        >>> from sindy_impulse.datasets import impact_record
        >>> rec = impact_record([40.0, 110.0], [0.01, 0.004], fs=2000.0, duration=2.0, random_state=0)
        >>> table = stabilisation(rec.y[rec.free_decay_index:], fs=rec.fs)
        >>> [(round(m.frequency_hz, 2), round(m.damping_ratio, 4)) for m in table.modes()]
        [(40.0, 0.01), (110.0, 0.004)]
        """
        f, zeta, k = self.frequency_hz[self.stable], self.damping_ratio[self.stable], self.order[self.stable]
        if f.size == 0:
            return []
        sort = np.argsort(f)
        f, zeta, k = f[sort], zeta[sort], k[sort]
        breaks = np.flatnonzero(np.diff(f) > FREQUENCY_TOL * f[1:]) + 1
        return [_stable_mode(f[g], zeta[g], k[g]) for g in np.split(np.arange(f.size), breaks)]


def _stable_mode(f: np.ndarray, zeta: np.ndarray, orders: np.ndarray) -> StableMode:
    """One cluster's :class:`StableMode`: medians, the orders it spans, the scatter about the medians."""
    fm, zm = float(np.median(f)), float(np.median(zeta))
    return StableMode(fm, zm, int(np.unique(orders).size), float(1.4826 * np.median(np.abs(f - fm))),
                      float(1.4826 * np.median(np.abs(zeta - zm))))


def mac_matrix(shapes_a: np.ndarray, shapes_b: np.ndarray) -> np.ndarray:
    """Modal assurance criterion between every row of ``shapes_a`` and every row of ``shapes_b``:
    ``|a^H b|**2 / ((a^H a) (b^H b))``, 1 for shapes equal up to a complex factor, 0 for orthogonal ones
    (and for a zero shape). The arithmetic only; :func:`sindy_impulse.analysis.mac` takes modes and
    surveys, checks them and leaves out modes without a shape.

    Examples
    --------
    >>> a = np.array([[1.0, 2.0], [1.0, -0.5]])
    >>> np.round(mac_matrix(a, 3j * a), 6).tolist()
    [[1.0, 0.0], [0.0, 1.0]]
    """
    a, b = np.atleast_2d(shapes_a), np.atleast_2d(shapes_b)
    norms = np.outer(np.sum(a.real**2 + a.imag**2, axis=1), np.sum(b.real**2 + b.imag**2, axis=1))
    cross = a.conj() @ b.T
    ratio = (cross.real**2 + cross.imag**2) / np.where(norms > 0, norms, 1.0)
    return np.where(norms > 0, np.minimum(ratio, 1.0), 0.0)  # a zero shape is like nothing


def _stable(f: np.ndarray, zeta: np.ndarray, order: np.ndarray, min_orders: int, shape=None) -> np.ndarray:
    """Per pole: whether poles within the tolerances (mode shapes too, with several channels) stand at
    ``min_orders`` orders or more."""
    close = np.abs(f[:, None] - f[None, :]) <= FREQUENCY_TOL * f[:, None]
    close &= np.abs(zeta[:, None] - zeta[None, :]) <= DAMPING_TOL * zeta[:, None]
    if shape is not None and shape.ndim == 2 and shape.shape[1] > 1:
        close &= mac_matrix(shape, shape) >= MAC_TOL
    levels = np.unique(order)
    at_order = order[None, :] == levels[:, None]  # (n_orders, n_poles)
    counts = (close.astype(np.int64) @ at_order.T.astype(np.int64) > 0).sum(axis=1)
    return counts >= min_orders


def stabilisation(
    y,
    t=None,
    *,
    fs: float | None = None,
    orders=ORDERS,
    min_orders: int = MIN_ORDERS,
    max_rows: int = MAX_ROWS,
    min_snr_db: float = 10.0,
) -> PoleTable:
    """The stabilisation diagram of a free decay: physical ESPRIT poles at each order, stable or not.

    Parameters
    ----------
    y : array-like (n,) or (n, n_channels)
        The free decay (from the end of the hit on), offset removed; channels share the poles.
    t : float or array-like, optional
        Time step or uniform time vector; or give ``fs``.
    fs : float, optional
        Sampling rate (Hz).
    orders : sequence of int, default=ORDERS (10, 12, ..., 60)
        Model orders (complex exponentials: two per mode); orders above what the record's Hankel matrix
        holds (``L - 2``) are left out.
    min_orders : int, default=MIN_ORDERS
        Orders a pole must recur at to be stable.
    max_rows, min_snr_db
        As in :func:`~sindy_impulse.poles.esprit`.

    Returns
    -------
    PoleTable

    Examples
    --------
    >>> from sindy_impulse.datasets import impact_record
    >>> rec = impact_record(80.0, 0.02, fs=1000.0, duration=1.0, snr_db=40, random_state=1)
    >>> table = stabilisation(rec.y[rec.free_decay_index:], fs=rec.fs)
    >>> bool(table.stable.any()), [round(m.frequency_hz) for m in table.modes()]
    (True, [80])
    """
    Y = check_signal(y, "y", min_samples=8)
    dt = _sampling_step(t, fs, Y.shape[0])
    check_param("min_orders", min_orders, [Interval(Integral, 1, None)], "stabilisation")
    check_param("max_rows", max_rows, [Interval(Integral, 3, None)], "stabilisation")
    check_param("min_snr_db", min_snr_db, [Interval(Real, None, None)], "stabilisation")
    wanted = np.asarray(list(orders) if not isinstance(orders, np.ndarray) else orders)
    integers = wanted.ndim == 1 and wanted.size > 0 and np.issubdtype(wanted.dtype, np.integer)
    if not integers or np.any(wanted < 1):
        raise ValueError(f"orders must be a non-empty sequence of positive integers, got {orders!r}")
    rows, shapes = [], []
    with one_thread("blas"):  # a loaded machine: threads made it 100x slower
        space = SignalSpace(Y, max_rows)
        usable = tuple(int(k) for k in np.unique(wanted) if k <= space.rows - 2)
        for k in usable:
            _, s, c, _, idx = space.poles(k, dt, min_snr_db)
            rows += [(abs(p) / (2 * np.pi), -p.real / abs(p), k) for p in s[idx]]
            shapes += list(c[idx])
    f, zeta, order = (np.array(col, dtype=float) for col in zip(*rows)) if rows else (np.empty(0),) * 3
    order = order.astype(int)
    shape = np.array(shapes, dtype=complex).reshape(len(rows), Y.shape[1])
    return PoleTable(f, zeta, order, _stable(f, zeta, order, min_orders, shape), usable, shape)

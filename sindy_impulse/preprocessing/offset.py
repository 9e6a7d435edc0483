"""Offset and trend of a hammer-test record: estimate (saying how) and remove.

Methods:

- ``"pre_trigger"``: mean of the samples before the onset (the sensor's resting value);
- ``"tail"``: mean of the last quarter of the ring-down. Without a pre-trigger this is the best simple
  estimate: the oscillation there is smallest and averages out over its periods (the bias is at most
  the tail's amplitude over pi times its number of periods);
- ``"linear"``: least-squares line through the ring-down (offset plus drift; the oscillation is nearly
  orthogonal to a line over many periods);
- ``"auto"``: ``"pre_trigger"`` with at least 32 pre-trigger samples, else ``"tail"``;
- a number: that offset, taken as given.
"""

from __future__ import annotations

from dataclasses import dataclass
from numbers import Integral, Real

import numpy as np

from .._utils.params import Interval, Options, check_param
from ._record import check_fs, check_signal_1d

__all__ = ["OffsetEstimate", "estimate_offset", "remove_offset"]

_METHODS = Options({"auto", "pre_trigger", "tail", "linear"})
#: Fewest pre-trigger samples the "auto" method averages; with fewer it uses the tail.
MIN_PRE_TRIGGER = 32
_TAIL_FRACTION = 0.25


@dataclass(frozen=True)
class OffsetEstimate:
    """An offset (and drift) and how it was estimated.

    Attributes
    ----------
    value : float
        The offset at the onset, in the units of the record.
    slope : float
        Drift per second (0 unless ``method == "linear"``).
    method : str
        ``"pre_trigger"``, ``"tail"``, ``"linear"`` or ``"given"``.
    onset_index : int
        The sample the line is anchored at.
    n_samples : int
        Samples the estimate averaged.
    relative : float
        ``|value|`` over the ring-down's largest excursion from it.
    """

    value: float
    slope: float
    method: str
    onset_index: int
    n_samples: int
    relative: float

    def trend(self, n_samples: int, fs: float) -> np.ndarray:
        """The offset (and drift) at each of ``n_samples`` samples."""
        return self.value + self.slope * (np.arange(n_samples) - self.onset_index) / fs

    def __repr__(self) -> str:
        drift = f", drift {self.slope:.4g}/s" if self.slope else ""
        return (
            f"OffsetEstimate({self.value:.6g}{drift} from the {self.method.replace('_', '-')} "
            f"({self.n_samples} samples), {self.relative:.3g} x the ring-down amplitude)"
        )


def _fit(ring: np.ndarray, method: str, fs: float) -> tuple[float, float, int]:
    """Offset at the first sample of ``ring``, slope per second, samples used."""
    if method == "tail":
        tail = ring[int((1 - _TAIL_FRACTION) * ring.size) :]
        return float(tail.mean()), 0.0, tail.size
    slope, value = np.polyfit(np.arange(ring.size) / fs, ring, 1)
    return float(value), float(slope), ring.size


def estimate_offset(y, fs: float, *, onset_index: int = 0, method="auto") -> OffsetEstimate:
    """Estimate the offset (and drift) of a record.

    Parameters
    ----------
    y : array-like (n,)
        The record.
    fs : float
        Sampling rate (Hz).
    onset_index : int
        First sample of the hit (0: no pre-trigger).
    method : {"auto", "pre_trigger", "tail", "linear"} or float
        See the module docstring; a number is taken as the offset.

    Returns
    -------
    OffsetEstimate

    Examples
    --------
    >>> t = np.arange(2000) / 1000
    >>> y = 0.5 + np.where(t >= 0.5, np.exp(-3 * (t - 0.5)) * np.sin(2 * np.pi * 40 * (t - 0.5)), 0)
    >>> estimate_offset(y, 1000.0, onset_index=500)
    OffsetEstimate(0.5 from the pre-trigger (500 samples), 0.51 x the ring-down amplitude)
    >>> round(estimate_offset(y[500:], 1000.0).value, 3)  # no pre-trigger: the tail
    0.5
    """
    rate = check_fs(fs)
    arr = check_signal_1d(y, "y")
    check_param("onset_index", onset_index, [Interval(Integral, 0, arr.size - 2)], "estimate_offset")
    check_param("method", method, [_METHODS, Real], "estimate_offset")
    ring = arr[onset_index:]
    if not isinstance(method, str):
        value, slope, used, name = float(method), 0.0, 0, "given"
    else:
        name = method
        if method == "auto":
            name = "pre_trigger" if onset_index >= MIN_PRE_TRIGGER else "tail"
        if name == "pre_trigger":
            if onset_index == 0:
                raise ValueError("method='pre_trigger' needs a pre-trigger: onset_index is 0")
            value, slope, used = float(arr[:onset_index].mean()), 0.0, onset_index
        else:
            value, slope, used = _fit(ring, name, rate)
    excursion = np.abs(ring - value - slope * np.arange(ring.size) / rate).max()
    relative = abs(value) / excursion if excursion > 0 else float("inf")
    return OffsetEstimate(value, slope, name, int(onset_index), int(used), float(relative))


def remove_offset(y, fs: float, estimate: OffsetEstimate) -> np.ndarray:
    """``y`` minus the estimated offset (and drift), as a new array.

    Examples
    --------
    >>> y = 3.0 + np.sin(np.arange(200) / 3)
    >>> est = estimate_offset(y, 100.0, method=3.0)
    >>> bool(abs(np.mean(remove_offset(y, 100.0, est)[:189])) < 0.01)  # 9 whole periods
    True
    """
    arr = check_signal_1d(y, "y")
    if not isinstance(estimate, OffsetEstimate):
        raise TypeError(f"estimate must be an OffsetEstimate (from estimate_offset), got {type(estimate)}")
    return arr - estimate.trend(arr.size, check_fs(fs))

"""The frequency axis cut into one band per peak, and joint bands for peaks too close for their damping.

- One band per peak (:func:`peak_bands`): ``(f / r, f r)``, ``r = 1 + max(width_factor hpw / f,
  min_half_width)``, with ``r`` at most the square root of the frequency ratio to either neighbour (the
  geometric midpoint): symmetric in log frequency, so the mode sits at the band's centre, off the
  filter's slopes, and a close neighbour narrows both edges and stays in the filter's stop band. A band
  never holds a neighbour's centre. The default :data:`WIDTH_FACTOR` (12 half-power widths) keeps what an
  isolated mode loses to the filter's transient (about ``1.9 / (r - 1)`` periods trimmed) at about 0.5
  neper of its decay at any damping (5 widths: up to 1.25 neper on a 1-2 %-damped mode, whose largest
  amplitudes, where an amplitude-dependent damping shows most, were then lost with the transient).
- Joint bands (:func:`band_groups`): the band-pass trims its transient, about ``4.2 / bandwidth``
  seconds, from the start of the ring-down. A strongly damped mode next to another (e.g. 205.9 Hz at
  2 % beside 216.6 Hz at 0.12 %: a 10.5 Hz band, 0.4 s trimmed, the first mode 88 dB down by then) loses
  its decay to it. Peaks whose own band costs them more than ``max_loss_db`` of decay are grouped with
  the neighbour that limits that band (and with the next one while the joint band is still too narrow
  for a member); a group's joint band runs from its lowest member's lower edge to its highest member's
  upper edge, each limited only by the neighbours outside the group. Such a group is one band signal
  holding several modes (fitted together, one oscillator each).
- Resolved modes (:func:`resolved`): two modes closer than the wider one's half-power half-width are not
  two modes a record can tell apart; a peak at a harmonic's place (:func:`at_harmonic_place`) is left
  whole for the harmonic test.
"""

from __future__ import annotations

from numbers import Real

import numpy as np

from .._utils.params import Interval, check_param
from ._record import check_fs
from .filters import transient_samples

__all__ = ["peak_bands", "band_groups", "resolved", "at_harmonic_place", "WIDTH_FACTOR", "HARMONIC_NEAR"]

#: Half-power widths a peak's own band spans on each side (at least ``min_half_width`` of its frequency).
WIDTH_FACTOR = 12.0
#: Highest band edge over the sampling rate.
_TOP = 0.499


def resolved(frequency_hz: tuple[float, float], damping_ratio: tuple[float, float]) -> bool:
    """Whether two modes are at least the wider one's half-power half-width (``zeta f``) apart.

    Closer than that they are the pieces of one mode that a linear fit cuts in two: the stable poles of a
    mode whose frequency moves with amplitude (593.0 Hz as 594.2 and 596.2 Hz), or an
    amplitude-dependent damping's two decay rates (a 73.0 Hz mode at damping ratio 0.015 with an ``x^2 x'``
    damper as poles at 73.04 Hz, 0.017, and 71.9 Hz, 0.137). Two true modes that a record resolves are
    farther apart, at least about the sum of their half-power half-widths (``zeta1 f1 + zeta2 f2``, more
    than the wider one's alone).

    Examples
    --------
    >>> resolved((73.04, 71.94), (0.017, 0.137)), resolved((252.99, 253.92), (0.0012, 0.0009))
    (False, True)
    """
    width = max(z * f for f, z in zip(frequency_hz, damping_ratio))
    return bool(abs(frequency_hz[1] - frequency_hz[0]) >= width)


#: A frequency within this relative distance of 2 or 3 times a lower one may be its harmonic (the harmonic
#: test of :mod:`sindy_impulse.modes._harmonics` looks at the same distance, ``NEAR``).
HARMONIC_NEAR = 0.06


def at_harmonic_place(frequency_hz: float, others) -> bool:
    """Whether ``frequency_hz`` lies within :data:`HARMONIC_NEAR` of 2 or 3 times one of ``others`` (those
    below ``frequency_hz / 1.5`` count): a peak or mode there may be a harmonic, and steps that would cut it
    or refit it leave it as it is for the harmonic test.

    Examples
    --------
    >>> at_harmonic_place(55.3, [18.79, 40.0]), at_harmonic_place(70.0, [18.79, 40.0])
    (True, False)
    """
    lower = np.asarray(others, float)
    lower = lower[lower < frequency_hz / 1.5]
    return bool(any(np.any(np.abs(frequency_hz / (n * lower) - 1) <= HARMONIC_NEAR) for n in (2, 3)))


def _ratios(f: np.ndarray, width: np.ndarray, width_factor: float, min_half_width: float):
    """For peaks sorted by frequency: own band ratio, and the ratios to the midpoints below and above."""
    own = 1.0 + np.maximum(width_factor * width / f, min_half_width)
    gaps = np.sqrt(f[1:] / f[:-1])
    below = np.concatenate([[np.inf], gaps])
    above = np.concatenate([gaps, [np.inf]])
    return own, below, above


def peak_bands(frequency_hz, half_power_width_hz, fs: float, *, width_factor: float = WIDTH_FACTOR,
               min_half_width: float = 0.1) -> list[tuple[float, float]]:
    """One band ``(low, high)`` in Hz per peak, not overlapping its neighbours (see the module).

    Examples
    --------
    >>> [tuple(round(e, 1) for e in b) for b in peak_bands([100.0, 103.0, 300.0], [0.5, 0.5, 2.0], 2000)]
    [(98.5, 101.5), (101.5, 104.5), (272.7, 330.0)]
    """
    f = np.asarray(frequency_hz, dtype=float)
    width = np.asarray(half_power_width_hz, dtype=float)
    rate = check_fs(fs)
    order = np.argsort(f)
    own, below, above = _ratios(f[order], width[order], width_factor, min_half_width)
    ratio = np.minimum(own, np.minimum(below, above))
    bands = [None] * f.size
    for k, i in enumerate(order):
        bands[i] = (float(f[i] / ratio[k]), float(min(f[i] * ratio[k], _TOP * rate)))
    return bands


def _loss_nepers(decay_rate: float, band: tuple, fs: float, method: str) -> float:
    return decay_rate * transient_samples(fs, band, method=method) / fs


def _joint_band(f, own, below, above, first: int, last: int, fs: float) -> tuple[float, float]:
    low = f[first] / min(own[first], below[first])
    return float(low), float(min(f[last] * min(own[last], above[last]), _TOP * fs))


def _grow(groups: list, f, decay, own, below, above, fs, limit, method) -> bool:
    """Extend each group by the neighbour limiting a member whose joint band is still too narrow."""
    for g, (first, last) in enumerate(groups):
        band = _joint_band(f, own, below, above, first, last, fs)
        for k in (first, last):
            if _loss_nepers(decay[k], band, fs, method) <= limit:
                continue
            side = -1 if below[first] < above[last] else 1
            if (side < 0 and first == 0) or (side > 0 and last == f.size - 1):
                side = -side
            if (side < 0 and first == 0) or (side > 0 and last == f.size - 1):
                continue
            groups[g] = (first - 1, last) if side < 0 else (first, last + 1)
            return True
    return False


def _merge_overlapping(groups: list) -> list:
    merged = []
    for first, last in sorted(groups):
        if merged and first <= merged[-1][1]:
            merged[-1] = (merged[-1][0], max(last, merged[-1][1]))
        else:
            merged.append((first, last))
    return merged


def band_groups(frequency_hz, decay_rate, half_power_width_hz, fs: float, *,
                width_factor: float = WIDTH_FACTOR, min_half_width: float = 0.1, max_loss_db: float = 20.0,
                method: str = "fft"):
    """Groups of peaks whose own bands are too narrow for their damping, and a joint band for each.

    Parameters
    ----------
    frequency_hz, decay_rate, half_power_width_hz : array-like (n_peaks,)
        The peaks: frequency (Hz), decay rate of the mode (1/s) and half-power width (Hz).
    fs : float
        Sampling rate (Hz).
    width_factor, min_half_width : float
        See :func:`peak_bands`.
    max_loss_db : float
        Decay (dB of amplitude) a mode may lose to its band's filter transient.
    method : {"fft", "butter"}
        The band-pass filter (its transient).

    Returns
    -------
    groups : list of tuple of int
        Indices of the peaks of each group (two or more, by frequency).
    bands : list of (float, float)
        The joint band of each group (Hz).

    Examples
    --------
    205.9 Hz at 2 % damping next to 216.6 Hz at 0.12 %, and a mode at 40.3 Hz:

    >>> f, zeta = np.array([40.3, 205.9, 216.6]), np.array([0.0023, 0.02, 0.0012])
    >>> groups, bands = band_groups(f, zeta * 2 * np.pi * f, 2 * zeta * f, 2048.0)
    >>> groups, [tuple(round(e, 1) for e in b) for b in bands]
    ([(1, 2)], [(139.1, 238.3)])
    """
    f = np.asarray(frequency_hz, dtype=float)
    rate = check_fs(fs)
    check_param("max_loss_db", max_loss_db, [Interval(Real, 0, None, "neither")], "band_groups")
    order = np.argsort(f)
    fs_, decay = f[order], np.asarray(decay_rate, dtype=float)[order]
    width = np.asarray(half_power_width_hz, dtype=float)[order]
    own, below, above = _ratios(fs_, width, width_factor, min_half_width)
    limit = max_loss_db / 20.0 * np.log(10.0)
    separate = peak_bands(fs_, width, rate, width_factor=width_factor, min_half_width=min_half_width)
    groups = []
    for k in range(fs_.size):
        if fs_.size > 1 and _loss_nepers(decay[k], separate[k], rate, method) > limit:
            groups.append((k - 1, k) if below[k] < above[k] else (k, k + 1))
    groups = _merge_overlapping(groups)
    while _grow(groups, fs_, decay, own, below, above, rate, limit, method):
        groups = _merge_overlapping(groups)
    bands = [_joint_band(fs_, own, below, above, first, last, rate) for first, last in groups]
    return [tuple(int(order[k]) for k in range(first, last + 1)) for first, last in groups], bands

"""Noise floor of a periodogram, robust to peaks and to the skirts of lightly damped modes."""

from __future__ import annotations

import math

import numpy as np
from scipy.ndimage import median_filter

from ._record import check_signal_1d

__all__ = ["noise_floor"]

_FLOOR_OCTAVES = 1.0
_FLOOR_MIN_BINS = 128
_FLOOR_GRID = 240
#: A bin is rough (noise) when the local median of its log jumps exceeds this fraction of ln 3; the
#: median of the gated floor over the true mean on white noise (measured, 4x zero padding).
_ROUGH = 0.5
_GATE_BIAS = 0.96
#: Resolution bins next to 0 Hz left out of every window (a removed offset depletes them).
_DC_BINS = 2
_OCTAVE_RATIO = 2.0 ** (_FLOOR_OCTAVES / 2)
_HALF_OCTAVE_RATIO = math.sqrt(2.0)


def _weighted_quantile(values: np.ndarray, weights: np.ndarray, q: float) -> float:
    order = values.argsort()
    return _sorted_quantile(values[order], weights[order], q)


def _sorted_quantile(values: np.ndarray, weights: np.ndarray, q: float) -> float:
    """The weighted ``q``-quantile of ``values`` sorted in ascending order, with their ``weights``."""
    cum = weights.cumsum()
    return float(values[min(cum.searchsorted(q * cum[-1]), values.size - 1)])


def _detrended_quantile(log_p: np.ndarray, bins: np.ndarray, k: int, q: float) -> float:
    """``q``-quantile at bin ``k`` of ``log_p`` over ``bins`` (1/f weights) after removing its weighted
    least-squares trend in log frequency (a power law of exponent -3 to 1): a power-law floor is
    followed where the window cannot be symmetric about ``k`` (near 0 Hz)."""
    x, w = np.log(bins / k), 1.0 / bins
    dx = x - (x * w).sum() / w.sum()
    spread = float((w * dx**2).sum())
    slope = float((w * dx * log_p).sum()) / spread if spread > 0 else 0.0
    return _weighted_quantile(log_p - min(max(slope, -3.0), 1.0) * x, w, q)


def _window_ratio(k, half: float):
    """Half-width (a frequency ratio) of the log-symmetric window around bin(s) ``k``: one octave, at
    least ``2 half`` bins."""
    return np.maximum(_OCTAVE_RATIO, (half + np.hypot(half, k)) / k)


def _windows(keep: np.ndarray, grid: np.ndarray, step: int, half: float) -> list:
    """The window around each grid bin (:func:`_window_ratio`), widened up to two octaves each side until
    it holds half its minimum count: ``(kept bins of its phase, phase, first, stop)``, its bins being
    ``kept[first:stop]``.

    Every window is a slice of the kept bins of its phase of the independent-bin grid (bins ``r, r +
    step, ...``), found for all grid bins at once by binary search.
    """
    phases = [np.flatnonzero(keep[r::step]) * step + r for r in range(step)]
    k = grid.astype(float)
    ratio = _window_ratio(k, half)
    found = np.zeros((3, grid.size), dtype=np.int64)  # phase, first, stop
    todo = np.arange(grid.size)
    while todo.size:
        lo = np.ceil(k[todo] / ratio[todo]).astype(np.int64)
        hi = np.minimum(keep.size, k[todo] * ratio[todo] + 1).astype(np.int64)
        phase = lo % step
        first, stop = np.empty_like(lo), np.empty_like(lo)
        for r in np.unique(phase):
            at = phase == r
            first[at], stop[at] = phases[r].searchsorted(lo[at]), phases[r].searchsorted(hi[at])
        done = (stop - first >= _FLOOR_MIN_BINS // 2) | (ratio[todo] >= 4.0)
        found[:, todo[done]] = phase[done], first[done], stop[done]
        todo = todo[~done]
        ratio[todo] *= _HALF_OCTAVE_RATIO
    return [(phases[r], r, i, j) for r, i, j in found.T]


#: A window holding more than this share of its phase's kept bins takes its order from the phase's one
#: sort (a mask of the window's positions) instead of sorting its own bins.
_SHARED_SORT = 0.1


def _running_level(log_p: np.ndarray, grid: np.ndarray, pad_factor: int, keep: np.ndarray, q: float):
    """``q``-quantile of ``log_p`` over the kept bins of the window around each grid bin (1/f weights;
    detrended where 0 Hz cuts the window); NaN where fewer than half the minimum count are kept.

    The wide windows (an octave of a long spectrum) take the order of their bins' values from one sort of
    their phase's kept bins (:data:`_SHARED_SORT`): the same order, so the same quantile, as sorting each
    window's own bins."""
    level = np.full(grid.size, np.nan)
    half = _FLOOR_MIN_BINS * pad_factor / 2
    near_dc = grid / _window_ratio(grid.astype(float), half) < _DC_BINS * pad_factor
    sorted_phase = {}
    windows = _windows(keep, grid, pad_factor, half)
    for i, (k, (kept, r, first, stop)) in enumerate(zip(grid.tolist(), windows)):
        bins = kept[first:stop]
        if bins.size < _FLOOR_MIN_BINS // 2:
            continue
        if near_dc[i]:
            level[i] = _detrended_quantile(log_p[bins], bins, k, q)
        elif bins.size <= _SHARED_SORT * kept.size:
            level[i] = _weighted_quantile(log_p[bins], 1.0 / bins, q)
        else:
            if r not in sorted_phase:
                sorted_phase[r] = log_p[kept].argsort()
            order = sorted_phase[r]
            inside = kept[order[(order >= first) & (order < stop)]]  # the window's bins, by value
            level[i] = _sorted_quantile(log_p[inside], 1.0 / inside, q)
    return level


def noise_floor(psd, *, pad_factor: int = 1, exclude=None) -> np.ndarray:
    """Mean noise level under ``psd``, ignoring peaks and their skirts.

    Noise makes a periodogram rough: the log ratio of two independent bins has a median magnitude of
    ln 3 (1.1), where peaks and skirts change smoothly. The floor is the median of the log PSD over the
    rough bins (local median roughness over 9 independent bins above half that value) in a window one
    octave wide, divided by ln 2 (the median of a chi-square-2 periodogram over its mean) and by 0.96
    (the gating's bias, measured on white noise). Windows are symmetric in log frequency, hold at least
    128 resolution bins and weigh each bin by ``1 / f``, so a power-law floor (pink, brown noise) is
    followed without bias; near 0 Hz, where a window cannot be symmetric, the log PSD's trend in log
    frequency is removed first. A window with too few rough bins is widened up to two octaves each side;
    a spectrum too short for any window (under 64 independent bins) gets the lower quartile of its bins.
    Under the skirts of strong, lightly damped modes no noise shows: there
    the floor is interpolated (in log frequency) between the nearest windows where it does, or held at
    their level beyond them. A spectrum without any rough stretch gets its lower quartile (the valleys).

    Parameters
    ----------
    psd : array-like (n_bins,)
        A periodogram on uniformly spaced frequencies from 0.
    pad_factor : int
        Zero-padding factor of the periodogram: independent bins are this many bins apart.
    exclude : array-like of bool (n_bins,), optional
        Bins to leave out (e.g. where fitted modes were subtracted from the signal); the lowest two
        resolution bins are always left out.

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> p = rng.exponential(2.0, 20000)  # white noise periodogram, mean 2
    >>> floor = noise_floor(p)
    >>> round(float(np.median(floor)), 1), bool(np.all(np.abs(floor[1000:] / 2 - 1) < 0.25))
    (2.0, True)
    """
    log_p = np.log(np.maximum(check_signal_1d(psd, "psd", 2), np.finfo(float).tiny))
    n, step = log_p.size, pad_factor
    jumps = np.abs(log_p[step:] - log_p[:-step])
    jumps = np.concatenate([jumps, jumps[-step:]])
    rough = median_filter(jumps, size=8 * step + 1, mode="nearest") > _ROUGH * np.log(3.0)
    rough[: _DC_BINS * step] = False
    if exclude is not None:
        rough &= ~np.asarray(exclude, dtype=bool)
    grid = np.unique(np.geomspace(1, n - 1, _FLOOR_GRID).astype(int))
    level = _running_level(log_p, grid, pad_factor, rough, 0.5) - np.log(np.log(2.0) * _GATE_BIAS)
    seen = np.isfinite(level)
    if not seen.any():
        level = _running_level(log_p, grid, pad_factor, np.ones(n, bool), 0.25)
        seen = np.isfinite(level)
    if not seen.any():  # fewer independent bins than one window holds: the lower quartile of them all
        return np.full(n, np.exp(np.quantile(log_p[_DC_BINS * step :: step], 0.25)))
    return np.exp(np.interp(np.arange(n), grid[seen], level[seen]))

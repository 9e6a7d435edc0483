"""State-level preprocessing of a fit: the rest level to measure the states from, the clipped samples to
leave out of the regression. The estimator calls both before it builds its library; the diagnostics only
read what they found.

The rest level of a ring-down
-----------------------------

A sensor offset (a DC level) does not change a ring-down's dynamics, but it ruins the regression: the
library's columns ``1, x, x^2, x^3`` of states sitting near a large constant are nearly collinear, and on
noisy data the threshold path then keeps spurious terms (measured: the paper's oscillator with an offset of
5x its amplitude at 40 dB SNR gives a 14-term model whose modal frequency is 2.2 Hz instead of 1.27 Hz).

A state's offset is removed when the physics makes its rest level well defined and the estimate is sure:

1. the state rings down: its RMS about the level falls by more than ``decay_db`` (6 dB) from the first to
   the last quarter of the record (:func:`~sindy_impulse.preprocessing.decay_db`), so it settles to a level
   (a limit cycle or a chaotic signal has a mean, not a rest level);
2. the offset matters: more than ``LIMITS["offset"]`` (0.1) of the largest excursion from it, the limit
   :func:`~sindy_impulse.preprocessing.check_quality` uses;
3. the estimate is sure: the level, the mean of the last quarter (``estimate_offset(method="tail")``), is
   more than 3 times its own possible bias, the tail's amplitude over ``pi`` times its periods (the mean of
   ``N`` periods of a sinusoid of amplitude ``A`` cut anywhere is at most ``A / (pi N)``).

The fit then builds the library on ``x - level`` and its models evaluate ``f(x - level)``
(:class:`~sindy_impulse.simulation.compile.AtRestLevel`): every state, simulation and error stays in the
measured coordinates, only the equations (``coef_``) are written in the deviations from the rest level.

Clipped samples
---------------
Where a sensor saturated, the flat tops and the derivative next to them are wrong: :func:`clipped_rows`
finds them (:func:`~sindy_impulse.preprocessing.clipping_mask`, widened by a margin) and
:func:`leave_out_clipped` leaves their rows out of the regression.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..simulation.scoring import oscillation_count
from .offset import estimate_offset
from .quality import LIMITS, clipping_mask, decay_db

__all__ = ["RestLevel", "rest_level", "clipped_rows", "leave_out_clipped", "MIN_KEPT", "CLIP_MARGIN"]

#: Fewest samples per trajectory the rest level is estimated from (a tail of 16).
MIN_SAMPLES = 64
#: Decay (dB, first over last quarter) a state needs to count as a ring-down to a rest level.
DECAY_DB = 6.0
#: The offset must exceed this multiple of its estimate's possible bias.
SURE = 3.0
#: Clipped samples are left out of the regression when at least this share of the samples remains.
MIN_KEPT = 0.5
#: Samples left out on each side of a clipped run (the filtered derivative is corrupted there too).
#: Measured on the paper's oscillator clipped at 0.5, 0.8, 0.95 of one or both states' amplitude (clean,
#: 40, 30 dB; 27 records): right structure and coefficients within 5 % in 8 of 27 fits with clipped samples
#: kept, 13 with them left out of the regression, 25 with them left out and the refinement (which would fit
#: the simulation to the flat tops) skipped.
CLIP_MARGIN = 5


@dataclass(frozen=True)
class RestLevel:
    """The rest level of each state and whether it is removed.

    Attributes
    ----------
    level : ndarray (n_states,)
        Estimated rest level (mean of the last quarter; median over trajectories).
    relative : ndarray (n_states,)
        ``|level|`` over the largest excursion from it.
    removed : ndarray of bool (n_states,)
        States whose level is removed before the regression.
    sure : ndarray of bool (n_states,)
        States with a sure offset (larger than 0.1 of the excursion and than 3 times its possible bias),
        removed or not.
    rings_down : ndarray of bool (n_states,)
        States that decay by more than ``DECAY_DB`` (in every trajectory).
    """

    level: np.ndarray
    relative: np.ndarray
    removed: np.ndarray
    sure: np.ndarray
    rings_down: np.ndarray

    @property
    def shift(self) -> np.ndarray:
        """What is subtracted from the states: the level where removed, else 0."""
        return np.where(self.removed, self.level, 0.0)


def _one_state(y: np.ndarray, fs: float) -> tuple[float, float, bool, bool, bool]:
    """Level, relative size, whether it is sure, whether it may be removed and whether the state rings
    down (one state, one trajectory)."""
    estimate = estimate_offset(y, fs, method="tail")
    level = estimate.value
    tail = y[int(0.75 * y.size) :] - level
    bias = float(np.max(np.abs(tail))) / (np.pi * max(oscillation_count(tail), 0.25))
    rings_down = decay_db(y - level) > DECAY_DB
    sure = abs(level) > SURE * bias and estimate.relative > LIMITS["offset"]
    return level, estimate.relative, bool(sure), bool(rings_down and sure), bool(rings_down)


def rest_level(trajectories, times, allow_removal: bool = True) -> RestLevel:
    """The rest level of each state over one or several trajectories, and which to remove.

    Parameters
    ----------
    trajectories : list of ndarray (n_samples, n_states)
        The measured (or filtered) states.
    times : list of ndarray
        Their time vectors.
    allow_removal : bool
        False: only estimate (plain PySINDy mode removes nothing).

    Returns
    -------
    RestLevel

    Examples
    --------
    >>> from sindy_impulse import damped_oscillator
    >>> t, x, _ = damped_oscillator()
    >>> rest = rest_level([x + [5.0, 30.0]], [t])
    >>> rest.removed.tolist(), rest.level.round(2).tolist()
    ([True, True], [5.0, 30.0])
    >>> rest_level([x], [t]).removed.tolist()
    [False, False]
    """
    n_states = trajectories[0].shape[1]
    rows = []
    for x, t in zip(trajectories, times):
        if x.shape[0] < MIN_SAMPLES or not np.all(np.isfinite(x)):
            continue
        fs = (x.shape[0] - 1) / float(t[-1] - t[0])
        flat = (0.0, 0.0, False, False, False)
        rows.append([_one_state(x[:, j], fs) if np.ptp(x[:, j]) > 0 else flat for j in range(n_states)])
    if not rows:
        zeros, yes = np.zeros(n_states), np.ones(n_states, bool)
        return RestLevel(zeros, zeros.copy(), ~yes, ~yes, yes)
    table = np.asarray(rows, dtype=float)  # (trajectories, states, 5)
    sure = np.all(table[:, :, 2] > 0, axis=0)
    removed = np.all(table[:, :, 3] > 0, axis=0) & bool(allow_removal)
    rings = np.all(table[:, :, 4] > 0, axis=0)
    level, relative = np.median(table[:, :, 0], axis=0), np.median(table[:, :, 1], axis=0)
    return RestLevel(level, relative, removed, sure, rings)


def clipped_rows(trajectories, widen: int = 2) -> list[np.ndarray]:
    """Per trajectory, the samples to leave out of the regression because a state is clipped there.

    A sample is left out when any state sits in a clipped run (:func:`~sindy_impulse.preprocessing.
    clipping_mask`) within ``widen`` samples (the derivative next to a flat top is corrupted too).

    Examples
    --------
    >>> x = np.clip(np.sin(np.arange(100) / 5), -2, 0.9)[:, None]
    >>> int(clipped_rows([x])[0].sum())  # 13 clipped samples in 3 runs, 2 more on each side of each
    25
    """
    out = []
    for x in trajectories:
        mask = np.zeros(x.shape[0], bool)
        if x.shape[0] >= 3:
            for j in range(x.shape[1]):
                if np.ptp(x[:, j]) > 0:
                    mask |= clipping_mask(x[:, j])
        if widen and mask.any():
            mask = np.convolve(mask, np.ones(2 * widen + 1), mode="same") > 0
        out.append(mask)
    return out


def leave_out_clipped(trajectories, derivs) -> tuple[list, int]:
    """The derivatives with the rows of clipped samples (:func:`clipped_rows`) set to NaN, which the
    regression then leaves out, and how many rows that is; unchanged (and 0) when fewer than ``MIN_KEPT``
    of the samples would remain.

    Examples
    --------
    >>> x = np.clip(np.sin(np.arange(200) / 5), -2, 0.9)[:, None]
    >>> derivs, n_out = leave_out_clipped([x], [np.cos(np.arange(200) / 5)[:, None]])
    >>> n_out, int(np.isnan(derivs[0]).sum())
    (97, 97)
    """
    rows = clipped_rows(trajectories, widen=CLIP_MARGIN)
    n_out, total = sum(int(r.sum()) for r in rows), sum(r.size for r in rows)
    if not n_out or total - n_out < MIN_KEPT * total:
        return derivs, 0
    out = []
    for d, r in zip(derivs, rows):
        d = np.array(d, dtype=float)
        d[r] = np.nan
        out.append(d)
    return out, n_out

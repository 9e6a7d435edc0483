"""The rest level of a ring-down: estimate it, decide whether to remove it, and the model measured from it.

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
(:class:`AtRestLevel`): every state, simulation and error stays in the measured coordinates, only the
equations (``coef_``) are written in the deviations from the rest level.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..preprocessing.offset import estimate_offset
from ..preprocessing.quality import LIMITS, decay_db
from ..simulation.scoring import oscillation_count

__all__ = ["RestLevel", "rest_level", "AtRestLevel", "at_rest_level"]

#: Fewest samples per trajectory the rest level is estimated from (a tail of 16).
MIN_SAMPLES = 64
#: Decay (dB, first over last quarter) a state needs to count as a ring-down to a rest level.
DECAY_DB = 6.0
#: The offset must exceed this multiple of its estimate's possible bias.
SURE = 3.0


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


class AtRestLevel:
    """A compiled model whose equations are written in the deviations from a rest level.

    ``rhs(x) = f(x - level)``; simulations start from ``x0 - level`` and come back with the level added,
    scores compare ``reference - level`` with the simulation. Everything else (coefficients, work counting,
    time scale) is the wrapped model's, read and written through.

    Examples
    --------
    >>> from sindy_impulse.simulation import CompiledModel, TermTable
    >>> inner = CompiledModel([[0.0, 1.0], [-64.0, -3.2]], TermTable.polynomial([[1, 0], [0, 1]]))
    >>> model = AtRestLevel(inner, np.array([5.0, 0.0]))
    >>> model.rhs(np.array([[5.0, 0.0], [6.0, 0.0]])).tolist()
    [[0.0, 0.0], [0.0, -64.0]]
    >>> bool(abs(model.simulate([6.0, 0.0], np.arange(401) * 0.01)[-1, 0] - 5.0) < 0.01)
    True
    """

    def __init__(self, model, level):
        object.__setattr__(self, "inner", model)
        object.__setattr__(self, "level", np.asarray(level, dtype=float))

    def __getattr__(self, name):
        if name in ("inner", "level") or name.startswith("__"):  # not yet set (copy, pickle)
            raise AttributeError(name)
        return getattr(self.inner, name)

    def __setattr__(self, name, value):
        setattr(self.inner, name, value)

    def rhs(self, x, u=None, coef=None):
        """The right-hand side at measured states ``x``."""
        shifted = np.asarray(x, dtype=float) - self.level
        return self.inner.rhs(shifted, u) if coef is None else self.inner.rhs(shifted, u, coef)

    def simulate(self, x0, t, *args, **kwargs):
        """A simulation from the measured state ``x0``, in measured coordinates."""
        x0 = np.asarray(x0, dtype=float).ravel()
        return self.inner.simulate(x0 - self.level, t, *args, **kwargs) + self.level

    def weighted_l1(self, reference, t, *args, **kwargs):
        """The fused error kernel against a measured reference."""
        return self.inner.weighted_l1(np.asarray(reference, dtype=float) - self.level, t, *args, **kwargs)

    def __repr__(self) -> str:
        return f"AtRestLevel({self.inner!r}, level={self.level.tolist()})"


def at_rest_level(model, level):
    """``model`` measured from ``level`` (:class:`AtRestLevel`), or ``model`` itself when the level is 0."""
    level = np.asarray(level, dtype=float)
    return model if not np.any(level) else AtRestLevel(model, level)

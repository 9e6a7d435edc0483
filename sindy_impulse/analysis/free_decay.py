"""The free decay of an identified model, simulated for its backbone (helper of backbone.py).

The model is simulated from the fitted data's initial state (the largest amplitude) on a grid of
``samples_per_period`` samples per period of the data's dominant frequency, in chunks, until the measured
coordinate's amplitude (half its peak-to-peak over the last two periods) has fallen a factor ``e`` below
the target amplitude, or ``max_periods`` periods have been simulated.
"""

from __future__ import annotations

import warnings

import numpy as np
from sklearn.exceptions import NotFittedError

from .._utils.validation import check_signal
from ..exceptions import DivergenceWarning, FitWarning
from .instantaneous import carrier_hz


def _trajectories(model) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """The fitted data (filtered states and their time vectors) of ``model`` as lists."""
    if not callable(getattr(model, "simulate", None)):
        raise TypeError(
            "model must be a fitted ImpulseSINDy (or any fitted object with simulate(x0, t), t_ and "
            f"x_filtered_), got {type(model).__name__}"
        )
    x, t = getattr(model, "x_filtered_", None), getattr(model, "t_", None)
    if x is None or t is None:
        raise NotFittedError(
            f"this {type(model).__name__} has no x_filtered_ / t_: fit it before computing its backbone"
        )
    xs = list(x) if isinstance(x, (list, tuple)) else [x]
    ts = list(t) if isinstance(t, (list, tuple)) else [t]
    if len(xs) != len(ts):
        raise ValueError(f"model has {len(xs)} trajectories in x_filtered_ but {len(ts)} in t_")
    xs = [check_signal(xi, "model.x_filtered_", min_samples=8) for xi in xs]
    return xs, [np.asarray(ti, dtype=float).ravel() for ti in ts]


def resolve_coordinate(model, coordinate, n_states: int) -> int:
    """The measured column: ``coordinate``, else ``model.coordinate_``, else 0 (negative: from the end)."""
    c = getattr(model, "coordinate_", 0) if coordinate is None else coordinate
    if isinstance(c, (bool, np.bool_)) or not isinstance(c, (int, np.integer)):
        raise TypeError(f"coordinate must be an integer state index, got {c!r}")
    if not -n_states <= c < n_states:
        raise ValueError(f"coordinate {c} is out of range for a model with {n_states} states")
    return int(c) % n_states


def _amplitude(y: np.ndarray) -> float:
    return 0.5 * float(np.ptp(y)) if y.size else 0.0


def _simulate(model, x0, tt, n_states):
    out = np.asarray(model.simulate(x0, tt), dtype=float)
    if out.ndim == 1 and n_states == 1:
        out = out[:, None]
    if out.shape != (len(tt), n_states):
        raise ValueError(f"model.simulate returned shape {out.shape}, expected {(len(tt), n_states)}")
    return out


def _run(model, state, c, n_states, dt, chunk, limit, min_samples, spp, target):
    """Chunks of the simulated coordinate and how the run ended ("decayed", "diverged" or "limit")."""
    pieces, t0, total = [], 0.0, 0
    while total < limit:
        tt = t0 + np.arange(min(chunk, limit - total) + 1) * dt
        out = _simulate(model, state, tt, n_states)
        bad = ~np.all(np.isfinite(out), axis=1)
        if bad.any():
            pieces.append(out[: int(np.argmax(bad)), c])
            return pieces, "diverged"
        pieces.append(out[:-1, c])
        state, t0, total = out[-1], tt[-1], total + len(tt) - 1
        if total >= min_samples and _amplitude(pieces[-1][-2 * spp :]) < target / np.e:
            return pieces, "decayed"
    return pieces, "limit"


def _lead_factor(y: np.ndarray, period: int, lead_periods: float) -> float:
    """How much the data's amplitude falls over its first ``lead_periods`` periods (1 if too short)."""
    k = int(round(lead_periods * period))
    if lead_periods <= 0 or y.size < k + 2 * period:
        return 1.0
    later = _amplitude(y[k : k + 2 * period])
    return max(1.0, _amplitude(y[: 2 * period]) / later) if later > 0 else 1.0


def simulate_free_decay(
    model,
    coordinate,
    samples_per_period: float,
    max_periods: float,
    target: float | None,
    min_periods: float,
    lead_periods: float = 0.0,
) -> tuple[np.ndarray, float, float]:
    """The simulated measured coordinate, its time step and the data's initial amplitude (module
    docstring). With ``lead_periods``, the simulation starts from the initial state scaled up by what the
    data lose over that many periods, so that an estimator trimming its first periods still covers the
    data's largest amplitudes (falls back to the initial state when that run does not decay)."""
    xs, ts = _trajectories(model)
    n_states = xs[0].shape[1]
    c = resolve_coordinate(model, coordinate, n_states)
    i = int(np.argmax([np.ptp(xi[:, c]) for xi in xs]))
    x_data, t_data = xs[i], ts[i]
    dt_data = float(np.median(np.diff(t_data)))
    if not dt_data > 0:
        raise ValueError("model.t_ must be increasing")
    f = carrier_hz(x_data[:, c], dt_data)
    dt = 1.0 / (f * samples_per_period)
    spp = int(round(samples_per_period))
    if target is None:  # the amplitude at the end of the data, at most 120 dB below the start
        period = int(np.ceil(1 / (f * dt_data)))
        target = max(_amplitude(x_data[-2 * period :, c]), 1e-6 * _amplitude(x_data[: 2 * period, c]))
    chunk = int(max((t_data[-1] - t_data[0]) / (4 * dt), min_periods * spp))
    limit = int(max_periods * spp)
    period = int(np.ceil(1 / (f * dt_data)))
    start = _amplitude(x_data[: 2 * period, c])
    lead = _lead_factor(x_data[:, c], period, lead_periods)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a divergence is reported below
        pieces, status = _run(model, lead * x_data[0], c, n_states, dt, chunk, limit, min_periods * spp, spp,
                              target)
        if lead > 1.0 and status != "decayed":  # the model does not decay from there: from the data's state
            pieces, status = _run(model, x_data[0], c, n_states, dt, chunk, limit, min_periods * spp, spp,
                                  target)
    if status == "diverged":
        warnings.warn(
            f"the model's free decay diverged after {sum(map(len, pieces)) / spp:.0f} periods; the backbone "
            "stops there (the model is unstable at these amplitudes)",
            DivergenceWarning,
            stacklevel=3,
        )
    elif status == "limit":
        warnings.warn(
            f"the model's free decay did not fall below amplitude {target:.4g} within {max_periods:g} "
            "periods (an undamped or very lightly damped model): the backbone stops at a larger amplitude; "
            "raise max_periods to go further",
            FitWarning,
            stacklevel=3,
        )
    return _cut_below(np.concatenate(pieces), spp, target / np.e, min_periods), dt, start


def _cut_below(y: np.ndarray, spp: int, level: float, min_periods: float) -> np.ndarray:
    """``y`` up to the end of the first period (after ``min_periods``) whose amplitude is below ``level``."""
    n = len(y) // spp
    if n == 0:
        return y
    amp = 0.5 * np.ptp(y[: n * spp].reshape(n, spp), axis=1)
    below = (amp < level) & (np.arange(n) >= min_periods)
    return y[: (int(np.argmax(below)) + 1) * spp] if below.any() else y

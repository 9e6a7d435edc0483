"""The initial state a fit's simulations start from (identification/initial_state.py)."""

import numpy as np
import pytest

from sindy_impulse import ImpulseSINDy, TVRegDiff
from sindy_impulse.datasets import damped_oscillator
from sindy_impulse.identification.initial_state import estimate_initial_states


def _noisy(x, level, seed):
    scale = np.abs(x).max(axis=0)
    return x + level * scale * np.random.default_rng(seed).standard_normal(x.shape), scale


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_an_offset_first_filtered_state_of_a_linear_decay_is_estimated_again(seed):
    ring = damped_oscillator()
    raw, scale = _noisy(ring.x, 0.01, seed)
    filtered, _ = _noisy(ring.x, 0.003, seed + 10)
    filtered[0] = ring.x[0] + 0.02 * scale * np.array([1.0, -1.0])
    out = estimate_initial_states([raw], [filtered], [ring.x_dot], [ring.t])[0]
    np.testing.assert_array_equal(out[1:], filtered[1:])  # only the first state changes
    assert np.max(np.abs(out[0] - ring.x[0]) / scale) < 0.2 * 0.02


def test_a_decay_that_starts_strongly_nonlinear_keeps_its_filtered_state():
    ring = damped_oscillator(k_nl=50)  # Duffing: its frequency falls by a quarter over the first periods
    raw, _ = _noisy(ring.x, 0.01, 0)
    filtered, _ = _noisy(ring.x, 0.003, 1)
    out = estimate_initial_states([raw], [filtered], [ring.x_dot], [ring.t])[0]
    np.testing.assert_array_equal(out, filtered)


def test_forced_and_non_oscillating_trajectories_keep_their_filtered_state():
    ring = damped_oscillator()
    raw, _ = _noisy(ring.x, 0.01, 0)
    filtered, _ = _noisy(ring.x, 0.003, 1)
    forced = estimate_initial_states([raw], [filtered], [ring.x_dot], [ring.t], [np.ones((len(ring.t), 1))])
    np.testing.assert_array_equal(forced[0], filtered)
    t = np.linspace(0, 4, 401)
    creep = np.column_stack([np.exp(-t), np.exp(-3 * t)])  # overdamped: no oscillatory pole
    derivs = np.column_stack([-np.exp(-t), -3 * np.exp(-3 * t)])
    out = estimate_initial_states([creep + 1e-3], [creep], [derivs], [t])[0]
    np.testing.assert_array_equal(out, creep)


def test_the_fit_starts_from_the_estimate_unless_the_derivatives_are_given():
    ring = damped_oscillator(snr_db=30, random_state=1)
    model = ImpulseSINDy().fit(ring.x, t=ring.t)
    smoother = TVRegDiff()
    smoother(ring.x, ring.t)
    np.testing.assert_array_equal(model.x_filtered_[1:], smoother.smoothed_x_[1:])
    clean = damped_oscillator().x[0]
    scale = np.abs(ring.x).max(axis=0)
    assert np.max(np.abs(model.x_filtered_[0] - clean) / scale) < 0.5 * np.max(
        np.abs(smoother.smoothed_x_[0] - clean) / scale
    )
    given = ImpulseSINDy().fit(ring.x, t=ring.t, x_dot=ring.x_dot)
    np.testing.assert_array_equal(given.x_filtered_, ring.x)

import numpy as np
import pytest

from sindy_impulse.datasets import add_noise, damped_oscillator


def test_oscillator_matches_closed_form():
    t, x, x_dot = damped_oscillator()
    wd = 8 * np.sqrt(1 - 0.2**2)
    s = 0.2 * 8
    exact = np.exp(-s * t) * (np.cos(wd * t) + s / wd * np.sin(wd * t))
    np.testing.assert_allclose(x[:, 0], exact, atol=1e-9)
    np.testing.assert_allclose(x_dot[:, 0], x[:, 1])


def test_noise_level_and_seed():
    x = damped_oscillator().x
    a = add_noise(x, 20, random_state=1)
    b = add_noise(x, 20, random_state=1)
    np.testing.assert_array_equal(a, b)
    ratio = np.std(a - x, axis=0) / np.std(x, axis=0)
    np.testing.assert_allclose(ratio, 0.1, rtol=0.15)


def test_bad_arguments():
    with pytest.raises(ValueError, match="x0"):
        damped_oscillator(x0=(1, 2, 3))
    with pytest.raises(ValueError, match="positive"):
        damped_oscillator(dt=0)

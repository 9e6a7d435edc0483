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


def test_load_silverbox_windows():
    from sindy_impulse.datasets import SilverboxWindows, load_silverbox

    sb = load_silverbox()
    assert isinstance(sb, SilverboxWindows)
    assert len(sb) == len(sb.inputs) == len(sb.start_rows) == 10
    assert sb.dt == pytest.approx(1 / 610.35, rel=1e-4)
    np.testing.assert_array_equal(sb.start_rows[:2], [40498, 49182])
    assert np.all(np.diff(sb.start_rows) > 8000)
    for y, u, t in zip(sb.windows, sb.inputs, sb.times()):
        assert y.ndim == 1 and 80 <= y.size <= 100 and y.shape == u.shape == t.shape
        assert np.all(np.isfinite(y))
        # the input is held at its quiet level; the output rings down freely
        assert np.all(np.abs(u - sb.quiet_level) < 0.001)
        first, last = np.abs(y[:20]).max(), np.abs(y[-20:]).max()
        assert last < 0.5 * first
    assert "n_windows=10" in repr(sb)


def test_load_silverbox_returns_fresh_arrays():
    from sindy_impulse.datasets import load_silverbox

    a = load_silverbox()
    a.windows[0][:] = 0
    assert np.any(load_silverbox().windows[0] != 0)


def test_silverbox_citation_shipped():
    from importlib.resources import files

    from sindy_impulse.datasets import load_silverbox

    assert "Wigren and J. Schoukens" in load_silverbox.__doc__
    readme = files("sindy_impulse").joinpath("data", "README.md").read_text()
    assert "Three free data sets for development and benchmarking" in readme

"""PySINDy 2.1.0's differentiation tests, asked of TVRegDiff (used by
``benchmarks/pysindy_suite/pysindy_suite.py``).

Each test repeats the assertion of the PySINDy test of the same name (``test/test_differentiation.py``)
with ``TVRegDiff`` in place of the method that test is about: the same fixtures (PySINDy's conftest), the
same data, the same tolerances. Tests about one method's own options (``FiniteDifference(d=...)``,
``periodic``, ``SmoothedFiniteDifference(save_smooth=...)``, ``SINDyDerivative``'s keyword handling, the
wrappers of the ``derivative`` package) have no counterpart. Where PySINDy's test compares two settings of
its method (``drop_endpoints``), the counterpart compares the matching TVRegDiff settings (``trim``).

The harness copies this file next to PySINDy's conftest.py (in a temporary directory) and runs it with
pytest; it is not a test of this project's own suite.
"""

import numpy as np
import pytest

from sindy_impulse.differentiation import TVRegDiff

LINEAR = np.linspace(1, 100, 100)
TRIMMED = (
    "TVRegDiff sets the derivative of the first and last `trim` samples (5, the paper's choice) to NaN, "
    "where PySINDy's test expects values; test_difference_1d_2d_untrimmed passes with trim=0"
)
NONLINEAR = (
    "mixed derivatives commute exactly only for a linear smoother; TVRegDiff's weights and alpha adapt to "
    "each series, so u_xy and u_yx differ by up to 1e-9 (absolute), above the test's rtol=1e-7 near zeros"
)
THREE_SAMPLES = (
    "3 samples per series, fewer than TVRegDiff needs (2 * trim + 3 = 13); test_nd_differentiation_long "
    "is the same test on 20 samples"
)


@pytest.fixture(params=["1d", "2d"])
def linear_data(request, data_derivative_1d, data_derivative_2d):
    return data_derivative_1d if request.param == "1d" else data_derivative_2d


def test_methods_store_smoothed_x_(data_derivative_1d):
    x, _ = data_derivative_1d
    method = TVRegDiff()
    assert not hasattr(method, "smoothed_x_")
    method(x)
    assert x.shape == method.smoothed_x_.shape


def test_methods_smooths(data_derivative_1d):
    x, _ = data_derivative_1d
    x_noisy = x + np.random.default_rng(0).normal(size=x.shape)
    method = TVRegDiff()
    method(x_noisy)
    assert np.linalg.norm(method.smoothed_x_ - x) < np.linalg.norm(x_noisy - x)


@pytest.mark.parametrize("trim", [0, 5])
def test_difference_length(trim):
    x = 2 * LINEAR
    assert len(TVRegDiff(trim=trim)(x)) == len(x)


def test_difference_variable_timestep_length():
    t = np.linspace(1, 10, 100) ** 2
    x = 2 * t
    assert len(TVRegDiff()(x, t)) == len(x)


def test_nan_derivatives(data_lorenz):
    # PySINDy: drop_endpoints=True equals drop_endpoints=False inside and is NaN at the ends
    x, t = data_lorenz
    x_dot = TVRegDiff(trim=0, alpha=1e-3)(x, t)
    x_dot_nans = TVRegDiff(trim=1, alpha=1e-3)(x, t)
    np.testing.assert_allclose(x_dot_nans[1:-1], x_dot[1:-1])
    assert np.isnan(x_dot_nans[:1]).all() and np.isnan(x_dot_nans[-1:]).all()


@pytest.mark.xfail(strict=True, reason=TRIMMED)
def test_difference_1d_2d(linear_data):
    # test_forward_difference_1d/2d, test_centered_difference_1d/2d, test_finite_difference,
    # test_smoothed_finite_difference: the exact derivative of linear data, ends included
    x, x_dot = linear_data
    np.testing.assert_allclose(TVRegDiff()(x), x_dot)


def test_difference_1d_2d_interior(linear_data):
    # the same on the samples TVRegDiff does not trim
    x, x_dot = linear_data
    np.testing.assert_allclose(TVRegDiff()(x)[5:-5], x_dot[5:-5])


def test_difference_1d_2d_untrimmed(linear_data):
    x, x_dot = linear_data
    np.testing.assert_allclose(TVRegDiff(trim=0)(x), x_dot)


def test_difference_2d_uniform_time(data_derivative_2d):
    x, x_dot = data_derivative_2d
    t = np.linspace(0, x.shape[0] - 1, x.shape[0])
    np.testing.assert_allclose(TVRegDiff(trim=0)(x, t), x_dot)


def test_difference_2d_nonuniform_time(data_derivative_2d):
    # PySINDy's test of this name passes a uniform time vector
    x, x_dot = data_derivative_2d
    t = np.linspace(0, x.shape[0] - 1, x.shape[0])
    np.testing.assert_allclose(TVRegDiff(trim=0)(x, t), x_dot, atol=1e-8)


def test_difference_2d_really_nonuniform_time():
    # not in PySINDy: t = s^2 (steps growing 20-fold), x = 2 t; the derivative of a smoother, 1 %
    t = np.linspace(1, 10, 100) ** 2
    x = np.column_stack([2 * t, -10 * t])
    x_dot = np.tile([2.0, -10.0], (100, 1))
    np.testing.assert_allclose(TVRegDiff(trim=0)(x, t), x_dot, rtol=1e-2)


@pytest.mark.xfail(strict=True, reason=NONLINEAR)
def test_difference_xy_yx(data_2dspatial):
    # mixed derivatives commute: a linear smoother's would exactly, TVRegDiff's only approximately
    x_grid, y_grid, u = data_2dspatial
    u_y = TVRegDiff(trim=0, axis=1)._differentiate(u, y_grid)
    u_x = TVRegDiff(trim=0, axis=0)._differentiate(u, x_grid)
    u_xy = TVRegDiff(trim=0, axis=1)._differentiate(u_x, y_grid)
    u_yx = TVRegDiff(trim=0, axis=0)._differentiate(u_y, x_grid)
    np.testing.assert_allclose(u_xy, u_yx)


def test_bad_t_values(data_derivative_1d):
    x, _ = data_derivative_1d
    method = TVRegDiff()
    with pytest.raises(ValueError):
        method(x, t=-1)
    with pytest.raises(ValueError):
        method._differentiate(x, t=-1)


@pytest.mark.parametrize("data", ["1d", "2d"])
def test_derivative_output_shape(data, data_derivative_1d, data_derivative_2d):
    x, x_dot = data_derivative_1d if data == "1d" else data_derivative_2d
    t = np.arange(x.shape[0])
    assert x_dot.shape == TVRegDiff()(x).shape
    assert x_dot.shape == TVRegDiff()(x, t).shape


def test_difference_hot_axis(data_2d_resolved_pde):
    # a step and the equivalent time vector give the same derivative, time on axis -2 of (8, 8, 1000, 2)
    _, u_flat, _ = data_2d_resolved_pde
    x = np.reshape(u_flat, (8, 8, 1000, 2))[:2]  # 2 x 8 x 2 series of 1000 samples: enough to compare
    t = np.linspace(0, 10, 1000)
    dt = t[1] - t[0]
    differentiate = TVRegDiff(axis=-2)._differentiate
    np.testing.assert_allclose(differentiate(x, t=dt), differentiate(x, t=t), atol=1e-8)


def test_difference_noaxis_vs_axis(data_2d_resolved_pde):
    # differentiating along axis -2 equals differentiating every (1000, 2) slice on its own
    _, u_flat, _ = data_2d_resolved_pde
    x = np.reshape(u_flat, (8, 8, 1000, 2))[:2, :2]
    t = np.linspace(0, 10, 1000)
    dt = t[1] - t[0]
    slow = np.zeros(x.shape)
    for i in range(x.shape[0]):
        for j in range(x.shape[1]):
            slow[i, j] = TVRegDiff()._differentiate(x[i, j], t=dt)
    np.testing.assert_allclose(TVRegDiff(axis=-2)._differentiate(x, t=dt), slow, atol=1e-10)


@pytest.mark.xfail(strict=True, reason=THREE_SAMPLES, raises=ValueError)
def test_nd_differentiation():
    t = np.arange(3)
    x = np.random.default_rng(0).random(size=(2, 3, 2))
    x[1, :, 1] = 1
    xdot = TVRegDiff(axis=-2)._differentiate(x, t)
    np.testing.assert_array_almost_equal(xdot[1, :, 1], np.zeros(3))


def test_nd_differentiation_long():
    # the same with enough samples for TVRegDiff's trim (13): a constant series has a zero derivative
    t = np.arange(20)
    x = np.random.default_rng(0).random(size=(2, 20, 2))
    x[1, :, 1] = 1
    xdot = TVRegDiff(axis=-2)._differentiate(x, t)
    np.testing.assert_array_almost_equal(xdot[1, 5:-5, 1], np.zeros(10))

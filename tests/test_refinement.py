import numpy as np
import pytest

from sindy_impulse.datasets import damped_oscillator
from sindy_impulse.feature_library import TermTable
from sindy_impulse.refinement import refine_coefficients
from sindy_impulse.simulation import CompiledModel, simulation_gamma

TERMS = TermTable.polynomial([[1, 0], [0, 1], [3, 0]])


def test_recovers_true_values_within_bounds():
    t, x, _ = damped_oscillator()
    start = CompiledModel([[0, 1.0, 0], [-58.0, -4.0, 0]], TERMS, x)
    res = refine_coefficients(start, [x], [t])
    np.testing.assert_allclose(res.coefficients[1, :2], [-64, -3.2], rtol=1e-4)
    assert res.gamma < 1e-3 < res.gamma_initial
    assert len(res.history["score"]) == len(res.history["coefficients"]) >= 2


def test_spurious_term_drops_out_and_never_worse():
    t, x, _ = damped_oscillator()
    start = CompiledModel([[0, 1.0, 0], [-64.0, -3.2, -0.5]], TERMS, x)
    res = refine_coefficients(start, [x], [t])
    assert res.coefficients[1, 2] == 0.0
    assert res.gamma <= res.gamma_initial


def test_bounds_keep_sign_and_limit():
    t, x, _ = damped_oscillator()
    # true c is 3.2; the start of 1.0 can only reach 1.5
    start = CompiledModel([[0, 1.0, 0], [-64.0, -1.0, 0]], TERMS, x)
    res = refine_coefficients(start, [x], [t])
    assert -1.5 - 1e-12 <= res.coefficients[1, 1] < 0


def test_diverging_start_is_returned_unchanged():
    t, x, _ = damped_oscillator()
    start = CompiledModel([[0, 1.0, 0], [-64.0, 30.0, 0]], TERMS, x)
    g = simulation_gamma(start, [x], [t])
    assert g == np.inf
    res = refine_coefficients(start, [x], [t])
    np.testing.assert_array_equal(res.coefficients, start.full_coefficients)


def test_bad_arguments():
    t, x, _ = damped_oscillator()
    start = CompiledModel([[0, 1.0, 0], [-64.0, -3.2, 0]], TERMS, x)
    with pytest.raises(ValueError, match="bound_factor"):
        refine_coefficients(start, [x], [t], bound_factor=-1)
    with pytest.raises(ValueError, match="max_iter"):
        refine_coefficients(start, [x], [t], max_iter=0)

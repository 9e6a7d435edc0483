"""Exact gradients from forward sensitivities (sindy_impulse.simulation.sensitivity) against finite
differences of the same simulations, and their use by the refinement and the output-error fit."""

import numpy as np
import pytest

from sindy_impulse.datasets import damped_oscillator
from sindy_impulse.identification import refinement
from sindy_impulse.identification.output_error import fit_output_error
from sindy_impulse.identification.refinement import _Objective, refine_coefficients
from sindy_impulse.simulation import CompiledModel, TermTable, WorkBudget
from sindy_impulse.simulation.compile import AtRestLevel
from sindy_impulse.simulation.scoring import Gamma, Segmented
from sindy_impulse.simulation.sensitivity import has_sensitivities, simulate_sensitivity

# x' = v and v' = ... for a linear model, a Duffing spring, and amplitude-dependent and quadratic damping
MODELS = {
    "linear": ([[1, 0], [0, 1]], [[0, 1.0], [-62.0, -3.0]], 0.0),
    "cubic spring": ([[1, 0], [0, 1], [3, 0]], [[0, 1.0, 0], [-62.0, -3.0, -9.0]], 10.0),
    "damping terms": ([[1, 0], [0, 1], [2, 1], [0, 3], [1, 1]],
                      [[0, 1.0, 0, 0, 0], [-62.0, -3.0, -1.5, -0.02, 0.3]], 10.0),
}


@pytest.fixture
def exact(monkeypatch):
    """The refinement and the output-error fit with exact gradients (off by default)."""
    monkeypatch.setattr(refinement, "EXACT_GRADIENTS", True)


def _case(name):
    powers, coef, k_nl = MODELS[name]
    t, x, _ = damped_oscillator(k_nl=k_nl)
    return CompiledModel(coef, TermTable.polynomial(powers), x), t, x


def _central(f, c0, idx):
    h = 1e-6 * abs(c0[idx])
    up, down = c0.copy(), c0.copy()
    up[idx] += h
    down[idx] -= h
    return (f(up) - f(down)) / (2 * h)


@pytest.mark.parametrize("name", list(MODELS))
@pytest.mark.parametrize("measure", [Gamma(), Segmented(2.0)], ids=["gamma", "segmented"])
def test_the_error_gradient_matches_finite_differences(name, measure):
    model, t, x = _case(name)
    bound = measure.bind([x], [t])
    error, gradient = bound.gradient(model, model.coef, model.coef != 0)
    assert error == pytest.approx(bound(model)[0], rel=1e-12)
    for idx in zip(*np.nonzero(model.coef)):
        fd = _central(lambda c: bound(model, c[None])[0], model.coef, idx)
        largest = np.max(np.abs(gradient[model.coef != 0]))
        assert gradient[idx] == pytest.approx(fd, rel=1e-6, abs=1e-6 * largest)
    assert np.all(np.isnan(gradient[model.coef == 0]))  # not asked for, not computed


@pytest.mark.parametrize("name", list(MODELS))
def test_the_trajectory_sensitivities_match_finite_differences(name):
    model, t, _ = _case(name)
    x0 = np.array([1.0, 0.0])
    x, by_coef, by_x0 = simulate_sensitivity(model, x0, t)
    np.testing.assert_allclose(x, model.simulate(x0, t), rtol=0, atol=1e-12)
    for idx in zip(*np.nonzero(model.coef)):
        fd = _central(lambda c: model.simulate(x0, t, coef=c), model.coef, idx)
        np.testing.assert_allclose(by_coef[(slice(None), slice(None)) + idx], fd, rtol=0,
                                   atol=1e-6 * np.max(np.abs(fd)))
    for i in range(2):
        step = np.eye(2)[i] * 1e-6
        fd = (model.simulate(x0 + step, t) - model.simulate(x0 - step, t)) / 2e-6
        np.testing.assert_allclose(by_x0[:, :, i], fd, rtol=0, atol=1e-6 * np.max(np.abs(fd)))


def test_a_model_measured_from_a_rest_level_has_the_gradient_of_its_measured_coordinates():
    model, t, x = _case("cubic spring")
    level = np.array([0.5, 0.0])
    at_rest = AtRestLevel(model, level)
    shifted = Gamma().bind([x + level], [t])
    error, gradient = shifted.gradient(at_rest, model.coef, model.coef != 0)
    assert error == pytest.approx(shifted(at_rest)[0], rel=1e-12)
    fd = _central(lambda c: shifted(at_rest, c[None])[0], model.coef, (1, 2))
    assert gradient[1, 2] == pytest.approx(fd, rel=1e-6)


def test_models_without_exact_gradients_are_named():
    t = np.arange(401) * 0.01
    three = CompiledModel(np.eye(3), TermTable.polynomial(np.eye(3, dtype=int)))
    assert not has_sensitivities(three, t)
    assert simulate_sensitivity(three, np.ones(3), t) is None
    assert has_sensitivities(_case("linear")[0], t)


def test_the_refinement_uses_the_exact_gradient_and_a_diverged_point_has_none(exact):
    model, t, x = _case("linear")
    objective = _Objective(model, Gamma().bind([x], [t]), WorkBudget(), 1.0)
    gradient = objective.gradient(np.ones(3))
    assert objective.exact is True
    fd = [(objective(np.ones(3) + 1e-7 * np.eye(3)[k]) - objective(np.ones(3))) / 1e-7 for k in range(3)]
    np.testing.assert_allclose(gradient, fd, rtol=1e-4)
    assert np.all(objective.exact_gradient(np.ones(3), np.inf) == 0)


def test_the_paper_oscillator_is_refined_as_before(exact):
    """test_refinement's assertion on the paper's oscillator, with the exact gradient."""
    t, x, _ = damped_oscillator()
    start = CompiledModel([[0, 1.0], [-60.0, -4.0]], TermTable.polynomial([[1, 0], [0, 1]]), x)
    res = refine_coefficients(start, [x], [t])
    np.testing.assert_allclose(res.coefficients[1, :2], [-64, -3.2], rtol=1e-4)


def test_the_output_error_fit_with_the_exact_jacobian_recovers_damping_and_initial_state(exact):
    t, x, _ = damped_oscillator()
    noisy = x + 0.01 * np.random.default_rng(0).standard_normal(x.shape) * np.max(np.abs(x), axis=0)
    start = CompiledModel([[0, 1.0], [-64.0, -3.84]], TermTable.polynomial([[1, 0], [0, 1]]))
    res = fit_output_error(start, [noisy], [t])
    assert res.success
    np.testing.assert_allclose(res.coefficients[1], [-64.0, -3.2], rtol=0.01)
    np.testing.assert_allclose(res.initial_states[0], [1.0, 0.0], atol=0.01)
    assert res.n_simulations < 30  # one simulation per Jacobian, not one per unknown

import numpy as np
import pytest

from sindy_impulse.datasets import damped_oscillator
from sindy_impulse.feature_library import TermTable
from sindy_impulse.identification.output_error import fit_output_error
from sindy_impulse.identification.refinement import refine_coefficients
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


def _noisy(x, level, seed=0):
    return x + level * np.random.default_rng(seed).standard_normal(x.shape) * np.max(np.abs(x), axis=0)


def test_output_error_fit_is_not_misled_by_the_first_sample():
    """Gamma's refinement starts its simulation from the measured first state: an error of 5 % there goes
    into the coefficients; the output-error fit takes the initial state as an unknown."""
    t, x, _ = damped_oscillator()
    measured = x.copy()
    measured[0, 0] += 0.05
    start = CompiledModel([[0, 1.0, 0], [-64.0, -3.2, 0]], TERMS, measured)
    by_gamma = refine_coefficients(start, [measured], [t]).coefficients[1, 1]
    start = CompiledModel([[0, 1.0, 0], [-64.0, -3.2, 0]], TERMS, measured)
    res = fit_output_error(start, [measured], [t])
    assert abs(res.coefficients[1, 1] / -3.2 - 1) < 2e-3 < abs(by_gamma / -3.2 - 1)
    # the erroneous sample is one of the residuals: it pulls the fitted state by a tenth of its error at most
    assert np.all(np.abs(res.initial_states[0] - x[0]) < 0.1 * 0.05 * np.max(np.abs(x), axis=0))
    assert res.success and res.cost < res.cost_initial and res.n_simulations > 0


def test_output_error_fit_of_several_trajectories_fits_each_initial_state():
    t, x, _ = damped_oscillator()
    second = 0.5 * x[100:]
    start = CompiledModel([[0, 1.0, 0], [-60.0, -4.0, 0]], TERMS, x)
    res = fit_output_error(start, [_noisy(x, 0.01), _noisy(second, 0.01, 1)], [t, t[100:]])
    np.testing.assert_allclose(res.coefficients[1, :2], [-64.0, -3.2], rtol=0.01)
    assert len(res.initial_states) == 2
    for fitted, true in zip(res.initial_states, (x[0], second[0])):
        np.testing.assert_allclose(fitted, true, atol=0.01 * np.max(np.abs(x)))


def test_output_error_fit_keeps_signs_bounds_and_never_does_worse():
    t, x, _ = damped_oscillator()
    # the true damping 3.2 is out of reach of a start of 1.0 (bound 1.5), a spurious term may vanish
    start = CompiledModel([[0, 1.0, 0], [-64.0, -1.0, -0.5]], TERMS, x)
    res = fit_output_error(start, [x], [t])
    assert -1.5 - 1e-12 <= res.coefficients[1, 1] < 0
    assert res.coefficients[1, 2] <= 0
    assert res.cost < res.cost_initial
    # the exact model: nothing to gain but the integrator's last digits
    start = CompiledModel([[0, 1.0, 0], [-64.0, -3.2, 0]], TERMS, x)
    res = fit_output_error(start, [x], [t])
    np.testing.assert_allclose(res.coefficients, start.full_coefficients, rtol=1e-6)
    assert res.cost <= res.cost_initial < 1e-12


def test_output_error_fit_from_a_diverging_start_does_not_raise():
    t, x, _ = damped_oscillator()
    start = CompiledModel([[0, 1.0, 0], [-64.0, 30.0, 0]], TERMS, x)
    res = fit_output_error(start, [x], [t])
    assert np.isfinite(res.cost) and res.cost <= res.cost_initial
    assert res.coefficients[1, 1] >= 0  # the sign is kept: the fit may only shrink the wrong damping


def test_output_error_fit_bad_arguments():
    t, x, _ = damped_oscillator()
    start = CompiledModel([[0, 1.0, 0], [-64.0, -3.2, 0]], TERMS, x)
    with pytest.raises(ValueError, match="bound_factor"):
        fit_output_error(start, [x], [t], bound_factor=0)
    with pytest.raises(ValueError, match="max_evaluations"):
        fit_output_error(start, [x], [t], max_evaluations=0)


def test_output_error_fit_of_a_model_without_terms_returns_it():
    t, x, _ = damped_oscillator()
    start = CompiledModel(np.zeros((2, 3)), TERMS, x)
    res = fit_output_error(start, [x], [t])
    assert not res.success and res.message == "nothing to fit" and res.cost == res.cost_initial
    np.testing.assert_array_equal(res.coefficients, 0.0)


def test_a_shared_memo_repeats_no_simulation_and_changes_nothing():
    """A finer refinement from the same start repeats the coarser one's iterations: with their memo it
    simulates only the rest, and gives the same coefficients, scores and budget as without it."""
    from sindy_impulse.identification.refinement import refine
    from sindy_impulse.simulation import WorkBudget, get_error_measure

    t, x, _ = damped_oscillator(snr_db=40, random_state=0)
    counted = get_error_measure("gamma", [x]).bind([x], [t], None)
    calls, evaluate = [], counted.evaluate
    counted.evaluate = lambda *args: (calls.append(1), evaluate(*args))[1]

    def start():
        return CompiledModel([[0, 1.0, 0], [-58.0, -4.0, -0.5]], TERMS, x)

    runs = {}
    for shared in (False, True):
        memo, budget, calls[:] = ({} if shared else None), WorkBudget(), []
        coarse = refine(start(), counted, budget=budget, ftol=1e-4, memo=memo)
        n_coarse = len(calls)
        fine = refine(start(), counted, budget=budget, ftol=1e-7, memo=memo)
        runs[shared] = (coarse, fine, budget.used, n_coarse, len(calls) - n_coarse)
    (c0, f0, used0, _, n0), (c1, f1, used1, _, n1) = runs[False], runs[True]
    for a, b in ((c0, c1), (f0, f1)):
        np.testing.assert_array_equal(a.coefficients, b.coefficients)
        assert a.score == b.score and a.history["score"] == b.history["score"]
    assert used0 == used1
    assert n1 < n0


def test_a_memo_serves_only_scores_that_depend_on_the_coefficients_alone():
    """An adaptive simulation stops where the work budget does: a fallback (or stiff) model, or a measure
    that is not a bound one, is scored anew every time."""
    from sindy_impulse.identification.refinement import _reproducible
    from sindy_impulse.simulation import FallbackModel, get_error_measure

    t, x, _ = damped_oscillator()
    measure = get_error_measure("gamma", [x]).bind([x], [t], None)
    compiled = CompiledModel([[0, 1.0, 0], [-64.0, -3.2, 0]], TERMS, x)
    assert _reproducible(compiled, measure)
    assert not _reproducible(compiled, lambda model, coefs: measure(model, coefs))
    fallback = FallbackModel([[0.0, 1.0], [-64.0, -3.2]], lambda Z: Z, n_inputs_total=2)
    assert not _reproducible(fallback, measure)
    stiff = CompiledModel([[0, 1.0, 0], [-64.0, -3.2, 0]], TERMS, x)
    stiff.spectral_radius = 1e9  # more RK4 sub-steps than MAX_SUBSTEPS: the adaptive integrator
    assert not _reproducible(stiff, measure)

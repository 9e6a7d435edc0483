"""Bounded scoring of the sweep: a candidate's simulation stops once its error passes the least error found
so far. The selection, the coefficients and (once ``path_`` is read) every score must be those of the
unbounded sweep, to the last bit; the stopped simulations resume where they stopped."""

import pickle

import numpy as np
import pytest

from sindy_impulse import ImpulseSINDy
from sindy_impulse.identification.selection import SELECTION_RULES, exact_scores_needed, reads_bounds
from sindy_impulse.simulation import CompiledModel, Gamma, Segmented, TermTable

from .test_four_states import SYSTEMS, ring_down


def _three_state_model():
    """A nonlinear three-state model (stepped stage by stage, not by a propagator) and its reference."""
    terms = TermTable.polynomial([[1, 0, 0], [0, 1, 0], [0, 0, 1], [3, 0, 0]])
    coef = [[0.0, 1.0, 0.0, 0.0], [-64.0, -0.8, 0.0, -20.0], [0.0, 0.0, -1.0, 0.0]]
    reference = CompiledModel([[0.0, 1.0, 0.0, 0.0], [-60.0, -1.0, 0.0, -10.0], [0.0, 0.0, -1.2, 0.0]],
                              terms, [[1.0, 0.0, 1.0]])
    t = np.arange(1200) * 0.01
    ref = reference.simulate([1.0, 0.0, 1.0], t)
    return CompiledModel(coef, terms, ref), ref, t


@pytest.mark.parametrize("measure", [Gamma(), Segmented(segment_periods=3.0)], ids=["gamma", "segmented"])
def test_bounded_error_is_the_kernels_to_the_last_bit(measure):
    model, ref, t = _three_state_model()
    measure.bind([ref], [t])
    full = measure(model)[0]
    work = model.work_done
    error, finished, progress = measure.bounded(model, np.inf)
    assert finished and progress is None and error == full  # bitwise: the kernel's order of summation
    assert model.work_done - work == work  # and the same work
    model.work_done = 0.0
    low, finished, progress = measure.bounded(model, 0.1 * full)
    assert not finished and 0.1 * full < low <= full
    assert model.work_done < work  # stopped early
    resumed, finished, _ = measure.bounded(model, np.inf, progress)
    assert finished and resumed == full and model.work_done == work  # resumed, not restarted


def test_linear_models_run_whole():
    terms = TermTable.polynomial([[1, 0, 0], [0, 1, 0], [0, 0, 1]])
    t = np.arange(800) * 0.01
    model = CompiledModel([[0.0, 1.0, 0.0], [-64.0, -0.8, 0.0], [0.0, 0.0, -1.0]], terms, [[1.0, 0.0, 1.0]])
    ref = model.simulate([1.0, 0.0, 1.0], t) * 1.01
    measure = Gamma().bind([ref], [t])
    assert measure.bounded(model, 0.0) == (measure(model)[0], True, None)


def test_the_rules_that_read_bounds():
    assert reads_bounds("auto") and reads_bounds("min_gamma") and reads_bounds(SELECTION_RULES["auto"])
    assert not reads_bounds(lambda scores, n_terms, refine, tolerance: 0)
    g, k = np.array([1.0, 1.05, 5.0, 80.0]), np.array([5, 3, 2, 1])
    assert exact_scores_needed("min_gamma", g, k).tolist() == [False] * 4
    assert exact_scores_needed("auto", g, k).tolist() == [False, True, True, False]
    with pytest.raises(ValueError, match="needs every score"):
        exact_scores_needed(lambda *args: 0, g, k)


@pytest.fixture(scope="module")
def four_state_fits():
    """A bounded fit (the default) and the same fit with every candidate simulated to the end (a rule
    the bounded sweep does not know: the built-in "auto" behind a wrapper)."""
    t, x, _ = ring_down(*SYSTEMS["2.44 and 6.27 Hz"], rate=100.0, n=1000)
    auto = SELECTION_RULES["auto"]
    bounded = ImpulseSINDy().fit(x, t=t)
    full = ImpulseSINDy(selection=lambda *args: auto(*args)).fit(x, t=t)
    return bounded, full


def test_bounded_sweep_selects_and_scores_as_the_full_one(four_state_fits):
    bounded, full = four_state_fits
    stopped = bounded._unfinished_scores
    assert stopped is not None and len(stopped.indices) > 0  # some simulations did stop early
    assert bounded.budget_used_ < full.budget_used_
    again = pickle.loads(pickle.dumps(bounded))  # the stopped simulations travel with the estimator
    np.testing.assert_array_equal(bounded.coef_, full.coef_)
    assert bounded.path_.selected == full.path_.selected and bounded.score_ == full.score_
    np.testing.assert_array_equal(bounded.path_.score, full.path_.score)  # finished when first read
    np.testing.assert_array_equal(again.path_.score, full.path_.score)
    assert bounded._unfinished_scores is None
    assert bounded.diagnostics_.verdict == full.diagnostics_.verdict

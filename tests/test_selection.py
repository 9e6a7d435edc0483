import numpy as np
import pytest

from sindy_impulse.identification.selection import select_candidate


def _refine_table(refined):
    return lambda i: (f"coef{i}", refined[i], {})


def test_auto_prefers_sparser_model_within_tolerance():
    gammas = np.array([1.00, 1.05, 1.30, 9.0])
    n_terms = np.array([8, 5, 3, 2])
    refined = {0: 0.95, 1: 1.0, 2: 1.02, 3: 8.0}
    index, (coef, g, _) = select_candidate("auto", gammas, n_terms, _refine_table(refined))
    assert index == 2 and g == 1.02


def test_auto_measures_tolerance_from_the_refined_best():
    # the 4-term model refines from 7.0 to 0.002; a 3-term model refining to 7.7 must not win
    # (the Duffing case of section 3.4 with k = 398)
    gammas = np.array([7.02, 7.9])
    n_terms = np.array([4, 3])
    refined = {0: 0.002, 1: 7.7}
    index, _ = select_candidate("auto", gammas, n_terms, _refine_table(refined))
    assert index == 0


def test_noise_widens_the_tolerance():
    gammas = np.array([1.0, 1.5])
    n_terms = np.array([6, 3])
    refined = {0: 0.9, 1: 1.4}
    assert select_candidate("auto", gammas, n_terms, _refine_table(refined))[0] == 0
    assert select_candidate("auto", gammas, n_terms, _refine_table(refined), noise_gamma=6.0)[0] == 1


def test_floor_makes_numerically_perfect_fits_equal():
    # clean data: 0.0018 vs 0.0015 is integrator/filter accuracy, not structure
    gammas = np.array([0.5, 0.6])
    n_terms = np.array([9, 4])
    refined = {0: 0.0015, 1: 0.0018}
    assert select_candidate("auto", gammas, n_terms, _refine_table(refined))[0] == 0
    assert select_candidate("auto", gammas, n_terms, _refine_table(refined), n_values=800)[0] == 1


def test_dense_best_is_not_refined_when_a_sparse_model_passes():
    gammas = np.array([1.0, 1.05, 1.08])
    n_terms = np.array([20, 5, 3])
    refined = {1: 1.0, 2: 1.02}
    calls = []

    def refine(i):
        calls.append(i)
        return None, refined[i], {}

    assert select_candidate("auto", gammas, n_terms, refine)[0] == 2
    assert 0 not in calls


def test_min_gamma_and_diverged_candidates():
    gammas = np.array([np.inf, 2.0, 3.0])
    n_terms = np.array([10, 4, 2])
    refined = {1: 1.5, 2: 1.6}
    assert select_candidate("min_gamma", gammas, n_terms, _refine_table(refined))[0] == 1
    with pytest.raises(ValueError, match="selection"):
        select_candidate("bic", gammas, n_terms, _refine_table(refined))

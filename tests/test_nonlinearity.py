"""nonlinearity_test: a decision with its statistic, quiet on noisy linear systems."""

import numpy as np
import pysindy as ps
import pytest

from sindy_impulse import ImpulseSINDy, damped_oscillator
from sindy_impulse.analysis import NonlinearityResult, nonlinearity_test


@pytest.fixture(scope="module")
def duffing():
    ring = damped_oscillator(k_nl=10.0, x0=(2.0, 0.0), snr_db=40, random_state=1)
    return ring, ImpulseSINDy().fit(ring.x, t=ring.t)


def test_clear_nonlinear_case(duffing):
    ring, model = duffing
    res = nonlinearity_test(model, ring.x, ring.t)
    assert isinstance(res, NonlinearityResult)
    assert res.nonlinear and bool(res)
    assert res.statistic > res.threshold > 0
    assert res.gamma_linear > 5 * res.gamma_nonlinear
    top = res.terms[0]
    assert (top.equation, top.term) == ("x1'", "x0^3")
    assert abs(top.coefficient + 10.0) < 1.0
    assert 0.0 < top.share < 1.0
    assert res.source == "model"
    assert res.nonlinear_coefficients.shape == res.linear_coefficients.shape == (2, 10)
    assert np.all(res.linear_coefficients[:, [i for i, n in enumerate(res.feature_names) if "^" in n]] == 0)
    assert "x0^3" in repr(res)


def test_noisy_linear_case_is_quiet():
    for seed in range(3):
        ring = damped_oscillator(snr_db=30, random_state=seed)
        model = ImpulseSINDy().fit(ring.x, t=ring.t)
        res = nonlinearity_test(model, ring.x, ring.t)
        assert not res.nonlinear, res
        assert res.statistic <= res.threshold


def test_search_finds_a_term_the_model_dropped():
    ring = damped_oscillator(k_nl=10.0, x0=(1.0, 0.0), snr_db=40, random_state=0)
    linear = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=1)).fit(ring.x, t=ring.t)
    # a cubic library but the linear model's coefficients: the model itself has no nonlinear term
    model = ImpulseSINDy().fit(ring.x, t=ring.t)
    model.coef_ = np.zeros_like(model.coefficients())
    model.coef_[:, 1:3] = linear.coefficients()[:, 1:3]
    res = nonlinearity_test(model, ring.x, ring.t)
    assert res.nonlinear and res.source == "search"
    assert res.terms[0].term == "x0^3"
    assert not nonlinearity_test(model, ring.x, ring.t, search=False).nonlinear


def test_new_data_and_list_input(duffing):
    _, model = duffing
    other = [damped_oscillator(k_nl=10.0, x0=(a, 0.0), snr_db=40, random_state=7).x for a in (1.5, -2.0)]
    res = nonlinearity_test(model, other, 0.01)
    assert res.nonlinear


def test_linear_library_has_nothing_to_test():
    ring = damped_oscillator(snr_db=40, random_state=0)
    model = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=1)).fit(ring.x, t=ring.t)
    res = nonlinearity_test(model, ring.x, ring.t)
    assert not res.nonlinear and res.terms == [] and res.source == "none"
    assert res.statistic == 0.0


def test_errors(duffing):
    ring, model = duffing
    with pytest.raises(TypeError, match="fitted ImpulseSINDy"):
        nonlinearity_test(object(), ring.x, ring.t)
    with pytest.raises(ValueError, match="not fitted"):
        nonlinearity_test(ImpulseSINDy(), ring.x, ring.t)
    with pytest.raises(ValueError, match="states"):
        nonlinearity_test(model, ring.x[:, :1], ring.t)
    with pytest.raises(ValueError, match="NaN"):
        nonlinearity_test(model, np.full_like(ring.x, np.nan), ring.t)
    with pytest.raises(ValueError, match="rel_tol"):
        nonlinearity_test(model, ring.x, ring.t, rel_tol=-1)
    with pytest.raises(ValueError, match="entries"):
        nonlinearity_test(model, ring.x, ring.t[:10])

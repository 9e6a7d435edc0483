import pickle

import numpy as np
import pysindy as ps
import pytest
from sklearn.base import clone
from sklearn.model_selection import GridSearchCV, KFold
from sklearn.pipeline import make_pipeline

from sindy_impulse import ImpulseSINDy, MechanicalLibrary, ThresholdSweep, damped_oscillator
from sindy_impulse.exceptions import DataWarning
from sindy_impulse.identification.estimator import SweepPath, fit_deferred


@pytest.fixture(scope="module")
def clean():
    return damped_oscillator()


@pytest.fixture(scope="module")
def fitted(clean):
    t, x, _ = clean
    return ImpulseSINDy().fit(x, t=t)


def test_analytic_derivatives_exact(clean):
    t, x, x_dot = clean
    model = ImpulseSINDy().fit(x, t=t, x_dot=x_dot)
    coef = model.coefficients()
    names = model.get_feature_names()
    assert np.count_nonzero(coef) == 3
    np.testing.assert_allclose(coef[0, names.index("x1")], 1.0, rtol=1e-6)
    np.testing.assert_allclose(coef[1, names.index("x0")], -64.0, rtol=1e-6)
    np.testing.assert_allclose(coef[1, names.index("x1")], -3.2, rtol=1e-6)


def test_states_only_paper_case_312(fitted):
    coef = fitted.coefficients()
    names = fitted.get_feature_names()
    assert np.count_nonzero(coef) == 3
    assert abs(coef[1, names.index("x0")] + 64) / 64 <= 0.002
    assert abs(coef[1, names.index("x1")] + 3.2) / 3.2 <= 0.01
    assert fitted.gamma_ <= 2.345  # the paper's result
    assert fitted.gamma_ <= fitted.gamma_sindy_


def test_fitted_attributes(fitted):
    path = fitted.path_
    assert isinstance(path, SweepPath)
    assert len(path.threshold) == len(path.gamma) == len(path.n_terms) == path.coefficients.shape[0]
    assert path.n_terms[0] == 20 and path.n_terms[-1] == 0
    assert fitted.threshold_ == path.threshold[path.selected]
    assert fitted.gamma_sindy_ == path.gamma[path.selected]
    hist = fitted.refinement_history_
    assert len(hist["score"]) == len(hist["coefficients"]) >= 1
    assert fitted.x_filtered_.shape == (401, 2)
    assert fitted.equations()[1].startswith("-64.0")
    assert fitted.complexity == 3


def test_simulate_and_predict(fitted, clean):
    t, x, x_dot = clean
    sim = fitted.simulate(x[0], t)
    assert np.max(np.abs(sim - x)) < 1e-3
    np.testing.assert_allclose(fitted.predict(x), x_dot, atol=0.05 * np.abs(x_dot).max())
    with pytest.raises(ValueError, match="x0 has 3 entries"):
        fitted.simulate([1, 0, 0], t)
    with pytest.raises(ValueError, match="strictly increasing"):
        fitted.simulate(x[0], t[::-1])


def test_print(fitted, capsys):
    fitted.print(precision=1)
    out = capsys.readouterr().out.splitlines()
    assert out == ["(x0)' =  1.0 x1", "(x1)' = -64.0 x0 + -3.2 x1"]


def test_drop_in_equals_pysindy(clean):
    t, x, _ = clean
    x = x + np.random.default_rng(0).normal(scale=1e-3, size=x.shape)
    kwargs = dict(
        optimizer=ps.STLSQ(threshold=0.05),
        feature_library=ps.PolynomialLibrary(degree=3),
        differentiation_method=ps.FiniteDifference(),
    )
    ours = ImpulseSINDy(**kwargs, sweep=False, refine=False).fit(x, t=t, feature_names=["x", "v"])
    theirs = ps.SINDy(**{k: clone(v) for k, v in kwargs.items()}).fit(x, t=t, feature_names=["x", "v"])
    np.testing.assert_allclose(ours.coefficients(), theirs.coefficients(), rtol=1e-12, atol=1e-14)
    assert ours.equations() == theirs.equations()
    assert ours.get_feature_names() == theirs.get_feature_names()
    np.testing.assert_allclose(ours.predict(x), theirs.predict(x), rtol=1e-9, atol=1e-9)


def test_min_gamma_selection_is_the_minimum(clean):
    t, x, _ = damped_oscillator(snr_db=30, random_state=3)
    model = ImpulseSINDy(selection="min_gamma", refine=False).fit(x, t=t)
    assert model.path_.selected == int(np.nanargmin(model.path_.gamma))
    assert model.gamma_ == pytest.approx(np.nanmin(model.path_.gamma))


def test_refine_false_keeps_swept_model(clean):
    t, x, _ = damped_oscillator(snr_db=40, random_state=1)
    model = ImpulseSINDy(refine=False).fit(x, t=t)
    np.testing.assert_array_equal(model.coefficients(), model.path_.coefficients[model.path_.selected])
    assert model.gamma_ == model.gamma_sindy_


def test_multiple_trajectories():
    data = [damped_oscillator(x0=(a, 0.0)) for a in (1.0, -0.5, 0.7)]
    model = ImpulseSINDy().fit([d.x for d in data], t=data[0].t)
    assert np.count_nonzero(model.coefficients()) == 3
    assert isinstance(model.x_filtered_, list) and len(model.x_filtered_) == 3
    model2 = ImpulseSINDy().fit([d.x for d in data], t=[d.t for d in data])
    np.testing.assert_allclose(model.coefficients(), model2.coefficients())


def test_dt_parameter_and_pipeline(clean):
    t, x, _ = clean
    a = ImpulseSINDy(dt=0.01).fit(x)
    b = ImpulseSINDy().fit(x, t=0.01)
    np.testing.assert_allclose(a.coefficients(), b.coefficients())
    pipe = make_pipeline(ImpulseSINDy(dt=0.01)).fit(x)
    np.testing.assert_allclose(pipe[-1].coefficients(), a.coefficients())


def test_mechanical_library_in_estimator():
    t, x, _ = damped_oscillator()
    model = ImpulseSINDy(feature_library=MechanicalLibrary(degree=2)).fit(x, t=t, feature_names=["x", "v"])
    names = model.get_feature_names()
    coef = model.coefficients()
    assert set(np.array(names)[coef[1] != 0]) == {"x", "v"}


def test_sklearn_contract(clean):
    t, x, _ = clean
    est = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=2), selection="min_gamma", dt=0.01)
    params = est.get_params()
    assert params["selection"] == "min_gamma" and params["optimizer"] is None
    assert params["feature_library__degree"] == 2
    est.set_params(feature_library__degree=1)
    cloned = clone(est)
    assert cloned.feature_library.degree == 1
    cloned.fit(x)
    restored = pickle.loads(pickle.dumps(cloned))
    np.testing.assert_array_equal(restored.coefficients(), cloned.coefficients())
    np.testing.assert_allclose(restored.simulate(x[0], t), cloned.simulate(x[0], t))
    # fit does not touch the given components
    opt = ThresholdSweep()
    ImpulseSINDy(optimizer=opt).fit(x, t=t)
    assert not hasattr(opt, "coef_")


def test_grid_search_over_degree(clean):
    t, x, _ = clean
    est = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=1), dt=0.01, refine=False)
    search = GridSearchCV(est, {"feature_library__degree": [1, 2]}, cv=KFold(2))
    search.fit(x)
    assert search.best_params_["feature_library__degree"] in (1, 2)
    assert np.isfinite(search.best_score_)


@pytest.mark.parametrize(
    "kwargs, fit_kwargs, exc, match",
    [
        ({"selection": "best"}, {}, ValueError, "selection"),
        ({"bound_factor": -1}, {}, ValueError, "bound_factor"),
        ({"refine": "yes"}, {}, TypeError, "refine"),
        ({"output_error": -1}, {}, ValueError, "output_error"),
        ({"output_error": "yes"}, {}, ValueError, "output_error"),
        ({"dt": -0.1}, {}, ValueError, "dt"),
        ({}, {"u": np.zeros(400)}, ValueError, "u\\[0\\] has 400 samples"),
        ({}, {"feature_names": ["a"]}, ValueError, "feature_names"),
        ({}, {"t": np.arange(400.0)}, ValueError, "400 entries"),
        ({}, {"x_dot": np.zeros((400, 2))}, ValueError, "x_dot"),
    ],
)
def test_bad_input(clean, kwargs, fit_kwargs, exc, match):
    t, x, _ = clean
    fit_kwargs = {"t": t, **fit_kwargs}
    with pytest.raises(exc, match=match):
        ImpulseSINDy(**kwargs).fit(x, **fit_kwargs)


def test_nan_and_too_few_samples(clean):
    t, x, _ = clean
    bad = x.copy()
    bad[5, 1] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        ImpulseSINDy().fit(bad, t=t)
    with pytest.raises(ValueError, match="samples"):
        ImpulseSINDy(differentiation_method=ps.FiniteDifference()).fit(x[:8], t=t[:8])
    plain = ImpulseSINDy(differentiation_method=ps.FiniteDifference(), sweep=False, refine=False)
    with pytest.warns(DataWarning, match="too few samples"):
        plain.fit(x[:8], t=t[:8])  # PySINDy accepts it (minimum-norm solution): a warning, not an error


def test_only_empty_model_left_gives_zero_model_with_warning():
    # exponential growth with a tiny admissible box: every non-trivial candidate leaves it
    t = np.arange(200) * 0.01
    x = np.column_stack([np.exp(3 * t), np.exp(3 * t)])
    est = ImpulseSINDy(divergence_factor=1e-3, differentiation_method=ps.FiniteDifference())
    with pytest.warns(RuntimeWarning, match="x' = 0"):
        est.fit(x, t=t)
    assert est.complexity == 0


def test_single_diverging_model_raises():
    # without the sweep (one candidate, refined) there is no fallback: a clear error
    t = np.arange(200) * 0.01
    x = np.column_stack([np.exp(3 * t), np.exp(3 * t)])
    est = ImpulseSINDy(
        optimizer=ps.STLSQ(threshold=0.0),
        sweep=False,
        divergence_factor=1e-3,
        differentiation_method=ps.FiniteDifference(),
    )
    with pytest.raises(RuntimeError, match="diverged"):
        est.fit(x, t=t)


def test_output_error_fit_is_off_by_default_and_fits_the_initial_state_when_on(clean):
    """``output_error=True``: the refined model is fitted once more with its initial state; the record's
    first sample carries an error of 5 % of the amplitude, which Gamma's simulation starts from."""
    t, x, x_dot = clean
    x = x.copy()
    x[0, 0] += 0.05
    linear = ps.PolynomialLibrary(degree=1, include_bias=False)
    plain = ImpulseSINDy(feature_library=linear).fit(x, t=t, x_dot=x_dot)
    assert plain.output_error_fit_ is None
    fitted = ImpulseSINDy(feature_library=linear, output_error=True).fit(x, t=t, x_dot=x_dot)
    fit = fitted.output_error_fit_
    assert fit.success and fit.cost < fit.cost_initial
    assert abs(fit.initial_states[0][0] - 1.0) < 0.1 * 0.05  # the first sample's error is not believed
    names = fitted.get_feature_names()
    plain_error, error = (abs(m.coefficients()[1, names.index("x1")] / -3.2 - 1) for m in (plain, fitted))
    assert error < 0.005 and error < 0.5 * plain_error


def test_output_error_as_a_number_of_periods_turns_the_fit_on_for_shorter_records(clean):
    """``output_error=P``: on when no trajectory holds more than P periods (the oscillator: 3)."""
    t, x, x_dot = clean
    linear = ps.PolynomialLibrary(degree=1, include_bias=False)
    short = ImpulseSINDy(feature_library=linear, output_error=3).fit(x, t=t, x_dot=x_dot)
    assert short.output_error_fit_ is not None
    long = ImpulseSINDy(feature_library=linear, output_error=2.5).fit(x, t=t, x_dot=x_dot)
    assert long.output_error_fit_ is None


@pytest.mark.parametrize("seed", [1, 4])
def test_deferred_diagnostics_are_the_fits_own_computed_on_first_read(seed):
    import warnings

    ring = damped_oscillator(snr_db=20, random_state=seed)
    eager = ImpulseSINDy().fit(ring.x, t=ring.t)
    deferred = fit_deferred(ImpulseSINDy(), ring.x, t=ring.t)
    assert "_diagnostics" not in vars(deferred)
    assert "_checks" not in vars(deferred)  # the data checks' spectra wait for the diagnostics too
    restored = pickle.loads(pickle.dumps(deferred))  # not yet computed: computed after unpickling
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # reading them never warns
        got = deferred.diagnostics_
        again = restored.diagnostics_
    assert deferred.diagnostics_ is got  # computed once
    assert deferred._screening.peaks_hz.tolist() == eager._screening.peaks_hz.tolist()
    for d in (got, again):
        assert d.verdict == eager.diagnostics_.verdict
        assert d.reasons == eager.diagnostics_.reasons
        assert d.unsupported_terms == eager.diagnostics_.unsupported_terms


def test_an_unfitted_model_has_no_diagnostics_and_a_refit_replaces_them():
    model = ImpulseSINDy()
    assert not hasattr(model, "diagnostics_")
    ring = damped_oscillator(snr_db=40, random_state=0)
    fit_deferred(model, ring.x, t=ring.t)
    first = model.diagnostics_
    model.fit(ring.x[:300], t=ring.t[:300])
    assert model.diagnostics_ is not first


def test_fit_deferred_fits_any_other_estimator_as_it_is():
    ring = damped_oscillator(snr_db=40, random_state=0)
    model = fit_deferred(ps.SINDy(), ring.x, t=ring.t)
    assert np.array_equal(model.coefficients(), ps.SINDy().fit(ring.x, t=ring.t).coefficients())

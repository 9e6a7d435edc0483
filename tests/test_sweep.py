import pickle

import numpy as np
import pysindy as ps
import pytest
from sklearn.base import clone

from sindy_impulse import ThresholdSweep
from sindy_impulse.datasets import damped_oscillator
from sindy_impulse.optimizers import threshold_path


def test_path_runs_from_all_terms_to_none():
    t, x, x_dot = damped_oscillator()
    X = ps.PolynomialLibrary(degree=3).fit(x).transform(x)
    thresholds, coefs = threshold_path(X, x_dot)
    # the first candidate is the full least-squares model on every (non-empty) column: some of its
    # coefficients may come out exactly 0.0 (x0' = x1 is exact in these data), so compare values, not counts
    full = np.linalg.lstsq(X, x_dot, rcond=None)[0].T
    assert coefs[0].shape == full.shape == (2, 10)  # 10 terms, all columns non-empty
    np.testing.assert_allclose(coefs[0], full, rtol=1e-6, atol=1e-9 * np.abs(full).max())
    assert thresholds[0] == 0
    n_terms = [np.count_nonzero(c) for c in coefs]
    assert n_terms[-1] == 0
    # each support is a subset of the one before, and no two candidates are the same model
    for a, b in zip(coefs, coefs[1:]):
        assert not np.any((b != 0) & (a == 0)) and not np.array_equal(a, b)
    assert all(a >= b for a, b in zip(n_terms, n_terms[1:]))
    assert np.all(np.diff(thresholds) > 0)
    assert 3 in n_terms


def test_path_is_unit_invariant():
    t, x, x_dot = damped_oscillator(snr_db=40, random_state=0)
    lib = ps.PolynomialLibrary(degree=3)
    supports = []
    for scale in (1e-6, 1.0, 1e6):
        X = lib.fit(x * scale).transform(x * scale)
        _, coefs = threshold_path(X, x_dot * scale)
        supports.append([tuple(np.flatnonzero(c.ravel())) for c in coefs])
    assert supports[0] == supports[1] == supports[2]


def test_standalone_optimizer_in_pysindy():
    t, x, x_dot = damped_oscillator()
    opt = ThresholdSweep()
    model = ps.SINDy(optimizer=opt, feature_library=ps.PolynomialLibrary(degree=3)).fit(x, t=t, x_dot=x_dot)
    coef = model.coefficients()
    names = model.get_feature_names()
    assert np.count_nonzero(coef) == 3
    assert coef[1, names.index("x0")] == np.float64(coef[1, names.index("x0")])
    np.testing.assert_allclose(coef[1, names.index("x0")], -64, rtol=1e-6)
    assert len(opt.history_) == len(opt.thresholds_) >= 3


def test_sklearn_params_clone_pickle():
    opt = ThresholdSweep(max_iter=5)
    assert opt.set_params(max_iter=7) is opt
    assert clone(opt).get_params()["max_iter"] == 7
    assert pickle.loads(pickle.dumps(opt)).max_iter == 7


def test_integer_sample_weight_equals_repeating_the_sample():
    t, x, x_dot = damped_oscillator(snr_db=30, random_state=1)
    X = ps.PolynomialLibrary(degree=2).fit(x).transform(x)
    weights = np.where(np.arange(len(X)) % 3 == 0, 2.0, 1.0)
    weights[::7] = 0.0
    weighted = ThresholdSweep().fit(X, x_dot, sample_weight=weights)
    rows = np.repeat(np.arange(len(X)), weights.astype(int))
    repeated = ThresholdSweep().fit(X[rows], x_dot[rows])
    assert weighted.best_index_ == repeated.best_index_
    np.testing.assert_allclose(weighted.aicc_, repeated.aicc_, rtol=1e-9)
    np.testing.assert_allclose(weighted.coef_, repeated.coef_, rtol=1e-9, atol=1e-12)
    with pytest.raises(ValueError, match="sample_weight is zero for every sample"):
        ThresholdSweep().fit(X, x_dot, sample_weight=np.zeros(len(X)))


def test_one_dimensional_target_gives_one_dimensional_coefficients():
    t, x, x_dot = damped_oscillator()
    X = ps.PolynomialLibrary(degree=1).fit(x).transform(x)
    opt = ThresholdSweep().fit(X, x_dot[:, 1])
    assert opt.coef_.shape == (X.shape[1],) and opt.predict(X).shape == (len(X),)
    assert opt.history_[0].shape == (1, X.shape[1]) and opt.n_iter_ >= 1 and opt.n_features_in_ == 3


def test_path_of_a_long_record_runs_on_a_reduced_problem_with_the_same_result():
    from sindy_impulse.optimizers.sweep import _path, reduced

    rng = np.random.default_rng(5)
    X = rng.normal(size=(20_001, 8)) * np.logspace(-3, 3, 8)  # columns of very different units
    Y = X[:, :2] @ [[1.0, 0.0], [0.0, -2.0]] + X[:, 5:6] * 1e-4 + 0.01 * rng.normal(size=(20_001, 2))
    Xr, Yr, rcond = reduced(X, Y)
    assert Xr.shape == (10, 8)  # more than REDUCE_ABOVE samples: reduced
    thresholds, coefs, _ = _path(Xr, Yr, 20, rcond)
    thresholds_full, coefs_full, _ = _path(X, Y, 20)
    assert [np.count_nonzero(c) for c in coefs] == [np.count_nonzero(c) for c in coefs_full]
    np.testing.assert_allclose(coefs, coefs_full, rtol=1e-9, atol=1e-12)


def test_protected_terms_are_never_thresholded():
    rng = np.random.default_rng(0)
    X = rng.normal(size=(200, 4))
    Y = X @ np.array([[2.0, 0.5], [0.0, 1e-3], [0.3, 0.0], [0.0, 0.0]]) + 1e-3 * rng.normal(size=(200, 2))
    protected = np.array([[False, True, False, False], [False, True, True, False]])
    thresholds, coefs = threshold_path(X, Y, protected=protected)
    assert all(np.all(c[protected] != 0) for c in coefs)  # every candidate keeps them
    assert np.count_nonzero(coefs[-1]) == protected.sum()  # the path ends with them alone
    sweep = ThresholdSweep(protected=protected).fit(X, Y)
    assert np.all(sweep.candidates_[:, protected] != 0)
    with pytest.raises(ValueError, match="protected must have shape"):
        ThresholdSweep(protected=[True, False]).fit(X, Y)


def _collinear_library(seed: int = 0):
    """Two independent terms and a third nearly equal to the first plus a little of the weak second:
    along the whole library's path the third takes the weak term's place."""
    rng = np.random.default_rng(seed)
    theta = rng.normal(size=(50, 3))
    theta[:, 2] = theta[:, 0] + 0.02 * theta[:, 1] + 0.01 * rng.normal(size=50)
    return theta, theta[:, :2] @ [[2.0], [0.1]]


def test_a_sub_library_path_adds_the_supports_the_full_path_lacks():
    from sindy_impulse.optimizers import candidate_path

    theta, y = _collinear_library()
    _, full = candidate_path(ps.STLSQ(threshold=0.05), theta, y)
    supports = [tuple(np.flatnonzero(c[0])) for c in full]
    assert (0, 1) not in supports  # the true model is not on the whole library's path
    thresholds, both = candidate_path(ps.STLSQ(threshold=0.05), theta, y,
                                      sub_libraries=[np.array([True, True, False])])
    assert len(thresholds) == len(both)
    n_terms = [np.count_nonzero(c) for c in both]
    assert n_terms == sorted(n_terms, reverse=True)  # densest first
    kept = [c for c in both if tuple(np.flatnonzero(c[0])) in supports]
    np.testing.assert_array_equal(kept, full)  # the full path's models, in its order
    added = [tuple(np.flatnonzero(c[0])) for c in both if tuple(np.flatnonzero(c[0])) not in supports]
    assert (0, 1) in added and len(added) == len(set(added)) == len(both) - len(full)
    true = next(c for c in both if tuple(np.flatnonzero(c[0])) == (0, 1))
    np.testing.assert_allclose(true[0, :2], [2.0, 0.1], rtol=1e-8)  # least squares on the sub-library
    assert np.all(true[:, 2] == 0)


def test_a_sub_library_path_keeps_the_protected_terms_of_its_columns():
    from sindy_impulse.optimizers import candidate_path

    theta, y = _collinear_library()
    protected = np.array([False, True, True])
    _, both = candidate_path(ThresholdSweep(protected=protected), theta, y,
                             sub_libraries=[np.array([True, True, False])])
    from_sub = [c for c in both if c[0, 2] == 0]  # the protected third term is in every full-path model
    assert from_sub and all(c[0, 1] != 0 for c in both)  # the weak term is protected in the sub-library too


def test_no_sub_library_path_without_a_sweep_or_for_the_whole_library():
    from sindy_impulse.optimizers import candidate_path

    theta, y = _collinear_library()
    single = candidate_path(ps.STLSQ(threshold=0.05), theta, y, sweep=False,
                            sub_libraries=[np.array([True, True, False])])[1]
    assert single.shape == (1, 1, 3)
    _, plain = candidate_path(ThresholdSweep(), theta, y)
    _, same = candidate_path(ThresholdSweep(), theta, y, sub_libraries=[np.ones(3, bool), np.zeros(3, bool)])
    np.testing.assert_array_equal(plain, same)

import pickle

import numpy as np
import pysindy as ps
from sklearn.base import clone

from sindy_impulse import ThresholdSweep
from sindy_impulse.datasets import damped_oscillator
from sindy_impulse.optimizers import threshold_path


def test_path_runs_from_all_terms_to_none():
    t, x, x_dot = damped_oscillator()
    X = ps.PolynomialLibrary(degree=3).fit(x).transform(x)
    thresholds, coefs = threshold_path(X, x_dot)
    n_terms = [np.count_nonzero(c) for c in coefs]
    assert n_terms[0] == 20 and n_terms[-1] == 0
    assert all(a > b for a, b in zip(n_terms, n_terms[1:]))  # distinct supports, sparser each step
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

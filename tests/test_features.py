"""SINDyFeatures: coefficients as features, failures as NaN rows, parallel, pipeline, sklearn contract."""

import pickle

import joblib
import numpy as np
import pysindy as ps
import pytest
from scipy import sparse
from sklearn.base import clone
from sklearn.cluster import KMeans
from sklearn.decomposition import PCA
from sklearn.pipeline import Pipeline

from sindy_impulse import DelayEmbedding, ImpulseSINDy, SINDyFeatures, damped_oscillator

DT = 0.01


def _linear_estimator():
    return ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=1))


@pytest.fixture(scope="module")
def series():
    """Two linear and two Duffing ring-downs (both states), 2 s long."""
    params = [(64, 0), (100, 0), (64, 50), (100, 50)]
    return [damped_oscillator(k=k, k_nl=k_nl, t_end=2.0).x for k, k_nl in params]


class _FailOnLarge:
    """A template that raises for series with a large first sample (to test the failure path)."""

    def __init__(self, limit=5.0, feature_library=None):
        self.limit = limit
        self.feature_library = feature_library

    def get_params(self, deep=True):
        return {"limit": self.limit, "feature_library": self.feature_library}

    def set_params(self, **params):
        for key, value in params.items():
            setattr(self, key, value)
        return self

    def fit(self, x, t=None):
        if np.abs(x[0]).max() > self.limit:
            raise RuntimeError("simulated failure")
        self.coef_ = np.array([[0.0, 1.0], [-float(np.abs(x[0]).max()), 0.0]])
        return self

    def coefficients(self):
        return self.coef_


def test_multivariate_features_and_names(series):
    feats = SINDyFeatures(dt=DT)
    X = feats.fit_transform(series)
    names = list(feats.get_feature_names_out())
    assert X.shape == (4, 20) and len(names) == 20
    assert names[0] == "x0' : 1" and "x1' : x0^3" in names
    assert feats.n_failed_ == 0 and feats.failures_ == {}
    cubic = X[:, names.index("x1' : x0^3")]
    np.testing.assert_allclose(cubic, [0, 0, -50, -50], atol=0.5)
    np.testing.assert_allclose(X[:, names.index("x1' : x0")], [-64, -100, -64, -100], rtol=1e-3)
    assert feats.embedding_ is None and feats.n_states_ == 2
    # transform of new data uses the same layout
    assert feats.transform(series[:1]).shape == (1, 20)


def test_univariate_series_are_embedded_with_common_parameters():
    rings = [damped_oscillator(k=k).x[:, 0] for k in (64, 81, 100)]
    X2d = np.vstack(rings)  # (n_series, n_times)
    feats = SINDyFeatures(estimator=_linear_estimator(), dt=DT)
    X = feats.fit_transform(X2d)
    assert feats.embedding_ is not None and feats.n_states_ == feats.embedding_.dimension_ == 2
    assert X.shape == (3, 6) and feats.n_failed_ == 0
    assert list(feats.get_feature_names_out())[:3] == ["q1' : 1", "q1' : q1", "q1' : q2"]
    # a given embedding is used as is
    fixed = SINDyFeatures(estimator=_linear_estimator(), dt=DT, embed=DelayEmbedding(tau=10, dimension=3))
    assert fixed.fit(rings).embedding_.tau_ == 10 and fixed.n_states_ == 3
    # no embedding: one state
    assert SINDyFeatures(estimator=_linear_estimator(), dt=DT, embed=False).fit(rings).n_states_ == 1


def test_failed_series_gives_nan_row_and_is_counted(series):
    bad = [series[0], np.zeros_like(series[0]), series[2]]
    feats = SINDyFeatures(estimator=_linear_estimator(), dt=DT)
    with pytest.warns(RuntimeWarning, match="1 of 3 reconstructions failed"):
        X = feats.fit_transform(bad)
    assert feats.n_failed_ == 1 and list(feats.failures_) == [1]
    assert "no dynamics" in feats.failures_[1]
    assert np.isnan(X[1]).all() and np.isfinite(X[[0, 2]]).all()
    with pytest.warns(RuntimeWarning):
        filled = clone(feats).set_params(fill_failed=0.0).fit_transform(bad)
    np.testing.assert_array_equal(filled[1], 0.0)


def test_exception_in_estimator_is_recorded():
    data = [np.ones((50, 2)), 10 * np.ones((50, 2)), np.ones((50, 2))]
    template = _FailOnLarge(feature_library=ps.PolynomialLibrary(degree=1, include_bias=False))
    feats = SINDyFeatures(estimator=template, dt=DT)
    feats.fit(data)
    assert feats.terms_ == ["x0", "x1"]  # the layout comes from the template's library
    with pytest.warns(RuntimeWarning):
        X = feats.transform(data)
    assert feats.n_failed_ == 1 and "RuntimeError: simulated failure" in feats.failures_[1]
    assert np.isnan(X[1]).all()


def test_pipeline():
    """Coefficient features in a clustering pipeline: two linear and two Duffing ring-downs whose
    stiffnesses differ less than their cubic terms split by the cubic term. (Standardised, the four
    feature vectors of the ``series`` fixture form a square, whose two halvings are equally good: which
    one KMeans returns is a tie scikit-learn's version breaks.)"""
    params = [(64, 0), (72, 0), (64, 50), (72, 50)]
    series = [damped_oscillator(k=k, k_nl=k_nl, t_end=2.0).x for k, k_nl in params]
    pipe = Pipeline(
        [
            ("sindy", SINDyFeatures(dt=DT)),
            ("pca", PCA(2)),
            ("km", KMeans(2, random_state=0, n_init=10)),
        ]
    )
    labels = pipe.fit_predict(series)
    assert labels[0] == labels[1] != labels[2] == labels[3]
    assert pipe.predict(series[:1])[0] == labels[0]


def test_parallel_matches_serial(series):
    serial = SINDyFeatures(estimator=_linear_estimator(), dt=DT).fit_transform(series)
    parallel = SINDyFeatures(estimator=_linear_estimator(), dt=DT, n_jobs=2, batch_size=1)
    np.testing.assert_array_equal(parallel.fit_transform(series), serial)


def test_progress_bar(series, capsys):
    pytest.importorskip("tqdm")
    SINDyFeatures(estimator=_linear_estimator(), dt=DT, progress=True).fit_transform(series[:2])
    assert "SINDy fits" in capsys.readouterr().err


def test_dask_backend(series):
    pytest.importorskip("distributed")
    from dask.distributed import Client, LocalCluster, get_task_stream

    serial = SINDyFeatures(estimator=_linear_estimator(), dt=DT).fit_transform(series[:2])
    features = SINDyFeatures(estimator=_linear_estimator(), dt=DT, batch_size=1)
    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as cluster:
        with Client(cluster), get_task_stream() as stream:
            with joblib.parallel_config(backend="dask"):
                X = features.fit_transform(series[:2])
    np.testing.assert_array_equal(X, serial)
    assert len(stream.data) >= 2  # the fits ran as tasks on the dask cluster


def test_sklearn_contract_clone_and_pickle(series):
    est = _linear_estimator()
    feats = SINDyFeatures(estimator=est, dt=DT, n_jobs=None)
    assert feats.get_params()["estimator"] is est  # untouched in __init__
    assert SINDyFeatures().estimator is None
    cloned = clone(feats)
    assert cloned.get_params()["dt"] == DT and not hasattr(cloned, "feature_names_out_")
    X = feats.fit_transform(series[:2])
    restored = pickle.loads(pickle.dumps(feats))
    np.testing.assert_array_equal(restored.transform(series[:2]), X)
    np.testing.assert_array_equal(restored.get_feature_names_out(), feats.get_feature_names_out())
    assert not hasattr(est, "optimizer_")  # the template is never fitted


def test_rounding():
    feats = SINDyFeatures(estimator=_linear_estimator(), dt=DT, significant_digits=2)
    X = feats.fit_transform([damped_oscillator(k=64, c=3.21).x])
    assert -3.2 in X[0] and -64.0 in X[0]


@pytest.mark.parametrize(
    "X, error, match",
    [
        (np.zeros(100), ValueError, "1-D"),
        (np.zeros((2, 3, 4, 5)), ValueError, "2-D .* or 3-D"),
        ([], ValueError, "empty"),
        (None, TypeError, "None"),
        ("abc", TypeError, "list of series"),
        ([np.full((100, 2), np.nan)], ValueError, r"X\[0\] contains 200 non-finite"),
        ([np.ones((100, 2)), np.ones((100, 3))], ValueError, "same number of states"),
        ([np.ones(100), np.ones((100, 2))], ValueError, "mixes univariate"),
        ([[[1.0, 2.0], [3.0]]], ValueError, "ragged"),
        (np.array([np.ones(3), np.ones(4)], dtype=object), ValueError, "ragged"),
        ([np.ones((5, 2))], ValueError, "series 0 has 5 samples; at least"),
        ([np.ones((100, 2), dtype=complex)], ValueError, r"X\[0\] is complex"),
        (sparse.csr_matrix(np.ones((3, 100))), TypeError, "sparse input is not supported"),
        (np.zeros((3, 0)), ValueError, r"0 feature\(s\)"),
    ],
)
def test_bad_input(X, error, match):
    with pytest.raises(error, match=match):
        SINDyFeatures(dt=DT).fit_transform(X)


@pytest.mark.parametrize(
    "params, error",
    [
        ({"embed": "yes"}, ValueError),
        ({"dt": -1.0}, ValueError),
        ({"n_jobs": 1.5}, TypeError),
        ({"progress": "no"}, TypeError),
        ({"batch_size": 0}, ValueError),
        ({"fill_failed": "zero"}, TypeError),
        ({"significant_digits": 0}, ValueError),
        ({"estimator": "ImpulseSINDy"}, TypeError),
    ],
)
def test_bad_params(params, error, series):
    with pytest.raises(error):
        SINDyFeatures(**params).fit(series)


def test_too_short_for_embedding():
    long = damped_oscillator().x[:, 0]
    feats = SINDyFeatures(dt=DT).fit([long])
    with pytest.raises(ValueError, match="embedding offset"):
        feats.transform([long[:40]])
    with pytest.raises(ValueError, match="univariate"):
        feats.transform([damped_oscillator().x])


def test_features_do_not_depend_on_n_jobs():
    # every fit runs with one BLAS thread, in the main process as in joblib's workers
    rng = np.random.default_rng(0)
    series = [damped_oscillator(k=k, k_nl=knl).x for k, knl in zip(rng.uniform(36, 400, 4), [0, 50] * 2)]
    serial = SINDyFeatures(dt=0.01, n_jobs=1).fit_transform(series)
    parallel = SINDyFeatures(dt=0.01, n_jobs=2).fit_transform(series)
    np.testing.assert_array_equal(serial, parallel)


def test_feature_names_after_the_input_features(series):
    feats = SINDyFeatures(estimator=_linear_estimator(), dt=DT).fit(series)
    names = ["x' : 1", "x' : x", "x' : v", "v' : 1", "v' : x", "v' : v"]
    assert list(feats.get_feature_names_out(["x", "v"])) == names
    assert list(feats.get_feature_names_out())[-1] == "x1' : x1"  # the default names are unchanged
    with pytest.raises(ValueError, match="input_features has 3 names for 2 states"):
        feats.get_feature_names_out(["x", "v", "a"])
    embedded = SINDyFeatures(estimator=_linear_estimator(), dt=DT).fit([s[:, 0] for s in series])
    assert list(embedded.get_feature_names_out(["x"])) == list(embedded.get_feature_names_out())
    with pytest.raises(ValueError, match="1 input feature"):
        embedded.get_feature_names_out(["x", "v"])

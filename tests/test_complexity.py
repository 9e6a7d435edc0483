"""complexity_error / ComplexityError: the complexity-error plane of the paper's section 3.2."""

import warnings

import numpy as np
import pysindy as ps
import pytest
from sklearn.pipeline import make_pipeline

from sindy_impulse import DelayEmbedding, ImpulseSINDy
from sindy_impulse.analysis import ComplexityError, complexity_error
from sindy_impulse.datasets import damped_oscillator
from sindy_impulse.simulation import gamma

DT = 0.01


@pytest.fixture(scope="module")
def ring_down():
    return damped_oscillator()


def _poly(p, **kwargs):
    return ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=p), **kwargs)


@pytest.fixture(scope="module")
def table(ring_down):
    """Table 1 of the paper, degrees 1..3: x1 embedded, one estimator per degree."""
    return complexity_error(
        {p: _poly(p) for p in (1, 2, 3)}, ring_down.x[:, 0], dt=DT, embedding=DelayEmbedding()
    )


def _mixed(ring_down, betas):
    x1, x2 = ring_down.x.T
    return {float(b): b * x1 + (1 - b) * x2 for b in betas}


# ------------------------------------------------------------------------------------------------------
# the study
# ------------------------------------------------------------------------------------------------------
def test_table1_degrees_on_embedded_x1(table, ring_down):
    assert isinstance(table, ComplexityError)
    assert len(table) == 3 and (table.n_estimators, table.n_inputs) == (3, 1)
    assert table.estimator_label.tolist() == [1, 2, 3]
    assert table.input_label.tolist() == [0, 0, 0]
    assert table.tau.tolist() == [18, 18, 18] and table.dimension.tolist() == [2, 2, 2]
    assert table.n_terms.tolist() == [4, 4, 4]
    assert table.succeeded.all() and table.stable.all()
    assert np.all(table.gamma < 0.05)  # the paper: 1.88, 1.82, 1.63
    assert np.all(table.gamma_filtered <= table.gamma_sindy)
    assert np.all(table.fit_time > 0)
    # the states are named as in the paper, the coefficients match the library
    model = table.models[2]
    assert model.feature_names_ == ["q1", "q2"]
    assert table.term_names[2] == model.get_feature_names()
    assert table.coefficients[2].shape == (2, len(table.term_names[2]))
    assert len(table.equations[0]) == 2
    # gamma is the paper's: simulation from q(0) against the embedded q
    q = DelayEmbedding().fit_transform(ring_down.x[:, 0])
    assert table.gamma[0] == pytest.approx(gamma(q, model.simulate(q[0], model.t_)), rel=1e-6, abs=1e-12)


def test_pareto_front_and_best_on_table(table):
    # equal sizes: the first of the tied least-error models is on the front
    front = table.pareto_front()
    assert front.size == 1
    assert table.best() == front[0]
    assert table.best(max_terms=4) == front[0]
    with pytest.raises(ValueError, match="no successful model"):
        table.best(max_terms=3)


def test_product_of_estimators_and_mixed_inputs(ring_down):
    betas = (0.0, 0.5, 1.0)
    res = complexity_error({1: _poly(1), 2: _poly(2)}, _mixed(ring_down, betas), t=DT,
                           embedding=DelayEmbedding())
    assert len(res) == 6
    # estimator-major order
    assert res.estimator_index.tolist() == [0, 0, 0, 1, 1, 1]
    assert res.input_index.tolist() == [0, 1, 2, 0, 1, 2]
    assert res.estimator_label.tolist() == [1, 1, 1, 2, 2, 2]
    assert res.input_label.tolist() == [0.0, 0.5, 1.0] * 2
    assert res.input_label.dtype.kind == "f"
    assert res.grid("n_terms").shape == (2, 3)
    np.testing.assert_array_equal(res.grid("tau")[0], res.grid("tau")[1])  # one embedding per input
    assert res.tau[2] == 18
    assert np.all(res.dimension == 2)
    assert np.all(res.gamma < 0.05)
    rec = res.to_records()
    assert rec.shape == (6,)
    assert set(rec.dtype.names) >= {"estimator_label", "input_label", "n_terms", "gamma", "pareto", "tau"}
    assert rec.pareto.sum() == res.pareto_front().size
    text = res.summary()
    assert text.splitlines()[0].split()[0] == "estimator" and len(text.splitlines()) == 3


def test_state_arrays_without_embedding(ring_down):
    res = complexity_error([_poly(1), _poly(3)], [ring_down.x], t=ring_down.t, estimator_labels=["p1", "p3"],
                           input_labels=["full state"], feature_names=["x", "v"])
    assert res.estimator_label.tolist() == ["p1", "p3"]
    assert res.tau.tolist() == [-1, -1] and res.dimension.tolist() == [-1, -1]
    assert res.n_terms.tolist() == [3, 3]
    np.testing.assert_allclose(res.coefficients[0][1, 1:], [-64.0, -3.2], rtol=1e-2)
    assert res.models[0].feature_names_ == ["x", "v"]
    assert np.all(res.gamma < 0.05)


def test_estimator_dt_is_used_without_t(ring_down):
    res = complexity_error(ImpulseSINDy(dt=DT), ring_down.x)
    np.testing.assert_allclose(np.diff(res.models[0].t_), DT)
    np.testing.assert_allclose(res.coefficients[0][1, 1:3], [-64.0, -3.2], rtol=1e-2)


def test_time_vectors_are_shortened_by_the_embedding(ring_down):
    signals = _mixed(ring_down, (0.5, 1.0))
    res = complexity_error(_poly(1), signals, t={b: ring_down.t for b in signals}, embedding=DelayEmbedding())
    for model, tau in zip(res.models, res.tau):
        assert model.t_[0] == pytest.approx(tau * DT)
    res_list = complexity_error(_poly(1), list(signals.values()), t=[ring_down.t, ring_down.t],
                                embedding=DelayEmbedding())
    np.testing.assert_allclose(res_list.gamma, res.gamma)


def test_originals_untouched_and_keep_models(ring_down):
    est = _poly(1)
    res = complexity_error(est, ring_down.x, t=DT, keep_models=False)
    assert not hasattr(est, "optimizer_")
    assert res.models == [None]
    assert res.coefficients[0] is not None and res.n_terms[0] == 3


def test_n_jobs_gives_the_serial_result(ring_down):
    signals = _mixed(ring_down, (0.25, 1.0))
    serial = complexity_error([_poly(1), _poly(2)], signals, t=DT, embedding=DelayEmbedding())
    parallel = complexity_error([_poly(1), _poly(2)], signals, t=DT, embedding=DelayEmbedding(), n_jobs=2)
    # other processes may round differently (BLAS threads); the Gammas here are ~1e-4
    np.testing.assert_allclose(parallel.gamma, serial.gamma, rtol=0.1, atol=1e-4)
    np.testing.assert_array_equal(parallel.n_terms, serial.n_terms)
    assert all(m is not None for m in parallel.models)


# ------------------------------------------------------------------------------------------------------
# failures are data points
# ------------------------------------------------------------------------------------------------------
def test_failing_fit_is_recorded(ring_down):
    short = ring_down.x[:16]  # degree 5 in 2 states: 21 terms, too few samples
    with pytest.warns(RuntimeWarning, match="1 of 2 fits failed"):
        res = complexity_error({1: _poly(1), 5: _poly(5)}, short, t=DT)
    assert res.succeeded.tolist() == [True, False]
    assert res.gamma[1] == np.inf and res.n_terms[1] == -1 and np.isnan(res.gamma_filtered[1])
    assert res.coefficients[1] is None and res.models[1] is None
    assert res.errors[0] is None and res.errors[1].startswith("ValueError: too few samples")
    assert 1 not in res.pareto_front().tolist()
    assert res.to_records().succeeded.tolist() == [True, False]
    with pytest.raises(ValueError, match="too few samples"):
        complexity_error(_poly(5), short, t=DT, errors="raise")


def test_failing_embedding_is_recorded(ring_down):
    signals = {"ok": ring_down.x[:, 0], "flat": np.ones(401)}
    with pytest.warns(RuntimeWarning, match="embedding of inputs\\[1\\] failed"):
        res = complexity_error(_poly(1), signals, t=DT, embedding=DelayEmbedding())
    assert res.succeeded.tolist() == [True, False]
    assert res.tau.tolist() == [18, -1]
    assert res.input_label.tolist() == ["ok", "flat"]


def test_pareto_front_on_constructed_plane():
    n_terms = np.array([4, 6, 3, 4, -1, 8, 3])
    err = np.array([1.0, 0.5, 2.0, 0.8, np.inf, 0.5, 2.0])
    n = n_terms.size
    res = ComplexityError(
        gamma=err, gamma_filtered=err, gamma_sindy=err, n_terms=n_terms,
        estimator_index=np.zeros(n, int), input_index=np.arange(n), estimator_label=np.zeros(n, int),
        input_label=np.arange(n), tau=np.full(n, -1), dimension=np.full(n, -1), fit_time=np.zeros(n),
        coefficients=[None] * n, term_names=[None] * n, equations=[None] * n, models=[None] * n,
        errors=[None, None, None, None, "ValueError: x", None, None], n_estimators=1, n_inputs=n,
    )
    assert res.pareto_front().tolist() == [2, 3, 1]  # 3 terms/2.0, 4/0.8, 6/0.5; the 8-term model dominated
    assert res.best() == 1
    assert res.best(max_terms=5) == 3
    with pytest.raises(ValueError, match="metric"):
        res.pareto_front("aic")
    with pytest.raises(ValueError, match="name must be"):
        res.grid("coefficients")


# ------------------------------------------------------------------------------------------------------
# bad input
# ------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        ({"estimators": "ImpulseSINDy"}, TypeError, "estimators must be"),
        ({"estimators": [object()]}, TypeError, "not an ImpulseSINDy-like"),
        ({"estimators": make_pipeline(DelayEmbedding(), ImpulseSINDy())}, TypeError, "embedding="),
        ({"estimators": []}, ValueError, "estimators is empty"),
        ({"inputs": []}, ValueError, "inputs is empty"),
        ({"inputs": np.full(100, np.nan)}, ValueError, "non-finite"),
        ({"inputs": np.ones((50, 2)) + 1j}, (TypeError, ValueError), "complex"),
        ({"inputs": np.zeros((50, 2))}, ValueError, "columns; an embedding needs one signal"),
        ({"t": 0.01, "dt": 0.01}, ValueError, "either t or dt"),
        ({"t": np.arange(10.0)}, ValueError, "entries but the data have"),
        ({"dt": -1.0}, ValueError, "positive"),
        ({"errors": "ignore"}, ValueError, "errors must be"),
        ({"n_jobs": 0}, ValueError, "n_jobs"),
        ({"keep_models": "yes"}, TypeError, "keep_models"),
        ({"embedding": "delay"}, TypeError, "embedding must be"),
        ({"estimator_labels": [1, 2]}, ValueError, "estimator_labels has 2 labels for 1"),
        ({"input_labels": "beta"}, TypeError, "input_labels must be a sequence"),
        ({"feature_names": "q"}, TypeError, "feature_names"),
        ({"estimators": {1: ImpulseSINDy()}, "estimator_labels": [1]}, ValueError, "keys are the labels"),
    ],
)
def test_bad_input(ring_down, kwargs, exc, match):
    args = {"estimators": ImpulseSINDy(), "inputs": ring_down.x[:, 0], "dt": DT}
    args["embedding"] = DelayEmbedding()
    if "t" in kwargs:
        args.pop("dt")
    args.update(kwargs)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no fit may run before the error
        with pytest.raises(exc, match=match):
            complexity_error(args.pop("estimators"), args.pop("inputs"), **args)

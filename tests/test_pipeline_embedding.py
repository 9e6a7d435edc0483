"""Single-sensor identification: DelayEmbedding followed by ImpulseSINDy in a scikit-learn Pipeline
(paper sections 2.2, 3.1.3 and 3.2)."""

import numpy as np
import pysindy as ps
import pytest
from sklearn.base import clone
from sklearn.pipeline import make_pipeline

from sindy_impulse import DelayEmbedding, ImpulseSINDy
from sindy_impulse.datasets import damped_oscillator
from sindy_impulse.simulation import gamma

DT = 0.01
OMEGA, ZETA = 8.0, 0.2


@pytest.fixture(scope="module")
def ring_down():
    return damped_oscillator()


def _modal(coef_2x2):
    """Natural frequency and damping ratio of a linear 2x2 system matrix."""
    lam = np.linalg.eigvals(coef_2x2)
    lam = lam[np.argmax(lam.imag)]
    return abs(lam), -lam.real / abs(lam)


def _linear_block(model):
    """The 2x2 matrix of the linear terms (columns named like the states)."""
    names = model.get_feature_names()
    cols = [names.index(n) for n in model.feature_names_]
    return model.coefficients()[:, cols]


def test_pipeline_on_x1(ring_down):
    s = ring_down.x[:, 0]
    pipe = make_pipeline(DelayEmbedding(), ImpulseSINDy(dt=DT))
    pipe.fit(s)  # the Pipeline calls fit(Xt, None): y=None lands in t and falls back to dt
    emb, model = pipe[0], pipe[-1]
    assert (emb.tau_, emb.dimension_) == (18, 2)
    assert model.n_features_in_ == 2
    q = emb.transform(s)
    assert model.x_filtered_.shape == q.shape
    np.testing.assert_allclose(np.diff(model.t_), DT)
    # the paper's Gamma: simulation from q(0) against the embedded trajectories
    assert gamma(q, model.simulate(q[0], model.t_)) < 0.05
    assert np.isfinite(model.gamma_) and model.gamma_ <= model.gamma_sindy_
    # a linear system stays linear in delay coordinates: four linear terms, no constant, no nonlinearity
    assert model.complexity == 4
    omega, zeta = _modal(_linear_block(model))
    assert omega == pytest.approx(OMEGA, rel=1e-3)
    assert zeta == pytest.approx(ZETA, rel=1e-2)


def test_pipeline_fit_params_and_predict(ring_down):
    s = ring_down.x[:, 0]
    sindy = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=2), dt=DT)
    pipe = make_pipeline(DelayEmbedding(), sindy)
    pipe.fit(s, impulsesindy__feature_names=["q1", "q2"])
    model = pipe[-1]
    assert model.get_feature_names()[:3] == ["1", "q1", "q2"]
    # predict runs through the embedding: the right-hand side at each delay vector
    rhs = pipe.predict(s)
    assert rhs.shape == (s.size - pipe[0].offset_, 2)
    assert np.all(np.isfinite(rhs))
    # and the pipeline is clonable (its parameters are untouched)
    assert clone(pipe).get_params()["impulsesindy__dt"] == DT


@pytest.mark.parametrize("beta", [0.0, 0.3, 0.75, 1.0])
def test_pipeline_on_mixed_signal(ring_down, beta):
    """s = beta x1 + (1 - beta) x2 (section 3.2): still a linear 2-D system in delay coordinates."""
    x1, x2 = ring_down.x.T
    s = beta * x1 + (1 - beta) * x2
    pipe = make_pipeline(DelayEmbedding(), ImpulseSINDy(dt=DT)).fit(s)
    emb, model = pipe[0], pipe[-1]
    assert emb.dimension_ == 2
    assert 15 <= emb.tau_ <= 25  # about a quarter period (19.6 samples)
    q = emb.transform(s)
    assert gamma(q, model.simulate(q[0], model.t_)) < 0.05
    assert model.complexity == 4
    omega, zeta = _modal(_linear_block(model))
    assert omega == pytest.approx(OMEGA, rel=1e-3)
    assert zeta == pytest.approx(ZETA, rel=1e-2)


def test_fixed_embedding_parameters_in_pipeline(ring_down):
    """Fixed tau/m skip the estimation; m = 3 over-embeds and the model must still simulate stably."""
    s = ring_down.x[:, 0]
    sindy = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=1), dt=DT)
    pipe = make_pipeline(DelayEmbedding(tau=18, dimension=3), sindy).fit(s)
    q = pipe[0].transform(s)
    assert q.shape == (s.size - 36, 3)
    sim = pipe[-1].simulate(q[0], pipe[-1].t_)
    assert np.all(np.isfinite(sim))
    assert gamma(q, sim) < 2.0  # the paper's level (Table 1: 1.6-1.9 for m = 2)


def test_pipeline_with_time_vector_via_fit_params(ring_down):
    """A time vector for the states has to be shortened by the embedding offset: transform_time."""
    s, t = ring_down.x[:, 0], ring_down.t
    emb = DelayEmbedding().fit(s)
    model = ImpulseSINDy().fit(emb.transform(s), t=emb.transform_time(t))
    np.testing.assert_allclose(model.t_[0], 0.18)
    assert model.complexity == 4

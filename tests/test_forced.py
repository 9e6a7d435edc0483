"""Control inputs everywhere: a forced oscillator identified from its measured force and response.

x'' + 0.8 x' + 64 x = f(t) (datasets.forced_oscillator), 40 dB noise on the response, the force given as
``u``: fit, predict, simulate, the sweep and the refinement are all driven by the force; a delay-embedded
displacement takes the force aligned by DelayEmbedding.transform_input.
"""

import warnings

import numpy as np
import pysindy as ps
import pytest

from sindy_impulse import DelayEmbedding, ImpulseSINDy
from sindy_impulse.datasets import forced_oscillator

K, C, M = 64.0, 0.8, 1.0
NAMES = ["x", "v", "f"]


@pytest.fixture(scope="module")
def shaker():
    return forced_oscillator(force="random", snr_db=40, random_state=0)


@pytest.fixture(scope="module")
def fitted(shaker):
    return ImpulseSINDy().fit(shaker.x, t=shaker.t, u=shaker.u, feature_names=NAMES)


def _k_c_gain(model):
    names, coef = model.get_feature_names(), model.coefficients()
    return -coef[1, names.index("x")], -coef[1, names.index("v")], coef[1, names.index("f")]


def test_random_force_gives_k_and_c_within_one_percent(fitted):
    k, c, gain = _k_c_gain(fitted)
    assert abs(k / K - 1) < 0.01 and abs(c / C - 1) < 0.01 and abs(gain * M - 1) < 0.01
    assert fitted.complexity == 4  # x' = v, v' = -k x - c v + f / m


@pytest.mark.parametrize("seed", [0, 1])
def test_hammer_force_gives_k_and_c_within_one_percent(seed):
    data = forced_oscillator(force="hammer", snr_db=40, random_state=seed)
    library = ps.PolynomialLibrary(degree=1)  # the force acts on 15 of 1001 samples: a small library
    model = ImpulseSINDy(feature_library=library).fit(data.x, t=data.t, u=data.u, feature_names=NAMES)
    k, c, gain = _k_c_gain(model)
    assert abs(k / K - 1) < 0.01 and abs(c / C - 1) < 0.01 and abs(gain * M - 1) < 0.01
    assert model.complexity == 4


def test_without_the_force_the_response_is_not_explained(shaker, fitted):
    model = ImpulseSINDy().fit(shaker.x, t=shaker.t)
    k = -model.coefficients()[1, model.get_feature_names().index("x0")]
    assert abs(k / K - 1) > 0.05 or model.gamma_ > 10 * fitted.gamma_


def test_the_sweep_and_the_refinement_simulate_with_the_force(shaker):
    seen = []

    def spy(model, reference, t, coefs, u=None):
        seen.append(u)
        sims = [model.simulate(reference[0], t, u=u, coef=c) for c in coefs]
        return np.array([np.sum(np.abs(s - reference)) for s in sims])

    model = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=1), error_measure=spy, refine_max_iter=5)
    model.fit(shaker.x, t=shaker.t, u=shaker.u)
    assert len(model.path_) > 2 and len(model.refinement_history_["score"]) >= 1
    assert len(seen) > len(model.path_)  # every candidate, then the refinement's evaluations
    assert all(u is not None and np.array_equal(u, shaker.u) for u in seen)


def test_simulate_and_predict_take_the_force(shaker, fitted):
    sim = fitted.simulate(shaker.x_clean[0], shaker.t, u=shaker.u)
    scale = np.max(np.abs(shaker.x_clean), axis=0)
    assert np.max(np.abs(sim - shaker.x_clean) / scale) < 0.02
    assert fitted.predict(shaker.x, u=shaker.u).shape == shaker.x.shape
    assert fitted.score(shaker.x, t=shaker.t, u=shaker.u) > -50
    with pytest.raises(TypeError, match="u is required"):
        fitted.simulate(shaker.x[0], shaker.t)
    with pytest.raises(ValueError, match="u has shape"):
        fitted.predict(shaker.x, u=shaker.u[:-1])


def test_transform_input_aligns_the_force_with_the_embedded_rows(shaker):
    s, u = shaker.x[:, 0], shaker.u
    emb = DelayEmbedding(tau=3, dimension=3).fit(s)
    q, tq = emb.transform(s), emb.transform_time(shaker.t)
    now, delayed = emb.transform_input(u, delayed=False), emb.transform_input(u)
    assert now.shape == (q.shape[0], 1) and delayed.shape == (q.shape[0], 3)
    np.testing.assert_array_equal(now[:, 0], u[emb.offset_ :, 0])  # row r is sample offset_ + r, time tq[r]
    np.testing.assert_array_equal(tq, shaker.t[emb.offset_ :])
    np.testing.assert_array_equal(delayed, emb.transform(u[:, 0]))  # the force at the same delays as q
    with pytest.raises(ValueError, match="u has 5 samples"):
        emb.transform_input(u[:5])


def test_embedded_displacement_with_the_force_at_the_delays():
    data = forced_oscillator(force="random", snr_db=40, random_state=1)
    emb = DelayEmbedding(tau=3, dimension=2).fit(data.x[:, 0])
    q, tq, uq = emb.transform(data.x[:, 0]), emb.transform_time(data.t), emb.transform_input(data.u)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=1, include_bias=False))
        model.fit(q, t=tq, u=uq)
    eig = np.linalg.eigvals(model.coefficients()[:, :2])
    wn = np.max(np.abs(eig))
    zeta = -eig[np.argmax(np.abs(eig))].real / wn
    assert abs(wn / 8.0 - 1) < 0.002 and abs(zeta / 0.05 - 1) < 0.02

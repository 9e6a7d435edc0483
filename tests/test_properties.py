"""Property-based tests (hypothesis): invariances of the identified model and pickling round trips.

Examples are drawn from the paper's oscillator family (random stiffness, damping, cubic stiffness and
noise) and derandomized, so the file is deterministic and runs in well under 90 s.
"""

from __future__ import annotations

import pickle

import numpy as np
import pysindy as ps
from hypothesis import given, settings
from hypothesis import strategies as st

from sindy_impulse import (
    DelayEmbedding,
    ImpulseSINDy,
    MechanicalLibrary,
    ThresholdSweep,
    TVRegDiff,
    damped_oscillator,
)

FEW = settings(max_examples=10, deadline=None, derandomize=True)


@st.composite
def ring_downs(draw):
    """A ring-down of the paper's oscillator with random parameters (clean or mildly noisy)."""
    k = draw(st.floats(20.0, 120.0))
    zeta = draw(st.floats(0.05, 0.3))
    k_nl = draw(st.sampled_from([0.0, 0.0, 10.0]))
    snr = draw(st.sampled_from([None, 60.0, 50.0]))
    seed = draw(st.integers(0, 2**16))
    return damped_oscillator(k=k, c=2 * zeta * np.sqrt(k), k_nl=k_nl, snr_db=snr, random_state=seed)


def _terms(model) -> dict:
    """{(state name, monomial as {name: power}) -> coefficient} for the non-zero coefficients."""
    names = model.feature_names_
    powers = np.asarray(model.feature_library_.powers_)
    out = {}
    for i, row in enumerate(model.coefficients()):
        for j in np.flatnonzero(row):
            monomial = frozenset((names[s], int(p)) for s, p in enumerate(powers[j]) if p)
            out[(names[i], monomial)] = row[j]
    return out


def _assert_same_model(a: dict, b: dict, rtol=1e-3):
    assert a.keys() == b.keys()
    scale = max(abs(v) for v in a.values())
    for key in a:
        assert abs(a[key] - b[key]) <= rtol * abs(a[key]) + 1e-6 * scale, (key, a[key], b[key])


@FEW
@given(ring_downs(), st.floats(-6.0, 6.0))
def test_scale_invariance(ring, log_scale):
    scale = 10.0**log_scale
    a = _terms(ImpulseSINDy().fit(ring.x, t=ring.t, feature_names=["x", "v"]))
    b = _terms(ImpulseSINDy().fit(ring.x * scale, t=ring.t, feature_names=["x", "v"]))
    degree = {key: sum(p for _, p in key[1]) for key in b}
    _assert_same_model(a, {key: value * scale ** (degree[key] - 1) for key, value in b.items()})


@FEW
@given(ring_downs(), st.floats(1.0, 1000.0))
def test_time_shift_invariance(ring, offset):
    a = _terms(ImpulseSINDy().fit(ring.x, t=ring.t, feature_names=["x", "v"]))
    b = _terms(ImpulseSINDy().fit(ring.x, t=ring.t + offset, feature_names=["x", "v"]))
    _assert_same_model(a, b)


@FEW
@given(ring_downs())
def test_reordering_the_states_permutes_the_model(ring):
    a = _terms(ImpulseSINDy().fit(ring.x, t=ring.t, feature_names=["x", "v"]))
    b = _terms(ImpulseSINDy().fit(ring.x[:, ::-1], t=ring.t, feature_names=["v", "x"]))
    _assert_same_model(a, b)


@FEW
@given(ring_downs(), st.booleans())
def test_refit_is_idempotent(ring, mechanical):
    model = ImpulseSINDy(feature_library=MechanicalLibrary() if mechanical else None)
    first = model.fit(ring.x, t=ring.t).coefficients().copy()
    gamma = model.gamma_
    second = model.fit(ring.x, t=ring.t).coefficients()
    np.testing.assert_array_equal(first, second)
    assert model.gamma_ == gamma


def _roundtrip(obj):
    return pickle.loads(pickle.dumps(obj))


@FEW
@given(ring_downs(), st.sampled_from(["auto", "min_gamma"]))
def test_pickle_impulse_sindy(ring, selection):
    model = ImpulseSINDy(selection=selection).fit(ring.x, t=ring.t)
    copy = _roundtrip(model)
    np.testing.assert_array_equal(copy.coefficients(), model.coefficients())
    np.testing.assert_array_equal(copy.simulate(ring.x[0], ring.t), model.simulate(ring.x[0], ring.t))
    np.testing.assert_array_equal(copy.predict(ring.x), model.predict(ring.x))
    assert copy.equations() == model.equations()


@FEW
@given(ring_downs(), st.sampled_from([1, 2, 3]), st.sampled_from(["auto", 0.1]))
def test_pickle_tvregdiff(ring, order, alpha):
    est = TVRegDiff(order=order, alpha=alpha).fit(ring.x)
    copy = _roundtrip(est)
    np.testing.assert_array_equal(copy.alpha_, est.alpha_)
    np.testing.assert_array_equal(copy.transform(ring.x), est.transform(ring.x))
    assert copy.get_params() == est.get_params()


@FEW
@given(ring_downs(), st.sampled_from(["acf", "mutual_information"]), st.sampled_from(["fnn", "cao"]))
def test_pickle_delay_embedding(ring, delay_method, dimension_method):
    s = ring.x[:, 0]
    emb = DelayEmbedding(delay_method=delay_method, dimension_method=dimension_method).fit(s)
    copy = _roundtrip(emb)
    assert (copy.tau_, copy.dimension_) == (emb.tau_, emb.dimension_)
    np.testing.assert_array_equal(copy.transform(s), emb.transform(s))


@FEW
@given(ring_downs(), st.integers(1, 4), st.booleans(), st.booleans())
def test_pickle_mechanical_library(ring, degree, damping, friction):
    lib = MechanicalLibrary(degree=degree, quadratic_damping=damping, friction=friction).fit(ring.x)
    copy = _roundtrip(lib)
    np.testing.assert_array_equal(copy.transform(ring.x), lib.transform(ring.x))
    assert copy.get_feature_names(["x", "v"]) == lib.get_feature_names(["x", "v"])


@FEW
@given(ring_downs(), st.integers(1, 30))
def test_pickle_threshold_sweep(ring, max_iter):
    theta = np.asarray(ps.PolynomialLibrary(degree=3).fit_transform(ring.x))
    sweep = ThresholdSweep(max_iter=max_iter).fit(theta, ring.x_dot)
    copy = _roundtrip(sweep)
    np.testing.assert_array_equal(copy.coef_, sweep.coef_)
    np.testing.assert_array_equal(np.asarray(copy.history_), np.asarray(sweep.history_))
    assert copy.get_params() == sweep.get_params()

"""consensus / consensus_fit: one coefficient matrix from repeated measurements."""

import numpy as np
import pysindy as ps
import pytest
from sklearn.base import clone

from sindy_impulse import ImpulseSINDy, damped_oscillator
from sindy_impulse.analysis import Consensus, consensus, modal_parameters
from sindy_impulse.analysis.consensus import consensus_fit


def _stack(rng, n=20, outliers=()):
    """Coefficient stack (n, 2, 3) around the oscillator with a few outliers and a spurious term."""
    true = np.array([[0.0, 0.0, 1.0], [0.0, -64.0, -3.2]])
    stack = true + 0.001 * rng.standard_normal((n, 2, 3)) * (true != 0)
    for j in outliers:
        stack[j, 1, 1] = -90.0
    stack[:3, 1, 0] = 0.4  # a spurious constant in 3 of n models
    return stack


def test_mode_ignores_outliers_and_minority_terms():
    rng = np.random.default_rng(0)
    stack = _stack(rng, outliers=(0, 1, 2, 3))
    res = consensus(stack, feature_names=["1", "x0", "x1"])
    assert isinstance(res, Consensus)
    assert abs(res.coefficients[1, 1] + 64.0) < 0.01
    assert res.coefficients[1, 0] == 0.0  # non-zero in 3 of 20 models only
    np.testing.assert_allclose(res.frequency_nonzero[1, 0], 0.15)
    np.testing.assert_allclose(res.frequency_nonzero[1, 1], 1.0)
    # median is pulled towards the outliers less than the mean but still a valid alternative
    med = consensus(stack, method="median", feature_names=["1", "x0", "x1"])
    assert abs(med.coefficients[1, 1] + 64.0) < 0.01


def test_histograms_kept_for_figure_12():
    rng = np.random.default_rng(1)
    stack = _stack(rng)
    res = consensus(stack, feature_names=["1", "x0", "x1"])
    assert set(res.histograms) == {(0, 2), (1, 0), (1, 1), (1, 2)}
    h = res.histograms[(1, 1)]
    assert h.counts.sum() == 20 and len(h.edges) == len(h.counts) + 1
    assert h.edges[h.peak] <= res.coefficients[1, 1] <= h.edges[h.peak + 1]
    assert res.names()[(1, 1)] == "x1' : x0"


def test_identical_values_and_min_frequency():
    stack = np.zeros((4, 1, 2))
    stack[:, 0, 0] = 2.5
    stack[:2, 0, 1] = 1.0
    res = consensus(stack)
    np.testing.assert_array_equal(res.coefficients, [[2.5, 1.0]])  # 1.0 in exactly half: kept
    res = consensus(stack, min_frequency=0.75)
    np.testing.assert_array_equal(res.coefficients, [[2.5, 0.0]])


def test_bimodal_picks_larger_peak():
    values = np.r_[np.full(7, 10.0) + np.linspace(0, 0.01, 7), np.full(4, 20.0)]
    res = consensus(values[:, None, None])
    assert abs(res.coefficients[0, 0] - 10.005) < 0.01


def test_fitted_models_repeated_impacts():
    rings = [damped_oscillator(x0=(a, v)) for a, v in [(1, 0), (0.6, -2), (-0.2, 1), (-1, 3)]]
    est = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=1))
    models = [clone(est).fit(r.x, t=r.t) for r in rings]
    res = consensus(models)
    np.testing.assert_allclose(res.coefficients, [[0, 0, 1], [0, -64, -3.2]], atol=1e-3)
    assert res.feature_names == ["1", "x0", "x1"] and res.state_names == ["x0", "x1"]
    # the consensus model simulates and has modal parameters
    sim = res.compiled(reference=rings[0].x).simulate(rings[0].x[0], rings[0].t)
    assert np.max(np.abs(sim - rings[0].x)) < 1e-3
    assert abs(modal_parameters(res).frequencies_hz[0] - 8 / (2 * np.pi)) < 1e-3
    assert "x1' = " in repr(res)


def test_consensus_fit_stacked():
    rings = [damped_oscillator(x0=(a, 0)) for a in (1.0, -0.5)]
    est = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=1))
    res = consensus_fit(est, [r.x for r in rings], t=0.01)
    assert res.method == "stacked" and res.n_models == 1 and res.histograms == {}
    np.testing.assert_allclose(res.coefficients, [[0, 0, 1], [0, -64, -3.2]], atol=1e-3)
    assert not hasattr(est, "optimizer_")  # the template is not fitted
    with pytest.raises(ValueError, match="non-empty list"):
        consensus_fit(est, rings[0].x)


def test_callable_in_any_import_order():
    import sindy_impulse.analysis as analysis

    assert callable(analysis.consensus)
    assert isinstance(analysis.consensus(np.ones((2, 1, 1))), Consensus)


def test_errors():
    stack = np.zeros((3, 2, 2))
    with pytest.raises(ValueError, match="method"):
        consensus(stack, method="stacked")
    with pytest.raises(ValueError, match="min_frequency"):
        consensus(stack, min_frequency=0)
    with pytest.raises(ValueError, match="max_bins"):
        consensus(stack, max_bins=0)
    with pytest.raises(ValueError, match="n_models, n_states, n_features"):
        consensus(np.zeros((3, 2)))
    with pytest.raises(ValueError, match="NaN"):
        consensus(np.full((2, 1, 1), np.nan))
    with pytest.raises(ValueError, match="feature names"):
        consensus(stack, feature_names=["a"])
    with pytest.raises(ValueError, match="non-empty"):
        consensus([])
    with pytest.raises(TypeError, match="not a fitted SINDy model"):
        consensus(["a", "b"])
    with pytest.raises(ValueError, match="not fitted"):
        consensus([ImpulseSINDy()])
    t, x, _ = damped_oscillator()
    m1 = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=1)).fit(x, t=t)
    m3 = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=2)).fit(x, t=t)
    with pytest.raises(ValueError, match="different library"):
        consensus([m1, m3])
    with pytest.raises(ValueError, match="library is unknown"):
        consensus(np.ones((2, 1, 1))).compiled()

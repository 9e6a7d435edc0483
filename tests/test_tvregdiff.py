import pickle

import numpy as np
import pysindy as ps
import pytest
from sklearn.base import clone

from sindy_impulse.datasets import add_noise, damped_oscillator
from sindy_impulse.differentiation import TVRegDiff
from sindy_impulse.differentiation._banded import (
    _trace_inverse_py,
    apply_difference,
    apply_difference_transpose,
    consistency_error,
    difference_stencil,
    lambda_max,
    lapack_smooth,
    normal_band,
    polynomial_residual,
    trace_inverse,
    tv_smooth,
)
from sindy_impulse.differentiation._smoother import smooth
from sindy_impulse.differentiation._spline import SplineBasis

T = np.arange(401) * 0.01
X = np.exp(-1.6 * T) * np.cos(7.8 * T)
X_DOT = np.exp(-1.6 * T) * (-1.6 * np.cos(7.8 * T) - 7.8 * np.sin(7.8 * T))


def interior_rms(d, exact, trim=5):
    return float(np.sqrt(np.mean((np.ravel(d)[trim:-trim] - exact[trim:-trim]) ** 2)))


# ---------------------------------------------------------------- banded building blocks
def dense_difference(coef, n):
    return np.array([apply_difference(coef, e) for e in np.eye(n)]).T  # (n - m, n)


@pytest.mark.parametrize("uniform", [True, False])
@pytest.mark.parametrize("m", [2, 3, 4])
def test_normal_band_and_trace_match_dense(uniform, m):
    rng = np.random.default_rng(m)
    n = 25
    tau = None if uniform else np.cumsum(rng.uniform(0.5, 1.5, n))
    coef, h = difference_stencil(tau, n, m)
    dense_d = dense_difference(coef, n)
    v = rng.standard_normal(n - m)
    np.testing.assert_allclose(apply_difference_transpose(coef, v), dense_d.T @ v, atol=1e-12)
    w = rng.uniform(0.1, 3.0, n - m)
    band = normal_band(coef, w, n)
    dense = np.eye(n) + dense_d.T @ np.diag(w) @ dense_d
    for s in range(m + 1):
        np.testing.assert_allclose(band[s, : n - s], np.diag(dense, -s), rtol=1e-12, atol=1e-12)
    expected = np.trace(np.linalg.inv(dense))
    assert trace_inverse(band) == pytest.approx(expected, rel=1e-10)
    assert _trace_inverse_py(band, np.ones((1, n))) == pytest.approx(expected, rel=1e-10)


@pytest.mark.parametrize("m", [2, 4])
def test_spline_basis_gram_rhs_and_trace_match_dense(m):
    rng = np.random.default_rng(10 + m)
    tau = np.sort(rng.uniform(0, 60, 200))
    basis = SplineBasis(tau, 20)
    dense_b = np.array([basis.values(e) for e in np.eye(basis.n_coef)]).T  # (n, n_coef)
    f = rng.standard_normal(tau.size)
    np.testing.assert_allclose(basis.rhs(f), dense_b.T @ f, atol=1e-10)
    gram = dense_b.T @ dense_b
    for s in range(4):
        np.testing.assert_allclose(basis.gram[s, : basis.n_coef - s], np.diag(gram, -s), atol=1e-8)
    coef, _ = difference_stencil(None, basis.n_coef, m)
    w = rng.uniform(0.1, 3.0, basis.n_coef - m)
    dense_d = dense_difference(coef, basis.n_coef)
    a = np.diag(basis.gram[0])
    for s in range(1, 4):
        a = a + np.diag(basis.gram[s, : basis.n_coef - s], -s) + np.diag(basis.gram[s, : basis.n_coef - s], s)
    a = a + dense_d.T @ np.diag(w) @ dense_d
    band = normal_band(coef, w, basis.n_coef, basis.gram)
    expected = np.trace(np.linalg.solve(a, gram))
    assert trace_inverse(band, basis.gram) == pytest.approx(expected, rel=1e-8)


def test_spline_basis_reproduces_cubics_and_their_slopes():
    tau = np.linspace(0, 50, 333)
    basis = SplineBasis(tau, 30)
    poly = 0.001 * tau**3 - 0.05 * tau**2 + tau - 2
    c, _ = tv_smooth(basis.rhs(poly), *difference_stencil(None, basis.n_coef, 4), 0.0, basis.start(poly),
                     basis.gram, max_iter=1)
    np.testing.assert_allclose(basis.values(c), poly, atol=1e-6)
    np.testing.assert_allclose(basis.slopes(c), 0.003 * tau**2 - 0.1 * tau + 1, atol=1e-6)


def test_spline_basis_scores_in_one_pass_match_the_arrays():
    rng = np.random.default_rng(3)
    tau = np.sort(rng.uniform(0, 80, 500))
    basis = SplineBasis(tau, 40)
    c, g = rng.standard_normal(basis.n_coef), rng.standard_normal(tau.size)
    values, slopes = basis.evaluate(c)
    rss, consistency = basis.fit_scores(c, g, trim=5)
    assert rss == pytest.approx(np.sum((g - values) ** 2), rel=1e-12)
    assert consistency == pytest.approx(consistency_error(g, slopes, tau, 5), rel=1e-10)


@pytest.mark.parametrize("basis", ["identity", "spline", "non-uniform"])
def test_compiled_smoother_follows_the_lapack_iteration(basis):
    rng = np.random.default_rng(4)
    tau = np.sort(rng.uniform(0, 300, 300)) if basis == "non-uniform" else np.arange(300.0)
    f = np.sin(tau / 20) + 0.05 * rng.standard_normal(tau.size)
    gram, rhs, n = None, f, tau.size
    if basis != "identity":
        spline = SplineBasis(tau, 60)
        gram, rhs, n = spline.gram, spline.rhs(f), spline.n_coef
    coef, h = difference_stencil(None, n, 4)
    start = np.interp(np.linspace(0, 1, n), np.linspace(0, 1, tau.size), f)
    c, its = smooth(rhs, coef, h, 3.0, start, gram, 30, 1e-8, 1.0)
    c_ref, its_ref = lapack_smooth(rhs, coef, h, 3.0, start, gram, 30, 1e-8, 1.0)
    assert abs(its - its_ref) <= 1
    # the same iteration; the systems are ill conditioned (weights up to 1e12), so rounding shows at 1e-9
    np.testing.assert_allclose(c, c_ref, rtol=0, atol=1e-7 * np.max(np.abs(c_ref)))


@pytest.mark.parametrize("uniform", [True, False])
def test_difference_stencil_is_exact_on_polynomials(uniform):
    rng = np.random.default_rng(0)
    n, m = 30, 3
    tau = np.arange(n, dtype=float) if uniform else np.cumsum(rng.uniform(0.5, 1.5, n))
    coef, _ = difference_stencil(None if uniform else tau, n, m)
    # the m-th derivative of tau^m is m! ; lower powers vanish
    np.testing.assert_allclose(apply_difference(coef, tau**3), 6.0, rtol=1e-8)
    np.testing.assert_allclose(apply_difference(coef, tau**2 + tau), 0.0, atol=1e-8)


@pytest.mark.parametrize("uniform", [True, False])
def test_lambda_max_gives_polynomial_and_below_it_does_not(uniform):
    rng = np.random.default_rng(1)
    tau = np.arange(60, dtype=float) if uniform else np.cumsum(rng.uniform(0.7, 1.3, 60))
    f = np.sin(tau / 10) + 0.1 * rng.standard_normal(60)
    coef, h = difference_stencil(None if uniform else tau, 60, 2)
    lam = lambda_max(polynomial_residual(f, tau, 1), coef, h)
    line = np.polyval(np.polyfit(tau, f, 1), tau)
    options = {"max_iter": 300, "tol": 1e-12, "eps_rel": 1e-6}
    above, _ = tv_smooth(f, coef, h, 1.05 * lam, f, **options)
    below, _ = tv_smooth(f, coef, h, 0.3 * lam, f, **options)
    assert np.max(np.abs(above - line)) < 1e-3
    assert np.max(np.abs(below - line)) > 1e-2


# ---------------------------------------------------------------- accuracy
def test_clean_ring_down_accuracy():
    d = TVRegDiff()(X[:, None], T)
    # np.gradient's truncation error is 1.7e-3 here; the regularization must not add to it
    assert interior_rms(d, X_DOT) < 2.5e-3


@pytest.mark.parametrize("snr, bound", [(40, 0.015), (20, 0.08)])
def test_noisy_ring_down_beats_finite_differences(snr, bound):
    f = add_noise(X, snr, random_state=3)
    d = TVRegDiff()(f[:, None], T)
    err = interior_rms(d, X_DOT)
    assert err < bound
    assert err < interior_rms(np.gradient(f, T), X_DOT) / 10


def test_smoothed_x_is_filtered_and_consistent():
    f = add_noise(X, 30, random_state=0)
    est = TVRegDiff()
    d = est(f[:, None], T)
    y = est.smoothed_x_[:, 0]
    assert np.all(np.isfinite(est.smoothed_x_))
    assert np.sqrt(np.mean((y - X) ** 2)) < 0.5 * np.sqrt(np.mean((f - X) ** 2))
    # the derivative integrates back to the smoothed signal (trapezoid rule on centred differences:
    # second-order consistent, O(dt^2) drift, 0.1% of the amplitude here)
    inner = slice(5, -5)
    integral = np.concatenate(([0.0], np.cumsum(0.5 * (d[inner][1:, 0] + d[inner][:-1, 0]) * 0.01)))
    assert np.max(np.abs(y[inner] - y[5] - integral)) < 2.5e-3


def test_no_lag_sine_gives_cosine_in_phase():
    t = np.linspace(0, 4 * np.pi, 500)
    d = TVRegDiff(alpha=1e-6)(np.sin(t)[:, None], t)[5:-5, 0]
    cos = np.cos(t)[5:-5]
    np.testing.assert_allclose(d, cos, atol=1e-3)
    # a lag of one sample would correlate better with a shifted cosine
    dt = t[1] - t[0]
    shifted = np.cos(t - dt)[5:-5]
    assert np.sum((d - cos) ** 2) < 0.01 * np.sum((d - shifted) ** 2)


@pytest.mark.parametrize("order", [1, 2, 3])
def test_orders_all_work_and_higher_order_is_better_on_ring_down(order):
    f = add_noise(X, 30, random_state=1)
    est = TVRegDiff(order=order)
    err = interior_rms(est(f[:, None], T), X_DOT)
    assert err < 0.15
    if order == 3:
        err1 = interior_rms(TVRegDiff(order=1)(f[:, None], T), X_DOT)
        assert err < err1


@pytest.mark.parametrize("factor", [1e-6, 1e6])
def test_unit_invariance(factor):
    f = add_noise(X, 30, random_state=2)[:, None]
    base = TVRegDiff()
    d = base(f, T)
    scaled = TVRegDiff()
    d_scaled = scaled(f * factor, T)
    atol = 1e-5 * np.nanmax(np.abs(d)) * factor  # rounding differences only
    np.testing.assert_allclose(d_scaled, d * factor, rtol=1e-5, atol=atol)
    np.testing.assert_allclose(scaled.smoothed_x_, base.smoothed_x_ * factor, rtol=1e-5, atol=1e-5 * factor)
    np.testing.assert_allclose(scaled.alpha_, base.alpha_ * factor, rtol=1e-6)
    # time units: t in ms instead of s
    in_ms = TVRegDiff()
    np.testing.assert_allclose(in_ms(f, T * 1e3), d * 1e-3, rtol=1e-6, atol=1e-12)


def test_float_alpha_is_used_and_reproduces_auto():
    f = add_noise(X, 30, random_state=4)[:, None]
    auto = TVRegDiff()
    d_auto = auto(f, T)
    fixed = TVRegDiff(alpha=float(auto.alpha_[0]))
    d_fixed = fixed(f, T)
    assert fixed.alpha_[0] == auto.alpha_[0]
    atol = 1e-6 * np.nanmax(np.abs(d_auto))  # up to the rounding of alpha_
    np.testing.assert_allclose(d_fixed, d_auto, rtol=1e-6, atol=atol)
    # more alpha, smoother derivative; alpha scales with amplitude
    rough = TVRegDiff(alpha=float(auto.alpha_[0]) / 1e4)(f, T)
    assert np.nanstd(np.diff(rough[:, 0])) > 3 * np.nanstd(np.diff(d_fixed[:, 0]))
    ten = TVRegDiff(alpha=10 * auto.alpha_[0])(10 * f, T)
    np.testing.assert_allclose(ten, 10 * d_fixed, rtol=1e-6, atol=1e-6 * np.nanmax(np.abs(ten)))


def test_zero_alpha_is_finite_differences():
    from sindy_impulse.differentiation._banded import centred_slopes

    d = TVRegDiff(alpha=0.0, trim=0)(X[:, None], T)
    np.testing.assert_allclose(d[:, 0], centred_slopes(X) / (T[1] - T[0]))
    inner = slice(3, -3)  # sixth order inside: the same as np.gradient to O(dt^2), far closer to the truth
    np.testing.assert_allclose(d[inner, 0], np.gradient(X, T)[inner], rtol=0, atol=0.01 * np.abs(d).max())


def test_a_coarsely_sampled_oscillation_keeps_its_derivative_amplitude():
    # 10 samples per period: second-order differences give sin(w dt) / (w dt) = 0.935 of the derivative
    t = np.arange(300) * 0.01
    w = 2 * np.pi * 10.0
    x = np.exp(-0.5 * t) * np.sin(w * t)
    exact = np.exp(-0.5 * t) * (w * np.cos(w * t) - 0.5 * np.sin(w * t))
    d = TVRegDiff(alpha=0.0)(x[:, None], t)[:, 0]
    kept = np.isfinite(d)
    gain = np.dot(d[kept], exact[kept]) / np.dot(exact[kept], exact[kept])
    assert abs(gain - 1) < 1e-3


def test_per_column_alpha_and_wrong_length():
    two = np.column_stack([X, 2 * X])
    est = TVRegDiff(alpha=[1e-3, 2e-3])
    est(two, T)
    np.testing.assert_allclose(est.alpha_, [1e-3, 2e-3])
    with pytest.raises(ValueError, match="alpha has 3 entries"):
        TVRegDiff(alpha=[1.0, 2.0, 3.0])(two, T)


@pytest.mark.parametrize("trim", [0, 5, 12])
def test_trim(trim):
    d = TVRegDiff(trim=trim)(X[:, None], T)
    nan_rows = np.isnan(d[:, 0])
    assert nan_rows.sum() == 2 * trim
    if trim:
        assert nan_rows[:trim].all() and nan_rows[-trim:].all()


def test_constant_column_gives_zero_derivative_without_warnings():
    data = np.column_stack([np.full(100, 3.7), np.zeros(100), X[:100]])
    with __import__("warnings").catch_warnings():
        __import__("warnings").simplefilter("error")
        est = TVRegDiff()
        d = est(data, 0.01)
    np.testing.assert_array_equal(d[5:-5, :2], 0.0)
    np.testing.assert_array_equal(est.smoothed_x_[:, :2], data[:, :2])
    assert np.isnan(est.alpha_[0]) and np.isfinite(est.alpha_[2])


def test_one_dimensional_input_keeps_shape():
    d = TVRegDiff()(X, T)
    assert d.shape == X.shape


def test_non_uniform_time_is_supported():
    rng = np.random.default_rng(5)
    t = T + rng.uniform(-0.3, 0.3, T.size) * 0.01  # +-30% jitter of a 100 Hz logger
    x = np.exp(-1.6 * t) * np.cos(7.8 * t)
    exact = np.exp(-1.6 * t) * (-1.6 * np.cos(7.8 * t) - 7.8 * np.sin(7.8 * t))
    f = x + 0.01 * rng.standard_normal(t.size) * np.std(x)
    d = TVRegDiff()(f[:, None], t)
    err = interior_rms(d, exact)
    assert err < 0.03
    assert err < interior_rms(np.gradient(f, t), exact) / 5
    # steps equal to 1e-6 relative count as uniform
    d_uniform = TVRegDiff()(f[:, None], 0.01)
    d_almost = TVRegDiff()(f[:, None], T * (1 + 1e-7 * np.sin(T)))
    np.testing.assert_allclose(d_almost, d_uniform, atol=1e-3 * np.nanmax(np.abs(d_uniform)))


def test_randomly_sampled_time_is_supported():
    rng = np.random.default_rng(5)
    t = np.sort(np.concatenate(([0.0, 4.0], rng.uniform(0, 4, 399))))  # gaps down to ~1e-5 s
    x = np.exp(-1.6 * t) * np.cos(7.8 * t)
    exact = np.exp(-1.6 * t) * (-1.6 * np.cos(7.8 * t) - 7.8 * np.sin(7.8 * t))
    f = x + 0.01 * rng.standard_normal(t.size) * np.std(x)
    d = TVRegDiff()(f[:, None], t)
    assert interior_rms(d, exact) < 0.05


def test_long_record_uses_spline_basis_and_is_accurate():
    t = np.linspace(0, 4, 20000)
    x = np.exp(-1.6 * t) * np.cos(7.8 * t)
    exact = np.exp(-1.6 * t) * (-1.6 * np.cos(7.8 * t) - 7.8 * np.sin(7.8 * t))
    f = add_noise(x, 30, random_state=0)
    est = TVRegDiff()
    d = est(f[:, None], t)
    # 50x more samples than the 401-sample record: more accurate, not less
    assert interior_rms(d, exact) < 0.012
    y = est.smoothed_x_[:, 0]
    assert np.sqrt(np.mean((y - x) ** 2)) < 0.1 * np.std(f - x)


def test_consistency_criterion_curve():
    f = add_noise(X, 30, random_state=6)
    est = TVRegDiff(alpha_selection="consistency")
    est(f[:, None], T)
    curve = est.alpha_curve_[0]
    assert curve["alpha"].size >= 20
    assert np.all(np.diff(curve["alpha"]) > 0)
    np.testing.assert_allclose(curve["error"], curve["consistency"])
    assert est.alpha_[0] == curve["alpha"][np.argmin(curve["error"])]
    # the paper's criterion degenerates on noisy data: its minimum sits at small alpha, below GCV's choice
    gcv = TVRegDiff()
    gcv(f[:, None], T)
    assert est.alpha_[0] < gcv.alpha_[0]
    assert gcv.alpha_curve_[0]["alpha"][np.argmin(gcv.alpha_curve_[0]["error"])] == gcv.alpha_[0]


def _two_modes(n=1500, dt=0.01):
    t = np.arange(n) * dt
    slow = np.exp(-0.8 * t) * np.sin(2 * np.pi * 2.6 * t)
    return t, slow + 0.5 * np.exp(-2.5 * t) * np.sin(2 * np.pi * 6.8 * t)


@pytest.mark.parametrize("signal, snr, seed", [("paper", 20, 0), ("paper", 30, 1), ("paper", 40, 2),
                                               ("two modes", 40, 3), ("two modes", 30, 4)])
def test_gcv_scan_stops_past_its_minimum_and_finds_the_whole_grids_minimum(monkeypatch, signal, snr, seed):
    """The GCV scan runs upwards and stops once GCV has turned up: the strongest weights (where the
    iteration converges slowest) are not computed, and the chosen alpha scores as well as the best of the
    whole quarter-decade grid, each point solved from a cold start."""
    from sindy_impulse.differentiation import _selection, tvregdiff

    seen = []

    def recording(problem, *args):
        out = _selection.select_alpha(problem, *args)
        seen.append((problem, out[1]))
        return out

    monkeypatch.setattr(tvregdiff, "select_alpha", recording)
    t, x = (T, X) if signal == "paper" else _two_modes()
    est = TVRegDiff()
    est(add_noise(x, snr, random_state=seed)[:, None], t)
    (problem, lam), curve = seen[0], est.alpha_curve_[0]

    def gcv(at):
        return problem.score(at, problem.smooth(at)[0])[0]

    lam_max = problem.lambda_max()
    whole = [gcv(lam_max * 10.0**-r) for r in np.arange(0.0, 12.0 + 1e-9, 0.25)]
    assert gcv(lam) <= 1.02 * min(whole)
    strongest = curve["alpha"].max() * lam / est.alpha_[0]  # in the normalized units of lam
    assert strongest < 1e-2 * lam_max


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "x, t, match",
    [
        (np.array([1.0, np.nan] + [0.0] * 30), 0.1, "NaN"),
        (np.array([1.0, np.inf] + [0.0] * 30), 0.1, "inf"),
        (np.zeros(10), 0.1, "10 samples; at least 13"),
        (np.zeros(30), np.arange(29.0), "29 entries"),
        (np.zeros(30), np.r_[np.arange(15.0), np.arange(15.0)], "strictly increasing"),
        (np.zeros(30), -0.1, "positive"),
    ],
)
def test_bad_input_raises(x, t, match):
    with pytest.raises(ValueError, match=match):
        TVRegDiff()(x, t)


@pytest.mark.parametrize(
    "params, match",
    [
        ({"order": 4}, "order"),
        ({"alpha": "best"}, "alpha"),
        ({"alpha": -1.0}, "alpha"),
        ({"alpha_selection": "lcurve"}, "alpha_selection"),
        ({"trim": -1}, "trim"),
        ({"eps": 0.0}, "eps"),
    ],
)
def test_bad_parameters_raise_when_differentiating(params, match):
    est = TVRegDiff(**params)  # stored untouched
    with pytest.raises(ValueError, match=match):
        est(X, T)


# ---------------------------------------------------------------- PySINDy and scikit-learn
def test_sindy_single_trajectory_recovers_oscillator():
    t, x, _ = damped_oscillator(snr_db=40, random_state=0)
    model = ps.SINDy(
        differentiation_method=TVRegDiff(),
        optimizer=ps.STLSQ(threshold=0.5),
        feature_library=ps.PolynomialLibrary(degree=2),
    )
    model.fit(x, t=t)
    coef = model.coefficients()
    names = model.get_feature_names()
    k, c = -coef[1, names.index("x0")], -coef[1, names.index("x1")]
    assert k == pytest.approx(64.0, rel=0.03)
    assert c == pytest.approx(3.2, rel=0.1)
    assert coef[0, names.index("x1")] == pytest.approx(1.0, rel=0.02)
    assert np.count_nonzero(coef) == 3


def test_sindy_several_trajectories():
    trajs = [damped_oscillator(x0=(a, 0.0), snr_db=40, random_state=i) for i, a in enumerate((1.0, 0.5))]
    model = ps.SINDy(differentiation_method=TVRegDiff(), optimizer=ps.STLSQ(threshold=0.5))
    model.fit([r.x for r in trajs], t=[r.t for r in trajs])
    coef = model.coefficients()
    names = model.get_feature_names()
    assert -coef[1, names.index("x0")] == pytest.approx(64.0, rel=0.03)
    assert np.count_nonzero(coef) == 3


def test_clone_get_set_params_pickle():
    est = TVRegDiff(alpha=0.5, order=2, trim=3)
    params = est.get_params()
    assert params["alpha"] == 0.5 and params["order"] == 2 and params["trim"] == 3
    cloned = clone(est)
    assert cloned.get_params() == params
    assert cloned.set_params(order=1) is cloned and cloned.order == 1
    fitted = TVRegDiff()
    d = fitted(X, T)
    restored = pickle.loads(pickle.dumps(fitted))
    np.testing.assert_array_equal(restored.alpha_, fitted.alpha_)
    np.testing.assert_allclose(restored(X, T), d)
    assert not hasattr(clone(fitted), "alpha_")


def test_transformer_fit_transform():
    f = np.column_stack([add_noise(X, 30, random_state=7), X])
    est = TVRegDiff(dt=0.01)
    assert est.fit(f) is est
    assert est.n_features_in_ == 2
    d = est.transform(f)
    np.testing.assert_allclose(d, est.fit_transform(f), atol=1e-8)
    np.testing.assert_allclose(d, TVRegDiff()(f, 0.01), atol=1e-8)
    with pytest.raises(ValueError, match="features"):
        est.transform(f[:, :1])


def test_long_ring_down_with_many_periods_is_not_oversmoothed():
    # 20,001 samples, about 250 periods: more than max_knots / 10 periods, so the spline gets more knots
    ring = damped_oscillator(c=0.02, t_end=200.0)
    diff = TVRegDiff()
    x_dot = diff(ring.x[:, :1], ring.t[1] - ring.t[0])
    interior = slice(10, -10)
    err = np.abs(x_dot[interior, 0] - ring.x_dot[interior, 0]).max() / np.abs(ring.x_dot[:, 0]).max()
    assert err < 1e-2
    assert np.abs(np.asarray(diff.smoothed_x_)[:, 0] - ring.x[:, 0]).max() < 1e-2


# ---------------------------------------------------------------- PySINDy's axis argument
def test_axis_differentiates_every_series_along_the_time_axis():
    # (2 points, 401 times, 2 coordinates): PySINDy's (..., time, coord) layout, time on axis -2
    rng = np.random.default_rng(3)
    x = np.stack([np.column_stack([X, 0.5 * X]), np.column_stack([2 * X, -X])])
    x = x + 1e-3 * rng.normal(size=x.shape)
    diff = TVRegDiff(alpha=1e-4)
    x_dot = diff(x, T)
    assert x_dot.shape == x.shape and diff.smoothed_x_.shape == x.shape
    for i in range(2):
        single = TVRegDiff(alpha=1e-4)
        np.testing.assert_allclose(x_dot[i], single(x[i], T), rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(diff.smoothed_x_[i], single.smoothed_x_, rtol=1e-10, atol=1e-12)
    assert np.isnan(x_dot[:, :5]).all() and np.isfinite(x_dot[:, 5:-5]).all()
    # the same data with the time on axis 0 give the same derivative, moved
    moved = TVRegDiff(alpha=1e-4, axis=0)(np.moveaxis(x, 1, 0), T)
    np.testing.assert_allclose(np.moveaxis(moved, 0, 1), x_dot, rtol=1e-10, atol=1e-12)


def test_axis_one_of_a_2d_array_is_time_and_a_1d_signal_ignores_axis():
    x = np.column_stack([X, 2 * X])
    np.testing.assert_allclose(TVRegDiff(axis=1)(x.T, T).T, TVRegDiff()(x, T), rtol=1e-10, atol=1e-12)
    np.testing.assert_array_equal(TVRegDiff(axis=-2)(X, T), TVRegDiff(axis=0)(X, T))
    with pytest.raises(ValueError, match=r"axis=2 is out of range for x with 2 dimensions"):
        TVRegDiff(axis=2)(x, T)
    with pytest.raises(ValueError, match=r"TVRegDiff: axis must be an integer"):
        TVRegDiff(axis=0.5)(x, T)

"""Backbone curves: hilbert_backbone (data) and backbone (model) against first-order averaging.

Free decays of ``x'' + (c0 + c2 x^2) x' + w0^2 x + k3 x^3 = 0`` are integrated by fine-step RK4 (the
project's compiled simulator, 16 sub-steps per sample, ``h w0 = 0.02``) at 10 Hz, 20 samples per period,
with white noise at 40 dB SNR. The true backbone is ``w(a)^2 = w0^2 + 3/4 k3 a^2``,
``zeta(a) = (c0 + c2 a^2 / 4) / (2 w(a))``. Acceptance targets over the middle 80 % of each curve's
amplitude range: data within 0.5 % (frequency) and 20 % (damping ratio), total shift within 25 %; model
within 0.2 %, 10 % and 10 %.
"""

from __future__ import annotations

import functools
import warnings

import matplotlib
import numpy as np
import pysindy as ps
import pytest
from sklearn.exceptions import NotFittedError

import sindy_impulse.analysis as analysis
from sindy_impulse import ImpulseSINDy
from sindy_impulse.analysis import Backbone, backbone, hilbert_backbone
from sindy_impulse.datasets import add_noise
from sindy_impulse.exceptions import DataWarning, DivergenceWarning, FitWarning, InvalidParameterError
from sindy_impulse.feature_library import TermTable
from sindy_impulse.plotting import plot_backbone
from sindy_impulse.simulation import CompiledModel

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after choosing the non-interactive backend)

F0, SPP = 10.0, 20
W0 = 2 * np.pi * F0
TERMS = TermTable.polynomial([[1, 0], [0, 1], [3, 0], [2, 1]])  # x, v, x^3, x^2 v

# name: (zeta0, frequency shift at a=1, damping-ratio factor at a=1, periods)
CASES = {
    "duffing": (0.002, 0.05, 1.0, 1500),
    "amplitude_damping": (0.001, 0.0, 2.5, 3000),
    "combined": (0.005, 0.04, 2.5, 600),
    "combined_1pct": (0.01, 0.1, 5.0, 300),
}
# what each case tests: the frequency shift, the damping change, or both
SHIFTS = {"duffing": ("f",), "amplitude_damping": ("z",), "combined": ("f", "z"), "combined_1pct": ("f", "z")}


def _coefficients(zeta, shift, factor):
    k3 = ((1 + shift) ** 2 - 1) * W0**2 / 0.75
    c0 = 2 * zeta * W0
    return np.array([[0.0, 1.0, 0.0, 0.0], [-(W0**2), -c0, -k3, -(factor - 1) * 4 * c0]])


def _truth(zeta, shift, factor):
    coef = _coefficients(zeta, shift, factor)
    k3, c0, c2 = -coef[1, 2], -coef[1, 1], -coef[1, 3]

    def truth(a):
        w = np.sqrt(W0**2 + 0.75 * k3 * a**2)
        return w / (2 * np.pi), (c0 + c2 * a**2 / 4) / (2 * w)

    return truth


@functools.cache
def _decay(name, phase=0.0):
    """Clean free decay from amplitude 1 (states x, v) and its time vector."""
    zeta, shift, factor, periods = CASES[name]
    compiled = CompiledModel(_coefficients(zeta, shift, factor), TERMS)
    t = np.arange(periods * SPP) / (SPP * F0)
    w = W0 * (1 + shift)
    x = compiled.simulate([np.cos(phase), -w * np.sin(phase)], t)
    return t, x


def _noisy(name, seed=0, phase=0.0):
    t, x = _decay(name, phase)
    return t, add_noise(x[:, 0], 40, random_state=seed)


class TrueModel:
    """A stand-in for a fitted model: the true equations, with simulate/coefficients/t_/x_filtered_."""

    def __init__(self, name, order=(0, 1)):
        zeta, shift, factor, _ = CASES[name]
        self.order = list(order)
        self.compiled = CompiledModel(_coefficients(zeta, shift, factor), TERMS)
        self.t_, x = _decay(name)
        self.x_filtered_ = x[:, self.order]

    def simulate(self, x0, t):
        back = np.argsort(self.order)
        return self.compiled.simulate(np.asarray(x0)[back], t)[:, self.order]

    def coefficients(self):
        return self.compiled.full_coefficients


def _errors(curve, truth):
    """Largest relative errors over the middle 80 % of the amplitude range, and of the total shifts."""
    a = curve.amplitude
    lo, hi = a.min(), a.max()
    mid = (a >= lo + 0.1 * (hi - lo)) & (a <= hi - 0.1 * (hi - lo))
    f_true, z_true = truth(a)
    i, j = np.argmin(a), np.argmax(a)
    true_f_shift, true_z_shift = f_true[j] / f_true[i] - 1, z_true[j] / z_true[i] - 1
    return {
        "f": np.max(np.abs(curve.frequency_hz[mid] / f_true[mid] - 1)),
        "z": np.max(np.abs(curve.damping_ratio[mid] / z_true[mid] - 1)),
        "f_shift": abs(curve.frequency_shift / true_f_shift - 1) if true_f_shift else np.inf,
        "z_shift": abs(curve.damping_ratio_shift / true_z_shift - 1) if true_z_shift else np.inf,
        "true_f_shift": true_f_shift,
        "true_z_shift": true_z_shift,
        "n_mid": int(mid.sum()),
    }


def _meets(errors, name, f_tol, z_tol, shift_tol):
    ok = errors["f"] <= f_tol and errors["z"] <= z_tol
    return ok and all(errors[f"{kind}_shift"] <= shift_tol for kind in SHIFTS[name])


# ------------------------------------------------------------------------------------------------------
# accuracy (the acceptance targets)
# ------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", CASES)
@pytest.mark.parametrize("seed", [0, 1])
def test_hilbert_backbone_matches_averaging_on_noisy_data(name, seed):
    t, y = _noisy(name, seed, phase=np.pi / 2 * seed)  # seed 1 starts at a zero crossing (an impulse)
    curve = hilbert_backbone(y, t)
    err = _errors(curve, _truth(*CASES[name][:3]))
    # a genuinely nonlinear case over a wide range: >= 2 % shift or >= 1.5x damping, >= 20 dB of amplitude
    assert err["true_f_shift"] >= 0.02 or err["true_z_shift"] >= 0.5
    assert curve.amplitude.max() / curve.amplitude.min() > 10 and err["n_mid"] >= 10
    assert err["f"] < 0.005 and err["z"] < 0.20, err
    for kind in SHIFTS[name]:
        assert err[f"{kind}_shift"] < 0.25, err


@pytest.mark.parametrize("name", CASES)
def test_model_backbone_matches_averaging(name):
    curve = backbone(TrueModel(name))
    err = _errors(curve, _truth(*CASES[name][:3]))
    assert curve.source == "model" and err["n_mid"] >= 5
    assert err["f"] < 0.002 and err["z"] < 0.10, err
    for kind in SHIFTS[name]:
        assert err[f"{kind}_shift"] < 0.10, err


def test_backbone_of_a_fitted_impulse_sindy():
    name = "combined"
    t, x = _decay(name)
    x_dot = TERMS.evaluate(x) @ _coefficients(*CASES[name][:3]).T
    model = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=3), refine=False)
    model.fit(x, t=t, x_dot=x_dot)
    err = _errors(backbone(model), _truth(*CASES[name][:3]))
    assert err["f"] < 0.002 and err["z"] < 0.10 and err["f_shift"] < 0.10 and err["z_shift"] < 0.10, err


@pytest.mark.parametrize("name", ["duffing", "amplitude_damping", "combined"])
def test_a_constant_backbone_fails_the_targets_on_a_nonlinear_decay(name):
    t, y = _noisy(name)
    curve = hilbert_backbone(y, t)
    truth = _truth(*CASES[name][:3])
    assert _meets(_errors(curve, truth), name, 0.005, 0.20, 0.25)
    n = len(curve)
    f_lin, z_lin = np.full(n, curve.frequency_hz_linear), np.full(n, curve.damping_ratio_linear)
    flat = Backbone(curve.amplitude, f_lin, z_lin, "model")
    assert flat.frequency_shift == 0 and flat.damping_ratio_shift == 0
    assert not _meets(_errors(flat, truth), name, 0.005, 0.20, 0.25)


def test_linear_decay_gives_a_flat_backbone():
    compiled = CompiledModel(_coefficients(0.002, 0.0, 1.0), TERMS)
    t = np.arange(1500 * SPP) / (SPP * F0)
    y = add_noise(compiled.simulate([1.0, 0.0], t)[:, 0], 40, random_state=3)
    curve = hilbert_backbone(y, t)
    assert abs(curve.frequency_shift) < 1e-3 and abs(curve.damping_ratio_shift) < 0.15
    np.testing.assert_allclose(curve.frequency_hz, F0, rtol=1e-3)
    np.testing.assert_allclose(curve.damping_ratio, 0.002, rtol=0.15)


# ------------------------------------------------------------------------------------------------------
# invariances and robustness
# ------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("scale", [1e-6, 1e6])
def test_units_scale_the_amplitude_only(scale):
    t, y = _noisy("combined")
    ref, scaled = hilbert_backbone(y, t), hilbert_backbone(y * scale, t)
    np.testing.assert_allclose(scaled.amplitude, ref.amplitude * scale, rtol=1e-6)
    np.testing.assert_allclose(scaled.frequency_hz, ref.frequency_hz, rtol=1e-9)
    np.testing.assert_allclose(scaled.damping_ratio, ref.damping_ratio, rtol=1e-6)


def test_offset_is_removed():
    t, y = _noisy("combined")
    ref, shifted = hilbert_backbone(y, t), hilbert_backbone(y + 3.0, t)
    assert len(shifted) == len(ref)
    np.testing.assert_allclose(shifted.amplitude, ref.amplitude, rtol=1e-3)
    np.testing.assert_allclose(shifted.frequency_hz, ref.frequency_hz, rtol=1e-5)
    np.testing.assert_allclose(shifted.damping_ratio, ref.damping_ratio, rtol=0.02)


def test_pre_trigger_stretch_is_skipped():
    t, y = _noisy("combined")
    quiet = np.random.default_rng(5).normal(scale=np.std(y - _decay("combined")[1][:, 0]), size=40 * SPP)
    curve = hilbert_backbone(np.concatenate([quiet, y]), np.arange(len(y) + len(quiet)) * t[1])
    err = _errors(curve, _truth(*CASES["combined"][:3]))
    assert curve.amplitude.max() > 0.5 and err["f"] < 0.005 and err["z"] < 0.20


def test_band_isolates_one_mode():
    t, y = _noisy("duffing")
    other = 0.5 * np.exp(-0.003 * 2 * np.pi * 37 * t) * np.sin(2 * np.pi * 37 * t)
    curve = hilbert_backbone(y + other, t, band=(7.0, 13.0))
    err = _errors(curve, _truth(*CASES["duffing"][:3]))
    assert err["f"] < 0.005 and err["z"] < 0.20 and err["f_shift"] < 0.25, err


def test_amplitudes_interpolate_with_nan_outside():
    t, y = _noisy("combined")
    curve = hilbert_backbone(y, t)
    inside = np.sqrt(curve.amplitude.min() * curve.amplitude.max())
    at = hilbert_backbone(y, t, amplitudes=[1e-9, inside, 100.0])
    assert np.isnan(at.frequency_hz[[0, 2]]).all() and np.isnan(at.damping_ratio[[0, 2]]).all()
    f_true, z_true = _truth(*CASES["combined"][:3])(inside)
    assert abs(at.frequency_hz[1] / f_true - 1) < 0.005 and abs(at.damping_ratio[1] / z_true - 1) < 0.2
    model_at = backbone(TrueModel("combined"), amplitudes=[inside, 100.0])
    assert abs(model_at.frequency_hz[0] / f_true - 1) < 0.002 and np.isnan(model_at.frequency_hz[1])


def test_measured_coordinate_of_the_model():
    ref = backbone(TrueModel("combined"))
    swapped = TrueModel("combined", order=(1, 0))  # (v, x): the measured x is the last column
    by_argument = backbone(swapped, coordinate=-1)
    swapped.coordinate_ = 1  # what a mode identification sets on its modes
    by_attribute = backbone(swapped)
    for curve in (by_argument, by_attribute):
        np.testing.assert_allclose(curve.amplitude, ref.amplitude, rtol=1e-9)
        np.testing.assert_allclose(curve.frequency_hz, ref.frequency_hz, rtol=1e-9)
        np.testing.assert_allclose(curve.damping_ratio, ref.damping_ratio, rtol=1e-9)


def test_model_with_several_trajectories_starts_from_the_largest():
    ref = backbone(TrueModel("combined"))
    model = TrueModel("combined")
    model.x_filtered_, model.t_ = [0.1 * model.x_filtered_, model.x_filtered_], [model.t_, model.t_]
    np.testing.assert_allclose(backbone(model).amplitude, ref.amplitude, rtol=1e-9)


def test_model_that_does_not_decay_far_enough_warns():
    with pytest.warns(FitWarning, match="did not fall below"):
        curve = backbone(TrueModel("amplitude_damping"), max_periods=200)
    assert len(curve) > 5


def test_diverging_model_warns_and_refuses():
    model = TrueModel("combined")
    growing = [[0.0, 1.0, 0.0, 0.0], [-(W0**2), 0.02 * W0, 0.0, 0.0]]  # negative damping
    model.compiled = CompiledModel(growing, TERMS, reference=[[1.0, W0]])
    with pytest.warns(DivergenceWarning), pytest.raises(ValueError, match="not a decay.*unstable"):
        backbone(model)


# ------------------------------------------------------------------------------------------------------
# the result, bad input, short records
# ------------------------------------------------------------------------------------------------------
def test_at_ignores_missing_points():
    curve = Backbone(np.array([0.1, np.nan, 1.0]), np.array([10.0, np.nan, 11.0]), np.full(3, 0.01), "data")
    at = curve.at([0.55, 2.0])
    np.testing.assert_allclose(at.frequency_hz, [10.5, np.nan])
    assert curve.frequency_shift == pytest.approx(0.1)


def test_result_is_sorted_and_readable():
    t, y = _noisy("combined")
    curve = hilbert_backbone(y, t, n_points=30)
    assert curve.source == "data" and 10 < len(curve) <= 30
    assert np.all(np.diff(curve.amplitude) > 0)
    assert curve.frequency_hz_linear == curve.frequency_hz[0]
    assert curve.damping_ratio_linear == curve.damping_ratio[0]
    assert curve.frequency_shift == pytest.approx(curve.frequency_hz[-1] / curve.frequency_hz[0] - 1)
    text = repr(curve)
    assert "source='data'" in text and "frequency_hz" in text and "damping_ratio" in text and "%" in text


def test_analysis_binds_the_function_not_the_module():
    assert callable(analysis.backbone) and type(analysis.backbone).__name__ == "function"


@pytest.mark.parametrize(
    "kwargs, exc, match",
    [
        ({"y": np.zeros((100, 2))}, ValueError, "one signal"),
        ({"y": np.r_[np.nan, np.ones(99)]}, ValueError, "NaN"),
        ({"y": np.ones(100)}, ValueError, "constant"),
        ({"t": np.r_[0.0, np.cumsum(np.full(99, 0.005)) * np.linspace(1, 1.5, 99)]}, ValueError, "uniformly"),
        ({"t": np.arange(50) * 0.005}, ValueError, "entries"),
        ({"t": -0.005}, ValueError, "positive"),
        ({"band": (13.0, 7.0)}, ValueError, "band"),
        ({"band": (200.0, 300.0)}, ValueError, "Nyquist"),
        ({"band": "wide"}, TypeError, "band"),
        ({"n_points": 1}, InvalidParameterError, "n_points"),
        ({"min_snr": -1.0}, InvalidParameterError, "min_snr"),
        ({"smooth_periods": 0.5}, InvalidParameterError, "smooth_periods"),
        ({"amplitudes": [-1.0, 0.5]}, ValueError, "positive"),
    ],
)
def test_bad_input_is_refused_clearly(kwargs, exc, match):
    t = np.arange(100) * 0.005
    args = {"y": np.sin(2 * np.pi * 10 * t) * np.exp(-t), "t": 0.005, **kwargs}
    y, tt = args.pop("y"), args.pop("t")
    with pytest.raises(exc, match=match):
        hilbert_backbone(y, tt, **args)


@pytest.mark.parametrize(
    "model, kwargs, exc, match",
    [
        (object(), {}, TypeError, "simulate"),
        (ImpulseSINDy(), {}, NotFittedError, "fit it"),
        ("true", {"coordinate": 2}, ValueError, "out of range"),
        ("true", {"coordinate": 0.5}, TypeError, "integer"),
        ("true", {"samples_per_period": 2}, InvalidParameterError, "samples_per_period"),
        ("true", {"amplitudes": [0.0]}, ValueError, "positive"),
    ],
)
def test_bad_model_input_is_refused_clearly(model, kwargs, exc, match):
    model = TrueModel("combined") if model == "true" else model
    with pytest.raises(exc, match=match):
        backbone(model, **kwargs)


def test_too_short_record_is_refused():
    t, y = _noisy("combined")
    with pytest.raises(ValueError, match="periods"):
        hilbert_backbone(y[: 10 * SPP], t[: 10 * SPP])


def test_noise_only_is_refused():
    y = np.random.default_rng(0).normal(size=20000)
    with pytest.raises(ValueError, match="noise floor|does not decay"):
        hilbert_backbone(y, 0.005)


def test_steady_sine_is_not_a_free_decay():
    t = np.arange(20000) * 0.005
    with pytest.raises(ValueError, match="does not decay"):
        hilbert_backbone(np.sin(2 * np.pi * 10 * t), t)


def test_short_decay_warns_of_a_narrow_range():
    compiled = CompiledModel(_coefficients(0.0002, 0.0, 1.0), TERMS)
    t = np.arange(300 * SPP) / (SPP * F0)
    y = add_noise(compiled.simulate([1.0, 0.0], t)[:, 0], 40, random_state=0)
    with pytest.warns(DataWarning, match="narrow amplitude range"):
        curve = hilbert_backbone(y, t)
    assert curve.amplitude.max() / curve.amplitude.min() < 2


def test_few_samples_per_period_warn():
    t, x = _decay("combined")
    with pytest.warns(DataWarning, match="samples per period"):
        hilbert_backbone(x[::4, 0], t[::4])  # 5 samples per period


# ------------------------------------------------------------------------------------------------------
# plotting
# ------------------------------------------------------------------------------------------------------
def test_plot_overlays_data_and_model():
    t, y = _noisy("combined")
    data, model = hilbert_backbone(y, t), backbone(TrueModel("combined"))
    fig, given = plt.subplots(1, 2)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        axes = plot_backbone(data, model, axes=given)
    assert list(axes) == list(given)
    assert [len(ax.get_lines()) for ax in axes] == [3, 3]  # the data's points and trend, the model
    ok = np.isfinite(data.damping_ratio)
    np.testing.assert_allclose(axes[1].get_lines()[0].get_ydata(), 100 * data.damping_ratio[ok])
    assert len(axes[1].collections) == 1  # the band of the data's spread
    texts = [t.get_text() for t in axes[0].get_legend().get_texts()]
    assert texts == ["data (points)", "data: trend ± spread", "model"]
    plt.close(fig)
    axes = plot_backbone(data, model, spread=False, damping_unit="fraction")
    assert [len(ax.get_lines()) for ax in axes] == [2, 2] and axes[1].get_ylabel() == "damping ratio"
    np.testing.assert_allclose(axes[1].get_lines()[0].get_ydata(), data.damping_ratio)
    plt.close(axes[0].figure)
    axes = plot_backbone(data, data, labels=["impact 1", "impact 2"])
    assert axes[0].get_xscale() == "log" and len(axes) == 2
    plt.close(axes[0].figure)


@pytest.mark.parametrize(
    "args, kwargs, exc",
    [
        ((), {}, ValueError),
        (("curve",), {}, TypeError),
        ((None,), {"labels": ["a", "b"]}, ValueError),
        ((None,), {"axes": "ax"}, TypeError),
    ],
)
def test_plot_refuses_bad_input(args, kwargs, exc):
    curve = Backbone(np.array([0.1, 1.0]), np.array([10.0, 10.1]), np.array([0.01, 0.02]), "data")
    args = tuple(curve if a is None else a for a in args)
    with pytest.raises(exc):
        plot_backbone(*args, **kwargs)
    plt.close("all")


def test_model_backbone_covers_the_datas_largest_amplitudes_and_nothing_above():
    # a 2 %-damped mode loses a third of its amplitude over the estimator's trimmed start: the model's
    # free decay starts above the data (a lead-in), so the curve reaches the data's largest amplitudes
    from scipy.linalg import expm

    A = np.array([[0.0, 1.0], [-(20 * np.pi) ** 2, -0.04 * 20 * np.pi]])
    t = np.arange(600) * 0.005
    x = np.array([expm(A * ti)[:, 0] for ti in t])
    curve = backbone(ImpulseSINDy(refine=False).fit(x, t=t, x_dot=x @ A.T))
    assert 0.85 < curve.amplitude.max() <= 1.0
    assert curve.damping_ratio == pytest.approx(0.02, rel=0.02)
    assert curve.frequency_hz == pytest.approx(10.0, rel=1e-3)

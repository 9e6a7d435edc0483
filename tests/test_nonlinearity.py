"""nonlinearity_test: amplitude dependence of frequency and damping, quiet on noisy linear systems,
the same verdict in any units and on rounded data."""

import warnings

import numpy as np
import pysindy as ps
import pytest

from sindy_impulse import ImpulseSINDy, MechanicalLibrary, damped_oscillator
from sindy_impulse.analysis import Backbone, NonlinearityResult, nonlinearity_test
from sindy_impulse.datasets import impact_record
from sindy_impulse.differentiation import TVRegDiff, differentiate
from sindy_impulse.preprocessing import preprocess

DAMPING_TERMS = {"x^2 v", "v^3", "|x| v", "v|v|", "x v^2"}


def _states(rec, scale=1.0, offset=0.0):
    """The benchmark's pipeline: one band around the mode, the band signal and its derivative."""
    f0 = rec.modes.frequency_hz[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pre = preprocess(rec.y * scale + offset, fs=rec.fs, force=rec.force, bands=[(f0 / 1.5, f0 * 1.5)])
    band = pre.bands[0]
    t = band.t - band.t[0]
    _, (dx,) = differentiate(TVRegDiff(), [band.y[:, None]], [t])
    x = np.column_stack([band.y, dx[:, 0]])
    keep = np.all(np.isfinite(x), axis=1)
    return x[keep], t[keep]


def _fit(x, t):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return ImpulseSINDy(feature_library=MechanicalLibrary()).fit(x, t=t, feature_names=["x", "v"])


def _hammer(c2=0.0, k3=0.0, snr_db=40, seed=0):
    """A 50 Hz mode, damping ratio 1.5 % (about 30 kept cycles), accelerometer, 16 samples per period."""
    return impact_record(50.0, 0.015, [1.0], fs=800.0, duration=1.0, snr_db=snr_db, damping_amplitude=c2,
                         cubic_stiffness=k3, random_state=seed)


def _degree(model, name):
    """Total degree in the states of a MechanicalLibrary term (|x| counts 1, x|x| counts 2)."""
    table = model.feature_library_.term_table_
    k = model.get_feature_names().index(name)
    return int(table.powers[k].sum()) + {1: 2, 3: 1}.get(int(table.func[k]), 0)


@pytest.fixture(scope="module")
def duffing():
    ring = damped_oscillator(k_nl=10.0, x0=(2.0, 0.0), snr_db=40, random_state=1)
    return ring, ImpulseSINDy().fit(ring.x, t=ring.t)


@pytest.fixture(scope="module")
def joint():
    """Damping ratio 1.67x higher at the start of the kept decay (26 cycles) than at its end, no frequency
    shift (``x^2 x'`` damping); the fitted model and its test."""
    x, t = _states(_hammer(c2=3.7e12))
    model = _fit(x, t)
    return x, t, model, nonlinearity_test(model, x, t)


@pytest.fixture(scope="module")
def linear_hammer():
    x, t = _states(_hammer())
    return x, t, _fit(x, t)


def test_clear_nonlinear_case(duffing):
    ring, model = duffing
    res = nonlinearity_test(model, ring.x, ring.t)
    assert isinstance(res, NonlinearityResult)
    assert res.nonlinear and bool(res)
    assert res.statistic > res.threshold == 1.0
    assert res.significance > 1 and res.gamma_linear > 5 * res.gamma_nonlinear
    top = res.terms[0]
    assert (top.equation, top.term) == ("x1'", "x0^3")
    assert abs(top.coefficient + 10.0) < 1.0  # in the data's units
    assert res.coefficient_units == "data" and 0.0 < top.share < 1.0
    assert res.source == "model"
    assert res.nonlinear_coefficients.shape == res.linear_coefficients.shape == (2, 10)
    assert np.all(res.linear_coefficients[:, [i for i, n in enumerate(res.feature_names) if "^" in n]] == 0)
    assert "x0^3" in repr(res) and "significance" in repr(res)


def test_noisy_linear_case_is_quiet():
    for seed in range(3):
        ring = damped_oscillator(snr_db=30, random_state=seed)
        model = ImpulseSINDy().fit(ring.x, t=ring.t)
        res = nonlinearity_test(model, ring.x, ring.t)
        assert not res.nonlinear, res
        assert res.statistic <= res.threshold


def test_amplitude_dependent_damping_is_nonlinear(joint):
    x, t, model, res = joint
    assert res.nonlinear, res
    assert res.terms[0].equation == "v'" and res.terms[0].term in DAMPING_TERMS
    assert res.damping_ratio_shift > 0.2 and abs(res.frequency_shift) < 5e-4
    assert res.data_damping_ratio_shift > 0  # the data backbone agrees
    assert res.amplitude_dependence == pytest.approx(res.damping_ratio_shift / 0.05)  # the resolution
    for curve in (res.backbone_model, res.backbone_data):  # amplitudes in the data's units
        assert isinstance(curve, Backbone)
        assert 0.05 * np.abs(x[:, 0]).max() < curve.amplitude.max() <= 1.05 * np.abs(x[:, 0]).max()


def test_linear_hammer_test_is_linear(linear_hammer):
    x, t, model = linear_hammer
    res = nonlinearity_test(model, x, t)
    assert not res.nonlinear, res
    assert res.statistic < 0.5 and res.amplitude_dependence < 0.5


def test_cubic_spring_is_nonlinear():
    # frequency about 0.6 % higher at the start of the kept decay than at its end
    x, t = _states(_hammer(k3=3.6e13, seed=2))
    res = nonlinearity_test(_fit(x, t), x, t)
    assert res.nonlinear, res
    assert 2e-3 < res.frequency_shift < 1e-2 and abs(res.damping_ratio_shift) < 0.1


@pytest.mark.parametrize("scale", [1e-6, 1e6])
def test_same_verdict_in_other_units(joint, scale):
    x, t, model, reference = joint
    res = nonlinearity_test(_fit(x * scale, t), x * scale, t)
    assert res.nonlinear == reference.nonlinear
    assert res.statistic == pytest.approx(reference.statistic, rel=1e-3)
    np.testing.assert_allclose(res.state_scale, reference.state_scale * scale, rtol=1e-9)
    assert [term.term for term in res.terms] == [term.term for term in reference.terms]
    top = reference.terms[0]
    expected = top.coefficient / scale ** (_degree(model, top.term) - 1)
    assert res.terms[0].coefficient == pytest.approx(expected, rel=1e-3)
    assert res.backbone_data.amplitude.max() == pytest.approx(reference.backbone_data.amplitude.max() * scale)


def test_offset_does_not_matter(joint):
    x, t, model, reference = joint
    shifted = x + np.array([0.3 * np.abs(x[:, 0]).max(), 0.0])
    res = nonlinearity_test(model, shifted, t)
    assert res.nonlinear == reference.nonlinear
    assert res.statistic == pytest.approx(reference.statistic, rel=1e-3)
    assert res.equilibrium[0] == pytest.approx(reference.equilibrium[0] + 0.3 * np.abs(x[:, 0]).max())


def test_rounded_record_gives_the_same_model_and_verdict(joint):
    x, t, model, reference = joint
    rounded = np.array([[float(f"{v:.7e}") for v in row] for row in x])  # 8 significant digits, as in a CSV
    other = _fit(rounded, t)
    np.testing.assert_array_equal(other.coefficients() != 0, model.coefficients() != 0)
    np.testing.assert_allclose(other.coefficients(), model.coefficients(), rtol=0.01)
    res = nonlinearity_test(other, rounded, t)
    assert res.nonlinear == reference.nonlinear
    assert [term.term for term in res.terms] == [term.term for term in reference.terms]
    assert res.terms[0].coefficient == pytest.approx(reference.terms[0].coefficient, rel=0.01)
    assert res.damping_ratio_shift == pytest.approx(reference.damping_ratio_shift, rel=0.01)
    assert res.frequency_shift == pytest.approx(reference.frequency_shift, abs=1e-4)


def test_search_finds_a_term_the_model_dropped():
    ring = damped_oscillator(k_nl=10.0, x0=(1.0, 0.0), snr_db=40, random_state=0)
    linear = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=1)).fit(ring.x, t=ring.t)
    # a cubic library but the linear model's coefficients: the model itself has no nonlinear term
    model = ImpulseSINDy().fit(ring.x, t=ring.t)
    model.coef_ = np.zeros_like(model.coefficients())
    model.coef_[:, 1:3] = linear.coefficients()[:, 1:3]
    res = nonlinearity_test(model, ring.x, ring.t)
    assert res.nonlinear and res.source == "search"
    assert res.terms[0].term == "x0^3"
    assert not nonlinearity_test(model, ring.x, ring.t, search=False).nonlinear


def test_new_data_and_list_input(duffing):
    _, model = duffing
    other = [damped_oscillator(k_nl=10.0, x0=(a, 0.0), snr_db=40, random_state=7).x for a in (1.5, -2.0)]
    res = nonlinearity_test(model, other, 0.01)
    assert res.nonlinear


def test_linear_library_has_nothing_to_test():
    ring = damped_oscillator(snr_db=40, random_state=0)
    model = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=1)).fit(ring.x, t=ring.t)
    res = nonlinearity_test(model, ring.x, ring.t)
    assert not res.nonlinear and res.terms == [] and res.source == "none"
    assert res.statistic == 0.0 and res.backbone_model is None


def test_errors(duffing):
    ring, model = duffing
    with pytest.raises(TypeError, match="fitted ImpulseSINDy"):
        nonlinearity_test(object(), ring.x, ring.t)
    with pytest.raises(ValueError, match="not fitted"):
        nonlinearity_test(ImpulseSINDy(), ring.x, ring.t)
    with pytest.raises(ValueError, match="states"):
        nonlinearity_test(model, ring.x[:, :1], ring.t)
    with pytest.raises(ValueError, match="NaN"):
        nonlinearity_test(model, np.full_like(ring.x, np.nan), ring.t)
    with pytest.raises(ValueError, match="rel_tol"):
        nonlinearity_test(model, ring.x, ring.t, rel_tol=-1)
    with pytest.raises(ValueError, match="frequency_resolution"):
        nonlinearity_test(model, ring.x, ring.t, frequency_resolution=0)
    with pytest.raises(ValueError, match="coordinate"):
        nonlinearity_test(model, ring.x, ring.t, coordinate=5)
    with pytest.raises(ValueError, match="entries"):
        nonlinearity_test(model, ring.x, ring.t[:10])


@pytest.mark.parametrize(
    ("seen", "expected"),
    [
        (0.2, 6.0),  # the data agree
        (-0.07, 6.0),  # the other way, but less than half the model's change: the data's scatter
        (-0.2, 0.0),  # the other way by more than half of it: contradicted
        (float("nan"), 6.0),  # no data backbone: not checked
    ],
)
def test_a_damping_change_counts_unless_the_data_clearly_show_it_the_other_way(seen, expected):
    from types import SimpleNamespace

    from sindy_impulse.analysis._nonlinear_fit import amplitude_ratio

    model = SimpleNamespace(frequency_shift=0.0, damping_ratio_shift=0.3)
    data = SimpleNamespace(frequency_shift=0.0, damping_ratio_shift=seen)
    assert amplitude_ratio(model, data, 1e-3, 0.05) == pytest.approx(expected)

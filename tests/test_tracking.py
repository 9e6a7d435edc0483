"""``track``: the values read from surveys, the backbone by averaging, mode matching, the tests, the alarms
and the term named, trends, the tables, the plot and the page."""

import json
import math
import warnings

import numpy as np
import pytest

from sindy_impulse import identify_modes, impact_record
from sindy_impulse.exceptions import InvalidParameterError
from sindy_impulse.modes import FailedRecord
from sindy_impulse.tracking import ModeValues, SurveyValues, survey_values, track
from sindy_impulse.tracking.averaging import backbone_at, term_shift
from sindy_impulse.tracking.matching import match_modes
from sindy_impulse.tracking.statistics import (
    fit_scatter,
    fit_scatter_rows,
    holm,
    mann_kendall,
    prediction_test,
)
from sindy_impulse.tracking.values import term_name, term_powers

W = 2 * np.pi * 100.0


# ----------------------------------------------------------------------------------------------------
# helpers: surveys as the tracker reads them
# ----------------------------------------------------------------------------------------------------
def _mode(f=100.0, zeta=0.01, amplitude=1.0, snr=40.0, f_std=1e-3, z_std=1e-4, **nonlinear):
    """One mode; ``nonlinear`` as ``{"y^3": (value, std)}`` keyed by the monomial."""
    terms = {k.replace("_", " "): v for k, v in nonlinear.items()}
    return ModeValues(f, f_std, zeta, z_std, amplitude, snr, terms=terms)


def _sequence(rng, n_ref=20, n_new=40, change=None, tau=3e-4, modes=(100.0, 250.0)):
    """Surveys of a structure with modes ``modes``: a common frequency scatter ``tau``, the damping ratios
    scattering 2 %, the hit's strength changing the ± and the amplitude; ``change(k, f, zeta, terms)``
    alters new survey ``k``."""
    out = []
    for k in range(n_ref + n_new):
        strength = np.exp(rng.uniform(np.log(0.5), np.log(2)))
        factor = 1 + tau * rng.standard_normal()
        modes_k = []
        for i, f0 in enumerate(modes):
            f, zeta, terms = f0 * factor, 0.01 * (1 + 0.02 * rng.standard_normal()), {}
            if change is not None and k >= n_ref:
                f, zeta, terms = change(k - n_ref, i, f, zeta)
            f_std, z_std = 2e-5 * f / strength, 1e-3 * zeta / strength
            f += f_std * rng.standard_normal()
            zeta += z_std * rng.standard_normal()
            mode = ModeValues(f, f_std, zeta, z_std, strength, 40 + 20 * np.log10(strength))
            for key, (value, std) in terms.items():
                mode.terms[key] = (value + std * rng.standard_normal(), std)
            modes_k.append(mode)
        out.append(SurveyValues(modes_k))
    return out


class _Model:
    """A fitted two-state model as the survey gives it: ``y' = a dy``, ``dy' = -k y - c dy - k3 y^3``."""

    feature_names_ = ["y", "dy"]

    def __init__(self, a, k, c, k3=0.0, c2=0.0):
        names = ["y", "dy", "y^2", "y dy", "dy^2", "y^3", "y^2 dy", "y dy^2", "dy^3"]
        coef = np.zeros((2, len(names)))
        coef[0, 1] = a
        coef[1, [0, 1, 5, 6]] = -k, -c, -k3, -c2
        self._coef, self._names = coef, names

    def coefficients(self):
        return self._coef

    def get_feature_names(self):
        return self._names


class _SurveyMode:
    def __init__(self, model, f, zeta):
        self.model, self.frequency_hz, self.damping_ratio = model, f, zeta
        self.frequency_std_hz, self.damping_ratio_std, self.amplitude, self.snr_db = 0.01, 1e-4, 2.0, 40.0
        self.coefficients_std = np.full(model.coefficients().shape, 0.5)
        self.coordinate_, self.shape, self.uncertainty_note = 0, None, ""


# ----------------------------------------------------------------------------------------------------
# values
# ----------------------------------------------------------------------------------------------------
def test_the_equation_is_rewritten_whatever_split_the_fit_chose_between_its_two_rows():
    a, w2, c, k3 = 1.25, W**2, 2.0, 3000.0
    # y' = a dy, dy' = -(w2 / a) y - c dy - (k3 / a) y^3: the same motion y'' = -w2 y - c y' - k3 y^3
    mode = _SurveyMode(_Model(a, w2 / a, c, k3 / a, c2=7.0), 100.0, 0.01)
    values = survey_values(type("S", (), {"modes": [mode]})()).modes[0]
    assert values.canonical
    assert values.terms["y"][0] == pytest.approx(W**2)  # from the frequency, as the modal table says
    assert values.terms["y^3"][0] == pytest.approx(k3)  # a positive cubic stiffness hardens
    assert values.terms["y^2 y'"][0] == pytest.approx(7.0)  # a^(1 - 1) = 1
    assert values.terms["y^3"][1] == pytest.approx(0.5 * a)
    assert term_name("y^3") == "cubic stiffness" and term_name("y^2 y'").startswith("amplitude-dependent")
    assert term_powers("y y'^2") == (1, 2) and term_powers("(dy)' x|x|") is None


def test_a_model_of_another_form_keeps_its_raw_nonlinear_terms_only():
    """A delay-embedded model (four states of ``y``) is not rewritten; its linear terms are left to the
    frequency and damping ratio, a quadratic one kept raw."""
    model = _Model(1.0, 1.0, 1.0)
    model.feature_names_ = ["y(t-2tau)", "y(t-1tau)", "y"]
    model._names = ["y(t-2tau)", "y(t-1tau)", "y", "y^2"]
    model._coef = np.array([[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [-3.0, 2.0, -1.0, 0.4]])
    values = survey_values(type("S", (), {"modes": [_SurveyMode(model, 100.0, 0.01)]})()).modes[0]
    assert not values.canonical and sorted(values.terms) == ["(y)' y^2", "y", "y'"]
    assert values.terms["(y)' y^2"][0] == pytest.approx(0.4)


def test_values_of_a_real_survey_and_their_json_round_trip():
    rec = impact_record([120.0, 260.0], [0.01, 0.005], fs=4000, duration=1.0, snr_db=50, random_state=0)
    values = survey_values(identify_modes(rec.y, fs=rec.fs), label="hit 1")
    assert [round(m.frequency_hz) for m in values.modes] == [120, 260]
    assert values.modes[0].terms["y"][0] == pytest.approx((2 * np.pi * values.modes[0].frequency_hz) ** 2)
    back = SurveyValues.from_dict(json.loads(json.dumps(values.to_dict())))
    assert back.label == "hit 1"
    assert back.modes[1].terms == values.modes[1].terms  # JSON keeps every digit of a float
    assert back.modes[1].snr_db == pytest.approx(values.modes[1].snr_db)


def test_a_failed_record_is_a_survey_without_modes_and_garbage_is_refused():
    failed = survey_values(FailedRecord(3, "hit3.csv", "ValueError", "too short"))
    assert failed.modes == [] and "too short" in failed.failed and failed.label == "hit3.csv"
    with pytest.raises(TypeError, match="identify_modes"):
        survey_values([1.0, 2.0])


# ----------------------------------------------------------------------------------------------------
# the backbone by averaging
# ----------------------------------------------------------------------------------------------------
def test_averaging_gives_the_duffing_and_the_amplitude_dependent_damper():
    m = _mode(**{"y^3": (0.04 * W**2 / 0.75, 1.0), "y^2_y'": (8.0, 0.1)})
    point = backbone_at(m, 1.0)
    assert point.frequency_hz == pytest.approx(100.0 * math.sqrt(1.04), rel=1e-9)
    c_eq = 2 * 0.01 * W + 8.0 / 4
    assert point.damping_ratio == pytest.approx(c_eq / (2 * W * math.sqrt(1.04)), rel=1e-9)
    assert point.frequency_shift_hz == pytest.approx(point.frequency_hz - 100.0)
    assert point.frequency_shift_std_hz > 0 and backbone_at(_mode(), 1.0).frequency_shift_std_hz == 0


def test_a_cubic_spring_lowers_the_damping_ratio_at_amplitude_but_dissipates_nothing():
    """zeta_eq = c_eq / (2 w_eq): a cubic spring lowers it through the frequency, and its ± with it; the
    nonlinear damping shift, dissipation alone, stays 0 (a spring is not named for a damping change)."""
    m = _mode(**{"y^3": (0.04 * W**2 / 0.75, 0.01 * W**2 / 0.75)})
    point = backbone_at(m, 1.0)
    assert point.damping_ratio < 0.01 and point.damping_ratio_std > 0.25 * (0.01 - point.damping_ratio)
    assert point.damping_shift == 0 and point.damping_shift_std == 0
    assert term_shift(m, "y^3", 0.0, 1.0)[1] == 0


def test_a_quadratic_spring_softens_at_second_order():
    k2 = 0.1 * W**2
    point = backbone_at(_mode(**{"y^2": (k2, 1.0)}), 1.0)
    expected = math.sqrt(W**2 - 5 / 6 * k2**2 / W**2) / (2 * np.pi)
    assert point.frequency_hz == pytest.approx(expected, rel=1e-9) and point.frequency_hz < 100.0


def test_the_shift_a_term_causes_is_measured_from_the_reference_value():
    m = _mode(**{"y^3": (0.008 * W**2 / 0.75, 1.0)})
    df, _ = term_shift(m, "y^3", 0.0, 1.0)  # the cubic spring appeared
    assert df == pytest.approx(backbone_at(m, 1.0).frequency_hz - 100.0, rel=1e-9)
    assert term_shift(m, "y^3", 0.0, 0.5)[0] == pytest.approx(df / 4, rel=0.01)  # a^2
    _, dz = term_shift(m, "y'", 2 * 0.01 * W / 1.3, 1.0)  # the damping 30 % higher than the reference's
    w_eq = 2 * np.pi * backbone_at(m, 1.0).frequency_hz
    assert dz == pytest.approx(2 * 0.01 * W * (1 - 1 / 1.3) / (2 * w_eq), rel=1e-9)


def test_averaging_agrees_with_the_simulated_backbone_of_a_fitted_duffing_mode():
    from sindy_impulse.analysis import backbone

    w0, a0 = 2 * np.pi * 50.0, 2e-3
    k3 = 4 / 3 * 0.02 * w0**2 / a0**2  # w^2 two per cent higher at the hit
    rec = impact_record(
        50.0,
        0.005,
        [a0],
        fs=1000.0,
        duration=3.0,
        sensor="displacement",
        cubic_stiffness=k3,
        snr_db=60,
        random_state=1,
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mode = identify_modes(rec.y, fs=rec.fs).modes[0]
    values = survey_values(type("S", (), {"modes": [mode]})()).modes[0]
    assert "y^3" in values.terms
    curve = backbone(mode.model, coordinate=mode.coordinate_)
    a = 0.5 * curve.amplitude.max()
    f_model = float(np.interp(a, curve.amplitude, curve.frequency_hz))
    assert backbone_at(values, a).frequency_hz == pytest.approx(f_model, rel=3e-4)


# ----------------------------------------------------------------------------------------------------
# matching
# ----------------------------------------------------------------------------------------------------
def test_a_vanished_mode_and_an_appeared_one_are_reported_not_forced():
    ref = [SurveyValues([_mode(100.0), _mode(103.0)]) for _ in range(3)]
    new = [SurveyValues([_mode(103.1)]), SurveyValues([_mode(100.1), _mode(103.0), _mode(140.0)])]
    tracks, slot = match_modes(ref + new, [0, 1, 2])
    assert [round(t.frequency_hz) for t in tracks] == [100, 103, 140]
    assert slot[3].tolist() == [-1, 0, -1]  # 103.1 Hz is the 103 Hz mode, not the missing 100 Hz one
    assert slot[4].tolist() == [0, 1, 2] and not tracks[2].in_reference


def test_mode_shapes_keep_two_modes_at_one_frequency_apart():
    bend, twist = np.array([1.0, 1.0, 1.0]), np.array([1.0, -1.0, 0.0])
    ref = [
        SurveyValues(
            [ModeValues(100.0, 0, 0.01, 0, 1.0, shape=bend), ModeValues(100.5, 0, 0.01, 0, 1.0, shape=twist)]
        )
        for _ in range(2)
    ]
    swapped = SurveyValues(
        [ModeValues(100.1, 0, 0.01, 0, 1.0, shape=twist), ModeValues(100.4, 0, 0.01, 0, 1.0, shape=bend)]
    )
    _, slot = match_modes(ref + [swapped], [0, 1])
    assert slot[2].tolist() == [1, 0]  # by shape, although each frequency is nearer the other mode


# ----------------------------------------------------------------------------------------------------
# the tests
# ----------------------------------------------------------------------------------------------------
def test_prediction_test_uses_students_t_not_the_normal_law():
    rng = np.random.default_rng(0)
    x = rng.standard_normal((20000, 21))
    _, p = prediction_test(fit_scatter_rows(x[:, :20]), x[:, 20])
    assert 0.007 < np.mean(p < 0.01) < 0.013  # exact for normal scatter
    ref = fit_scatter(x[0, :20])
    t, _ = prediction_test(ref, [ref.mean + 3 * ref.std * math.sqrt(1 + 1 / 20)])
    assert t[0] == pytest.approx(3.0)


@pytest.mark.parametrize("calibration, tau", [(1.0, 0.0), (3.0, 0.0), (10.0, 0.0), (1 / 3, 0.0), (1.0, 1.0)])
def test_the_false_alarm_rate_holds_whatever_the_fits_plus_minus_says(calibration, tau):
    """The ± of each test follow the hit's strength (0.5-2x); the true noise is ``calibration`` times
    them, plus a scatter ``tau`` the ± do not know."""
    rng = np.random.default_rng(int(10 * calibration + tau))
    s = 1 / np.exp(rng.uniform(np.log(0.5), np.log(2), (20000, 21)))
    x = rng.standard_normal(s.shape) * np.sqrt(tau**2 + (calibration * s) ** 2)
    _, p = prediction_test(fit_scatter_rows(x[:, :20], s[:, :20]), x[:, 20], s[:, 20])
    assert np.mean(p < 0.01) < 0.013
    assert np.mean(p < 0.001) < 0.0016  # the tail, where a family of tests puts each threshold


def test_a_value_is_never_judged_more_precise_than_its_own_plus_minus():
    rng = np.random.default_rng(4)
    ref = fit_scatter(1e-3 * rng.standard_normal(20), np.full(20, 1e-12))  # ± far below the scatter
    t, _ = prediction_test(ref, [1.0], [1.0])
    assert abs(t[0]) < 1.01
    over = fit_scatter(0.1 * rng.standard_normal(20), np.full(20, 1.0))  # ± ten times too large
    t, _ = prediction_test(over, [1.0], [1.0])
    assert abs(t[0]) > 5  # the reference shows the ± too large: the scatter judges


def test_without_plus_minus_the_reference_scatter_carries_the_uncertainty():
    ref = fit_scatter([1.0, 1.1, 0.9, 1.05, 0.95], [np.nan] * 5)
    assert not ref.uses_std and ref.std == pytest.approx(np.std([1.0, 1.1, 0.9, 1.05, 0.95], ddof=1))
    t, p = prediction_test(ref, [1.0, np.nan], [np.nan, 0.1])
    assert t[0] == pytest.approx(0.0) and np.isnan(p[1])


def test_a_term_no_reference_has_is_judged_by_its_own_plus_minus():
    ref = fit_scatter(np.zeros(20), np.full(20, np.nan))
    t, p = prediction_test(ref, [5.0, 5.0, 0.0], [1.0, np.nan, np.nan])
    assert t[0] == pytest.approx(5.0) and np.isnan(t[1]) and t[2] == 0.0


def test_holm_and_mann_kendall():
    reject = holm(np.array([[0.001, 0.011, 0.02, 0.9]]), 0.05)[0]
    assert reject.tolist() == [True, True, True, False]  # 0.001<0.0125, 0.011<0.0167, 0.02<0.025
    assert not holm(np.array([[0.02, 0.02, 0.02, 0.02]]), 0.05).any()
    from scipy.stats import kendalltau

    x = np.random.default_rng(3).standard_normal(40) + 0.03 * np.arange(40)
    z, p = mann_kendall(x)
    tau = kendalltau(np.arange(40), x, method="asymptotic")
    assert p == pytest.approx(tau.pvalue, rel=0.1) and np.sign(z) == np.sign(tau.statistic)
    assert np.isnan(mann_kendall([1.0, 2.0, np.nan])[1])


# ----------------------------------------------------------------------------------------------------
# track
# ----------------------------------------------------------------------------------------------------
def test_no_change_keeps_to_the_false_alarm_rate():
    rng = np.random.default_rng(5)
    flagged = [track(_sequence(rng), reference=20).changed[20:].mean() for _ in range(25)]
    assert np.mean(flagged) < 0.025  # 1000 new surveys at 1 % (Bonferroni over 8 tests: below it)


def test_a_stiffness_loss_is_named_the_linear_stiffness_of_the_right_mode():
    def soften(k, i, f, zeta):
        return (f * math.sqrt(0.995) if i == 1 else f), zeta, {}

    result = track(_sequence(np.random.default_rng(6), change=soften), reference=20)
    assert result.changed[20:].mean() > 0.9 and not result.changed[:20].any()
    assert {a.mode for a in result.alarms} == {1}
    assert all(a.term.key == "y" and a.term_significant for a in result.alarms)
    assert all(
        a.term.frequency_shift_hz / a.frequency_hz == pytest.approx(-0.0025, abs=8e-4) for a in result.alarms
    )


def test_more_damping_is_named_the_damping():
    def damp(k, i, f, zeta):
        return f, (zeta * 1.3 if i == 0 else zeta), {}

    result = track(_sequence(np.random.default_rng(7), change=damp), reference=20)
    assert result.changed[20:].mean() > 0.9
    assert {a.mode for a in result.alarms} == {0} and all(a.term.key == "y'" for a in result.alarms)
    assert all(a.quantity == "damping_ratio" for a in result.alarms)


def test_a_cubic_spring_that_appears_is_named_not_the_linear_stiffness():
    k3 = (1.003**2 - 1) * (2 * np.pi * 100) ** 2 / 0.75  # +0.3 % frequency at amplitude 1

    def crack(k, i, f, zeta):
        return f, zeta, ({"y^3": (k3, 0.05 * k3)} if i == 0 else {})

    result = track(_sequence(np.random.default_rng(8), change=crack), reference=20)
    assert result.changed[20:].mean() > 0.8
    named = [a.term.key for a in result.alarms if a.mode == 0]
    assert named.count("y^3") / len(named) > 0.9
    alarm = next(a for a in result.alarms if a.term.key == "y^3")
    assert alarm.term.status == "appeared"
    assert "cubic stiffness appeared" in alarm.text(result) and "frequency at the hit" in alarm.text(result)


def test_a_slow_drift_below_the_single_test_threshold_is_a_trend():
    def drift(k, i, f, zeta):  # 0.003 % per test, a tenth of the test-to-test scatter
        return (f * (1 - 3e-5 * (k + 1)) if i == 1 else f), zeta, {}

    result = track(_sequence(np.random.default_rng(9), change=drift, tau=3e-4), reference=20)
    assert result.changed[20:40].mean() <= 0.1  # two scatters by the 20th test: single tests hardly see it
    trend = [t for t in result.trend_alarms if t.quantity == "frequency_hz"]
    assert [t.mode for t in trend] == [1] and trend[0].z < 0
    assert trend[0].slope / 250 == pytest.approx(-3e-5, rel=0.5)
    assert "per survey" in trend[0].text(result)


def test_missing_plus_minus_is_said_and_the_reference_scatter_carries_it():
    surveys = _sequence(np.random.default_rng(10), n_new=5)
    for s in surveys:
        s.modes[0].frequency_std_hz = math.nan
    result = track(surveys, reference=20)
    assert any("reference scatter carries" in n for n in result.notes())
    assert not np.isnan(result.p["frequency_hz"][20:, 0]).any()


def test_a_mode_missing_from_new_surveys_is_an_event_not_an_alarm():
    surveys = _sequence(np.random.default_rng(11), n_new=4)
    for s in surveys[21:23]:
        s.modes = s.modes[:1]
    result = track(surveys, reference=20)
    assert not result.changed[21:23].any()
    (event,) = result.mode_events
    assert (event.kind, event.found_new, event.n_new, event.significant) == ("vanished", 2, 4, False)
    assert "found in 20 of 20 reference and 2 of 4 new surveys" in result.events()[0]


def test_a_mode_gone_from_every_new_survey_and_a_new_one_are_beyond_chance():
    surveys = _sequence(np.random.default_rng(14), n_new=10)
    for s in surveys[20:]:
        s.modes = s.modes[:1] + [_mode(180.0)]  # the 250 Hz mode moved far: gone, and a new one
    result = track(surveys, reference=20)
    kinds = {(e.kind, round(result.tracks[e.mode].frequency_hz)) for e in result.event_alarms}
    assert kinds == {("vanished", 250), ("appeared", 180)}
    assert "1 mode(s)" not in repr(result) and "2 mode(s) vanished or appeared" in repr(result)


def test_a_small_reference_is_warned_about_and_a_failed_survey_noted():
    from sindy_impulse.exceptions import DataWarning

    surveys = _sequence(np.random.default_rng(15), n_ref=5, n_new=2)
    surveys[6] = SurveyValues([], "hit7.csv", "ValueError: too short")
    with pytest.warns(DataWarning, match="the reference has 5 surveys"):
        result = track(surveys, reference=5)
    assert not result.changed[6] and result.notes()[0].startswith("hit7.csv: its survey failed")


def test_surveys_without_modes_and_a_reference_without_new_surveys():
    empty = track([SurveyValues([])] * 5, reference=3)
    assert not empty.changed.any() and empty.to_frame().empty and "0 mode(s)" in repr(empty)
    with pytest.raises(ValueError, match="no mode to plot"):
        empty.plot()
    only = track(_sequence(np.random.default_rng(16), n_ref=12, n_new=0), reference=12)
    assert only.new.size == 0 and not only.alarms and not only.trends
    assert 'id="tracking"' in only.to_html()


def test_reference_by_indices_labels_and_bad_arguments():
    surveys = _sequence(np.random.default_rng(12), n_ref=10, n_new=4)
    result = track(surveys, reference=list(range(4, 14)), labels=[f"hit{i}.csv" for i in range(14)])
    assert result.new.tolist() == [0, 1, 2, 3] and result.labels[0] == "hit0.csv"
    with pytest.raises(ValueError, match="first n surveys"):
        track(surveys, reference=1)
    with pytest.raises(ValueError, match="distinct"):
        track(surveys, reference=[1, 1, 2])
    with pytest.raises(TypeError, match="reference"):
        track(surveys, reference=2.5)
    with pytest.raises(InvalidParameterError, match="alpha"):
        track(surveys, reference=10, alpha=1.0)
    with pytest.raises(ValueError, match="labels"):
        track(surveys, reference=10, labels=["a"])
    with pytest.raises(TypeError, match="identify_modes"):
        track([np.zeros(3)] * 5, reference=3)


def test_frame_json_plot_and_page():
    import matplotlib

    matplotlib.use("Agg")

    def soften(k, i, f, zeta):
        return (f * 0.99 if i == 0 and k >= 2 else f), zeta, {}

    result = track(_sequence(np.random.default_rng(13), n_new=4, change=soften), reference=20)
    frame = result.to_frame()
    assert len(frame) == 24 * 2 and {"frequency_hz_p", "coef[y]", "coef[y]_std", "term", "note"} <= set(frame)
    assert frame.loc[frame.changed, "term"].eq("linear stiffness").all() and frame.changed.sum() == 2
    data = json.loads(json.dumps(result.to_dict()))
    assert len(data["alarms"]) == 2 and data["alarms"][0]["terms"][0]["name"] == "linear stiffness"
    axes = result.plot()
    assert axes.shape == (4,)
    page = result.to_html(source="beam")
    assert 'id="tracking"' in page and "linear stiffness" in page and page.count("<img") == 1
    assert "2 of 4 new surveys changed" in repr(result)


def test_a_mode_event_says_when_only_holms_correction_makes_it_chance():
    from types import SimpleNamespace

    from sindy_impulse.tracking.result import ModeEvent

    track = SimpleNamespace(label=lambda k: f"mode {k} (3.9 Hz)")
    result = SimpleNamespace(labels=["a", "b"], new=[1], slot=np.array([[0], [-1]]), tracks=[track],
                             alpha=0.01)
    line = ModeEvent(0, "vanished", 5, 5, 0, 6, 0.0022, False).text(result)
    assert "Fisher p = 0.0022; within chance after Holm's correction over the modes" in line
    assert "p = 0.4; within chance)" in ModeEvent(0, "vanished", 5, 5, 4, 6, 0.4, False).text(result)
    assert "within chance" not in ModeEvent(0, "vanished", 5, 5, 0, 6, 0.0001, True).text(result)

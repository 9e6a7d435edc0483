"""The survey as a declared pipeline (sindy_impulse/modes/pipeline.py, survey.py): its stages, the trace,
the kinds and codes of the candidates, every mode's standard deviations, parallel bands."""

import warnings

import numpy as np
import pytest

from sindy_impulse import identify_modes, impact_record
from sindy_impulse.modes.kinds import Kind, Reason
from sindy_impulse.modes.pipeline import Pipeline, Stage, StageTrace, SurveyTrace
from sindy_impulse.modes.survey import SURVEY
from sindy_impulse.optimizers.fixed import FixedCoefficients
from sindy_impulse.poles import modal_parameters


def _survey(y, fs, **kws):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return identify_modes(y, fs=fs, **kws)


@pytest.fixture(scope="module")
def three_modes():
    rec = impact_record([118.0, 243.0, 402.0], [0.002, 0.004, 0.008], amplitudes=[1.0, 0.5, 0.3], fs=5000.0,
                        duration=2.0, offset=2.0, snr_db=45, random_state=7)
    return rec, _survey(rec.y, rec.fs)


def test_the_survey_is_a_declared_list_of_stages():
    assert [s.name for s in SURVEY] == ["read", "poles", "candidates", "classify", "identify", "reconcile",
                                    "coupling"]
    text = repr(SURVEY)
    assert text.startswith("Pipeline of 7 stages") and all(s.summary in text for s in SURVEY)
    with pytest.raises(ValueError, match="unique"):
        Pipeline([Stage("a", print), Stage("a", print)])


def test_the_trace_holds_every_stage_with_its_time_and_decisions(three_modes):
    _, survey = three_modes
    assert [t.stage for t in survey.trace] == [s.name for s in SURVEY]
    assert all(t.seconds >= 0 and t.decisions for t in survey.trace)
    assert set(survey.trace.seconds()) == {s.name for s in SURVEY}
    assert "candidates" in str(survey.trace)
    assert str(SurveyTrace([StageTrace("x", 1, 0.5, [])])) == "record 1  x              500.0 ms  -"


def test_linear_modes_come_from_their_poles_with_standard_deviations(three_modes):
    rec, survey = three_modes
    assert np.allclose([m.frequency_hz for m in survey], rec.modes.frequency_hz, rtol=1e-3)
    for mode in survey:
        assert mode.source == "poles"
        assert np.isfinite(mode.frequency_std_hz) and mode.frequency_std_hz > 0
        assert np.isfinite(mode.damping_ratio_std) and mode.damping_ratio_std > 0
        f, zeta = modal_parameters(mode.model)  # the equation carries the reported values
        assert f[0] == pytest.approx(mode.frequency_hz, rel=1e-9)
        assert zeta[0] == pytest.approx(mode.damping_ratio, rel=1e-9)
        std = mode.coefficients_std
        assert std.shape == mode.model.coefficients().shape and np.isfinite(std[1, :2]).all()


def test_bands_in_parallel_give_the_serial_result(three_modes):
    rec, serial = three_modes
    parallel = _survey(rec.y, rec.fs, n_jobs=2)
    assert [m.frequency_hz for m in parallel] == [m.frequency_hz for m in serial]
    assert [m.damping_ratio_std for m in parallel] == [m.damping_ratio_std for m in serial]
    with pytest.raises(ValueError, match="n_jobs"):
        identify_modes(rec.y, fs=rec.fs, n_jobs=0)


def test_hum_is_named_a_tone_not_reported_as_a_mode():
    """50 Hz hum at 5 % of the peak over a lightly damped two-mode record: a tone, with its code."""
    rec = impact_record([31.0, 87.0], [0.004, 0.003], fs=2000.0, duration=3.0, snr_db=50, pre_trigger=0.05,
                        random_state=3)
    t = np.arange(rec.y.size) / rec.fs
    hum = 0.05 * np.max(np.abs(rec.y - np.median(rec.y))) * np.sin(2 * np.pi * 50.0 * t + 0.4)
    survey = _survey(rec.y + hum, rec.fs)
    assert np.allclose(sorted(m.frequency_hz for m in survey), rec.modes.frequency_hz, rtol=1e-3)
    tones = [r for r in survey.rejected if r.code is Reason.TONE]
    assert len(tones) == 1 and tones[0].band_hz[0] < 50.0 < tones[0].band_hz[1]
    assert "tone" in tones[0].reason


@pytest.mark.parametrize("shift", [0.06, -0.06])
def test_a_cubic_spring_is_one_mode_fitted_by_the_papers_model(shift):
    """A hardening or softening spring moving the frequency squared by 6 % at the hit: its chirp's pieces
    are one mode, whose equation carries the cubic term with the right sign and size."""
    k3 = 4 / 3 * shift * (2 * np.pi * 60.0) ** 2  # displacement amplitude 1 at the hit
    rec = impact_record(60.0, 0.01, fs=2000.0, duration=3.0, snr_db=50, sensor="displacement",
                        cubic_stiffness=k3, random_state=0)
    survey = _survey(rec.y, rec.fs)
    assert len(survey) == 1
    mode = survey.modes[0]
    assert mode.source == "equation"
    assert mode.frequency_hz == pytest.approx(60.0, rel=0.003)
    assert mode.damping_ratio == pytest.approx(0.01, rel=0.1)
    cubic = dict(zip(mode.model.get_feature_names(), mode.model.coefficients()[1]))["y^3"]
    assert -cubic == pytest.approx(k3, rel=0.2)
    assert all(r.code in (Reason.HARMONIC, None) for r in survey.rejected)


def test_a_broad_component_nothing_supports_is_rejected_not_reported():
    """A softening quadratic spring: beside its mode and second harmonic, the linear decay fit leaves a broad
    component (a damping ratio of 17 %) that no stable pole confirms, that its linear decay does not
    explain and whose model does not reproduce its band: a poor fit, not a mode."""
    rec = impact_record(486.6, 0.0078, fs=25600.0, duration=0.217, sensor="displacement", pre_trigger=0.095,
                        offset=1.375, snr_db=58.7, quadratic_stiffness=-1.247e6, random_state=3)
    survey = _survey(rec.y, rec.fs)
    assert [round(m.frequency_hz) for m in survey] == [487]
    poor = [r for r in survey.rejected if r.code is Reason.POOR_FIT]
    assert len(poor) == 1 and "no stable pole" in poor[0].reason
    assert poor[0].evidence["fit_error"] > 0.25 and poor[0].evidence["damping_ratio"] > 0.05
    assert {r.code for r in survey.rejected} == {Reason.POOR_FIT, Reason.HARMONIC}


def test_a_mode_is_rejected_only_where_nothing_supports_it(three_modes):
    """The rule's four legs: a stable pole, a linear decay that explains it, an equation (not the decay
    fit's values) or a band its model reproduces each keep the mode."""
    from dataclasses import replace
    from types import SimpleNamespace

    from sindy_impulse.modes.identify import _supported
    from sindy_impulse.modes.result import Rejected

    mode = three_modes[1].modes[0]

    def case(stable=False, explained=False, source="poles", fit_error=0.4):
        cand = SimpleNamespace(stable=stable, explained=explained, damped_frequency_hz=600.0,
                               lack_of_fit=500.0, band_hz=(540.0, 650.0))
        state = SimpleNamespace(candidates=[cand], index=0)
        return _supported(state, 0, replace(mode, source=source, fit_error=fit_error))

    assert isinstance(case(), Rejected) and case().code is Reason.POOR_FIT
    assert case().evidence["fit_error"] == 0.4
    for kept in (case(stable=True), case(explained=True), case(source="equation"), case(fit_error=0.2)):
        assert not isinstance(kept, Rejected) and kept.source in ("poles", "equation")


def test_a_doubtful_mode_whose_equation_agrees_with_its_poles_takes_their_values(three_modes, monkeypatch):
    """A mode sent to the paper's fit for a doubtful change of its frequency: where its equation's
    small-amplitude values agree with its poles' within DOUBT_SIGMAS combined standard deviations, the
    poles' mode is its answer; a disagreement, a change beyond doubt or a component the linear decay does
    not explain keep the equation's."""
    from dataclasses import replace
    from types import SimpleNamespace

    from sindy_impulse.modes import identify
    from sindy_impulse.modes._envelope import DOUBT_SIGMAS

    base = three_modes[1].modes[0]
    poles = replace(base, source="poles", frequency_hz=100.0, frequency_std_hz=0.01, damping_ratio=0.01,
                    damping_ratio_std=1e-4)  # the candidate's values, as linear_mode reports them
    monkeypatch.setattr(identify, "linear_mode", lambda state, k: poles)
    monkeypatch.setattr(identify, "_nonlinear_equation", lambda out: True)

    def case(frequency=100.4, frequency_std=0.6, damping=0.0102, damping_std=0.002, explained=True,
             nonlinear=False):
        cand = SimpleNamespace(explained=explained, kind=Kind.NONLINEAR, parent=None, frequency_hz=100.0,
                               frequency_std_hz=0.01, damping_ratio=0.01, damping_ratio_std=1e-4,
                               evidence={"amplitude_dependence": SimpleNamespace(nonlinear=nonlinear)})
        state = SimpleNamespace(candidates=[cand], index=0)
        out = replace(base, source="equation", frequency_hz=frequency, frequency_std_hz=frequency_std,
                      damping_ratio=damping, damping_ratio_std=damping_std)
        return identify._agreeing_poles(state, 0, out)

    assert case() is poles
    beyond = DOUBT_SIGMAS * np.hypot(0.6, 0.01) + 0.01
    assert case(frequency=100.0 + beyond) is None
    assert case(damping=0.01 + DOUBT_SIGMAS * np.hypot(0.002, 1e-4) + 1e-4) is None
    assert case(nonlinear=True) is None and case(explained=False) is None


def test_an_undescribed_chirp_whose_equation_is_linear_keeps_its_poles(three_modes, monkeypatch):
    """A candidate sent to the paper's fit because neither cheap reading described it: an equation without
    nonlinear terms calls it linear after all, and its poles' mode is its answer; a nonlinear equation
    stands."""
    from dataclasses import replace
    from types import SimpleNamespace

    from sindy_impulse.modes import identify

    base = three_modes[1].modes[0]
    poles = replace(base, source="poles", frequency_hz=100.0)
    monkeypatch.setattr(identify, "linear_mode", lambda state, k: poles)
    monkeypatch.setattr(identify, "with_uncertainty", lambda out, index: out)

    def case(nonlinear_terms: bool, undescribed=True):
        monkeypatch.setattr(identify, "_nonlinear_equation", lambda out, significant=False: nonlinear_terms)
        e = SimpleNamespace(nonlinear=False)
        cand = SimpleNamespace(explained=False, kind=Kind.NONLINEAR, parent=None, frequency_hz=100.0,
                               evidence={"amplitude_dependence": e, "undescribed": undescribed})
        state = SimpleNamespace(candidates=[cand], index=0)
        out = replace(base, source="equation", frequency_hz=96.0)
        return identify._kept(state, 0, out)[0][1]

    assert case(False) is poles
    assert case(True).frequency_hz == 96.0 and case(True).source == "equation"
    assert case(False, undescribed=False).frequency_hz == 96.0  # not sent for that: its equation stands


def test_one_mode_found_from_two_bands_is_reported_once(three_modes):
    """Two modes closer than the wider one's half-power half-width whose frequencies agree within two
    combined standard deviations are one mode: the more precise stands, the other is a DUPLICATE row; a
    resolved pair, or one whose frequencies disagree beyond their standard deviations, stays two."""
    from dataclasses import replace
    from types import SimpleNamespace

    from sindy_impulse.modes.reconcile import _found_twice

    base = three_modes[1].modes[0]

    def case(f2, std2=3.1, zeta=0.0035):
        a = replace(base, frequency_hz=245.657, frequency_std_hz=0.7, damping_ratio=zeta)
        b = replace(base, frequency_hz=f2, frequency_std_hz=std2, damping_ratio=zeta, band_hz=(52.7, 1665.0))
        state = SimpleNamespace(modes=[b, a], origin=[3, 1], rejected=[], index=0)
        _found_twice(state)
        return state

    twice = case(245.745)
    assert [m.frequency_hz for m in twice.modes] == [245.657] and twice.origin == [1]
    assert twice.rejected[0].code is Reason.DUPLICATE and twice.rejected[0].evidence["mode_hz"] == 245.657
    assert len(case(245.745, std2=0.01).modes) == 1  # the more precise one stands, whichever it is
    assert case(245.745, std2=0.01).modes[0].frequency_hz == 245.745
    assert len(case(247.5).modes) == 2  # resolved: 1.84 Hz apart, half-widths 0.86 Hz
    assert len(case(245.745, std2=0.01, zeta=0.01).modes) == 1
    assert len(case(247.2, std2=0.1, zeta=0.01).modes) == 2  # unresolved, but 2.2 standard deviations apart


def test_kinds_and_reasons_have_words():
    assert all(k.words for k in Kind) and all(r.words for r in Reason)
    assert Reason("tone") is Reason.TONE


def test_fixed_coefficients_must_fit_the_library():
    import pysindy as ps

    from sindy_impulse import ImpulseSINDy

    t = np.arange(100) * 0.01
    x = np.column_stack([np.cos(t), -np.sin(t)])
    model = ImpulseSINDy(optimizer=FixedCoefficients([[1.0, 0.0, 0.0]]),
                         feature_library=ps.PolynomialLibrary(degree=1, include_bias=False), sweep=False,
                         refine=False)
    with pytest.raises(ValueError, match="do not match"):
        model.fit(x, t=t)


def test_fixed_coefficients_hand_back_their_values_whatever_the_data():
    """No regression is solved: NaN rows and a rank-deficient matrix change nothing."""
    theta = np.ones((50, 3))  # rank 1
    theta[5] = np.nan
    y = np.random.default_rng(0).normal(size=(50, 2))
    opt = FixedCoefficients([[0.0, 1.0, 0.0], [-4.0, 0.0, -0.2]]).fit(theta, y)
    assert opt.coef_.tolist() == [[0.0, 1.0, 0.0], [-4.0, 0.0, -0.2]]
    assert opt.ind_.tolist() == [[False, True, False], [True, False, True]]
    assert opt.Theta_.shape == (49, 3) and opt.coef_ is not opt.coefficients
    with pytest.raises(ValueError, match="do not match"):
        FixedCoefficients([[1.0, 2.0]]).fit(theta, y)


def _values(survey) -> list:
    return [(m.frequency_hz, m.damping_ratio, m.frequency_std_hz, m.damping_ratio_std, m.uncertainty_note,
             m.source, m.fit_error, m.model.coefficients().tolist()) for m in survey]


@pytest.mark.parametrize("nonlinear", [False, True])
def test_signals_kept_for_reuse_and_deferred_standard_deviations_change_nothing(nonlinear, monkeypatch):
    """The survey keeps each candidate's own signal and its band-passes for the later stages, and computes
    the standard deviations of a nonlinear candidate's fit only where its mode is kept: the modes are those
    of a survey that keeps nothing (bit for bit), and every mode has its standard deviations."""
    from sindy_impulse.modes import signals
    from sindy_impulse.modes.band_fit import PENDING

    if nonlinear:
        k3 = 4 / 3 * 0.06 * (2 * np.pi * 60.0) ** 2
        rec = impact_record(60.0, 0.01, fs=2000.0, duration=3.0, snr_db=50, sensor="displacement",
                            cubic_stiffness=k3, random_state=0)
    else:
        rec = impact_record([118.0, 243.0, 402.0], [0.002, 0.004, 0.008], amplitudes=[1.0, 0.5, 0.3],
                            fs=5000.0, duration=2.0, snr_db=45, random_state=7)
    kept = _survey(rec.y, rec.fs)
    monkeypatch.setattr(signals, "CACHE_BYTES", 0)
    assert _values(_survey(rec.y, rec.fs)) == _values(kept)
    assert all(m.uncertainty_note != PENDING and np.isfinite(m.frequency_std_hz) for m in kept)
    assert any(m.source == "equation" for m in kept) == nonlinear


def test_a_candidates_own_signal_is_computed_once_and_read_only(three_modes):
    from sindy_impulse.modes.band_fit import default_estimator
    from sindy_impulse.modes.pipeline import SurveyOptions, SurveyState
    from sindy_impulse.modes.signals import deflated

    rec, _ = three_modes
    options = SurveyOptions(template=default_estimator())
    state = SurveyState(0, rec.y.reshape(-1, 1), None, rec.fs, None, options)
    Pipeline(SURVEY[:4])(state)
    first = deflated(state, 0)
    assert deflated(state, 0) is first and not first.flags.writeable
    with pytest.raises(ValueError):
        first[0] = 1.0


def test_the_table_does_not_depend_on_the_records_units():
    """A record of three modes one nonlinear element couples (a cubic spring and an amplitude-dependent
    damper), in volts, millivolts and microvolts: the same modes from the same sources, their values and ±
    alike (the paper's fit is not exact arithmetic: within 1e-6 in frequency, 1 % in the rest)."""
    rec = impact_record([26.65, 64.26, 121.29], [0.0011, 0.0253, 0.0023], amplitudes=[0.155, 0.275, 0.946],
                        fs=1000.0, duration=20.5, sensor="velocity", pre_trigger=0.03, offset=1.0, snr_db=45,
                        random_state=1144241433, cubic_stiffness=-3.095e9, damping_amplitude=4.28e5)
    surveys = [_survey(rec.y * units, rec.fs).modes for units in (1.0, 1e-3, 1e6)]
    assert len(surveys[0]) == 3
    for modes in surveys[1:]:
        assert [m.source for m in modes] == [m.source for m in surveys[0]]
        for m, ref in zip(modes, surveys[0]):
            assert m.frequency_hz == pytest.approx(ref.frequency_hz, rel=1e-6)
            for name in ("damping_ratio", "frequency_std_hz", "damping_ratio_std"):
                assert getattr(m, name) == pytest.approx(getattr(ref, name), rel=1e-2), name

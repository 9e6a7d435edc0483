"""The modes read together where one nonlinear element couples them (sindy_impulse/modes/coupling.py): the
reading, its band test, and the survey's ``coupling`` stage."""

import warnings
from dataclasses import replace

import numpy as np
import pytest
from survey_helpers import assert_true_modes_found, nearest_mode

from sindy_impulse import identify_modes, impact_record
from sindy_impulse.modes import coupling
from sindy_impulse.modes.coupling import NOISE_LEVEL, band_consistency, one_element_reading


def _coupled(fs=2000.0, n=8000, shares=(0.02, 0.03), rates=(1.0, 8.0), noise=1e-3, seed=0):
    """Two decays moved by one element: mode k's frequency by ``w_k g_k (sum_m (2 - delta_km) I_m)``."""
    t = np.arange(n) / fs
    a = np.array([1.0, 0.5])
    integrals = [a[m] ** 2 * (1 - np.exp(-2 * rates[m] * t)) / (2 * rates[m]) for m in range(2)]
    w = 2 * np.pi * np.array([40.0, 90.0])
    y = sum(np.real(a[k] * np.exp(-rates[k] * t + 1j * w[k] * t + 1j * w[k] * shares[k]
                                  * sum((2 - (k == m)) * integrals[m] for m in range(2))))
            for k in range(2))
    return y + noise * np.random.default_rng(seed).standard_normal(n), fs, w, np.array(rates)


def test_the_reading_recovers_small_amplitude_values_a_linear_decay_reads_offset():
    y, fs, w, rates = _coupled()
    true_hz = np.hypot(w, rates) / (2 * np.pi)
    # the strongly damped mode's frequency is held high by the other's amplitude while it rings: its linear
    # decay starts at the offset frequency (as a mode's own reading sees it)
    start = [(1.0, 1.0, 40.0 * 1.02), (0.5, 8.0, 90.0 * 1.06)]
    reading = one_element_reading(y, fs, start)
    assert np.allclose(reading.frequency_hz, true_hz, rtol=2e-4)
    assert np.allclose(reading.damping_ratio, rates / np.hypot(w, rates), rtol=0.02)
    assert np.all(reading.frequency_std_hz > 0) and np.all(np.isfinite(reading.damping_ratio_std))
    off = np.abs(reading.frequency_hz - true_hz) / reading.frequency_std_hz
    assert np.all(off < 5)
    assert reading.rms == pytest.approx(1e-3, rel=0.1)


def _bent(fs=2000.0, n=8000, G=(0.5, 1.5), H=(0.4, 3.0), rates=(1.0, 8.0), noise=1e-3, seed=0):
    """Two modes of one element with an amplitude-dependent damper, from their averaged equations: mode k's
    amplitude decays at ``rate_k + H_k s_k`` and its phase turns at ``w_k + G_k s_k``, ``s_k = sum_m (2 -
    delta_km) a_m^2`` (the amplitudes are bent away from linear decays by the damper)."""
    from scipy.integrate import solve_ivp

    w, rates, G, H = 2 * np.pi * np.array([40.0, 90.0]), np.array(rates), np.array(G), np.array(H)

    def slow_flow(_, state):
        a = state[:2]
        drive = (2 - np.eye(2)) @ a**2
        return np.concatenate([-(rates + H * drive) * a, w + G * drive])

    t = np.arange(n) / fs
    flow = solve_ivp(slow_flow, (0, t[-1]), [1.0, 0.5, 0.0, 0.0], t_eval=t, rtol=1e-10, atol=1e-12)
    y = (flow.y[:2] * np.cos(flow.y[2:])).sum(axis=0)
    return y + noise * np.random.default_rng(seed).standard_normal(n), fs, w, rates


def test_the_reading_integrates_its_own_amplitudes_where_a_damper_bends_them(monkeypatch):
    y, fs, w, rates = _bent()
    true_hz, true_zeta = np.hypot(w, rates) / (2 * np.pi), rates / np.hypot(w, rates)
    start = [(1.0, 1.5, 40.2), (0.5, 9.0, 90.5)]  # the linear decays a mode's own reading gives
    reading = one_element_reading(y, fs, start)
    assert np.all(np.abs(reading.frequency_hz - true_hz) < 4 * reading.frequency_std_hz)
    assert np.all(np.abs(reading.damping_ratio - true_zeta) < 4 * reading.damping_ratio_std)
    assert band_consistency(reading.residual, reading.fs, start).min() > NOISE_LEVEL
    assert reading.rms == pytest.approx(1e-3, rel=0.1)
    # held at the linear decays' amplitudes, the coupling reads the lightly damped mode tens of its standard
    # deviations off and leaves its band far from noise
    monkeypatch.setattr(coupling, "ROUNDS", 1)
    held = one_element_reading(y, fs, start)
    assert abs(held.frequency_hz[0] - true_hz[0]) > 20 * held.frequency_std_hz[0]
    assert band_consistency(held.residual, held.fs, start).min() < 1e-10


def test_the_reading_refuses_what_is_not_one_free_decay():
    with pytest.raises(ValueError, match="y must be 1-D"):
        one_element_reading(np.zeros((10, 2)), 100.0, [(1.0, 1.0, 10.0)])
    with pytest.raises(ValueError, match="at least one component"):
        one_element_reading(np.zeros(100), 100.0, [])
    with warnings.catch_warnings(), pytest.raises(ValueError, match="give no finite signal"):
        warnings.simplefilter("ignore", RuntimeWarning)  # (the overflow it reports)
        one_element_reading(np.zeros(2000), 1000.0, [(1.0, -1e5, 10.0)])
    with pytest.raises(ValueError, match="NaN"):
        one_element_reading(np.full(100, np.nan), 100.0, [(1.0, 1.0, 10.0)])
    with pytest.raises(ValueError, match="fs \\(sampling rate\\) must be a positive"):
        band_consistency(np.zeros(100), -1.0, [(1.0, 1.0, 10.0)])
    with pytest.raises(TypeError, match="fs \\(sampling rate\\) must be a number"):
        one_element_reading(np.zeros(100), "fast", [(1.0, 1.0, 10.0)])
    with pytest.raises(ValueError, match="residual has 3 samples; at least 6"):
        band_consistency(np.zeros(3), 100.0, [(1.0, 1.0, 10.0)])


def test_the_band_test_holds_its_level_on_noise_and_finds_what_is_left():
    rng = np.random.default_rng(1)
    components = [(1.0, 2.0, 120.0), (1.0, 20.0, 300.0)]
    chances = np.array([band_consistency(rng.standard_normal(2000), 1000.0, components)
                        for _ in range(400)])
    assert 0.02 <= np.mean(chances < 0.05) <= 0.09  # about 5 % of the bands' tests under 0.05
    t = np.arange(2000) / 1000.0
    left = rng.standard_normal(2000) + 3 * np.exp(-20 * t) * np.cos(2 * np.pi * 300 * t)
    low, high = band_consistency(left, 1000.0, components)
    assert low > NOISE_LEVEL and high < NOISE_LEVEL
    # a frequency beyond the residual's Nyquist frequency is tested where it folds
    assert band_consistency(left, 1000.0, [(1.0, 20.0, 700.0)])[0] < NOISE_LEVEL


def _survey(rec):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return identify_modes(rec.y, fs=rec.fs)


def _coupling_trace(survey):
    return next(t for t in survey.trace if t.stage == "coupling")


def test_a_linear_record_is_left_to_its_own_readings():
    rec = impact_record([118.0, 243.0], [0.002, 0.004], fs=5000.0, duration=2.0, snr_db=45, random_state=7)
    survey = _survey(rec)
    decisions = _coupling_trace(survey).decisions
    assert decisions == ["no candidate moves with its amplitude: nothing to read together"]
    assert all(m.source != "coupling" for m in survey)


#: Four modes, a softening cubic spring and an amplitude-dependent damper at mass 0; the 80 Hz mode (1.8 %)
#: rings beside lightly damped ones that move it through the element.
FOUR_COUPLED = dict(frequencies_hz=[34.834, 49.754, 80.374, 111.765],
                    damping_ratios=[0.00953, 0.00350, 0.01820, 0.00222],
                    amplitudes=[0.756, 0.961, 0.213, 0.108], fs=1000.0, duration=17.595,
                    sensor="acceleration", pre_trigger=0.036, offset=3.93, snr_db=44.36,
                    random_state=1085967314, cubic_stiffness=-1.8037e14, damping_amplitude=4.8698e11)


def test_a_strongly_damped_mode_beside_a_nonlinear_element_takes_the_joint_reading():
    config = FOUR_COUPLED
    rec = impact_record(**config)
    survey = _survey(rec)
    decisions = " ".join(_coupling_trace(survey).decisions)
    assert "modes read together" in decisions
    coupled = [m for m in survey if m.source == "coupling"]
    assert coupled, decisions
    for mode in coupled:
        i = int(np.argmin(np.abs(np.array(config["frequencies_hz"]) - mode.frequency_hz)))
        assert mode.frequency_hz == pytest.approx(config["frequencies_hz"][i], rel=3e-3)
        assert mode.damping_ratio == pytest.approx(config["damping_ratios"][i], rel=0.1)
        assert np.isfinite(mode.frequency_std_hz) and mode.damping_ratio_std > 0
        assert "coupling through one nonlinear element" in mode.uncertainty_note


def test_a_mode_moved_less_than_a_table_reads_still_calls_for_the_joint_reading():
    """A softening cubic spring moves a lightly damped 190 Hz mode's frequency by 0.06 % over its decay
    (44 standard errors, but under the 0.1 % a modal table reads: a linear mode), and through that mode's
    amplitude a strongly damped 141 Hz mode's by -0.6 % for as long as it rings. No candidate is
    nonlinear; the 190 Hz one's linear decay does not explain it while its averaged equations do, so the
    modes are read together, and the 141 Hz mode's small-amplitude frequency is within 0.3 %."""
    config = dict(frequencies_hz=[140.85009715167496, 190.25191646145404],
                  damping_ratios=[0.025029114115913517, 0.0015224449398296084],
                  amplitudes=[0.2373420208206005, 0.5269495089171031], fs=2048.0, duration=13.4052734375,
                  sensor="displacement", pre_trigger=0.03368659681214203, offset=1.8828797834618527,
                  snr_db=39.03900146298076, random_state=51485343, cubic_stiffness=-1746946.6061082266)
    survey = _survey(impact_record(**config))
    assert next(t for t in survey.trace if t.stage == "classify").decisions == ["2 linear"]
    decisions = " ".join(_coupling_trace(survey).decisions)
    assert "modes read together" in decisions
    assert len(survey.modes) == 2
    for mode, f, z in zip(sorted(survey.modes, key=lambda m: m.frequency_hz), config["frequencies_hz"],
                          config["damping_ratios"]):
        assert mode.frequency_hz == pytest.approx(f, rel=3e-3)
        assert mode.damping_ratio == pytest.approx(z, rel=0.1)


def test_moves_with_amplitude_needs_a_misfit_of_the_linear_decay_and_a_significant_change():
    import types

    from sindy_impulse.modes._envelope import AmplitudeDependence
    from sindy_impulse.modes.classify import moves_with_amplitude

    def cand(change, std, explained=False, misfit=1.0):
        e = AmplitudeDependence(change, std, 0.0, 1.0, (1.0, 0.1), misfit=misfit)
        return types.SimpleNamespace(evidence={"amplitude_dependence": e}, explained=explained)

    assert moves_with_amplitude(cand(6e-4, 1e-5))  # 60 standard errors, under the table's 0.1 %
    assert not moves_with_amplitude(cand(6e-4, 1e-5, explained=True))  # its linear decay explains it
    assert not moves_with_amplitude(cand(6e-4, 1e-5, misfit=5.0))  # its averaged equations do not either
    assert not moves_with_amplitude(cand(2e-5, 1e-5))  # 2 standard errors
    assert not moves_with_amplitude(types.SimpleNamespace(evidence={}, explained=False))


def test_a_failing_reading_leaves_the_modes_own_values(monkeypatch):
    def broken(*args, **kws):
        raise FloatingPointError("overflow")

    monkeypatch.setattr(coupling, "one_element_reading", broken)
    config = dict(frequencies_hz=[43.848, 86.575], damping_ratios=[0.002458, 0.004892], amplitudes=[0.2, 0.9],
                  fs=2048.0, duration=1.506, sensor="velocity", pre_trigger=0.049, offset=2.69, snr_db=36.1,
                  random_state=1426074761, cubic_stiffness=5.5538e9, damping_amplitude=7.4898e6)
    survey = _survey(impact_record(**config))
    decisions = _coupling_trace(survey).decisions
    assert decisions[0].startswith("the coupling reading failed (FloatingPointError: overflow)"), decisions
    assert len(survey.modes) == 2 and all(m.source != "coupling" for m in survey)


# A hardening cubic spring coupling four modes: a strongly damped 459.1 Hz one rings beside a lightly damped
# 518.4 Hz one whose amplitude moves it (family g of benchmarks/accuracy/modes.py).
COUPLED_459 = dict(frequencies_hz=[459.11463279706936, 518.427338675233, 2464.867473678721,
                                   3159.596625661936],
                   damping_ratios=[0.009605714799099153, 0.003319432331107731, 0.025215373885126905,
                                   0.0059627847558094025],
                   amplitudes=[0.34225611627188224, 0.30616756284783847, 0.18949624050458388,
                               0.17814136229501232], fs=25600.0, duration=0.8265625, sensor="acceleration",
                   pre_trigger=0.025023058486183292, offset=4.896248687080899, snr_db=51.97345050468782,
                   random_state=1492823299, cubic_stiffness=1.726170163507745e22)


def test_a_reading_that_misses_a_tenth_of_what_the_linear_decays_miss_is_taken_with_a_widened_std():
    """A hardening cubic spring couples four modes; the strongly damped 459.1 Hz one (0.96 %) rings beside
    a lightly damped 518.4 Hz one whose amplitude moves it, and its own reading (its stable poles) puts it
    at 461.0 Hz. The joint reading leaves more than noise in one band (a combination tone beside the
    two), but there less than a tenth of what the modes' own linear decays leave: of two readings that
    both miss something, the one that misses far less is reported, its ± widened by the difference from
    the mode's own (what it misses may move it as far). Before, the own value stood (461.01 +- 0.06 Hz, 31
    standard deviations off, then widened to hold the truth)."""
    survey = _survey(impact_record(**COUPLED_459))
    decisions = " ".join(_coupling_trace(survey).decisions)
    assert "leaves more than noise" in decisions and "but at most 10%" in decisions
    mode = min(survey.modes, key=lambda m: abs(m.frequency_hz - 459.1))
    assert mode.source == "coupling" and abs(mode.frequency_hz / 459.115 - 1) < 3e-4
    assert abs(mode.frequency_hz - 459.115) <= 2 * mode.frequency_std_hz
    assert mode.frequency_std_hz >= abs(461.01 - mode.frequency_hz) * 0.9  # the own reading's difference


def test_a_reading_that_leaves_more_than_noise_and_explains_little_leaves_the_own_values(monkeypatch):
    """Where the joint reading leaves more than noise in a band and more than a tenth of what the linear
    decays leave there, the modes' own values stand, their ± widened by the reading."""
    monkeypatch.setattr(coupling, "EXPLAINED_SHARE", 0.0)
    survey = _survey(impact_record(**COUPLED_459))
    decisions = " ".join(_coupling_trace(survey).decisions)
    assert "leaves more than noise" in decisions and "their ± widened by it" in decisions
    mode = min(survey.modes, key=lambda m: abs(m.frequency_hz - 459.1))
    assert mode.source != "coupling" and abs(mode.frequency_hz / 459.115 - 1) > 3e-3  # its own value stands
    assert abs(mode.frequency_hz - 459.115) <= 2 * mode.frequency_std_hz
    assert "the record does not decide between the two" in mode.uncertainty_note


def test_explains_compares_band_power_with_the_linear_decays():
    """:func:`coupling._explains`: the reading's band power over the linear decays' in the failing bands."""
    y, fs, w, rates = _coupled()
    start = [(1.0, 1.0, 40.0 * 1.02), (0.5, 8.0, 90.0 * 1.06)]
    reading = one_element_reading(y, fs, start)
    assert coupling._explains(y, fs, start, reading, [True, True])
    worse = replace(reading, residual=y[:: int(fs // reading.fs)])  # a "reading" that explains nothing
    assert not coupling._explains(y, fs, start, worse, [True, True])


def test_a_reading_that_does_not_describe_the_decay_leaves_the_modes_std_alone(monkeypatch):
    """A joint reading whose residual is far above the noise says nothing of the modes: their ± stand."""
    real = coupling.one_element_reading

    def off(*args, **kws):
        reading = real(*args, **kws)
        return replace(reading, frequency_hz=reading.frequency_hz * 1.01, residual=reading.residual * 100)

    rec = impact_record(**FOUR_COUPLED)
    monkeypatch.setattr(coupling, "one_element_reading", off)
    survey = _survey(rec)
    decisions = " ".join(_coupling_trace(survey).decisions)
    assert "does not describe the decay" in decisions and "widened" not in decisions
    assert all("does not decide" not in (m.uncertainty_note or "") for m in survey.modes)


def test_a_reading_that_lets_a_mode_grow_is_not_taken(monkeypatch):
    """A joint reading that describes the decay by letting one mode grow (its damping ratio below zero) has
    traded the physics for the noise: no mode takes its values, none is widened by it."""
    real = coupling.one_element_reading

    def growing(*args, **kws):
        reading = real(*args, **kws)
        zeta = reading.damping_ratio.copy()
        zeta[-1] = -abs(zeta[-1])
        return replace(reading, damping_ratio=zeta, frequency_hz=reading.frequency_hz * 1.01)

    rec = impact_record(**FOUR_COUPLED)
    monkeypatch.setattr(coupling, "one_element_reading", growing)
    survey = _survey(rec)
    decisions = " ".join(_coupling_trace(survey).decisions)
    assert "no free decay" in decisions and "widened" not in decisions
    assert all(m.source != "coupling" and m.damping_ratio > 0 for m in survey.modes)
    assert all("does not decide" not in (m.uncertainty_note or "") for m in survey.modes)


def test_a_mode_takes_the_reading_where_it_is_off_or_known_better():
    from types import SimpleNamespace

    own = SimpleNamespace(frequency_hz=200.0, damping_ratio=0.01, frequency_std_hz=0.1,
                          damping_ratio_std=1e-3)
    assert coupling.takes_reading(own, 200.5, 0.01, 0.1, 1e-3)  # 5 of the reading's sd off in frequency
    assert coupling.takes_reading(own, 200.0, 0.0135, 0.1, 1e-3)  # 3.5 sd off in damping ratio
    assert not coupling.takes_reading(own, 200.2, 0.011, 0.1, 1e-3)  # agrees, known as well
    assert coupling.takes_reading(own, 200.05, 0.0105, 0.05, 5e-4)  # agrees, known better in both
    assert not coupling.takes_reading(own, 200.05, 0.0105, 0.05, 2e-3)  # known better in frequency only
    assert not coupling.takes_reading(own, 200.05, 0.0105, 0.2, 5e-4)  # known better in damping only


def test_a_reading_that_sends_a_mode_out_of_its_band_is_not_taken(monkeypatch):
    """The reading samples every m-th point, so a component may drift to an alias, or be damped away to a
    huge natural frequency: a reading that puts a mode's damped frequency outside its band has dropped it
    from the model, and no mode takes its values."""
    real = coupling.one_element_reading

    def astray(*args, **kws):
        reading = real(*args, **kws)
        frequency = reading.frequency_hz.copy()
        frequency[-1] += reading.fs  # an alias of the strided samples: the same fit
        return replace(reading, frequency_hz=frequency)

    rec = impact_record(**FOUR_COUPLED)
    monkeypatch.setattr(coupling, "one_element_reading", astray)
    survey = _survey(rec)
    decisions = " ".join(_coupling_trace(survey).decisions)
    assert "out of its band" in decisions and "widened" not in decisions
    assert all(m.source != "coupling" for m in survey.modes)


def test_a_reading_of_one_mode_and_what_is_not_one_leaves_its_values_alone():
    """A hardening mode (158.6 Hz) and its third harmonic, which its backbone names: the joint reading of
    the two leaves more than noise, and reads one mode only; the mode keeps its own values (the reading's
    159.96 Hz was 0.84 % off)."""
    rec = impact_record(158.62537118062534, 0.0037097025593240017, [1.0], fs=4853.687975314075,
                        duration=0.7354855392824855, snr_db=35.672931998913825,
                        cubic_stiffness=1.070541445488249e17, random_state=7)
    survey = _survey(rec)
    decisions = " ".join(_coupling_trace(survey).decisions)
    assert "reads 1 mode(s) only" in decisions
    assert len(survey.modes) == 1 and survey.modes[0].source != "coupling"
    assert abs(survey.modes[0].frequency_hz / 158.625 - 1) < 3e-3


def test_band_power_refuses_a_noise_level_that_is_no_power():
    with pytest.raises(ValueError, match="noise must be a positive"):
        coupling.band_power(np.zeros(100), 100.0, [(1.0, 1.0, 10.0)], noise=0.0)


def test_a_reading_that_moves_one_mode_against_the_others_leaves_that_modes_values():
    """One softening spring: the reading gave the strongly damped 476.3 Hz mode a stiffness share and a
    share of the element both of the other sign than the two lightly damped ones' (G 115 beside -22 and
    -20, E -0.53 beside 1.11 and 0.74), moving it 3.3 of its standard deviations down to 470.95 Hz (1.1 %
    off). One element couples every pair one way: that mode keeps its own values, and its ± is not widened
    by a reading that is not one element's for it."""
    rec = impact_record([76.27522144043209, 196.63525963871692, 476.27316423886487],
                        [0.0023796929423656583, 0.0016503256236752493, 0.021754277188739814],
                        [0.3348258452829384, 0.2006636904840418, 0.1965550175902566], fs=5000.0,
                        duration=6.792, sensor="velocity", pre_trigger=0.06403204793632962,
                        offset=1.282238409026114, snr_db=54.681417574137605, random_state=1004091664,
                        cubic_stiffness=-63853206345.97671)
    survey = _survey(rec)
    assert_true_modes_found(survey, rec)
    strong = nearest_mode(survey, 476.27)
    assert strong.source != "coupling" and strong.frequency_std_hz < 0.5


def test_against_element_needs_both_shares_surely_of_the_other_sign():
    from types import SimpleNamespace as Reading

    reading = Reading(stiffness=np.array([-3.0, 1.0]), stiffness_std=np.array([0.1, 0.1]),
                      element=np.array([2.0, -0.5]), element_std=np.array([0.1, 0.3]))
    assert coupling._against_element(reading) == set()  # E under 3 standard deviations
    reading.element_std = np.array([0.1, 0.1])
    assert coupling._against_element(reading) == {1}
    reading.stiffness = np.array([-3.0, -1.0])  # its stiffness share has the others' sign
    assert coupling._against_element(reading) == set()
    reading.stiffness, reading.element_std = np.array([-3.0, 1.0]), None  # not computed: nothing to judge
    assert coupling._against_element(reading) == set()


def test_the_reading_gives_its_shares_standard_deviations():
    y, fs, w, rates = _coupled()
    reading = one_element_reading(y, fs, [(1.0, rates[0], 40.3), (0.5, rates[1], 91.0)])
    assert reading.stiffness_std.shape == (2,) and np.all(reading.stiffness_std > 0)
    assert reading.element_std.shape == (2,) and np.all(reading.element_std > 0)
    assert np.all(np.abs(reading.element) > 3 * reading.element_std)  # both shares sure, one sign
    assert np.all(reading.element * reading.element[0] > 0)


def test_a_damper_records_stiffness_shares_do_not_keep_a_mode_from_its_reading():
    """An amplitude-dependent damper (no stiffness): the reading's stiffness shares are small and of both
    signs, several standard deviations each (what the model misses), while the element's shares have one
    sign but for a strongly damped 118.2 Hz mode's. Neither alone keeps a mode from the reading: the 29.2
    Hz mode (1.39 %), whose own reading holds the lightly damped modes' damping added (1.53 %, 10 % off),
    takes the reading's 1.38 %."""
    rec = impact_record([29.202727079676556, 44.39850964976903, 118.23976143179215, 131.83139063368603],
                        [0.013853017568517988, 0.001822627500607232, 0.013456693748704908,
                         0.0014820076987013132],
                        [0.16686559249816163, 0.5606618646180161, 0.21088807756825673, 0.4873900413172157],
                        fs=2048.0, duration=10.1943359375, sensor="velocity", pre_trigger=0.03354228540120302,
                        offset=2.1190391531124275, snr_db=59.74182825754869, random_state=1453962030,
                        damping_amplitude=23802383.680398293)
    survey = _survey(rec)
    assert_true_modes_found(survey, rec)


def test_a_strongly_damped_modes_share_of_the_element_alone_does_not_refuse_its_reading():
    """A cubic spring and a damper: the reading gives the 1095.2 Hz mode (0.66 %) a share of the element
    of the other sign (-0.41 beside 4.7 and 0.94, 19 standard deviations) but a stiffness share of the
    others' sign: it is moved by the others' amplitudes the way they are, and takes the reading (0.683 %;
    its own reading, which holds their damping added, 0.764 %, 16 % off)."""
    rec = impact_record([698.4683561955727, 866.5637656258177, 1095.193395641992],
                        [0.00571590909867236, 0.0033803756441591324, 0.006604115036445274],
                        [0.4123294088690974, 0.482914697830745, 0.8538480916540528], fs=10000.0,
                        duration=2.676, sensor="acceleration", pre_trigger=0.0092679665547584,
                        offset=4.786243491275263, snr_db=40.49124353641092, random_state=2086165683,
                        cubic_stiffness=1.4674292459511356e+23, damping_amplitude=1.0480952675349023e+19)
    survey = _survey(rec)
    assert_true_modes_found(survey, rec)


def test_a_mode_whose_own_reading_does_not_measure_its_damping_reports_its_linear_decay():
    """A 2.9 %-damped 594.5 Hz mode beside a cubic spring's 191.9 Hz mode: the averaged equations of the
    two read together, every amplitude gone, gave 0.38 +- 0.56 % (no measure of its damping), while its
    stable pole read 2.87 %. The poles' values are reported, and the note says why."""
    rec = impact_record([191.91021285955054, 594.4597757982991], [0.005626732859179287, 0.028758490280921],
                        [0.7433267139584046, 0.692027692661656], fs=5000.0, duration=0.455,
                        sensor="velocity", pre_trigger=7.39196223194183e-05, offset=1.7802468449747666,
                        snr_db=51.86800341399843, random_state=816534835, cubic_stiffness=-191566555764.2128)
    survey = _survey(rec)
    mode = nearest_mode(survey, 594.46)
    assert mode.damping_ratio == pytest.approx(0.02876, rel=0.1)
    assert mode.frequency_hz == pytest.approx(594.46, rel=0.003)
    assert "does not measure its damping" in mode.uncertainty_note
    assert mode.damping_ratio > 3 * mode.damping_ratio_std

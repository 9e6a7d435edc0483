"""Detection on stable poles beside the spectral peaks, and harmonics decided from the data (issue 25)."""

import warnings

import numpy as np
import pytest
from survey_helpers import nearest_mode

from sindy_impulse import identify_modes, impact_record
from sindy_impulse.modes._harmonics import MIN_EXPONENT, _near_order, harmonic_evidence

SEEDS = (0, 1, 2)


def _survey(rec, **kws):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return identify_modes(rec.y, fs=rec.fs, **kws)


@pytest.mark.parametrize("seed", SEEDS)
def test_a_close_pair_one_bandwidth_apart_is_two_modes(seed):
    """100 and 100.8 Hz at 0.4 and 0.3 % damping: 0.8 Hz apart, one half-power bandwidth of the first. The
    spectrum shows one peak between them; the stable poles seed both and the decay fit resolves them."""
    rec = impact_record([100.0, 100.8], [0.004, 0.003], [1.0, 0.7], fs=1000.0, duration=4.0, snr_db=50,
                        pre_trigger=0.05, random_state=seed)
    survey = _survey(rec)
    assert len(survey.preprocessing[0].peaks) == 2
    assert np.allclose([m.frequency_hz for m in survey], rec.modes.frequency_hz, rtol=5e-4)
    assert np.allclose([m.damping_ratio for m in survey], rec.modes.damping_ratio, rtol=0.1)


@pytest.mark.parametrize("seed", SEEDS)
def test_a_weak_mode_on_a_strong_ones_skirt_is_kept_and_nothing_is_added(seed):
    rec = impact_record([100.0, 102.5, 180.0], [0.004, 0.004, 0.002], [1.0, 0.05, 0.3], fs=1000.0,
                        duration=4.0, snr_db=60, pre_trigger=0.05, random_state=seed)
    survey = _survey(rec)
    assert np.allclose([m.frequency_hz for m in survey], rec.modes.frequency_hz, rtol=1e-3)


def test_noise_alone_gives_no_mode():
    rng = np.random.default_rng(0)
    for seed in SEEDS:
        y = np.concatenate([np.zeros(200), np.random.default_rng(seed).standard_normal(3800)]) + 2.0
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            survey = identify_modes(y + 1e-3 * rng.standard_normal(y.size), fs=1000.0)
        assert len(survey) == 0



def test_a_component_that_does_not_decay_and_that_nothing_confirms_is_not_a_mode():
    """A 15 ms record of two strongly damped modes: after they die out, the decay fit gives components of
    the noise that do not decay at all (damping ratio 0), which no stable pole confirms and whose bands the
    linear decay does not explain. They are named, not reported as modes with a damping ratio of 0."""
    from sindy_impulse.modes.kinds import Reason

    rec = impact_record([290.2537796809218, 394.49374288521307], [0.022807334702375528, 0.023812583307074194],
                        [0.8654280294064918, 0.7511720165813819], fs=10000.0, duration=0.015,
                        sensor="acceleration", pre_trigger=0.027740480215439192, offset=0.31262923082758465,
                        snr_db=51.2072197087901, random_state=870296877)
    survey = _survey(rec)
    found = [m.frequency_hz for m in survey.modes]
    assert all(any(abs(f / g - 1) < 3e-3 for f in found) for g in rec.modes.frequency_hz)
    assert all(m.damping_ratio > 0 for m in survey.modes)
    unsupported = [r for r in survey.rejected if r.code is Reason.UNSUPPORTED]
    assert unsupported and all("does not decay measurably" in r.reason for r in unsupported)

@pytest.mark.parametrize("seed", [41, 43, 45])
def test_a_mode_with_amplitude_dependent_damping_is_one_mode(seed):
    """``x^2 x'`` damping (the damping ratio 1.6 times its small-amplitude value at the hit): its record's
    stabilisation diagram has a slowly and a fast decaying pole at the mode and a pole near 3 f; on these
    seeds the survey reported two or three modes before the poles had to be resolved to split a peak
    (``benchmarks/accuracy/model_backbone.py``'s damper seed 39)."""
    rec = impact_record(73.0, 0.0154, [1.0], fs=2400.0, duration=1.44, snr_db=33.0,
                        damping_amplitude=1.88e13, random_state=seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        survey = identify_modes(rec.y, fs=rec.fs, force=rec.force)
    assert len(survey.modes) == 1
    assert survey.modes[0].frequency_hz == pytest.approx(73.0, rel=3e-3)


def _tones(seed, *, f2=None, p=2, order=2, zeta2=None, chirp=0.0, snr_db=50.0):
    """A decaying (optionally chirping) tone at 50 Hz with either its harmonic (amplitude a^p, phase n
    times the tone's) or an independent mode at f2."""
    fs = 2000.0
    t = np.arange(8000) / fs
    phase = 2 * np.pi * (50 * t + chirp * t**2)
    a = np.exp(-2 * np.pi * 0.004 * 50 * t)
    y = a * np.cos(phase)
    if f2 is None:
        y = y + 0.05 * a**p * np.cos(order * phase + 0.7)
    else:
        y = y + 0.05 * np.exp(-2 * np.pi * zeta2 * f2 * t) * np.cos(2 * np.pi * f2 * t + 0.7)
    noise = 10 ** (-snr_db / 20) * np.random.default_rng(seed).standard_normal(t.size)
    bands = (45.0, 55.0), (order * 45.0, order * 55.0)
    sigma = 10 ** (-snr_db / 20) * np.sqrt(np.array([10.0, 10.0 * order]) / (fs / 2))
    return harmonic_evidence(y + noise, fs, *bands, order, tuple(sigma))


@pytest.mark.parametrize("seed", SEEDS)
def test_harmonics_are_locked_with_their_power_as_exponent(seed):
    for order, p, chirp in ((2, 2, 0.0), (3, 3, 0.0), (3, 2, 0.0), (2, 2, 0.1), (3, 3, 0.1)):
        e = _tones(seed, order=order, p=p, chirp=chirp)
        assert e["locked"] and e["harmonic"], (order, p, chirp, e)
        assert abs(e["frequency_ratio"] - order) <= 1e-3 * order
        assert abs(e["exponent"] - p) < 0.3 and e["exponent"] >= MIN_EXPONENT


@pytest.mark.parametrize("seed", SEEDS)
def test_a_true_mode_near_twice_or_three_times_is_not_locked(seed):
    """0.5-2 % off the exact ratio; with equal damping ratios the exponent is n, as a harmonic's would be:
    only the phase tells them apart."""
    for order, off in ((2, 0.005), (2, -0.01), (3, 0.02), (3, -0.005)):
        for zeta2 in (0.004, 0.02):
            e = _tones(seed, f2=order * 50 * (1 + off), order=order, zeta2=zeta2)
            assert not e["locked"] and not e["harmonic"], (order, off, zeta2, e)
            if zeta2 == 0.004:  # (at 2 % the mode is under the floor before the transients end: undecided)
                assert abs(e["frequency_ratio"] / order - 1 - off) < 1e-3
                assert abs(e["exponent"] - order * (1 + off)) < 0.3


def test_a_slow_wander_whose_decay_the_record_does_not_measure_is_not_a_mode():
    """A 4.2 s record of two modes: the decay fit also gives a 0.76 Hz component (three periods of it),
    damping ratio 0.030 +- 0.042, which no stable pole confirms. Its decay is not measured, nor is it shown
    to be a steady tone: it is named, not reported as a mode."""
    from sindy_impulse.modes.kinds import Reason

    rec = impact_record([394.31230663113445, 460.89965121197133],
                        [0.003206874255180988, 0.0048219996258454575], [1.0, 0.016162783427555567],
                        fs=5000.0, duration=4.2202, sensor="acceleration", pre_trigger=0.009504550230159293,
                        offset=0.291983659934561, snr_db=56.35398166402105, random_state=405163037)
    survey = _survey(rec)
    assert np.allclose([m.frequency_hz for m in survey.modes], rec.modes.frequency_hz, rtol=1e-3)
    assert any(r.code is Reason.UNSUPPORTED and r.band_hz[0] < 1.0 for r in survey.rejected)


def test_a_fast_decaying_mode_near_three_times_a_hardening_one_is_a_mode():
    """A 120.6 Hz mode (1.6 % damping) at 2.90 times a hardening 41.5 Hz mode, seen for 18 of its periods:
    its phase ratio to the mode, 2.899 +- 0.003, was taken as locked at 3 (the Student-t quantile of a
    stretch of few independent samples let any ratio pass) and the mode was named a harmonic. The whole
    stretch's resolved ratio is tested at 3 standard errors: not locked, a mode."""
    rec = impact_record([28.43250391270066, 41.486962592011324, 120.60893044345408, 193.51925726154488],
                        [0.004053825953025651, 0.012418016938888488, 0.016092291813712724,
                         0.0026626495266664166],
                        [0.5529423076437548, 0.33632669560878486, 0.10442594237615038, 0.2343725684115309],
                        fs=2048.0, duration=4.30517578125, sensor="acceleration",
                        pre_trigger=0.056942451832926316, offset=4.243471130170286, snr_db=42.83952111362685,
                        random_state=1936642309, cubic_stiffness=61906386481333.34,
                        damping_amplitude=132455653833.69447)
    survey = _survey(rec)
    mode = min(survey.modes, key=lambda m: abs(m.frequency_hz - 120.609))
    assert mode.frequency_hz == pytest.approx(120.609, rel=3e-3)
    assert not any("harmonic" in r.reason and r.band_hz[0] < 120.6 < r.band_hz[1] for r in survey.rejected)


def test_a_steady_parents_sweep_reads_steady_across_the_candidates_gaps():
    """Where the candidate's envelope dips under its floor (here two tones in its band beating to nulls)
    the kept samples leave gaps; the parent's phase, unwrapped over the kept samples only, lost whole turns
    across them and a steady 50 Hz parent read as sweeping 5.7 %, enough to prove any locking."""
    fs = 2000.0
    t = np.arange(8000) / fs
    parent = np.exp(-0.5 * t) * np.cos(2 * np.pi * 50 * t)
    beat = 0.2 * np.exp(-0.5 * t) * (np.cos(2 * np.pi * 100.4 * t) + np.cos(2 * np.pi * 102.4 * t))
    e = harmonic_evidence((parent, beat), fs, (40, 60), (90, 115), 2, (1e-4, 2e-3))
    assert e["parent_sweep"] < 1e-4
    assert not e["locking_proven"]


def test_a_strongly_damped_mode_near_twice_a_parent_is_a_mode():
    """A 2588.8 Hz mode (1.65 % damping) 0.2 % off twice a 1291.6 Hz one: its band's candidate dips under
    its floor late in the stretch, the parent's phase lost turns across the gaps and read a 30 % sweep,
    which proved a locking 15 standard errors off 2. Read whole, the parent is steady: a mode."""
    rec = impact_record([1291.5998987226008, 2588.8020759876363, 2825.0867374308377],
                        [0.0107915429781925, 0.016538897758702712, 0.004638880368018476],
                        [0.29917891247799927, 0.5234506781333172, 0.697194317534396], fs=25600.0,
                        duration=0.5217578125, sensor="velocity", pre_trigger=0.058472498540041544,
                        offset=3.889048652441651, snr_db=55.702185935863106, random_state=1104208949,
                        cubic_stiffness=-7351952819707152.0, damping_amplitude=367036704688.27704)
    survey = _survey(rec)
    assert np.allclose(sorted(m.frequency_hz for m in survey.modes), rec.modes.frequency_hz, rtol=3e-3)


def test_a_mode_decaying_faster_than_a_harmonic_can_is_not_named_by_a_backbone():
    """An 85.25 Hz mode (2 % damping) 0.34 % off twice a cubic-spring 42.54 Hz mode: the phase test, off
    by more than its errors and less than the parent's sweep, left it to the parent's backbone, which passes
    42.63 Hz. Its envelope goes as the parent's to the power 4.7 +- 0.4, far beyond what a harmonic 2 (a
    term of power at most 2) can: a mode."""
    rec = impact_record([35.45130501371054, 42.54225580116049, 85.24793698575607],
                        [0.004738878909455645, 0.008779107666907558, 0.020359310985201325],
                        [0.9513357096668946, 0.13531168402305915, 0.48701516168917847], fs=1000.0,
                        duration=14.954, sensor="displacement", pre_trigger=0.060112540484447675,
                        offset=4.750401404692392, snr_db=35.88711204050437, random_state=1485373093,
                        cubic_stiffness=304505.7875594295)
    survey = _survey(rec)
    mode = nearest_mode(survey, 85.248)
    assert mode.frequency_hz == pytest.approx(85.248, rel=3e-3)
    assert mode.damping_ratio == pytest.approx(0.02036, rel=0.1)


def test_a_strongly_damped_mode_near_a_product_place_that_decays_too_fast_for_one_is_a_mode():
    """A 109.46 Hz mode (2 % damping, 12 dB over the noise), a stable pole under the detection threshold,
    0.8 % off ``2 x 41.85 + 26.64`` Hz beside an amplitude-dependent damper: its place was taken for an
    intermodulation tone's. It decays 13.8 /s, the two modes 0.3 and 0.4 /s: no product of them decays
    so fast. A mode, and its ± is not widened by a coupling reading that does not resolve it."""
    rec = impact_record([26.642175966317932, 41.8473091917635, 109.45650096272824],
                        [0.0025549855909586107, 0.00116243802984278, 0.020250931625120188],
                        [0.39683663127814, 0.9720940264483683, 0.20061363061231818], fs=1000.0,
                        duration=24.087, sensor="acceleration", pre_trigger=0.04618452425053831,
                        offset=4.411063367974613, snr_db=32.98610895990803, random_state=1404169713,
                        damping_amplitude=23619554104.983047)
    survey = _survey(rec)
    mode = nearest_mode(survey, 109.457)
    assert mode.frequency_hz == pytest.approx(109.457, rel=3e-3)
    assert mode.damping_ratio == pytest.approx(0.02025, rel=0.1)
    assert abs(mode.frequency_hz - 109.457) < 3 * mode.frequency_std_hz < 0.01 * 109.457


def test_a_chirping_parent_crossing_the_ratio_halfway_is_not_locked():
    e = _tones(0, f2=2 * 50.8, order=2, zeta2=0.004, chirp=0.2)
    assert not e["locked"]


def _survey(rec):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return identify_modes(rec.y, fs=rec.fs)


@pytest.mark.slow  # three surveys of about 3 s each
@pytest.mark.parametrize("seed", SEEDS)
def test_quadratic_spring_gives_one_mode_and_its_second_harmonic_with_evidence(seed):
    w0, a0 = 2 * np.pi * 60.0, 1e-3
    rec = impact_record(60.0, 0.004, [a0], fs=2000.0, duration=3.0, sensor="displacement", snr_db=50,
                        quadratic_stiffness=0.15 * w0**2 / a0, random_state=seed)
    found = _survey(rec)
    assert len(found.modes) == 1 and abs(found.modes[0].frequency_hz / 60.0 - 1) < 0.003
    (row,) = [r for r in found.rejected if r.evidence.get("order") == 2]
    assert "harmonic 2" in row.reason
    assert abs(row.evidence["frequency_ratio"] - 2) < 2.5e-3 * 2 and row.evidence["locked"]
    assert 1.5 <= row.evidence["exponent"] <= 2.5


@pytest.mark.slow
@pytest.mark.parametrize("seed", SEEDS)
def test_cubic_spring_gives_one_mode_and_its_third_harmonic_with_evidence(seed):
    """A hardening spring 3.3 % stiffer at the start (benchmarks/accuracy/model_backbone.py's cubic row,
    seed 37)."""
    rec = impact_record(145.98385111493212, 0.0030984742414416995, [1.0], fs=6681.011979487065,
                        duration=0.7991751537970851, snr_db=45, cubic_stiffness=6.6998793379225256e16,
                        random_state=seed)
    found = _survey(rec)
    assert len(found.modes) == 1
    (row,) = [r for r in found.rejected if r.evidence.get("order") == 3]
    assert "harmonic 3" in row.reason and row.evidence["locked"]
    assert 2.3 <= row.evidence["exponent"] <= 3.7


@pytest.mark.slow  # about 9 s a record: the harmonic's band fit runs first and fails
@pytest.mark.parametrize("seed", (880091738, *SEEDS))
def test_a_softening_springs_short_lived_third_harmonic_whose_band_fit_fails_is_named(seed):
    """Family e's record 7 (benchmarks/accuracy/modes.py, seed 0; its noise seed first): a softening spring,
    damping ratio 2.5 %, so the third harmonic (28 dB band SNR) decays within its band filter's transient: its
    fit fails, and the peak at 3 x 156 Hz (the early, large-amplitude frequency) was left as "no oscillatory
    mode" (with the benchmark's unrounded configuration). On some noise seeds the peak is not detected at all
    (nothing to name; no mode either)."""
    rec = impact_record([159.854633190464], [0.024638558750460046], [1.0], fs=10000.0, duration=0.3846,
                        sensor="velocity", pre_trigger=0.0105, offset=3.1455, snr_db=57.8,
                        cubic_stiffness=-86193619452.48882, random_state=seed)
    found = _survey(rec)
    assert len(found.modes) == 1 and abs(found.modes[0].frequency_hz / 159.8546 - 1) < 0.003
    near_3f = [r for r in found.rejected if r.band_hz and r.band_hz[0] < 3 * 156 < r.band_hz[1]]
    assert all("harmonic 3" in r.reason and r.evidence["order"] == 3 for r in near_3f)
    if seed == 880091738:  # the recorded case: detected (twice: it drifts), named from the backbone
        assert near_3f and all(r.evidence["by_backbone"] for r in near_3f)


@pytest.mark.slow
@pytest.mark.parametrize("seed", SEEDS)
def test_a_linear_one_to_two_pair_with_equal_damping_ratios_is_two_modes(seed):
    rec = impact_record([100.0, 201.2], [0.004, 0.004], [1.0, 0.3], fs=2048.0, duration=4.0, snr_db=50,
                        sensor="displacement", random_state=seed)
    found = _survey(rec)
    assert np.allclose([m.frequency_hz for m in found.modes], [100.0, 201.2], rtol=3e-3)
    assert not any("harmonic" in r.reason for r in found.rejected)


@pytest.mark.slow
@pytest.mark.parametrize("seed", SEEDS)
def test_a_close_pair_is_resolved_by_the_survey(seed):
    rec = impact_record([100.0, 100.8], [0.004, 0.003], [1.0, 0.7], fs=1000.0, duration=4.0, snr_db=50,
                        pre_trigger=0.05, random_state=seed)
    found = _survey(rec)
    assert np.allclose([m.frequency_hz for m in found.modes], [100.0, 100.8], rtol=3e-3)
    assert np.allclose([m.damping_ratio for m in found.modes], [0.004, 0.003], rtol=0.1)


@pytest.mark.parametrize("seed", [2, 40, 41])
def test_a_linear_mode_at_exactly_twice_another_is_a_mode_not_its_harmonic(seed):
    # issue 26's shock record: 2400 and 4800 Hz, damping 0.5 and 0.6 %: locked (exact 2:1), amplitude
    # exponent 2.4 (neither a whole power nor from a parent with nonlinear terms): three modes
    from sindy_impulse import identify_modes, impact_record

    rec = impact_record([804.0, 2400.0, 4800.0], [0.01, 0.005, 0.006], fs=50000, duration=0.11,
                        pre_trigger=0.005, sensor="acceleration", snr_db=40, random_state=seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        survey = identify_modes(rec.y, fs=rec.fs)
    assert [round(m.frequency_hz, -1) for m in survey.modes] == [800.0, 2400.0, 4800.0]
    assert not any("harmonic" in r.reason for r in survey.rejected)


@pytest.mark.parametrize("seed", [0, 1, 3])
def test_a_linear_mode_0_03_percent_off_twice_another_decaying_faster_is_a_mode(seed):
    # family (a) record 73 of benchmarks/accuracy/modes.py: locked within its few independent samples and
    # with an amplitude exponent of 2.19, but a linear mode's harmonic decays exactly twice as fast: this
    # one 2.21 times. Three modes on noise seeds 0-11 but 2, 5 and 10 (none before), where the 987.5 Hz
    # band's fit leaves its damping ratio 25 % uncertain: the decay rates cannot tell it from a harmonic
    rec = impact_record([493.64, 918.67, 987.54], [0.00929, 0.02407, 0.01027], amplitudes=[0.43, 0.12, 0.15],
                        fs=10000, duration=1.0556, sensor="velocity", pre_trigger=0.0107, offset=1.45,
                        snr_db=53.7, random_state=seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        survey = identify_modes(rec.y, fs=rec.fs)
    assert np.allclose([m.frequency_hz for m in survey.modes], [493.64, 918.67, 987.54], rtol=3e-3)
    assert not any("harmonic" in r.reason for r in survey.rejected)


#: A softening spring, 2.8 % damped, whose third harmonic decays within 0.2 s, before the filter transient of
#: a band narrow enough to find it in ends.
_FAST_SOFTENING = dict(frequencies_hz=[33.179476036761656], damping_ratios=[0.027862307352959814], fs=1000.0,
                       duration=22.105, sensor="velocity", pre_trigger=0.0319681636282665,
                       offset=0.9375385786389245, snr_db=50.17579901750608, random_state=1244721830,
                       cubic_stiffness=-246890056.6420581)


@pytest.mark.slow  # about 1 s
def test_a_short_lived_third_harmonic_is_not_reported_as_a_mode():
    found = _survey(impact_record(**_FAST_SOFTENING))
    assert [round(m.frequency_hz, 1) for m in found.modes] == [33.2]


@pytest.mark.slow
def test_a_short_lived_third_harmonic_is_named():
    """The harmonic decays below 10 dB over its band's noise within the band filter's transient, so its
    locking cannot be measured; the diagram's stable pole at 96.8 Hz, on three times the backbone, names
    it."""
    found = _survey(impact_record(**_FAST_SOFTENING))
    named = [r for r in found.rejected if "harmonic 3" in r.reason]
    assert len(named) == 1 and "stable pole" in named[0].evidence["detection"]


def test_a_ratio_over_few_independent_samples_is_judged_with_its_uncertain_standard_error():
    # 5 standard errors off 2 (beyond RATIO_TOL): no lock over 200 independent samples, a lock over 4,
    # whose standard error is itself a guess from 2 degrees of freedom
    assert not _near_order(2.01, 0.002, 200.0, 2)
    assert _near_order(2.01, 0.002, 4.0, 2)
    assert not _near_order(2.05, 0.002, 4.0, 2)  # 25 of them: no lock either way
    assert _near_order(2.004, 1e-6, 200.0, 2)  # within RATIO_TOL


#: Family (e) of benchmarks/accuracy/modes.py (seed 0), record 60: a quadratic spring's second harmonic about
#: 20 dB over the noise, whose quarters hold 4 independent samples each. Over noise seeds 0-9 it is named on
#: 7 and reported as a mode on 3 (before the Student-t quantile: 5 and 5); some seeds also split the
#: softening mode's peak (189 and 192 Hz), another matter.
_QUADRATIC = dict(frequencies_hz=[192.04603547543297], damping_ratios=[0.008478320855115242], fs=5000.0,
                  duration=5.5176, sensor="velocity", pre_trigger=0.017, offset=0.749, snr_db=33.66,
                  quadratic_stiffness=467088935.09099233)


@pytest.mark.slow  # 5 s a record
@pytest.mark.parametrize("seed", [1922892883, 8])
def test_a_weak_second_harmonic_is_named_not_reported_as_a_mode(seed):
    rec = impact_record(**_QUADRATIC, random_state=seed)
    survey = identify_modes(rec.y, fs=rec.fs)
    assert not [m.frequency_hz for m in survey.modes if 370 < m.frequency_hz < 395]
    assert any("harmonic 2" in r.reason for r in survey.rejected)


#: A softening cubic spring's third harmonic, phase-locked to its mode, measured by an accelerometer: the
#: sensor weights each component by its frequency squared, which moves with the amplitude, so the envelopes'
#: exponent reads above 3 (3.6-3.9), too steep for a power of at most 3 by itself.
_SOFT_CUBIC = dict(frequencies_hz=[18.782589184586058], damping_ratios=[0.0039079465414459304], fs=1000.0,
                   duration=17.483, sensor="acceleration", pre_trigger=0.00714, offset=3.9065, snr_db=44.26,
                   cubic_stiffness=-450528005016.52454)


@pytest.mark.slow  # 2 s a record
@pytest.mark.parametrize("seed", [1109946744, 3])
def test_a_harmonic_locked_while_its_mode_sweeps_is_named_whatever_its_exponent(seed):
    """Locked within its errors while the mode's frequency moved more than those errors allow a mode of its
    own: the locking proves it."""
    survey = identify_modes(impact_record(**_SOFT_CUBIC, random_state=seed).y, fs=1000.0)
    assert [round(m.frequency_hz) for m in survey.modes] == [19]
    row = next(r for r in survey.rejected if "harmonic 3" in r.reason)
    assert row.evidence["locking_proven"] and row.evidence["exponent"] > 3.5

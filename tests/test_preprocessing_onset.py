"""Impact onset, end of contact, double hits, offset and drift (sindy_impulse.preprocessing)."""

import warnings

import numpy as np
import pytest
from preprocessing_records import FS, half_sine, record

from sindy_impulse.exceptions import DataWarning
from sindy_impulse.preprocessing import (
    estimate_offset,
    find_impact,
    force_pulses,
    remove_offset,
    response_onset,
)

MODES = [(120.0, 0.005, 1.0), (410.0, 0.003, 0.5), (980.0, 0.01, 0.3)]


@pytest.mark.parametrize("offset", [0.0, 5.0, -120.0])
@pytest.mark.parametrize("noise", [1e-4, 1e-2])
@pytest.mark.parametrize("phase", [0.0, 1.2])
def test_onset_from_the_response_within_a_few_samples(offset, noise, phase):
    t, y = record(MODES, onset=0.2, offset=offset, noise=noise, phase=phase)
    assert abs(response_onset(y) - int(0.2 * FS)) <= 3


def test_a_lone_spike_in_the_pre_trigger_is_not_the_onset():
    t, y = record(MODES, onset=0.2, noise=1e-3)
    y[300] += 0.05  # 50 sigma
    assert abs(response_onset(y) - 1000) <= 3


def test_onset_is_zero_without_pre_trigger():
    t, y = record(MODES, onset=0.0, offset=3.0, noise=1e-3)
    assert response_onset(y) == 0


def test_onset_with_a_slow_rise_to_the_peak():
    # beating modes starting in opposite phase: the largest sample comes many periods after the onset
    t, y = record([(200.0, 0.0005, 0.5), (203.0, 0.0005, -0.5)], onset=0.3, noise=1e-4, phase=0.0)
    assert np.argmax(np.abs(y)) > int(0.35 * FS)
    assert abs(response_onset(y) - int(0.3 * FS)) <= 3


def test_onset_and_contact_end_from_the_force():
    n = int(2 * FS)
    force = 0.2 + half_sine(n, 1000, 10, 50.0) + 0.01 * np.random.default_rng(1).standard_normal(n)
    t, y = record(MODES, duration=2.0, onset=1000 / FS, noise=1e-4)
    impact = find_impact(y, FS, force=force)
    assert impact.source == "force" and not impact.double_hit
    assert abs(impact.onset_index - 1000) <= 1
    assert abs(impact.ringdown_index - 1011) <= 1  # after the contact: 10 samples wide


def test_negative_force_pulse_is_found():
    force = -half_sine(4000, 500, 12, 3.0)
    pulses = force_pulses(force)
    assert len(pulses) == 1 and abs(pulses[0].start - 500) <= 1 and abs(pulses[0].end - 512) <= 1


def test_double_hit_detected_with_times_and_relative_amplitudes():
    n = int(2 * FS)
    force = half_sine(n, 1000, 10, 50.0) + half_sine(n, 1060, 8, 12.0)
    force += 0.01 * np.random.default_rng(2).standard_normal(n)
    t, y = record(MODES, duration=2.0, onset=1000 / FS, noise=1e-4)
    with pytest.warns(DataWarning, match="double hit"):
        impact = find_impact(y, FS, force=force)
    assert impact.double_hit and len(impact.pulses) == 2
    second = impact.pulses[1]
    assert abs(second.start - 1060) <= 1 and second.relative_amplitude == pytest.approx(12 / 50, abs=0.01)
    assert impact.ringdown_index >= 1068  # the free decay starts after the last contact
    (t1, a1), (t2, a2) = impact.hits
    assert t1 == pytest.approx(1000 / FS, abs=1.5 / FS) and t2 == pytest.approx(1060 / FS, abs=1.5 / FS)
    assert a1 == 1.0 and "double hit: 0.24" in repr(impact)


def test_single_hit_gives_no_warning():
    force = half_sine(5000, 800, 10)
    t, y = record(MODES, duration=1.0, onset=800 / FS)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert not find_impact(y, FS, force=force).double_hit


def test_force_of_another_length_is_refused():
    t, y = record(MODES, duration=1.0)
    with pytest.raises(ValueError, match="force has shape"):
        find_impact(y, FS, force=np.zeros(100))


def test_pre_trigger_offset_removed_to_noise_level():
    noise = 1e-3
    t, y = record(MODES, onset=0.2, offset=2.5, noise=noise)
    onset = response_onset(y)
    est = estimate_offset(y, FS, onset_index=onset)
    clean = remove_offset(y, FS, est)
    assert est.method == "pre_trigger" and est.n_samples == onset
    assert abs(np.mean(clean[:onset])) < 3 * noise / np.sqrt(onset)
    assert est.relative == pytest.approx(2.5 / np.max(np.abs(y[onset:] - 2.5)), rel=1e-3)


def test_tail_offset_without_pre_trigger_within_noise():
    noise = 1e-3
    t, y = record(MODES, onset=0.0, offset=-0.7, noise=noise)
    est = estimate_offset(y, FS)
    assert est.method == "tail"
    assert abs(est.value + 0.7) < noise


def test_linear_drift_removed():
    t, y = record(MODES, onset=0.0, noise=1e-4)
    y = y + 0.3 + 0.05 * t
    est = estimate_offset(y, FS, method="linear")
    assert est.slope == pytest.approx(0.05, abs=2e-3) and est.value == pytest.approx(0.3, abs=2e-3)
    assert np.max(np.abs(remove_offset(y, FS, est)[-2000:])) < 0.01


def test_given_offset_is_used_as_is():
    t, y = record(MODES, offset=1.0)
    est = estimate_offset(y, FS, onset_index=1000, method=0.9)
    assert est.method == "given" and est.value == 0.9


def test_pre_trigger_method_needs_a_pre_trigger():
    t, y = record(MODES, onset=0.0)
    with pytest.raises(ValueError, match="needs a pre-trigger"):
        estimate_offset(y, FS, method="pre_trigger")


def test_unknown_offset_method_is_refused():
    t, y = record(MODES)
    with pytest.raises(ValueError, match="method must be one of"):
        estimate_offset(y, FS, method="median")

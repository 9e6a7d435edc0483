"""Data-quality checks (sindy_impulse.preprocessing.quality)."""

import numpy as np
import pytest
from preprocessing_records import FS, pink_noise, record

from sindy_impulse.datasets import add_noise
from sindy_impulse.preprocessing import (
    check_quality,
    clipping_mask,
    decay_db,
    quantisation_step,
    ringdown_snr_db,
    spectral_peaks,
)

MODES = [(120.0, 0.005, 1.0), (410.0, 0.003, 0.5)]


def test_clean_record_has_no_problems():
    t, y = record(MODES, offset=0.01, noise=1e-4)
    report = check_quality(y, FS, onset_index=1000)
    assert report.problems == {} and report.ringdown_found and not report.clipped.any()


@pytest.mark.slow  # the clipped record's harmonics take 10 s of sinusoid fits: CI's second step
def test_clipping_is_flagged_with_a_mask_of_the_clipped_samples():
    t, y = record(MODES, noise=1e-4)
    clipped = np.clip(y, -0.9, 0.9)
    mask = clipping_mask(clipped)
    assert mask.any() and np.all(np.abs(clipped[mask]) == 0.9)
    assert np.array_equal(mask, (np.abs(y) >= 0.9) & mask)  # only samples that were cut
    assert "clipping" in check_quality(clipped, FS, onset_index=1000).problems


def test_one_sample_peaks_are_not_clipping():
    t, y = record(MODES, noise=1e-4)
    assert not clipping_mask(y).any()


def test_coarse_quantisation_is_flagged():
    t, y = record(MODES, offset=0.2, noise=1e-4)
    step = 0.02
    quantised = np.round(y / step) * step
    assert quantisation_step(quantised) == pytest.approx(step, rel=1e-6)
    report = check_quality(quantised, FS, onset_index=1000)
    assert report.relative_step > 0.005 and "quantisation" in report.problems


def test_fine_quantisation_is_measured_not_flagged():
    t, y = record(MODES, noise=1e-4)
    quantised = np.round(y / 1e-5) * 1e-5
    report = check_quality(quantised, FS, onset_index=1000)
    assert report.quantisation_step == pytest.approx(1e-5, rel=1e-6) and "quantisation" not in report.problems


def test_unquantised_record_has_no_step():
    t, y = record(MODES, noise=1e-3)
    assert quantisation_step(y) == 0.0


def test_csv_rounded_record_is_not_flagged():
    t, y = record(MODES, noise=1e-3)
    rounded = np.array([float(f"{v:.8g}") for v in y])
    report = check_quality(rounded, FS, onset_index=1000)
    assert report.relative_step < 1e-7 and "quantisation" not in report.problems


@pytest.mark.parametrize("snr", [10.0, 20.0, 40.0])
def test_snr_estimate_of_a_ring_down(snr):
    t = np.arange(10000) / FS
    x = np.exp(-2 * np.pi * 0.005 * 120 * t) * np.sin(2 * np.pi * 120 * t)
    assert ringdown_snr_db(add_noise(x, snr, random_state=1), FS) == pytest.approx(snr, abs=1.5)


def test_snr_from_the_pre_trigger_noise():
    t, y = record(MODES, noise=1e-3)
    ring = y[1000:]
    truth = 10 * np.log10((np.mean(ring**2) - 1e-6) / 1e-6)
    assert check_quality(y, FS, onset_index=1000).snr_db == pytest.approx(truth, abs=0.5)


def test_low_snr_is_flagged():
    t, y = record(MODES, noise=0.2)
    assert "snr" in check_quality(y, FS, onset_index=1000).problems


@pytest.mark.parametrize("kind", ["white", "pink"])
def test_no_ring_down_found_in_noise(kind):
    rng = np.random.default_rng(7)
    x = rng.standard_normal(10000) if kind == "white" else pink_noise(10000, rng)
    report = check_quality(x, FS)
    assert not report.ringdown_found and "no_ringdown" in report.problems


def test_decay_of_a_ring_down_and_of_noise():
    t, y = record(MODES, onset=0.0, noise=1e-4)
    assert decay_db(y) > 30
    assert abs(decay_db(np.random.default_rng(0).standard_normal(10000))) < 1


def test_large_offset_is_flagged():
    t, y = record(MODES, offset=3.0, noise=1e-4)
    report = check_quality(y, FS, onset_index=1000)
    expected = 3.0 / np.max(np.abs(y[1000:] - 3.0))
    assert report.offset_ratio == pytest.approx(expected, rel=1e-3) and "offset" in report.problems


def test_pure_noise_has_no_signal_above_the_noise():
    rng = np.random.default_rng(8)
    x = 3.0 + rng.standard_normal(10000)
    x[:2000] = 3.0 + rng.standard_normal(2000)  # a "pre-trigger" of the same noise
    report = check_quality(x, FS, onset_index=2000)
    assert report.snr_db == -np.inf or report.snr_db < -10
    assert "-3" not in report.problems["snr"] and "dB" not in report.problems["snr"].split("(")[0]


def test_snr_without_pre_trigger_uses_the_peaks_floor():
    # a lightly damped mode ringing through the record hides the noise from the spectrum's own floor
    t = np.arange(20000) / FS
    x = np.exp(-2 * np.pi * 0.0005 * 120 * t) * np.sin(2 * np.pi * 120 * t)
    y = add_noise(x, 40, random_state=2)
    report = check_quality(y, FS, peaks=spectral_peaks(y, FS))
    assert report.snr_db == pytest.approx(40, abs=1.5)


def test_snr_without_pre_trigger_is_bounded_by_the_tail_where_the_floor_stands_on_the_modes():
    # a short hammer record of strongly ringing modes (5,446 samples at 50 kHz, 40 dB): the spectrum's floor
    # stands on their skirts, above the whole ring-down's power; the decay's quiet last tenth bounds the noise
    from sindy_impulse import impact_record
    from sindy_impulse.preprocessing.pipeline import prepare_record

    rec = impact_record([804.0, 2400.0, 4800.0], [0.01, 0.005, 0.006], fs=50000, duration=0.11,
                        pre_trigger=0.005, sensor="acceleration", snr_db=40, random_state=0)
    pre, raw = prepare_record(rec.y, fs=rec.fs)
    ring = pre.y[pre.impact.ringdown_index:]
    peaks = spectral_peaks(ring, rec.fs, refine=False)
    report = check_quality(raw, rec.fs, onset_index=pre.impact.onset_index, peaks=peaks)
    floor = np.sum(peaks.spectrum.floor) * peaks.spectrum.frequency_hz[1]
    assert floor > np.mean(ring**2)  # what the floor alone would say: no signal above the noise
    assert "snr" not in report.problems and 25 < report.snr_db < 40
    assert not report.noise_measured


def test_the_snr_measured_again_words_its_problem_again():
    t, y = record(MODES, noise=0.2)
    report = check_quality(y, FS, onset_index=1000)
    assert report.noise_measured and "snr" in report.problems
    better = report.with_snr(35.0)
    assert better.snr_db == 35.0 and "snr" not in better.problems and better.noise_measured
    assert better.with_snr(5.0).problems["snr"].startswith("low signal-to-noise ratio (5.0 dB)")
    assert better.offset_ratio == report.offset_ratio and better.n_peaks == report.n_peaks


def test_the_snr_measured_again_refuses_what_is_not_a_level_and_calls_a_negative_one_no_signal():
    t, y = record(MODES, noise=0.2)
    report = check_quality(y, FS, onset_index=1000)
    for bad, error in (("30", TypeError), (None, TypeError), (True, TypeError), (float("nan"), ValueError)):
        with pytest.raises(error, match="snr_db"):
            report.with_snr(bad)
    for quieter in (-np.inf, -11.0, 0.0):
        assert report.with_snr(quieter).problems["snr"].startswith("no signal above the noise")


def test_the_snr_takes_a_spectrum_already_computed_and_refuses_anything_else():
    t, y = record(MODES, onset=0.0, noise=1e-3)
    from sindy_impulse.preprocessing import ringdown_spectrum

    spectrum = ringdown_spectrum(y, FS)
    assert ringdown_snr_db(y, FS, spectrum=spectrum) == pytest.approx(ringdown_snr_db(y, FS))
    with pytest.raises(TypeError, match="spectrum"):
        ringdown_snr_db(y, FS, spectrum=np.ones(10))

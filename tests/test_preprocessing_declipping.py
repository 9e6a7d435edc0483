"""Clipped records (sindy_impulse.preprocessing.declipping, the saturated samples of quality and the
pipeline's use of them): repaired from the unclipped samples, no clipping harmonics, no mode lost."""

import warnings

import numpy as np
import pytest

from sindy_impulse import identify_modes, impact_record
from sindy_impulse.modes._clipped import clipping_product
from sindy_impulse.modes.kinds import Reason
from sindy_impulse.preprocessing import clipping_end, clipping_mask, preprocess, saturated_mask
from sindy_impulse.preprocessing.declipping import declip, declip_attempt

FS = 2000.0
T = np.arange(4000) / FS


def _two_modes():
    """A lightly damped 40 Hz mode and a 310 Hz mode (damping ratio 2 %) that decays while the first
    holds the sensor at its limit."""
    return (np.exp(-2 * T) * np.sin(2 * np.pi * 40 * T)
            + 0.3 * np.exp(-39 * T) * np.sin(2 * np.pi * 310 * T + 0.5))


def test_saturated_mask_counts_every_sample_at_a_clipped_level_also_alone():
    y = np.clip(np.exp(-T) * np.sin(2 * np.pi * 40 * T), -0.5, 0.7)  # the lower side is clipped more often
    mask = saturated_mask(y)
    assert np.array_equal(mask, (y == 0.7) | (y == -0.5))
    assert clipping_end(y) == int(np.flatnonzero(mask)[-1]) + 1
    ring = np.exp(-T) * np.sin(2 * np.pi * 40 * T) + 1e-3 * np.random.default_rng(0).standard_normal(T.size)
    assert not saturated_mask(ring).any() and clipping_end(ring) == 0


def test_a_limit_touched_one_sample_at_a_time_is_saturation():
    """A 570 Hz mode at 3.5 samples a period touches the limit one or two samples at a time."""
    ring = np.exp(-T) * (np.sin(2 * np.pi * 40 * T) + 0.6 * np.sin(2 * np.pi * 570 * T))
    y = np.clip(ring + 1e-3 * np.random.default_rng(0).standard_normal(T.size), -1.2, 1.2)
    assert saturated_mask(y).sum() == np.sum(np.abs(y) == 1.2) >= 5  # no run of 3 samples at the limit


def test_a_finely_quantised_record_touching_its_limit_one_sample_at_a_time_is_saturation():
    """An ADC record (fine steps) whose sensor clipped a high-frequency mode: runs of one or two samples at
    the limit, far more than a smooth crest puts at its top level."""
    ring = np.exp(-T) * (np.sin(2 * np.pi * 40 * T) + 0.6 * np.sin(2 * np.pi * 570 * T))
    step = 2.0**-14
    noisy = ring + 1e-3 * np.random.default_rng(0).standard_normal(T.size)
    y = np.round(np.clip(noisy, -1.2, 1.2) / step) * step
    mask = saturated_mask(y)
    assert mask.sum() == np.sum(np.abs(y) >= 1.2 - step / 2) >= 5 and not clipping_mask(y).any()
    assert not saturated_mask(np.round(noisy / step) * step).any()  # the same record unclipped


def test_a_coarsely_quantised_crest_is_not_saturation():
    """Eight-bit steps: the crests of a lightly damped mode reach the top level again and again (six
    samples there), and pass the levels just inside it as often -- not a limit."""
    t = np.arange(20000) / 10000.0
    ring = np.exp(-2 * np.pi * 500 * 2e-4 * t) * np.sin(2 * np.pi * 500 * t + 0.1)  # damping ratio 0.02 %
    y = np.round(ring * 127) / 127
    assert np.sum(y == y.max()) >= 5 and not saturated_mask(y).any()


def test_a_repair_whose_model_misses_the_decay_is_refused_where_the_noise_is_known():
    """A chirping mode (its frequency falls with its amplitude) is no sum of damped sinusoids: the fit's
    residual is far above the noise, and its error would be in every repaired sample."""
    amplitude = np.exp(-2 * T)
    phase = 2 * np.pi * (40 * T + 0.5 * (1 - np.exp(-4 * T)) / 4)  # 40.5 Hz at the hit, 40 Hz at the end
    noise = 1e-3
    noisy = amplitude * np.sin(phase) + noise * np.random.default_rng(4).standard_normal(T.size)
    y = np.clip(noisy, -0.6, 0.6)
    mask = np.abs(y) >= 0.6
    out = declip(y, FS, mask, 0, [40.0], [2.0])
    assert out is not None and out.noise_rms > 10 * noise  # no noise given: repaired regardless
    assert declip(y, FS, mask, 0, [40.0], [2.0], noise_rms=noise) is None
    assert declip(y, FS, mask, 0, [40.0], [2.0], noise_rms=out.noise_rms) is not None
    with pytest.raises(ValueError, match="noise_rms"):
        declip(y, FS, mask, 0, [40.0], [2.0], noise_rms=-1.0)


def test_declip_attempt_says_why_and_refuses_bad_arguments():
    y = np.clip(_two_modes() + 1e-3 * np.random.default_rng(1).standard_normal(T.size), -0.6, 0.6)
    mask = np.abs(y) >= 0.6
    assert declip_attempt(y, FS, np.zeros(T.size, bool), 0, [40.0], [2.0]) == (None, "nothing to repair")
    out, why = declip_attempt(y, FS, mask, 0, [40.0], [2.0])
    assert why == "repaired" and out.repaired == mask.sum()
    for start in (-1, T.size, 2.5):
        with pytest.raises((ValueError, TypeError), match="start"):
            declip_attempt(y, FS, mask, start, [40.0], [2.0])
    with pytest.raises(ValueError, match="one flag per sample"):
        declip_attempt(y, FS, mask[:10], 0, [40.0], [2.0])


def test_a_clipped_chirp_is_not_repaired_and_no_later_start_is_tried(monkeypatch):
    """The survey's preprocessing: the model's residual far above the noise of the record's last samples
    refuses the repair at the contact's end, and starting later cannot help; the decay starts after the
    clipping."""
    import sindy_impulse.preprocessing.pipeline as pipeline

    t = np.arange(8000) / FS
    phase = 2 * np.pi * (40 * t + 1.0 * (1 - np.exp(-6 * t)) / 6)  # 41 Hz at the hit, 40 Hz later
    noisy = np.exp(-3 * t) * np.sin(phase) + 1e-3 * np.random.default_rng(4).standard_normal(t.size)
    y = np.clip(noisy, -0.6, 0.6)
    tried = []
    attempt = pipeline.declip_attempt

    def spy(*args, **kwargs):
        out = attempt(*args, **kwargs)
        tried.append(out[1])
        return out

    monkeypatch.setattr(pipeline, "declip_attempt", spy)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pre = preprocess(y, fs=FS)
    assert tried == ["unexplained"]
    assert pre.impact.clipping == "skipped" and pre.impact.ringdown_index > np.flatnonzero(y == 0.6)[-1]


def test_a_mode_that_dies_while_the_sensor_clips_is_recovered():
    clean = _two_modes()
    y = np.clip(clean + 1e-3 * np.random.default_rng(1).standard_normal(T.size), -0.6, 0.6)
    mask = np.abs(y) >= 0.6
    out = declip(y, FS, mask, 0, [40.0], [2.0])  # only the tail's mode given
    assert out is not None and out.repaired == mask.sum() and out.consistent >= 0.9
    k = int(np.argmin(np.abs(out.frequency_hz - 310.0)))
    assert abs(out.frequency_hz[k] / (310 * np.sqrt(1 - 0.02**2)) - 1) < 1e-3
    assert abs(out.decay_rate[k] / 39.0 - 1) < 0.05
    assert np.abs(out.y - clean).max() < 0.02 and np.array_equal(out.y[~mask], y[~mask])


def test_clipping_harmonics_are_not_taken_for_modes():
    clean = np.exp(-2 * T) * np.sin(2 * np.pi * 40 * T)
    y = np.clip(clean + 1e-3 * np.random.default_rng(2).standard_normal(T.size), -0.4, 0.4)
    out = declip(y, FS, np.abs(y) >= 0.4, 0, [40.0], [2.0])
    assert out is not None and out.extra_hz.size == 0 and out.frequency_hz.size == 1
    assert np.abs(out.y - clean).max() < 0.01


def test_a_window_that_is_not_a_free_decay_is_not_repaired():
    y = np.clip(_two_modes() + np.where(T < 0.05, 3 * (0.05 - T), 0.0), -0.6, 0.6)  # a hit still under way
    y = y + 1e-3 * np.random.default_rng(3).standard_normal(T.size)
    y = np.clip(y, -0.6, 0.6)
    assert declip(y, FS, np.abs(y) >= 0.6, 0, [40.0], [2.0]) is None
    assert declip(y, FS, np.zeros(T.size, bool), 0, [40.0], [2.0]) is None  # nothing clipped
    with pytest.raises(ValueError, match="one flag per sample"):
        declip(y, FS, np.ones(3, bool), 0, [40.0], [2.0])


CASES = [("displacement", 0.3, 0), ("displacement", 0.5, 1), ("velocity", 0.3, 2), ("velocity", 0.5, 3)]


def _record(sensor, clip, seed):
    """Two modes, the 410 Hz one (damping ratio 2 %) decaying by 2-12 e-folds while the sensor clips."""
    return impact_record([120.0, 410.0], [0.004, 0.02], fs=5000, duration=1.0, snr_db=50, clip=clip,
                         sensor=sensor, random_state=seed)


@pytest.mark.parametrize(("sensor", "clip", "seed"), CASES)
def test_preprocess_repairs_a_clipped_impact_record_and_finds_no_harmonic(sensor, clip, seed):
    rec = _record(sensor, clip, seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pre = preprocess(rec.y, fs=rec.fs)
    assert pre.impact.clipping == "repaired" and pre.impact.saturated > 0
    assert "clipping" in pre.quality.problems  # the raw record's quality is reported
    np.testing.assert_allclose(pre.peaks.frequency_hz, rec.modes.damped_frequency_hz, rtol=2e-3)
    start = pre.impact.ringdown_index
    clean = rec.y_clean[start:] - np.mean(rec.y_clean[start:])
    repaired = pre.y[start:] - np.mean(pre.y[start:])
    assert np.abs(repaired - clean).max() < 0.05 * np.abs(clean).max()


@pytest.mark.parametrize(("sensor", "clip", "seed"), [("velocity", 0.5, 5)]
                         + [pytest.param(*c, marks=pytest.mark.slow) for c in CASES[::2]])
def test_identify_modes_on_clipped_records_gives_the_modes_and_no_clipping_harmonic(sensor, clip, seed):
    rec = _record(sensor, clip, seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        survey = identify_modes(rec.y, fs=rec.fs)
    found = np.array([(m.frequency_hz, m.damping_ratio) for m in survey.modes])
    assert found.shape == (2, 2)  # no harmonic or intermodulation product of the clipping
    np.testing.assert_allclose(found[:, 0], rec.modes.frequency_hz, rtol=3e-3)
    np.testing.assert_allclose(found[:, 1], rec.modes.damping_ratio, rtol=0.1)


def test_clipping_harmonics_given_as_start_values_are_dropped():
    clean = np.exp(-0.1 * T) * np.sin(2 * np.pi * 10.6 * T)  # clipped to the record's end
    y = np.clip(clean + 1e-3 * np.random.default_rng(4).standard_normal(T.size), -0.8, 0.8)
    out = declip(y, FS, np.abs(y) >= 0.8, 0, [10.6, 31.8, 53.0], [0.1, 0.1, 0.1], prune=True)
    assert out is not None and out.frequency_hz.size == 1 and abs(out.frequency_hz[0] - 10.6) < 0.01
    np.testing.assert_allclose(np.sort(out.dropped_hz), [31.8, 53.0], atol=1.0)
    assert np.abs(out.y - clean).max() < 0.01


def test_a_record_clipped_to_its_end_is_repaired_and_gives_no_harmonic():
    rec = impact_record(10.6, 0.0015, fs=1000, duration=1.3, sensor="displacement", snr_db=50, clip=0.8,
                        random_state=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pre = preprocess(rec.y, fs=rec.fs)
    assert pre.impact.clipping == "repaired" and saturated_mask(rec.y)[-200:].any()
    np.testing.assert_allclose(pre.peaks.frequency_hz, rec.modes.damped_frequency_hz, rtol=2e-3)


def test_the_survey_rejects_the_clipping_products_with_evidence():
    rec = impact_record(10.6, 0.0015, fs=1000, duration=1.3, sensor="displacement", snr_db=50, clip=0.8,
                        random_state=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        survey = identify_modes(rec.y, fs=rec.fs)
    assert len(survey.modes) == 1 and abs(survey.modes[0].frequency_hz / 10.6 - 1) < 3e-3
    assert abs(survey.modes[0].damping_ratio / 0.0015 - 1) < 0.1
    products = [r for r in survey.rejected if r.evidence.get("clipping_product")]
    assert products and all(r.band_hz is not None for r in products)
    for r in products:  # odd harmonics of the clipped mode
        n = r.evidence["frequency_hz"] / survey.modes[0].frequency_hz
        assert abs(n / round(n) - 1) < 5e-3 and round(n) % 2 == 1 and r.evidence["combination_offset"] < 5e-3
    assert any("repaired from the unclipped samples" in note for note in survey.notes)
    assert all(r.code is Reason.CLIPPING_PRODUCT for r in products)  # programs decide on the code


def _clipped_to_the_end(freqs, damping, **kw):
    """A ring-down clipped on most of its samples up to its last: no repair fits, nothing follows the
    clipping (the impact's clipping is "kept")."""
    rec = impact_record(freqs, damping, fs=1000, duration=0.2, pre_trigger=0.01, clip=0.3, snr_db=50,
                        random_state=0, sensor="displacement", **kw)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        survey = identify_modes(rec.y, fs=rec.fs)
    return rec, survey, [str(w.message) for w in caught]


def test_a_record_that_stays_clipped_names_its_clipping_harmonics_not_modes():
    """Clipped on 141 of its 196 free-decay samples up to the last one: the clipping's odd harmonics (3, 5,
    7 and 9 times 50 Hz, the ninth close to the Nyquist frequency) were reported as four modes with damping
    ratios. They are rejected as the clipping's products, and the note says the record could not be
    repaired and what that does to the damping ratio."""
    rec, survey, said = _clipped_to_the_end(50.0, 0.01)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert preprocess(rec.y, fs=rec.fs).impact.clipping == "kept"
    assert [round(m.frequency_hz) for m in survey.modes] == [50]
    products = [r for r in survey.rejected if r.code is Reason.CLIPPING_PRODUCT]
    assert sorted(r.evidence["combination"] for r in products) == [f"{k} x 49.998 Hz" for k in (3, 5, 7, 9)]
    assert all("stays clipped" in r.reason and r.evidence["clipping_product"] for r in products)
    assert any("could not be repaired" in w and "damping ratios" in w for w in said)


def test_a_mode_off_the_harmonics_of_a_record_that_stays_clipped_is_kept():
    """The same clipped record with a second mode at 137 Hz, on no harmonic of 50 Hz: still a mode."""
    _, survey, _ = _clipped_to_the_end([50.0, 137.0], [0.01, 0.01], amplitudes=[1.0, 0.5])
    found = [m.frequency_hz for m in survey.modes]
    assert any(abs(f / 137.0 - 1) < 3e-3 for f in found) and any(abs(f / 50.0 - 1) < 3e-3 for f in found)
    assert not any(r.code is Reason.CLIPPING_PRODUCT and abs(r.evidence["frequency_hz"] / 137 - 1) < 0.01
                   for r in survey.rejected)


def test_clipping_product_folds_about_nyquist_and_bounds_the_amplitude():
    one = [(50.0, 0.0, 1.0)]
    assert clipping_product(149.99, 0.5, 0.1, [(50.0, 0.001, 1.0)], fs=1000.0) == (
        "3 x 50 Hz", pytest.approx(0.01, abs=1e-9))
    assert clipping_product(250.0, 0.5, 0.1, one, fs=1000.0)[0] == "5 x 50 Hz"  # the lowest of 5, 15, ...
    assert clipping_product(600.0, 0.5, 0.1, [(700.0, 0.0, 1.0)], fs=2000.0) == ("2 x 700 Hz", 0.0)
    assert clipping_product(150.0, 0.5, 0.6, one, fs=1000.0) is None  # beyond 1.5 / 3 of its parent
    assert clipping_product(152.0, 0.5, 0.1, one, fs=1000.0) is None  # 2 Hz off the third
    assert clipping_product(152.0, 0.5, 0.1, [(50.0, 0.4, 1.0)], fs=1000.0)[0] == "3 x 50 Hz"  # 3 x 3 x 0.4


def test_clipping_product_of_two_components_names_the_lowest_order_and_bounds_by_the_weaker():
    two = [(255.0, 0.01, 1.0), (44.0, 0.01, 0.2)]
    assert clipping_product(343.0, 1.0, 0.02, two, fs=1000.0)[0] == "1 x 255 Hz + 2 x 44 Hz"
    assert clipping_product(343.0, 1.0, 0.11, two, fs=1000.0) is None  # over 1.5 / 3 of the weaker (0.2)
    # 350 Hz lies 1 Hz from 9 x 44 + 255 Hz folded (order 10): past the pair orders that name a product
    assert clipping_product(350.0, 1.0, 0.02, two, fs=1000.0) is None
    # ... and 8 Hz from 2 x 255 + 3 x 44 Hz folded, within 3 standard deviations when the two are that loose
    assert clipping_product(350.0, 1.0, 0.02, [(255.0, 0.5, 1.0), (44.0, 0.5, 0.2)], fs=1000.0)[0] == (
        "2 x 255 Hz + 3 x 44 Hz")


def test_two_modes_clipped_on_half_the_samples_to_the_end_are_repaired():
    rec = impact_record([12.0, 47.0], [0.0005, 0.002], fs=2048, duration=3, sensor="displacement", snr_db=50,
                        clip=0.3, random_state=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pre = preprocess(rec.y, fs=rec.fs)
    assert saturated_mask(rec.y).mean() > 0.4 and pre.impact.clipping == "repaired"
    assert pre.declipped.dropped_hz.size > 5  # the clipping's products, dropped
    np.testing.assert_allclose(pre.peaks.frequency_hz, rec.modes.damped_frequency_hz, rtol=1e-3)
    np.testing.assert_allclose(pre.peaks.damping_ratio, rec.modes.damping_ratio, rtol=0.1)


def test_a_record_that_stays_clipped_names_intermodulation_products_and_keeps_its_modes():
    """Two modes (41 and 285 Hz) clipped at 28 % of the peak up to the record's end: the clipping's
    harmonics of the strong one and its intermodulation products with the other (e.g. 3 x 285 - 2 x 41 Hz,
    folded about the Nyquist frequency) are rejected rows, and both modes stay."""
    rec = impact_record([40.78401674206438, 284.71247662472615],
                        [0.0018209299698003518, 0.0039650300927774745], [1.0, 0.4728363739307891], fs=1000,
                        duration=0.23804731641328025, pre_trigger=0.01, clip=0.2777394460833474,
                        snr_db=41.78911331865627, random_state=9, sensor="displacement")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        survey = identify_modes(rec.y, fs=rec.fs)
    found = [m.frequency_hz for m in survey.modes]
    for f in rec.modes.frequency_hz:
        assert any(abs(g / f - 1) < 3e-3 for g in found)
    products = [r.evidence for r in survey.rejected if r.code is Reason.CLIPPING_PRODUCT]
    assert any(" - " in e["combination"] or " + " in e["combination"] for e in products)
    assert not any(abs(e["frequency_hz"] / f - 1) < 3e-3 for e in products for f in rec.modes.frequency_hz)

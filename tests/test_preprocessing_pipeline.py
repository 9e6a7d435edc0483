"""preprocess(), the transformers and the input contract (sindy_impulse.preprocessing)."""

import warnings

import numpy as np
import pytest
from preprocessing_records import FS, envelope_fit, half_sine, record
from sklearn.base import clone
from sklearn.pipeline import make_pipeline

from sindy_impulse.exceptions import DataWarning
from sindy_impulse.preprocessing import (
    BandExtractor,
    ImpactTrimmer,
    OffsetRemover,
    extract_band,
    find_impact,
    preprocess,
    response_onset,
    spectral_peaks,
)

MODES = [(120.0, 0.005, 1.0), (410.0, 0.003, 0.5), (590.0, 0.01, 0.3)]  # 8.5 samples per period and up


@pytest.fixture(scope="module")
def raw():
    return record(MODES, onset=0.2, offset=0.4, noise=1e-3)


def test_preprocess_end_to_end(raw):
    t, y = raw
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        pre = preprocess(y, t)
    assert pre.impact.onset_index == pytest.approx(1000, abs=3)
    assert pre.offset.method == "pre_trigger" and pre.offset.value == pytest.approx(0.4, abs=1e-3)
    assert len(pre.bands) == 3 and pre.skipped == []
    for (f, zeta, _), band in zip(MODES, pre.bands):
        f_hat, sigma_hat = envelope_fit(band.y, band.fs, f)
        assert f_hat == pytest.approx(f * np.sqrt(1 - zeta**2), rel=1e-4)
        assert sigma_hat == pytest.approx(zeta * 2 * np.pi * f, rel=0.01)
        assert band.t[0] > pre.impact.ringdown_time


def test_preprocess_repr_says_what_was_done(raw):
    text = repr(preprocess(raw[1], fs=FS))
    for words in ("onset", "pre-trigger", "decimation", "trimmed", "SNR", "3 peak(s)"):
        assert words in text


def test_preprocess_overrides(raw):
    t, y = raw
    pre = preprocess(y, fs=FS, onset=900, offset=0.4, bands=[(100.0, 140.0)], samples_per_period=12)
    assert pre.impact.source == "given" and pre.impact.onset_index == 900
    assert pre.offset.method == "given" and pre.peaks.band_hz == [(100.0, 140.0)]
    assert len(pre.bands) == 1 and pre.bands[0].decimation == int(FS / np.sqrt(100 * 140) // 12)


def test_preprocess_with_force_and_double_hit():
    n = int(3 * FS)
    force = half_sine(n, 1000, 10, 40.0) + half_sine(n, 1100, 8, 10.0)
    t, y = record(MODES, onset=0.2, noise=1e-3)
    with pytest.warns(DataWarning, match="double hit"):
        pre = preprocess(y, fs=FS, force=force)
    assert pre.impact.double_hit and pre.impact.ringdown_index >= 1108
    assert all(b.start_index > pre.impact.ringdown_index for b in pre.bands)


def test_preprocess_resamples_a_band_with_few_samples_per_period():
    # 1500 Hz at 5 kHz: 3.3 samples per period (below the analysers' fs / 2.56): resampled, not refused
    t, y = record([(120.0, 0.005, 1.0), (1500.0, 0.005, 1.0)], noise=1e-3)
    pre = preprocess(y, fs=FS)
    assert len(pre.bands) == 2 and not pre.skipped
    low, high = sorted(pre.bands, key=lambda b: b.band_hz[0])
    assert low.upsampling == 1 and high.upsampling == 5 and high.samples_per_period >= 16
    assert high.record_fs == FS and high.fs == 5 * FS


def test_preprocess_warns_on_pure_noise():
    y = np.random.default_rng(0).standard_normal(10000)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        pre = preprocess(y, fs=FS)
    assert any("no ring-down found" in str(w.message) and w.category is DataWarning for w in caught)
    assert len(pre.bands) == 0


def test_transformers_in_a_pipeline(raw):
    t, y = raw
    pipe = make_pipeline(OffsetRemover(fs=FS), ImpactTrimmer(fs=FS), BandExtractor(fs=FS, band_hz=(380, 440)))
    out = pipe.fit_transform(y)
    assert out.ndim == 1 and out.size == pipe[-1].band_.y.size
    f_hat, _ = envelope_fit(out, pipe[-1].fs_out_, 410.0)
    assert f_hat == pytest.approx(410.0 * np.sqrt(1 - 0.003**2), rel=1e-4)


def test_transformers_keep_two_d_input(raw):
    t, y = raw
    col = y[:, None]
    assert OffsetRemover(fs=FS).fit_transform(col).shape == col.shape
    assert ImpactTrimmer(fs=FS).fit_transform(col).shape[1] == 1


def test_impact_trimmer_reads_a_force_column(raw):
    t, y = raw
    force = half_sine(y.size, 1000, 10)
    trimmer = ImpactTrimmer(fs=FS).fit(np.column_stack([y, force]))
    assert trimmer.impact_.source == "force" and trimmer.n_features_in_ == 2


def test_transformer_parameters_untouched_and_checked_at_fit():
    est = BandExtractor(fs=-1.0, method="wavelet")
    assert clone(est).get_params()["method"] == "wavelet"  # stored as given
    with pytest.raises(ValueError, match="BandExtractor: fs must be a number in"):
        est.fit(np.zeros(1000))
    with pytest.raises(ValueError, match="OffsetRemover: fs must be"):
        OffsetRemover().fit(np.zeros(1000))


# ---------------------------------------------------------------------------------------------- bad input
def test_nan_is_refused(raw):
    y = raw[1].copy()
    y[50] = np.nan
    with pytest.raises(ValueError, match=r"y contains 1 non-finite value\(s\) \(NaN first at index \(50,"):
        preprocess(y, fs=FS)
    with pytest.raises(ValueError, match="non-finite"):
        response_onset(y)


def test_t_not_increasing_is_refused(raw):
    t, y = raw
    t = t.copy()
    t[10] = t[9]
    with pytest.raises(ValueError, match="t must be strictly increasing"):
        preprocess(y, t)


def test_t_not_uniform_is_refused(raw):
    t, y = raw
    with pytest.raises(ValueError, match="not uniformly sampled"):
        preprocess(y, t**1.01)


def test_t_and_fs_disagreeing_are_refused(raw):
    t, y = raw
    with pytest.raises(ValueError, match="disagree"):
        preprocess(y, t, fs=2 * FS)


def test_sampling_missing_is_refused(raw):
    with pytest.raises(ValueError, match="give the sampling of y"):
        preprocess(raw[1])


def test_too_short_record_is_refused():
    with pytest.raises(ValueError, match="y has 20 samples; at least 64 are needed"):
        preprocess(np.ones(20), fs=FS)
    with pytest.raises(ValueError, match="at least 64"):
        spectral_peaks(np.ones(20), FS)


@pytest.mark.parametrize("fs", [0.0, -5.0, np.inf, np.nan])
def test_non_positive_fs_is_refused(raw, fs):
    with pytest.raises(ValueError, match="fs \\(sampling rate\\) must be a positive finite number"):
        preprocess(raw[1], fs=fs)
    with pytest.raises(ValueError, match="positive finite"):
        find_impact(raw[1], fs)


def test_fs_of_wrong_type_is_refused(raw):
    with pytest.raises(TypeError, match="fs \\(sampling rate\\) must be a number"):
        extract_band(raw[1], "5 kHz", (100, 140))


def test_two_channels_are_refused(raw):
    with pytest.raises(ValueError, match="y must be one channel"):
        preprocess(np.column_stack([raw[1], raw[1]]), fs=FS)


def test_a_band_of_few_samples_per_period_is_resampled_not_refused():
    t, y = record([(820.0, 0.003, 1.0)], noise=1e-4)
    band = extract_band(y, FS, (780.0, 860.0), start=int(0.2 * FS) + 5)  # 6.1 samples per period at FS
    assert band.upsampling == 3 and band.decimation == 1
    assert band.samples_per_period == pytest.approx(3 * FS / np.sqrt(780.0 * 860.0))
    assert np.allclose(np.diff(band.t), 1 / (3 * FS))

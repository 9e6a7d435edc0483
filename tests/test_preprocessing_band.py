"""Zero-phase band-pass, decimation, transient trim and record end (sindy_impulse.preprocessing)."""

import numpy as np
import pytest
from preprocessing_records import FS, envelope_fit, modes_response

from sindy_impulse.preprocessing import (
    bandpass,
    decimation_factor,
    extract_band,
    filter_gain,
    peak_bands,
    record_end,
    transient_samples,
)


def _mode(f, zeta, duration=3.0, noise=1e-4, others=(), seed=0):
    t = np.arange(int(duration * FS)) / FS
    y = modes_response(t, [(f, zeta, 1.0), *others], phase=0.3)
    return y + noise * np.random.default_rng(seed).standard_normal(t.size)


def _truth(f, zeta):
    return f * np.sqrt(1 - zeta**2), zeta * 2 * np.pi * f


@pytest.mark.parametrize("method", ["fft", "butter"])
@pytest.mark.parametrize("zeta", [0.0005, 0.003, 0.01, 0.03])
def test_single_mode_frequency_and_decay_kept(method, zeta):
    f = 150.0
    (band,) = peak_bands([f], [2 * zeta * f], FS)
    out = extract_band(_mode(f, zeta), FS, band, method=method)
    f_hat, sigma_hat = envelope_fit(out.y, out.fs, f)
    f_d, sigma = _truth(f, zeta)
    assert abs(f_hat / f_d - 1) < 1e-4
    assert abs(sigma_hat / sigma - 1) < 0.01


def test_mode_next_to_others_kept():
    f, zeta = 150.0, 0.003
    others = [(95.0, 0.002, 1.0), (230.0, 0.005, 1.0)]
    bands = peak_bands([95.0, f, 230.0], [0.4, 2 * zeta * f, 2.3], FS)
    out = extract_band(_mode(f, zeta, others=others), FS, bands[1])
    f_hat, sigma_hat = envelope_fit(out.y, out.fs, f)
    f_d, sigma = _truth(f, zeta)
    assert abs(f_hat / f_d - 1) < 1e-4 and abs(sigma_hat / sigma - 1) < 0.01


def test_decimation_and_time_vector():
    out = extract_band(_mode(150.0, 0.003), FS, (136.4, 165.0), t0=2.0)
    assert out.decimation == 2 and out.fs == FS / 2
    assert 16 <= out.samples_per_period < 32
    assert out.t[0] == pytest.approx(2.0 + out.start_index / FS)
    assert np.allclose(np.diff(out.t), 2 / FS)
    assert out.y.size == out.t.size == out.envelope.size


def test_filter_transient_trimmed_from_the_start():
    band = (136.4, 165.0)
    out = extract_band(_mode(150.0, 0.003), FS, band, start=100)
    assert out.trimmed_start == transient_samples(FS, band) and out.start_index == 100 + out.trimmed_start


def test_record_ends_where_the_mode_meets_the_noise():
    f, zeta, noise = 150.0, 0.003, 1e-3
    band = (136.4, 165.0)
    out = extract_band(_mode(f, zeta, duration=4.0, noise=noise), FS, band)
    sigma_band = noise * np.sqrt(2 * (band[1] - band[0]) * 0.86 / FS)  # white noise through the filter
    amplitude_at_end = np.exp(-_truth(f, zeta)[1] * out.stop_index / FS)
    local_snr_db = 20 * np.log10(amplitude_at_end / (np.sqrt(2) * sigma_band))
    assert out.end_reason == "noise floor"
    assert 8.0 < local_snr_db < 14.0  # 10 dB asked
    assert out.noise_rms == pytest.approx(sigma_band, rel=0.2)


def test_record_end_never_reached_keeps_everything():
    env = np.ones(1000)
    assert record_end(env, 1e-3, fs=1000.0, frequency_hz=50.0, bandwidth_hz=10.0) == 1000


def test_no_end_at_noise_when_asked():
    out = extract_band(_mode(150.0, 0.01, noise=1e-2), FS, (136.4, 165.0), end_snr_db=None)
    assert out.end_reason == "filter transient" and out.trimmed_end == out.trimmed_start


def test_bandpass_methods_agree_in_the_pass_band():
    t = np.arange(10000) / FS
    y = np.sin(2 * np.pi * 150 * t) + np.sin(2 * np.pi * 600 * t)
    fft, butter = (bandpass(y, FS, (120, 190), method=m) for m in ("fft", "butter"))
    inner = slice(2000, -2000)
    assert np.max(np.abs(fft[inner] - np.sin(2 * np.pi * 150 * t[inner]))) < 1e-3
    assert np.max(np.abs(butter[inner] - fft[inner])) < 0.05


def test_a_mode_with_few_samples_per_period_keeps_its_frequency_and_decay_when_resampled():
    # 720 Hz at 5 kHz: 6.9 samples per period, below min_samples_per_period: the band is resampled x3
    band = extract_band(_mode(720.0, 0.003), FS, (690.0, 750.0), min_samples_per_period=8)
    assert band.upsampling == 3 and band.fs == 3 * FS
    crossings = np.flatnonzero(np.diff(np.sign(band.y)) > 0)
    frequency = (crossings.size - 1) / (band.t[crossings[-1]] - band.t[crossings[0]])
    assert frequency == pytest.approx(720.0 * np.sqrt(1 - 0.003**2), rel=2e-4)
    decay = -np.polyfit(band.t, np.log(band.envelope), 1)[0]
    assert decay == pytest.approx(2 * np.pi * 720.0 * 0.003, rel=0.02)


def test_resampling_a_band_is_exact_interpolation():
    from sindy_impulse.preprocessing.band import resample_band

    rate, f = 1000.0, 370.0  # 2.7 samples per period
    k = np.arange(2000)
    z = np.exp(2j * np.pi * f * k / rate) * np.exp(-0.5 * k / rate)
    signal, envelope, position = resample_band(z, 200, 1800, rate, 360.0, 6)
    assert position[0] == 200 and np.allclose(np.diff(position), 1 / 6)
    truth = np.exp(2j * np.pi * f * position / rate) * np.exp(-0.5 * position / rate)
    np.testing.assert_allclose(signal, truth.real, atol=1e-9)
    np.testing.assert_allclose(envelope, np.abs(truth), rtol=1e-9)


def test_a_band_above_the_analysers_limit_is_tried_with_a_warning():
    from sindy_impulse.exceptions import DataWarning

    with pytest.warns(DataWarning, match="fs / 2.56"):
        band = extract_band(_mode(2100.0, 0.005), FS, (2000.0, 2200.0))
    assert band.upsampling == 7 and band.samples_per_period >= 16


def test_decimation_factor_keeps_the_target():
    assert decimation_factor(10000.0, 100.0, samples_per_period=12) == 8
    assert decimation_factor(1000.0, 100.0) == 1


def test_band_too_short_after_trimming_is_refused():
    with pytest.raises(ValueError, match="periods remain"):
        extract_band(_mode(150.0, 0.003, duration=0.1), FS, (148.0, 152.0))


@pytest.mark.parametrize("band", [(160, 140), (0, 100), (100, 2500), (1, 2, 3), None])
def test_bad_band_is_refused(band):
    with pytest.raises(ValueError, match="band_hz"):
        extract_band(_mode(150.0, 0.003), FS, band)


def test_bad_start_is_refused():
    with pytest.raises(ValueError, match="start must be"):
        extract_band(_mode(150.0, 0.003), FS, (136.4, 165.0), start=10**6)


def test_the_fft_band_pass_weights_only_positive_frequencies_by_the_filter_gain():
    """The analytic band-pass equals the full two-sided construction: the positive frequencies doubled and
    weighted by ``filter_gain``, the rest zero (the gain is evaluated on the band's support only)."""
    from scipy.fft import next_fast_len

    fs = 2000.0
    x = np.random.default_rng(3).normal(size=1001)
    for band in [(40.0, 60.0), (900.0, 990.0)]:
        pad = transient_samples(fs, band)
        n_fft = next_fast_len(x.size + 2 * pad)
        freq = np.fft.fftfreq(n_fft, 1.0 / fs)
        gain = filter_gain(freq, fs, band) * np.where(freq > 0, 2.0, 0.0)
        expected = np.fft.ifft(np.fft.fft(x, n_fft) * gain)[: x.size]
        got = bandpass(x, fs, band, analytic=True)
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-12 * np.abs(expected).max())


def test_a_given_analytic_signal_gives_the_same_band():
    """A caller that has the band-pass already hands it over: the same band signal, bit for bit."""
    y = _mode(150.0, 0.003)
    band = (136.4, 165.0)
    z = bandpass(y[40:], FS, band, analytic=True)
    own, given = extract_band(y, FS, band, start=40), extract_band(y, FS, band, start=40, analytic_signal=z)
    for name in ("y", "t", "envelope"):
        assert np.array_equal(getattr(own, name), getattr(given, name))
    assert (own.stop_index, own.snr_db, own.end_reason) == (given.stop_index, given.snr_db, given.end_reason)
    with pytest.raises(ValueError, match="analytic_signal"):
        extract_band(y, FS, band, start=40, analytic_signal=z[1:])

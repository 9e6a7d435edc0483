"""Spectral peaks, noise floor and bands (sindy_impulse.preprocessing.spectrum)."""

import numpy as np
import pytest
from preprocessing_records import FS, modes_response, pink_noise

from sindy_impulse.exceptions import DataWarning
from sindy_impulse.preprocessing import noise_floor, peak_bands, ringdown_spectrum, spectral_peaks

CASES = {
    "one": [(150.0, 0.003, 1.0)],
    "two": [(95.0, 0.002, 1.0), (640.0, 0.008, 0.6)],
    "three": [(120.0, 0.005, 1.0), (410.0, 0.003, 0.5), (980.0, 0.01, 0.3)],
    "four": [(80.0, 0.002, 1.0), (210.0, 0.005, 0.7), (505.0, 0.005, 0.5), (1130.0, 0.01, 0.5)],
    "close pair 3 %": [(150.0, 0.003, 1.0), (154.5, 0.003, 1.0)],
}


def _ringdown(modes, noise=1e-3, duration=3.0, seed=0):
    t = np.arange(int(duration * FS)) / FS
    rng = np.random.default_rng(seed)
    return modes_response(t, modes, phase=rng.uniform(0, 2 * np.pi)) + noise * rng.standard_normal(t.size)


@pytest.mark.parametrize("name", CASES)
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_peaks_at_the_mode_frequencies(name, seed):
    modes = CASES[name]
    peaks = spectral_peaks(_ringdown(modes, seed=seed), FS)
    expected = np.array([f * np.sqrt(1 - z**2) for f, z, _ in modes])
    assert len(peaks) == len(modes)
    half_power = np.array([2 * z * f for f, z, _ in modes])
    assert np.all(np.abs(peaks.frequency_hz - expected) < np.maximum(0.25 * half_power, 0.1))


def test_close_pair_bands_separate_the_modes():
    peaks = spectral_peaks(_ringdown(CASES["close pair 3 %"]), FS)
    (lo1, hi1), (lo2, hi2) = peaks.band_hz
    assert hi1 <= lo2 + 1e-9  # no overlap: they meet at the geometric midpoint
    assert hi1 == pytest.approx(np.sqrt(150.0 * 154.5), rel=2e-3)
    assert lo1 < 150.0 - 0.45 and hi2 > 154.5 + 0.46  # each holds its half-power band


def test_bands_hold_several_half_power_widths():
    peaks = spectral_peaks(_ringdown(CASES["three"]), FS)
    for f, w, (lo, hi) in zip(peaks.frequency_hz, peaks.half_power_width_hz, peaks.band_hz):
        assert lo < f - 2.5 * w and hi > f + 2.5 * w
        assert lo / f == pytest.approx(1 / (hi / f), rel=1e-9)  # symmetric in log frequency


def test_half_power_width_estimates_the_damping():
    zeta, f = 0.01, 300.0
    peaks = spectral_peaks(_ringdown([(f, zeta, 1.0)], noise=1e-5), FS)
    assert peaks.half_power_width_hz[0] == pytest.approx(2 * zeta * f, rel=0.15)


@pytest.mark.parametrize("kind", ["white", "pink"])
def test_no_peaks_on_pure_noise_records(kind):
    rng = np.random.default_rng(2024 if kind == "white" else 2025)
    found = 0
    for i in range(50):
        n = [1000, 4000, 20000][i % 3]
        x = rng.standard_normal(n) if kind == "white" else pink_noise(n, rng)
        found += len(spectral_peaks(x, FS))
    assert found == 0


def test_noise_floor_follows_white_noise_level():
    rng = np.random.default_rng(3)
    spectrum = ringdown_spectrum(0.1 * rng.standard_normal(20000), FS)
    assert np.median(spectrum.floor) == pytest.approx(2 * 0.01 / FS, rel=0.1)


def test_noise_floor_ignores_peaks():
    rng = np.random.default_rng(4)
    psd = rng.exponential(1.0, 40000)
    psd[10000:10040] += 1e6
    floor = noise_floor(psd)
    assert floor[10020] == pytest.approx(1.0, rel=0.3)


def test_n_modes_keeps_the_strongest():
    peaks = spectral_peaks(_ringdown(CASES["three"]), FS, n_modes=2)
    assert len(peaks) == 2 and 980.0 * 0.99 > peaks.frequency_hz.max()


def test_n_modes_larger_than_found_warns():
    with pytest.warns(DataWarning, match="only 1 peak"):
        spectral_peaks(_ringdown(CASES["one"]), FS, n_modes=3)


def test_given_bands_override_detection():
    bands = [(100.0, 140.0), (380.0, 440.0)]
    peaks = spectral_peaks(_ringdown(CASES["three"]), FS, bands=bands)
    assert peaks.band_hz == bands and np.isnan(peaks.threshold_db)
    assert peaks.frequency_hz == pytest.approx([120.0, 410.0], abs=0.2)


def test_given_bands_and_other_n_modes_are_refused():
    with pytest.raises(ValueError, match="n_modes=3 but 1 band"):
        spectral_peaks(_ringdown(CASES["one"]), FS, bands=[(100, 200)], n_modes=3)


@pytest.mark.parametrize("band", [(200, 100), (-1, 10), (10, 2600), "ab", (1, 2, 3)])
def test_bad_given_band_is_refused(band):
    with pytest.raises(ValueError, match=r"bands\[0\]"):
        spectral_peaks(_ringdown(CASES["one"]), FS, bands=[band])


def test_peak_bands_clip_at_nyquist():
    (lo, hi), = peak_bands([2400.0], [5.0], 5000.0)
    assert hi < 2500.0 and lo == pytest.approx(2400.0 / 1.1)


@pytest.mark.parametrize(("n", "pad"), [(60, 1), (100, 4), (201, 8)])
def test_noise_floor_of_a_spectrum_too_short_for_a_window_is_its_lower_quartile(n, pad):
    from sindy_impulse.preprocessing import noise_floor

    psd = np.random.default_rng(0).exponential(2.0, n)
    floor = noise_floor(psd, pad_factor=pad)
    assert floor.shape == (n,) and np.all(floor == floor[0])
    assert 0.2 < floor[0] < 2.0  # the lower quartile of an exponential of mean 2 is 0.58


@pytest.mark.parametrize("seed", range(4))
def test_candidate_peaks_measures_prominence_on_the_high_maxima_only_with_the_same_answer(seed):
    """Prominences are measured for the local maxima high enough and in range only (a long spectrum holds
    thousands of noise ripples): the same peaks and heights as measuring every maximum's."""
    from scipy.signal import find_peaks

    from sindy_impulse.preprocessing.spectrum import (
        _noise_prominence_db,
        candidate_peaks,
        peak_threshold_db,
        ringdown_spectrum,
        search_range,
    )

    rng = np.random.default_rng(seed)
    fs, t = 2000.0, np.arange(40000) / 2000.0
    draws = zip(rng.uniform(0.01, 1, 6), rng.uniform(0.1, 5, 6), rng.uniform(5, 900, 6), rng.uniform(0, 6, 6))
    y = sum(a * np.exp(-r * t) * np.cos(2 * np.pi * f * t + p) for a, r, f, p in draws)
    s = ringdown_spectrum(y + 1e-4 * rng.standard_normal(t.size), fs)
    lo, hi = search_range(s)
    idx, height = candidate_peaks(s, lo, hi, 13.0, 3.0)
    level = 10 * np.log10(np.maximum(s.psd, np.finfo(float).tiny))
    every, props = find_peaks(level, prominence=3.0)
    h = level[every] - 10 * np.log10(s.floor[every])
    f = s.frequency_hz[every]
    keep = ((f >= lo) & (f <= hi) & (h >= peak_threshold_db(f, s, 13.0))
            & (props["prominences"] >= np.maximum(3.0, _noise_prominence_db(h))))
    assert idx.size >= 3
    np.testing.assert_array_equal(idx, every[keep])
    np.testing.assert_array_equal(height, h[keep])


@pytest.mark.parametrize("pad_factor", [1, 4])
def test_the_noise_floors_wide_windows_share_one_sort_with_the_same_floor(pad_factor, monkeypatch):
    """Wide windows take their order from one sort of their phase's bins: the same floor as sorting every
    window's own bins (ties included: a quantised stretch), with and without excluded bins."""
    import importlib

    module = importlib.import_module("sindy_impulse.preprocessing.noise_floor")
    rng = np.random.default_rng(pad_factor)
    n = 40001
    psd = rng.exponential(1.0, n) * (1 + 1e4 * np.exp(-((np.arange(n) - 9000.0) / 800.0) ** 2))
    psd[: n // 4] = np.round(psd[: n // 4], 1)
    exclude = rng.random(n) < 0.2

    def floors():
        return [noise_floor(psd, pad_factor=pad_factor, exclude=mask) for mask in (None, exclude)]

    shared = floors()
    monkeypatch.setattr(module, "_SHARED_SORT", 2.0)  # every window sorts its own bins
    own = floors()
    for a, b in zip(shared, own):
        np.testing.assert_array_equal(a, b)

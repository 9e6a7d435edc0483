"""The decay fit of a free decay's spectrum (sindy_impulse/poles/decay_fit.py): values, standard deviations,
lack of fit, missed modes, channels, bad input."""

import numpy as np
import pytest

from sindy_impulse.poles.decay_fit import fit_decay, missing_peaks

FS = 1000.0
T = np.arange(4000) / FS


def _two_modes(noise: float, seed: int, t=T):
    rng = np.random.default_rng(seed)
    y = np.exp(-1.2 * t) * np.cos(2 * np.pi * 50.0 * t + 0.3)
    y += 0.4 * np.exp(-3.0 * t) * np.sin(2 * np.pi * 121.0 * t)
    return y + noise * rng.standard_normal(t.size)


def _truth():
    sigma = np.array([1.2, 3.0])
    omega = 2 * np.pi * np.array([50.0, 121.0])
    wn = np.hypot(sigma, omega)
    return wn / (2 * np.pi), sigma / wn


def test_two_modes_are_found_where_they_are():
    fit = fit_decay(_two_modes(1e-3, 0), FS, [50.2, 120.7], [1.0, 3.5])
    f, zeta = _truth()
    assert len(fit) == 2
    assert np.all(np.abs(fit.frequency_hz - f) < 4 * fit.frequency_std_hz)
    assert np.all(np.abs(fit.damping_ratio - zeta) < 4 * fit.damping_ratio_std)
    assert np.all(fit.lack_of_fit < 2.0) and np.all(fit.height_db > 40)


def test_standard_deviations_are_calibrated():
    """Over noise seeds the errors over the reported standard deviations have unit RMS (the estimate is
    the maximum-likelihood one; its spread is the Fisher information's)."""
    f, zeta = _truth()
    z_f, z_z = [], []
    for seed in range(60):
        fit = fit_decay(_two_modes(1e-2, seed), FS, [50.1, 121.2], [1.0, 2.0])
        z_f.append((fit.frequency_hz - f) / fit.frequency_std_hz)
        z_z.append((fit.damping_ratio - zeta) / fit.damping_ratio_std)
    for z in (np.array(z_f), np.array(z_z)):
        rms = np.sqrt(np.mean(z**2, axis=0))
        assert np.all((rms > 0.7) & (rms < 1.3)), rms



def test_a_weak_component_beside_a_strong_one_is_not_reported_as_known_exactly():
    """A component 110 dB under a lightly damped neighbour in the same bins: its pole's information is
    tiny beside the neighbour's amplitudes', and its standard deviations must still be its scatter's
    (not the round-off that an unscaled pseudo-inverse leaves of that direction)."""
    t = np.arange(2000) / FS
    truth = np.hypot(2.0, 2 * np.pi * 53.0) / (2 * np.pi)
    z = []
    for seed in range(30):
        rng = np.random.default_rng(seed)
        y = np.exp(-0.3 * t) * np.cos(2 * np.pi * 50.0 * t)
        y += 3e-6 * np.exp(-2.0 * t) * np.cos(2 * np.pi * 53.0 * t + 1.0) + 1e-6 * rng.standard_normal(t.size)
        fit = fit_decay(y, FS, [50.0, 53.0], [0.3, 2.0])
        z.append((fit.frequency_hz[1] - truth) / fit.frequency_std_hz[1])
    rms = float(np.sqrt(np.mean(np.square(z))))
    assert 0.6 < rms < 1.6, rms

def test_a_chirp_is_not_explained_by_a_linear_decay():
    a = np.exp(-1.0 * T)
    chirp = a * np.cos(2 * np.pi * (50.0 * T + 0.5 * (1 - a**2) / 2.0))  # 1 % higher at the start
    rng = np.random.default_rng(0)
    clean = a * np.cos(2 * np.pi * 50.0 * T)
    linear = fit_decay(clean + 1e-3 * rng.standard_normal(T.size), FS, [50.0], [1.0])
    nonlinear = fit_decay(chirp + 1e-3 * rng.standard_normal(T.size), FS, [50.0], [1.0])
    assert linear.lack_of_fit_p[0] > 1e-3
    assert nonlinear.lack_of_fit_p[0] < 1e-6 and nonlinear.lack_of_fit[0] > 10


def test_a_missed_mode_is_found_in_what_the_fit_leaves():
    rng = np.random.default_rng(1)
    y = np.exp(-1.0 * T) * np.cos(2 * np.pi * 50.0 * T)
    y += 0.01 * np.exp(-2.0 * T) * np.cos(2 * np.pi * 80.0 * T)
    fit = fit_decay(y + 1e-4 * rng.standard_normal(T.size), FS, [50.0], [1.0])
    found, decay = missing_peaks(fit, 15.0)
    assert found.size == 1 and found[0] == pytest.approx(80.0, abs=0.3) and decay[0] > 0
    assert missing_peaks(fit, 15.0, lo_hz=90.0)[0].size == 0  # outside the searched range


def test_other_channels_get_their_own_amplitudes_at_the_reference_poles():
    y = _two_modes(1e-4, 2)
    other = -0.5 * np.exp(-1.2 * T) * np.cos(2 * np.pi * 50.0 * T + 0.3)
    other += 2.0 * 0.4 * np.exp(-3.0 * T) * np.sin(2 * np.pi * 121.0 * T)
    fit = fit_decay(np.column_stack([y, other]), FS, [50.0, 121.0], [1.2, 3.0])
    ratio = fit.amplitude[:, 1] / fit.amplitude[:, 0]
    assert ratio == pytest.approx([-0.5, 2.0], abs=1e-3)


def test_a_known_noise_level_or_an_earlier_floor_is_used():
    y = _two_modes(1e-3, 3)
    first = fit_decay(y, FS, [50.0, 121.0], [1.2, 3.0])
    again = fit_decay(y, FS, first.damped_frequency_hz, first.decay_rate, noise=first.noise_power)
    known = fit_decay(y, FS, [50.0, 121.0], [1.2, 3.0], noise=1e-6)
    assert again.frequency_hz == pytest.approx(first.frequency_hz, rel=1e-7)
    assert known.noise_std == pytest.approx([1e-3, 1e-3], rel=0.05)
    with pytest.raises(ValueError, match="noise holds"):
        fit_decay(y, FS, [50.0], [1.0], noise=np.ones(10))


@pytest.mark.parametrize(("f", "s", "match"), [([600.0], [1.0], "lie in"), ([50.0, 80.0], [1.0], "length"),
                                               ([np.nan], [1.0], "lie in")])
def test_bad_starting_poles_are_refused(f, s, match):
    with pytest.raises(ValueError, match=match):
        fit_decay(_two_modes(1e-3, 0), FS, f, s)


def test_a_trial_fit_can_keep_the_floor_it_was_fitted_against():
    """``refloor=False``: the same fit and statistics, the given floor reported instead of a new one."""
    fs = 1000.0
    t = np.arange(4000) / fs
    noise = 1e-3 * np.random.default_rng(2).standard_normal(t.size)
    y = np.exp(-1.2 * t) * np.cos(2 * np.pi * 50.0 * t) + noise
    first = fit_decay(y, fs, [50.1], [1.0])
    again = fit_decay(y, fs, [50.1], [1.0], noise=first.noise_power)
    trial = fit_decay(y, fs, [50.1], [1.0], noise=first.noise_power, refloor=False)
    assert np.array_equal(trial.damped_frequency_hz, again.damped_frequency_hz)
    assert np.array_equal(trial.lack_of_fit, again.lack_of_fit)
    assert np.array_equal(trial.noise_power, first.noise_power)
    assert not np.array_equal(again.noise_power, first.noise_power)

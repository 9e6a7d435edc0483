"""The deflated band of one peak (its neighbours removed) and the fixed-pole amplitude fit behind it."""

import numpy as np
import pytest

from sindy_impulse.preprocessing import preprocess
from sindy_impulse.preprocessing.deflation import deflated_band
from sindy_impulse.preprocessing.sinusoids import fit_amplitudes

FS = 2000.0
MODES = ((1.0, 100.0, 0.002), (1.0, 105.0, 0.025), (1.0, 112.0, 0.003))


def _record(modes=MODES, noise=1e-4):
    t = np.arange(8000) / FS
    y = sum(a * np.exp(-2 * np.pi * z * f * t) * np.sin(2 * np.pi * f * t) for a, f, z in modes)
    return np.concatenate([np.zeros(200), y]) + noise * np.random.default_rng(0).standard_normal(8200)


def test_fit_amplitudes_recovers_amplitudes_phases_and_constant():
    t = np.arange(3000) / 1000
    y = 0.5 + 2 * np.exp(-3 * t) * np.cos(2 * np.pi * 40 * t + 0.5) + 0.2 * np.cos(2 * np.pi * 90 * t - 1)
    fit = fit_amplitudes(y, 1000.0, [40.0, 90.0], [3.0, 0.0])
    assert fit.amplitude == pytest.approx([2.0, 0.2], rel=1e-9)
    assert fit.phase == pytest.approx([0.5, -1.0], abs=1e-9)
    assert fit.constant == pytest.approx(0.5, rel=1e-9)
    assert np.max(np.abs(fit.residual)) < 1e-9


def test_fit_amplitudes_refuses_mismatched_poles():
    with pytest.raises(ValueError, match="decay_rate has 1 value"):
        fit_amplitudes(np.ones(100), 1000.0, [40.0, 90.0], [3.0])


def test_deflated_band_holds_the_target_mode_alone():
    pre = preprocess(_record(), fs=FS)
    assert len(pre.peaks) == 3
    band = deflated_band(pre, 1)
    assert band.band_hz[0] < 100.0 and band.band_hz[1] > 112.0  # wide: the neighbours are inside
    # the band signal is the 105 Hz mode alone: it matches that mode's own response
    a, f, z = MODES[1]
    tt = band.t - band.t[0] + (band.start_index - 200) / FS
    target = a * np.exp(-2 * np.pi * z * f * tt) * np.sin(2 * np.pi * f * tt)
    assert np.max(np.abs(band.y - target)) < 0.03 * np.max(np.abs(target))


def test_deflated_band_checks_its_arguments():
    pre = preprocess(_record(), fs=FS)
    with pytest.raises(ValueError, match="peak"):
        deflated_band(pre, 3)
    with pytest.raises(ValueError, match="widen"):
        deflated_band(pre, 1, widen=0.5)


def test_deflated_band_needs_fitted_peaks():
    pre = preprocess(_record(), fs=FS, bands=[(95.0, 102.5), (102.5, 108.5), (108.5, 116.0)])
    with pytest.raises(ValueError, match="damped sinusoids"):
        deflated_band(pre, 1)

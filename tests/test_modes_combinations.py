"""Combination tones: a component at a sum or difference of two modes' frequencies, made by a nonlinear
element driven by both, is named (``Reason.COMBINATION``), not reported as a mode; a mode of its own there
stays a mode."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from sindy_impulse import identify_modes, impact_record
from sindy_impulse.modes._harmonics import combination_evidence
from sindy_impulse.modes.kinds import Reason


def _survey(rec):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return identify_modes(rec.y, fs=rec.fs)


def _chirping_pair(n: int = 12000, fs: float = 2000.0):
    """A hardening mode whose frequency falls from 50.5 to 50 Hz as it decays, a steady 71 Hz mode, and
    the phase of ``2 f_1 - f_2`` (about 29-30 Hz)."""
    t = np.arange(n) / fs
    a1, a2 = np.exp(-0.4 * t), np.exp(-0.25 * t)
    f1 = 50 + 0.5 * a1**2
    p1, p2 = 2 * np.pi * np.cumsum(f1) / fs, 2 * np.pi * 71 * t + 0.4
    return t, fs, (a1, p1, f1), (a2, p2)


@pytest.mark.parametrize("own_mode", [False, True])
def test_combination_evidence_follows_moving_parents(own_mode):
    """A product of a chirping mode and a steady one stays locked to ``2 phi_1 - phi_2`` while the sum
    moves 1.5 %; a tone of its own at the sum's mean frequency, as strong and decaying as fast, drifts
    against it piece by piece and is no combination."""
    t, fs, (a1, p1, f1), (a2, p2) = _chirping_pair()
    envelope = 0.02 * a1**2 * a2
    if own_mode:
        mean = np.average(2 * f1 - 71, weights=envelope**2)
        y3 = envelope * np.cos(2 * np.pi * mean * t)
    else:
        y3 = envelope * np.cos(2 * p1 - p2 + 1)
    rng = np.random.default_rng(3)
    noise = 1e-5
    ys = tuple(y + noise * rng.standard_normal(t.size) for y in (a1 * np.cos(p1), a2 * np.cos(p2), y3))
    e = combination_evidence(ys, fs, ((45, 55), (66, 76), (24, 34)), (2, -1), (noise * 0.1,) * 3)
    assert e["resolved"]
    assert e["combination"] is (not own_mode)
    assert e["locked"] is (not own_mode)
    assert abs(e["exponent"] - 1) < 0.05  # both decay as the product: only the phase tells them apart


def test_combination_evidence_needs_enough_periods():
    """A stretch of a few periods of the combination (0.1 s, three periods) decides nothing."""
    t, fs, (a1, p1, _), (a2, p2) = _chirping_pair(n=200)
    ys = (a1 * np.cos(p1), a2 * np.cos(p2), 0.02 * a1**2 * a2 * np.cos(2 * p1 - p2))
    e = combination_evidence(ys, fs, ((45, 55), (66, 76), (24, 34)), (2, -1), (1e-6,) * 3)
    assert not e["combination"] and np.isnan(e["drift"])


def test_combination_tone_of_a_cubic_element_is_named():
    """Three modes (36.1, 147.9 and 227.7 Hz) of a chain with a cubic spring and an amplitude-dependent
    damper at one mass, measured in velocity: the element makes a component at ``2 x 36.1 + 147.9`` Hz
    that the decay fit finds (17 dB), phase-locked to that sum, whose amplitude goes as the product of the
    two modes'. It is a rejected row naming both modes, not a fourth mode."""
    rec = impact_record(
        frequencies_hz=[36.10016017904027, 147.91250982373577, 227.6589437594645],
        damping_ratios=[0.0023725219107108004, 0.0016229201678406651, 0.0029943506361289267],
        amplitudes=[0.3339249006724555, 0.31959884696411445, 0.21790635753223855], fs=2048.0,
        duration=11.7431640625, sensor="velocity", pre_trigger=0.049208682367750826,
        offset=3.2643370586213036,
        snr_db=58.811382469199614, random_state=117104542, cubic_stiffness=1966318766.4497366,
        damping_amplitude=1379574.479766721)
    survey = _survey(rec)
    found = sorted(m.frequency_hz for m in survey.modes)
    assert len(found) == 3
    assert np.allclose(found, rec.modes.frequency_hz, rtol=3e-3)
    rows = [r for r in survey.rejected if r.code is Reason.COMBINATION]
    assert len(rows) == 1
    e = rows[0].evidence
    assert e["powers"] == (2, 1) and e["combination"]
    assert np.allclose(sorted(e["parent_frequencies_hz"]), rec.modes.frequency_hz[:2], rtol=3e-3)
    assert abs(e["frequency_hz"] / (2 * found[0] + found[1]) - 1) < 3e-3
    assert "combination tone" in rows[0].reason and "not a mode" in rows[0].reason


def test_linear_mode_at_a_combination_frequency_stays_a_mode():
    """A linear structure makes no combination tones: a mode of its own 0.05 % off ``2 f_1 - f_2`` of two
    stronger modes, damped about as fast as their product would decay, is reported as a mode."""
    f1, f2 = 1976.46, 2891.0
    f3 = (2 * f1 - f2) * 1.0005
    rec = impact_record(frequencies_hz=[f3, f1, f2], damping_ratios=[0.0113, 0.0019, 0.002],
                        amplitudes=[0.14, 0.92, 0.38], fs=25600.0, duration=0.4, sensor="acceleration",
                        pre_trigger=0.03, snr_db=40.0, random_state=11)
    survey = _survey(rec)
    assert not any(r.code is Reason.COMBINATION for r in survey.rejected)
    assert any(abs(m.frequency_hz / f3 - 1) < 3e-3 for m in survey.modes)

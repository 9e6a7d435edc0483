"""Intermodulation products of two modes through one nonlinear element (classify._products and
_harmonics.product_evidence): named, not reported as modes; a mode of its own near such a place stays a
mode."""

import types
import warnings

import numpy as np
import pytest

from sindy_impulse import identify_modes, impact_record
from sindy_impulse.modes import classify
from sindy_impulse.modes._harmonics import product_evidence
from sindy_impulse.modes.kinds import Kind, Reason

FS = 4000.0
T = np.arange(12000) / FS
BANDS = ((30, 44), (85, 101), (155, 179))
NOISE = (1e-5, 1e-5, 1e-5)


def _modes():
    pa, pb = 2 * np.pi * 37.0 * T, 2 * np.pi * 93.0 * T + 0.4
    aa, ab = np.exp(-0.9 * T), 0.8 * np.exp(-0.6 * T)
    return aa * np.cos(pa), ab * np.cos(pb), (aa, pa), (ab, pb)


def test_a_tone_locked_to_two_modes_phases_with_their_amplitudes_is_a_product():
    ya, yb, (aa, pa), (ab, pb) = _modes()
    tone = 0.02 * aa**2 * ab * np.cos(2 * pa + pb + 1.0)
    e = product_evidence((ya, yb, tone), FS, BANDS, (2, 1), NOISE)
    assert e["resolved"] and e["locked"] and e["product"]
    assert abs(e["offset"]) < 1e-4 and e["exponent"] == pytest.approx(1.0, abs=0.05)
    assert e["frequency_hz"] == pytest.approx(167.0, rel=1e-4)


def test_a_difference_tone_is_a_product_too():
    ya, yb, (aa, pa), (ab, pb) = _modes()
    tone = 0.02 * aa * ab**2 * np.cos(2 * pb - pa)  # 2 x 93 - 37 = 149 Hz
    e = product_evidence((ya, yb, tone), FS, (BANDS[0], BANDS[1], (140, 158)), (-1, 2), NOISE)
    assert e["product"] and e["frequency_hz"] == pytest.approx(149.0, rel=1e-4)


def test_a_mode_of_its_own_near_the_place_is_not_a_product():
    ya, yb, *_ = _modes()
    mode = 0.02 * np.exp(-1.5 * T) * np.cos(2 * np.pi * 167.0 * 1.005 * T)  # 0.5 % off, its own decay
    e = product_evidence((ya, yb, mode), FS, BANDS, (2, 1), NOISE)
    assert e["resolved"] and not e["locked"] and not e["product"]


def test_a_locked_tone_whose_amplitude_does_not_go_as_the_modes_is_not_a_product():
    ya, yb, (aa, pa), (ab, pb) = _modes()
    tone = 0.02 * np.exp(-0.2 * T) * np.cos(2 * pa + pb)  # locked, but decaying far slower than aa^2 ab
    e = product_evidence((ya, yb, tone), FS, BANDS, (2, 1), NOISE)
    assert e["locked"] and not e["product"] and e["exponent"] < 0.7


def test_too_short_a_stretch_decides_nothing():
    ya, yb, (aa, pa), (ab, pb) = _modes()
    tone = 0.02 * aa**2 * ab * np.cos(2 * pa + pb)
    e = product_evidence((ya[:200], yb[:200], tone[:200]), FS, BANDS, (2, 1), NOISE)
    assert np.isnan(e["offset"]) and not e["resolved"] and not e["product"]


def _cand(f, kind=Kind.LINEAR, explained=True, zeta=0.001):
    return types.SimpleNamespace(damped_frequency_hz=f, kind=kind, explained=explained, damping_ratio=zeta)


def test_combinations_nearest_first_and_within_reach():
    a, b = _cand(37.0, Kind.NONLINEAR), _cand(93.0)
    assert classify._combinations(_cand(167.3), a, b)[0] == (2, 1)  # 2 x 37 + 93 = 167
    assert classify._combinations(_cand(149.2), a, b)[0] == (-1, 2)  # 2 x 93 - 37 = 149
    assert classify._combinations(_cand(400.0), a, b) == []
    # within the phase test's tolerance only (a real beam's mode 0.34 % off a sum read as locked to it)
    assert classify._combinations(_cand(167.0 * 1.0034, zeta=0.0016), a, b) == []
    assert classify._combinations(_cand(167.0 * 1.001), a, b) == [(2, 1)]


# A cubic spring couples three modes (family g of benchmarks/accuracy/modes.py); a tone at 2 f_1 + f_2
# (166.8 Hz, 27 dB) stands 2.4 Hz under the third mode.
COUPLED = dict(frequencies_hz=[36.689758717615504, 93.42045431794939, 169.1740183968844],
               damping_ratios=[0.0032020819979306572, 0.002131859053828444, 0.0027248151359649643],
               amplitudes=[0.24453141618827903, 0.3204375868243063, 0.7172563515281227], fs=2048.0,
               duration=19.39697265625, sensor="acceleration", pre_trigger=0.03389826009976724,
               offset=3.056681030610931, snr_db=57.40242376571493, random_state=487006981,
               cubic_stiffness=-463360757456686.2)


@pytest.mark.slow
def test_an_intermodulation_tone_of_a_coupled_record_is_named_not_reported():
    rec = impact_record(**COUPLED)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        survey = identify_modes(rec.y, fs=rec.fs)
    found = sorted(m.frequency_hz for m in survey.modes)
    assert len(found) == 3
    assert np.allclose(found, COUPLED["frequencies_hz"], rtol=1e-3)
    rows = [r for r in survey.rejected if r.code is Reason.INTERMODULATION]
    assert len(rows) == 1 and rows[0].band_hz[0] < 166.8 < rows[0].band_hz[1]
    assert "2 x 36.6" in rows[0].reason and "93.2" in rows[0].reason


def test_a_mode_just_off_the_place_decaying_as_a_product_would_is_not_one():
    """A mode 0.18 % off ``2 f_a + f_b`` whose decay rate equals the product's (so its amplitude goes as
    the modes' product): it keeps its own frequency while theirs stay put, and its phase drifts."""
    ya, yb, (aa, pa), (ab, pb) = _modes()
    rate = 2 * 0.9 + 0.6
    mode = 0.02 * np.exp(-rate * T) * np.cos(2 * np.pi * 167.0 * (1 - 0.0018) * T)
    e = product_evidence((ya, yb, mode), FS, BANDS, (2, 1), NOISE)
    assert e["exponent"] == pytest.approx(1.0, abs=0.1)  # the amplitude alone would say product
    assert e["resolved"] and not e["locked"] and not e["product"]


def test_the_longest_run_of_samples():
    from sindy_impulse.modes._harmonics import _longest_run

    mask = np.array([0, 1, 1, 0, 1, 1, 1, 0, 1], bool)
    assert _longest_run(mask).tolist() == [4, 5, 6]
    assert _longest_run(np.zeros(5, bool)).size == 0


@pytest.mark.parametrize("kwargs, error, words", [
    (dict(signals=(np.zeros(100), np.zeros(100))), TypeError, "three arrays"),
    (dict(signals=(np.zeros(100), np.zeros(100), np.zeros(90))), ValueError, "one length"),
    (dict(counts=(0, 1)), ValueError, "non-zero whole"),
    (dict(counts=(1.5, 1)), ValueError, "non-zero whole"),
    (dict(bands=((30, 44), (101, 85), (155, 179))), ValueError, "low < high"),
    (dict(noise_rms=(1e-5, -1.0, 1e-5)), ValueError, "noise_rms"),
    (dict(fs=-1.0), ValueError, "fs"),
])
def test_product_evidence_names_bad_input(kwargs, error, words):
    ya, yb, (aa, pa), (ab, pb) = _modes()
    args = dict(signals=(ya, yb, ya), fs=FS, bands=BANDS, counts=(2, 1), noise_rms=NOISE) | kwargs
    with pytest.raises(error, match=words):
        product_evidence(args["signals"], args["fs"], args["bands"], args["counts"], args["noise_rms"])

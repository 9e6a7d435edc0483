"""identify_modes on close, strongly damped pairs: the joint bands of the preprocessing (groups)."""

import warnings

import numpy as np
import pytest

from sindy_impulse import identify_modes, impact_record


def test_close_strongly_damped_pair_is_identified_in_its_joint_band():
    # 2 % and 2.5 % damping 15 % apart: each own band loses its mode to the band-pass transient
    f, zeta = [534.7, 616.8], [0.0196, 0.0246]
    rec = impact_record(f, zeta, [1.0, 0.8], fs=5000.0, duration=0.8, sensor="displacement", snr_db=45,
                        pre_trigger=0.05, random_state=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        survey = identify_modes(rec.y, fs=rec.fs)
    found = sorted((m.frequency_hz, m.damping_ratio) for m in survey)
    assert len(found) == 2
    assert [g for g, _ in found] == pytest.approx(f, rel=3e-3)
    assert [z for _, z in found] == pytest.approx(zeta, rel=0.1)
    assert all(m.band_hz[0] < f[0] and m.band_hz[1] > f[1] for m in survey)  # the joint band


def test_well_separated_modes_keep_their_own_bands():
    # lightly damped and well apart: no group, the own bands' modes stand
    rec = impact_record([120.0, 410.0], [0.004, 0.003], fs=5000.0, duration=1.0, snr_db=50, random_state=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        survey = identify_modes(rec.y, fs=rec.fs)
    assert len(survey) == 2 and all(m.band_hz[1] / m.band_hz[0] < 1.5 for m in survey)
    assert np.allclose(sorted(m.frequency_hz for m in survey), [120.0, 410.0], rtol=3e-3)

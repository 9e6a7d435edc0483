"""Short, strongly damped records whose bands the band-pass transient would swallow (issue 25, family d):
such a band is identified without band-pass from its stable pole, the other stable modes removed."""

import warnings

import numpy as np
import pytest

from sindy_impulse import identify_modes, impact_record

SEEDS = (0, 1, 2)


def _survey(rec):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return identify_modes(rec.y, fs=rec.fs)


def _assert_modes(survey, rec, f_tol=0.005, z_tol=0.1):
    found = sorted((m.frequency_hz, m.damping_ratio) for m in survey.modes)
    assert len(found) == len(rec.modes.frequency_hz), found
    for (f, z), f_true, z_true in zip(found, rec.modes.frequency_hz, rec.modes.damping_ratio):
        assert f == pytest.approx(f_true, rel=f_tol)
        assert z == pytest.approx(z_true, rel=z_tol)


@pytest.mark.parametrize("seed", SEEDS)
def test_two_short_bands_are_identified_from_their_stable_poles(seed):
    """Five periods of a 10.9 %-damped 24 Hz mode beside a 3.3 %-damped 48 Hz one (0.22 s): every band, and
    the pair's joint band, has too few periods left after the filter transient."""
    rec = impact_record([24.3466, 47.8707], [0.1092, 0.0331], [0.1143, 0.4314], fs=1000, duration=0.224,
                        sensor="acceleration", pre_trigger=0.00908, offset=3.1455, snr_db=57.81,
                        random_state=seed)
    survey = _survey(rec)
    _assert_modes(survey, rec)
    assert sum("too short for the band-pass" in n for n in survey.notes) == 2
    assert not survey.rejected

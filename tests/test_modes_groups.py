"""identify_modes on close, strongly damped modes beside lightly damped ones: the decay fit has no band-pass
transient, so no mode is lost to one."""

import warnings

import numpy as np
import pytest

from sindy_impulse import identify_modes, impact_record


def test_close_strongly_damped_pair_is_identified():
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
    assert all(np.isfinite(m.frequency_std_hz) and np.isfinite(m.damping_ratio_std) for m in survey)


def test_two_stable_poles_in_one_half_power_band_are_two_modes():
    """Two modes whose half-power bands touch (13.2 Hz apart, half-widths 5.0 + 8.1 Hz) seed the decay fit
    once; the one component it fits leaves a misfit, and the stabilisation's two poles split it."""
    f, zeta = [488.6, 501.8], [0.0103, 0.0162]
    rec = impact_record(f, zeta, [0.4, 0.96], fs=25600.0, duration=0.18, sensor="acceleration",
                        pre_trigger=0.06, snr_db=40, random_state=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        survey = identify_modes(rec.y, fs=rec.fs)
    found = sorted((m.frequency_hz, m.damping_ratio) for m in survey)
    assert [g for g, _ in found] == pytest.approx(f, rel=1e-3)
    assert [z for _, z in found] == pytest.approx(zeta, rel=0.1)


def test_well_separated_modes_keep_their_own_bands():
    # lightly damped and well apart: no group, the own bands' modes stand
    rec = impact_record([120.0, 410.0], [0.004, 0.003], fs=5000.0, duration=1.0, snr_db=50, random_state=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        survey = identify_modes(rec.y, fs=rec.fs)
    assert len(survey) == 2 and all(m.band_hz[1] / m.band_hz[0] < 1.5 for m in survey)
    assert np.allclose(sorted(m.frequency_hz for m in survey), [120.0, 410.0], rtol=3e-3)


def _survey(**kwargs):
    rec = impact_record(**kwargs)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return rec, identify_modes(rec.y, fs=rec.fs)


@pytest.mark.parametrize(
    "case",
    [
        # a 1.4 %-damped mode 9 % above a lightly damped one and 27 % below another (modes record 83)
        dict(frequencies_hz=[160.42, 182.26, 198.65, 251.68], damping_ratios=[0.0063, 0.001, 0.0144, 0.0037],
             fs=2048.0, duration=3.45, sensor="displacement", snr_db=48.0, random_state=11),
        # a 2.7 %-damped mode 5 % below a lightly damped one (record 113's middle mode)
        dict(frequencies_hz=[723.1, 873.08, 918.91], damping_ratios=[0.0049, 0.0273, 0.007],
             fs=10000.0, duration=3.7, sensor="velocity", snr_db=40.0, random_state=12),
    ],
)
def test_strongly_damped_mode_between_lightly_damped_ones_is_found(case):
    # its own band is too narrow (a band-pass transient would swallow it): the decay fit has none
    rec, survey = _survey(pre_trigger=0.05, offset=1.0, **case)
    assert len(survey) == len(case["frequencies_hz"])
    for mode, f, z in zip(survey.modes, case["frequencies_hz"], case["damping_ratios"]):
        assert mode.frequency_hz == pytest.approx(f, rel=3e-3)
        assert mode.damping_ratio == pytest.approx(z, rel=0.1)
    strong = survey.modes[int(np.argmax(case["damping_ratios"]))]
    assert strong.source == "poles" and np.isfinite(strong.damping_ratio_std)

"""Standard deviations of the modes' values from the fit itself (sindy_impulse.modes.uncertainty)."""

import copy
import json
import math
import warnings

import numpy as np
import pytest

from sindy_impulse import identify_modes, impact_record
from sindy_impulse.cli import main as cli_main
from sindy_impulse.exceptions import DataWarning
from sindy_impulse.modes._hits import _combined_std
from sindy_impulse.modes.uncertainty import mode_uncertainty
from sindy_impulse.simulation.scoring import FunctionMeasure


def _survey(snr_db, seed=0, frequencies=(150.0,), damping=(0.006,)):
    rec = impact_record(list(frequencies), list(damping), fs=2000, duration=1.0, snr_db=snr_db,
                        random_state=seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DataWarning)
        return rec, identify_modes(rec.y, fs=rec.fs)


@pytest.fixture(scope="module")
def noisy():
    return {snr: _survey(snr)[1].modes[0] for snr in (30, 60)}


def test_std_finite_and_positive_on_a_clean_record():
    _, survey = _survey(None)
    mode = survey.modes[0]
    assert math.isfinite(mode.frequency_std_hz) and mode.frequency_std_hz > 0
    assert math.isfinite(mode.damping_ratio_std) and mode.damping_ratio_std > 0
    assert mode.uncertainty_note == ""


def test_std_scales_with_the_noise(noisy):
    # 30 dB more noise amplitude: about 31.6 times the standard deviation
    for name in ("frequency_std_hz", "damping_ratio_std"):
        ratio = getattr(noisy[30], name) / getattr(noisy[60], name)
        assert 10 < ratio < 100, (name, ratio)


def test_coefficient_stds_match_the_model(noisy):
    mode = noisy[30]
    coef = mode.model.coefficients()
    assert mode.coefficients_std.shape == coef.shape
    active = coef != 0
    assert np.all(np.isnan(mode.coefficients_std[~active]))
    assert np.all(np.isfinite(mode.coefficients_std[active]))
    # a linear mode's equation from its poles: y' = dy holds exactly (no std); its stiffness and damping
    # have theirs
    kinematic = mode.source == "poles"
    assert np.all(mode.coefficients_std[1, active[1]] > 0)
    assert (mode.coefficients_std[0, active[0]] == 0).all() if kinematic else (
        mode.coefficients_std[0, active[0]] > 0).all()
    # the stiffness is determined far better than to its own size
    assert mode.coefficients_std[1, 0] < 1e-2 * abs(coef[1, 0])


def test_fields_in_row_repr_and_json(noisy, tmp_path):
    _, survey = _survey(45, seed=1, frequencies=(120.0, 240.0), damping=(0.004, 0.008))
    for row, mode in zip(survey.table(), survey.modes):
        assert row["frequency_std_hz"] == mode.frequency_std_hz > 0
        assert row["damping_ratio_std"] == mode.damping_ratio_std > 0
    text = repr(survey)
    assert text.count("±") == 2 * len(survey)
    rec = impact_record([150.0], [0.01], fs=2000, duration=1.0, snr_db=50, random_state=0)
    path = tmp_path / "hit.csv"
    path.write_text("t,y\n" + "\n".join(f"{t:.9g},{y:.9g}" for t, y in zip(rec.t, rec.y)))
    out = tmp_path / "modes.json"
    assert cli_main(["modes", str(path), "--columns", "y", "--no-nonlinearity", "--json", str(out)]) == 0
    row = json.loads(out.read_text())["modes"][0]
    assert 0 < row["frequency_std_hz"] < 0.1 and 0 < row["damping_ratio_std_percent"] < 0.1  # in per cent
    assert set(row["coefficients_std"]) == {"y'", "dy'"} and 0 < row["coefficients_std"]["dy'"]["y"]


def test_nan_with_a_reason_when_the_fit_is_not_known(noisy):
    mode = noisy[60]
    model = copy.deepcopy(mode.model)
    model.output_error_fit_ = None
    model.error_measure = FunctionMeasure(lambda *args: np.zeros(1), name="mine")
    u = mode_uncertainty(model, mode.states, mode.t, mode.band_hz, mode.frequency_hz)
    assert math.isnan(u.frequency_std_hz) and math.isnan(u.damping_ratio_std)
    assert "mine" in u.reason


def test_repeated_hits_combine_the_stds():
    assert _combined_std([2.0, 2.0]) == pytest.approx(2.0 / np.sqrt(2))
    assert _combined_std([1.0, 1.0, 1.0, 1.0]) == pytest.approx(np.sqrt(np.pi / 2) / 2)
    assert math.isnan(_combined_std([1.0, math.nan]))


@pytest.mark.slow
def test_calibrated_over_seeds():
    errors = []
    for seed in range(10):
        rec, survey = _survey(40, seed=seed)
        mode = survey.modes[0]
        errors.append(((mode.frequency_hz - rec.modes.frequency_hz[0]) / mode.frequency_std_hz,
                       (mode.damping_ratio - rec.modes.damping_ratio[0]) / mode.damping_ratio_std))
    errors = np.array(errors)
    rms = np.sqrt(np.mean(errors**2, axis=0))
    assert np.all((rms > 0.5) & (rms < 2.0)), rms
    assert np.all(np.mean(np.abs(errors) <= 2, axis=0) >= 0.7), errors


def test_systematic_term_zero_for_a_linear_model_and_grows_with_a_cubic_term():
    from sindy_impulse.modes.uncertainty import _model_form
    from sindy_impulse.simulation import CompiledModel, TermTable

    terms = TermTable.polynomial([[1, 0], [0, 1], [3, 0]])
    t = np.arange(2000) * 0.005
    moved = []
    for k3 in (0.0, 5.0, 20.0):
        model = CompiledModel([[0.0, 1.0, 0.0], [-400.0, -0.4, -k3]], terms)
        states = model.simulate([1.0, 0.0], t)
        moved.append(_model_form(model, states, np.zeros(2), np.full(2, 1e-6), 20 / (2 * np.pi)))
    assert np.all(moved[0] < 1e-9)
    # a hardening spring raises the frequency over the data: the shift grows with k3
    assert 0 < moved[1][0] < moved[2][0]

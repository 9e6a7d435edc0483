"""The small-amplitude damping ratio of a nonlinear mode whose model lost its amplitude-dependent damping
(``modes/_envelope.py``)."""

import types

import numpy as np
import pysindy as ps
import pytest

from sindy_impulse.modes import _envelope
from sindy_impulse.modes.result import Mode

F_HZ, FS = 50.0, 2000.0


def _decay(seed: int, c2: float, zeta: float = 0.002, duration: float = 6.0):
    """A free decay from amplitude 1 of ``x'' + 2 zeta omega x' + omega^2 x + c2 x^2 x' = 0`` (the
    ``impact_record`` damper) by first-order averaging, its decay rate ``zeta omega + c2 a^2 / 8``; 0.1 %
    noise on both states."""
    omega = 2 * np.pi * F_HZ
    t = np.arange(int(duration * FS)) / FS
    s0, b = zeta * omega, c2 / 8
    a = np.sqrt(s0 / ((s0 + b) * np.exp(2 * s0 * t) - b))
    da = -(s0 + b * a**2) * a
    x = np.column_stack([a * np.cos(omega * t), da * np.cos(omega * t) - a * omega * np.sin(omega * t)])
    rng = np.random.default_rng(seed)
    return x * (1 + 0.001 * rng.standard_normal(x.shape)), t, omega


class _Model:
    """A fitted-model stand-in: ``[y, dy]``, cubic library, the given ``dy'`` coefficients."""

    def __init__(self, row):
        self.feature_library_ = ps.PolynomialLibrary(degree=3, include_bias=False).fit(np.ones((4, 2)))
        self._coef = np.vstack([[0, 1, 0, 0, 0, 0, 0, 0, 0], row])

    def coefficients(self):
        return self._coef


def _mode(x, t, omega, zeta, row, nonlinear=True) -> Mode:
    mode = Mode(frequency_hz=omega / (2 * np.pi), damping_ratio=zeta, band_hz=(40.0, 60.0), amplitude=1.0,
                fit_error=0.01, model=_Model(row), states=x, t=t)
    mode.__dict__["nonlinearity"] = types.SimpleNamespace(nonlinear=nonlinear)  # the test's verdict
    return mode


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_envelope_regression_recovers_the_zero_amplitude_damping(seed):
    rng = np.random.default_rng(seed)
    zeta = float(rng.uniform(0.001, 0.004))
    omega = 2 * np.pi * F_HZ
    c2 = float(rng.uniform(0.5, 1.0)) * 8 * omega * zeta  # damping ratio 1.5-2x at x = 1
    x, t, omega = _decay(seed, c2, zeta)
    s0, s1, *_ = _envelope.envelope_decay(x[:, 0], x[:, 1], 1 / FS, omega)
    assert s0 / omega == pytest.approx(zeta, rel=0.03)
    assert s1 > 0.3 * s0  # the rate grows with amplitude


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_model_without_the_damper_gets_the_envelopes_small_amplitude_damping(seed):
    zeta = 0.002
    omega = 2 * np.pi * F_HZ
    x, t, omega = _decay(seed, 8 * omega * zeta * 0.8, zeta)
    average = 1.3 * zeta  # what a linear damping term absorbing the damper reports
    linear_row = [-(omega**2), -2 * average * omega, 0, 0, 0, 0, 0, 0, 0]
    found = _envelope._missing_damping(_mode(x, t, omega, average, linear_row))
    assert found is not None
    small, small_std, change, model_change = found
    assert small == pytest.approx(zeta, rel=0.05) and 0 < small_std < 0.05 * zeta
    assert change > 0.3 and abs(model_change) < 0.01  # the data's change, none in the model


def test_a_model_with_the_damper_and_a_linear_mode_are_left_alone():
    zeta, omega = 0.002, 2 * np.pi * F_HZ
    c2 = 8 * omega * zeta * 0.8
    x, t, omega = _decay(0, c2, zeta)
    with_damper = [-(omega**2), -2 * zeta * omega, 0, 0, 0, 0, -c2, 0, 0]
    assert _envelope._missing_damping(_mode(x, t, omega, zeta * 1.01, with_damper)) is None
    linear_x, t, _ = _decay(0, 0.0, zeta)
    linear_row = [-(omega**2), -2 * zeta * omega, 0, 0, 0, 0, 0, 0, 0]
    assert _envelope._missing_damping(_mode(linear_x, t, omega, zeta, linear_row)) is None


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_amplitude_dependence_of_a_damper_and_of_a_linear_decay(seed):
    """The averaged equations on the analytic signal: a damper raising the decay rate by 80 % at the
    largest amplitude is nonlinear, a linear decay is not."""
    zeta, omega = 0.002, 2 * np.pi * F_HZ
    for c2, nonlinear in ((8 * omega * zeta * 0.8, True), (0.0, False)):
        x, t, _ = _decay(seed, c2, zeta)
        z = x[:, 0] + 1j * (-x[:, 1] / omega)  # y and its quadrature: the analytic signal
        e = _envelope.amplitude_dependence(z[200:-200], FS, 10.0, 1e-3, frequency_hz=F_HZ)  # 0.1 % noise
        assert e.misfit < 3  # the averaged equations describe this envelope
        assert e.nonlinear is nonlinear
        assert e.coefficients[2] == pytest.approx(zeta * omega, rel=0.05)  # the rate at zero amplitude


@pytest.mark.slow
def test_survey_of_a_damper_record_whose_sweep_drops_the_damper():
    """``python -m benchmarks modes --family g`` record 58 (seed 0): a 108.5 Hz mode whose damping ratio is 68
    % higher at the hit; its model keeps ``y^3`` but not the damper, so its linear part said +11 %."""
    from sindy_impulse import identify_modes, impact_record

    rec = impact_record([108.53213509223399], [0.0013040495464960464], [0.4136953157710286], fs=1000.0,
                        duration=27.778, sensor="velocity", pre_trigger=0.016486371752648665,
                        offset=1.9000394831662826, snr_db=30.39023020124656,
                        random_state=1108615737, cubic_stiffness=-100577498051.19955,
                        damping_amplitude=13172325.265452731)
    with pytest.warns(Warning, match="zero amplitude"):
        survey = identify_modes(rec.y, fs=rec.fs)
    (mode,) = survey.modes
    assert mode.damping_ratio == pytest.approx(rec.modes.damping_ratio[0], rel=0.05)
    assert mode.nonlinear

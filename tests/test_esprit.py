import numpy as np
import pytest

from sindy_impulse.analysis import EspritModes, esprit
from sindy_impulse.datasets import impact_record

F = np.array([35.0, 120.0, 410.0, 900.0])
Z = np.array([0.01, 0.004, 0.002, 0.003])
AMPS = [1.0, 0.5, 2.0, 1.0]


def _record(**kw):
    args = dict(fs=10000.0, duration=4.0)
    args.update(kw)
    return impact_record(F, Z, AMPS, **args)


def _decay(rec):
    return rec.y[rec.free_decay_index :], rec.t[rec.free_decay_index] - rec.onset_time


def test_clean_record_gives_the_exact_table():
    rec = _record()
    y, lag = _decay(rec)
    m = esprit(y, fs=rec.fs)
    assert isinstance(m, EspritModes)
    np.testing.assert_allclose(m.frequencies_hz, F, rtol=1e-9)
    np.testing.assert_allclose(m.damped_frequencies_hz, rec.modes.damped_frequency_hz, rtol=1e-9)
    np.testing.assert_allclose(m.damping_ratios, Z, rtol=1e-6)
    # amplitudes refer to the first sample given: the table's, decayed over the lag since the onset
    np.testing.assert_allclose(
        m.amplitudes, rec.modes.amplitude * np.exp(-Z * 2 * np.pi * F * lag), rtol=1e-6
    )
    assert m.noise_std < 1e-9 * np.abs(y).max()


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_noisy_record_accuracy(seed):
    """Field-note order: frequencies to about 1e-5, damping to a few tenths of a percent at 40 dB."""
    rec = _record(snr_db=40, random_state=seed)
    y, _ = _decay(rec)
    m = esprit(y, fs=rec.fs)
    assert m.frequencies_hz.size == 4
    assert np.max(np.abs(m.frequencies_hz / F - 1)) < 1e-4
    assert np.max(np.abs(m.damping_ratios / Z - 1)) < 0.02
    assert m.noise_std == pytest.approx(rec.noise_std, rel=0.05)


def test_offset_is_not_a_mode():
    rec = _record(offset=5.0, snr_db=50, random_state=0)
    y, _ = _decay(rec)
    for kw in ({}, {"subtract_tail_mean": 0.2}):
        m = esprit(y, fs=rec.fs, **kw)
        np.testing.assert_allclose(m.frequencies_hz, F, rtol=1e-4)


@pytest.mark.parametrize("duration, seed", [(4.0, 0), (1.5, 2)])
def test_pink_noise_gives_no_spurious_mode(duration, seed):
    """(1.5 s, seed 2) once split the 900 Hz mode into two close poles: the split rule drops the weak one."""
    rec = _record(duration=duration, snr_db=40, noise="pink", random_state=seed)
    m = esprit(_decay(rec)[0], fs=rec.fs)
    np.testing.assert_allclose(m.frequencies_hz, F, rtol=1e-3)


def test_close_modes_of_similar_strength_are_kept():
    rec = impact_record(
        [100.0, 100.8], [0.005, 0.005], [1.0, 0.5], fs=2000.0, duration=8.0, snr_db=40, random_state=0
    )
    m = esprit(_decay(rec)[0], fs=rec.fs)
    np.testing.assert_allclose(m.frequencies_hz, [100.0, 100.8], rtol=1e-4)


def test_noise_alone_has_no_mode():
    m = esprit(np.random.default_rng(0).standard_normal(5000), fs=1000.0)
    assert m.frequencies_hz.size == 0 and m.amplitudes.shape == (0,)


def test_channels_share_the_poles():
    rec = _record(duration=1.0, sensor_dof=[0, 1, 2, 3])
    y, lag = _decay(rec)
    m = esprit(y, fs=rec.fs)
    assert m.amplitudes.shape == (4, 4)
    np.testing.assert_allclose(m.frequencies_hz, F, rtol=1e-9)
    expected = rec.modes.amplitude * np.exp(-Z * 2 * np.pi * F * lag)[:, None]
    np.testing.assert_allclose(m.amplitudes, expected, rtol=1e-5, atol=1e-9 * expected.max())


def test_time_step_vector_and_rate_agree():
    rec = _record(duration=0.5, snr_db=50, random_state=1)
    y, _ = _decay(rec)
    a = esprit(y, fs=rec.fs)
    b = esprit(y, 1 / rec.fs)
    c = esprit(y, np.arange(y.size) / rec.fs + 3.0)
    np.testing.assert_allclose(a.frequencies_hz, b.frequencies_hz, rtol=1e-12)
    np.testing.assert_allclose(a.frequencies_hz, c.frequencies_hz, rtol=1e-9)


def test_explicit_order_and_few_rows():
    rec = _record(duration=1.0)
    y, _ = _decay(rec)
    m = esprit(y, fs=rec.fs, order=8, max_rows=40)
    assert m.order == 8
    np.testing.assert_allclose(m.frequencies_hz, F, rtol=1e-8)


@pytest.mark.parametrize(
    "args, kwargs, match",
    [
        ((np.ones(100),), {}, "either t"),
        ((np.ones(100), 0.1), {"fs": 10.0}, "either t"),
        ((np.ones(100), np.r_[0.0, np.cumsum(np.linspace(1, 2, 99))]), {}, "uniformly"),
        ((np.ones(100),), {"fs": -1.0}, "fs"),
        ((np.ones(100),), {"fs": 1.0, "order": 0}, "order"),
        ((np.ones(100),), {"fs": 1.0, "order": 40}, "order"),
        ((np.ones(100),), {"fs": 1.0, "subtract_tail_mean": 0.9}, "subtract_tail_mean"),
        ((np.ones(100),), {"fs": 1.0, "max_rows": 2}, "max_rows"),
        ((np.r_[np.ones(99), np.nan],), {"fs": 1.0}, "NaN"),
        ((np.ones(5),), {"fs": 1.0}, "samples"),
    ],
)
def test_bad_arguments(args, kwargs, match):
    with pytest.raises((ValueError, TypeError), match=match):
        esprit(*args, **kwargs)

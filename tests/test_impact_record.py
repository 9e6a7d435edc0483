import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.signal import hilbert

from sindy_impulse.datasets import ImpactRecord, impact_record
from sindy_impulse.datasets._response import linear_modal_response, nonlinear_modal_response

F3 = [35.0, 120.0, 410.0]
Z3 = [0.01, 0.004, 0.002]


def _table_signal(rec, tau):
    """The free decay the modal table describes, (n, n_channels)."""
    m = rec.modes
    w, wd = 2 * np.pi * m.frequency_hz, 2 * np.pi * m.damped_frequency_hz
    amp = m.amplitude.reshape(len(m), -1)
    phase = m.phase.reshape(len(m), -1)
    env = np.exp(-np.outer(tau, m.damping_ratio * w))[:, :, None]
    return np.sum(amp[None] * env * np.cos(np.outer(tau, wd)[:, :, None] + phase[None]), axis=1)


def test_chain_has_exactly_the_requested_modes():
    rec = impact_record(F3, Z3, fs=5000.0, duration=1.0)
    ch = rec.chain
    n = ch.masses.size
    Minv = np.diag(1 / ch.masses)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ ch.stiffness_matrix, -Minv @ ch.damping_matrix]])
    s = np.linalg.eigvals(A)
    s = s[s.imag > 0]
    s = s[np.argsort(np.abs(s))]
    np.testing.assert_allclose(np.abs(s) / (2 * np.pi), F3, rtol=1e-9)
    np.testing.assert_allclose(-s.real / np.abs(s), Z3, rtol=1e-9)
    assert np.all(ch.masses > 0) and np.all(ch.springs > 0)
    K = ch.stiffness_matrix  # a grounded chain: tridiagonal, only mass 0 tied to the ground
    np.testing.assert_allclose(np.triu(K, 2), 0.0, atol=0)
    np.testing.assert_allclose(K.sum(axis=1)[1:], 0.0, atol=1e-9 * np.abs(K).max())


def test_record_is_the_physical_chain_response():
    """Independent check: integrate M x'' + C x' + K x = e_p F(t) with the half-sine and compare."""
    rec = impact_record(
        F3,
        Z3,
        [1.0, 0.3, 2.0],
        fs=4000.0,
        duration=0.3,
        tap_dof=1,
        sensor_dof=[0, 1, 2],
        sensor="displacement",
        pre_trigger=0.05,
        force_snr_db=None,
    )
    ch, p = rec.chain, rec.params
    n = ch.masses.size
    Minv = 1 / ch.masses

    def force(t):
        u = t - rec.onset_time
        return (
            p["force_amplitude"] * np.sin(np.pi * u / p["contact_time"])
            if 0 <= u <= p["contact_time"]
            else 0.0
        )

    def rhs(t, y):
        x, v = y[:n], y[n:]
        f = np.zeros(n)
        f[1] = force(t)
        return np.concatenate([v, Minv * (f - ch.stiffness_matrix @ x - ch.damping_matrix @ v)])

    sol = solve_ivp(
        rhs,
        (0, rec.t[-1]),
        np.zeros(2 * n),
        t_eval=rec.t,
        method="DOP853",
        rtol=1e-11,
        atol=1e-14,
        max_step=p["contact_time"] / 8,
    )
    np.testing.assert_allclose(rec.y, sol.y[:n].T, atol=1e-7 * np.abs(rec.y).max())
    np.testing.assert_allclose(rec.force, [force(t) for t in rec.t], atol=1e-12)


@pytest.mark.parametrize("sensor", ["displacement", "velocity", "acceleration"])
def test_table_describes_the_free_decay(sensor):
    amps = [1.0, 0.5, 2.0]
    rec = impact_record(F3, Z3, amps, fs=5000.0, duration=1.0, sensor=sensor, sensor_dof=[2, 0])
    np.testing.assert_allclose(rec.modes.amplitude[:, 0], amps, rtol=1e-9)  # the tapped mass
    i = rec.free_decay_index
    tau = rec.t[i:] - rec.onset_time
    np.testing.assert_allclose(rec.y_clean[i:], _table_signal(rec, tau), atol=1e-9 * np.abs(rec.y).max())
    np.testing.assert_allclose(rec.modes.damped_frequency_hz, np.array(F3) * np.sqrt(1 - np.array(Z3) ** 2))
    lo, hi = rec.modes.band_hz.T
    np.testing.assert_allclose(hi - lo, 2 * np.array(Z3) * F3, rtol=1e-3)


def test_single_mode_fit_recovers_the_table():
    rec = impact_record(80.0, 0.02, [3.0], fs=2000.0, duration=1.0, sensor="velocity")
    i = rec.free_decay_index
    tau = rec.t[i:] - rec.onset_time
    y = rec.y[i:]
    # linear least squares for the two quadratures with the true pole, then check the pole by residual
    m = rec.modes[0]
    sigma, wd = m.damping_ratio * 2 * np.pi * m.frequency_hz, 2 * np.pi * m.damped_frequency_hz
    B = np.exp(-sigma * tau)[:, None] * np.column_stack([np.cos(wd * tau), np.sin(wd * tau)])
    c, *_ = np.linalg.lstsq(B, y, rcond=None)
    assert np.hypot(*c) == pytest.approx(3.0, rel=1e-9)
    assert np.abs(B @ c - y).max() < 1e-9 * np.abs(y).max()


def test_sensor_kinds_are_derivatives_of_one_motion():
    w = 2 * np.pi * np.array(F3)
    kw = dict(fs=50000.0, duration=0.2, force_snr_db=None)
    disp = impact_record(F3, Z3, [1e-3, 1e-3, 1e-3], sensor="displacement", **kw)
    vel = impact_record(F3, Z3, 1e-3 * w, sensor="velocity", **kw)  # same residues, so the same chain
    acc = impact_record(F3, Z3, 1e-3 * w**2, sensor="acceleration", **kw)
    np.testing.assert_allclose(acc.chain.masses, disp.chain.masses, rtol=1e-9)
    i, dt = disp.free_decay_index + 5, 1 / kw["fs"]
    d = disp.y[i - 2 :]
    dv = (d[2:] - d[:-2]) / (2 * dt)
    da = (d[2:] - 2 * d[1:-1] + d[:-2]) / dt**2
    np.testing.assert_allclose(dv, vel.y[i - 1 : -1], atol=2e-3 * np.abs(vel.y).max())
    np.testing.assert_allclose(da, acc.y[i - 1 : -1], atol=2e-3 * np.abs(acc.y).max())


def test_channels_and_shapes():
    one = impact_record(F3, Z3, fs=3000.0, duration=0.5, tap_dof=1)
    many = impact_record(F3, Z3, fs=3000.0, duration=0.5, tap_dof=1, sensor_dof=[0, 1, 2])
    assert one.y.shape == (1500,) and many.y.shape == (1500, 3) and many.n_channels == 3
    assert one.modes.amplitude.shape == (3,) and many.modes.amplitude.shape == (3, 3)
    np.testing.assert_allclose(many.y[:, 1], one.y)
    assert isinstance(one, ImpactRecord) and one.true_backbone is None


def test_offset_and_pre_trigger():
    rec = impact_record(F3, Z3, fs=5000.0, duration=1.0, pre_trigger=0.25, offset=5.0, force_snr_db=None)
    peak = np.abs(rec.y_clean).max()
    assert rec.offset == pytest.approx(5 * peak)
    np.testing.assert_allclose(rec.y - rec.y_clean, 5 * peak, rtol=1e-12)
    before = rec.t < rec.onset_time
    assert before.sum() == pytest.approx(0.25 * rec.t.size, abs=2)
    assert np.all(rec.y_clean[before] == 0) and np.abs(rec.y_clean[~before]).max() > 0
    assert np.all(rec.force[before] == 0) and rec.force.max() == pytest.approx(100.0, rel=1e-3)
    assert 0 <= rec.onset_time - rec.t[np.argmax(~before) - 1] <= rec.params["contact_time"]


@pytest.mark.parametrize("noise", ["white", "pink"])
def test_noise_level_follows_snr(noise):
    rec = impact_record(F3, Z3, fs=5000.0, duration=2.0, snr_db=30, noise=noise, random_state=3)
    start = np.searchsorted(rec.t, rec.onset_time)
    first = rec.y_clean[start : start + int(np.ceil(0.1 * (rec.t.size - start)))]
    expected = np.sqrt(np.mean(first**2)) / 10 ** (30 / 20)
    assert rec.noise_std == pytest.approx(expected, rel=1e-12)
    assert np.std(rec.y - rec.y_clean) == pytest.approx(expected, rel=0.05)


def test_pink_noise_is_pink():
    kw = dict(fs=5000.0, duration=2.0, snr_db=0, random_state=0)
    spectra = {}
    for noise in ("white", "pink"):
        rec = impact_record(F3, Z3, noise=noise, **kw)
        psd = np.abs(np.fft.rfft(rec.y - rec.y_clean)) ** 2
        spectra[noise] = psd[10:500].mean() / psd[2000:4000].mean()
    assert spectra["white"] == pytest.approx(1.0, rel=0.15)
    assert spectra["pink"] > 20


def test_double_hit_is_in_the_force():
    rec = impact_record(F3, Z3, fs=20000.0, duration=0.5, double_hit=(0.004, 0.4), contact_time=1e-3)
    hit = rec.force > 0.1 * rec.force.max()
    starts = np.flatnonzero(np.diff(hit.astype(int)) == 1)
    assert starts.size == 2
    assert (starts[1] - starts[0]) / rec.fs == pytest.approx(0.004, abs=2 / rec.fs)
    second = rec.force[starts[1] : starts[1] + 30].max()
    assert second / rec.force.max() == pytest.approx(0.4, rel=0.02)
    assert rec.t[rec.free_decay_index] > rec.onset_time + 0.005
    i = rec.free_decay_index
    np.testing.assert_allclose(
        rec.y_clean[i:],
        _table_signal(rec, rec.t[i:] - rec.onset_time)[:, 0],
        atol=1e-9 * np.abs(rec.y_clean).max(),
    )


def test_contact_time_lasts_at_least_one_sample():
    rec = impact_record(100.0, 0.01, fs=1000.0, duration=1.0, force_snr_db=None)
    assert rec.params["contact_time"] == pytest.approx(1e-3)
    assert np.count_nonzero(rec.force) >= 1 and rec.force.max() == pytest.approx(100.0)


def test_random_state_makes_records_repeatable():
    kw = dict(fs=3000.0, duration=0.5, snr_db=20)
    a = impact_record(F3, Z3, random_state=7, **kw)
    b = impact_record(F3, Z3, random_state=7, **kw)
    c = impact_record(F3, Z3, random_state=8, **kw)
    np.testing.assert_array_equal(a.y, b.y)
    np.testing.assert_array_equal(a.force, b.force)
    assert np.any(a.y != c.y)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(frequencies_hz=[100.0, 3000.0]), "Nyquist"),
        (dict(frequencies_hz=[100.0, 100.0]), "distinct"),
        (dict(frequencies_hz=[-5.0, 100.0]), "frequencies_hz"),
        (dict(damping_ratios=[0.01, -0.01]), "negative damping"),
        (dict(damping_ratios=[0.01, 0.02, 0.03]), "damping_ratios"),
        (dict(amplitudes=[1.0, 0.0]), "amplitudes"),
        (dict(amplitudes=[1.0]), "amplitudes"),
        (dict(fs=-1.0), "fs"),
        (dict(duration=0.0), "duration"),
        (dict(sensor="strain"), "sensor"),
        (dict(noise="brown"), "noise"),
        (dict(tap_dof=2), "tap_dof"),
        (dict(sensor_dof=[0, 0]), "sensor_dof"),
        (dict(sensor_dof=[0, 5]), r"sensor_dof\[1\]"),
        (dict(pre_trigger=0.7), "pre_trigger"),
        (dict(contact_time=1e-5), "contact_time"),
        (dict(double_hit=(1e-4, 0.5)), "double_hit"),
        (dict(double_hit=0.01), "double_hit"),
        (dict(offset=np.nan), "offset"),
        (dict(snr_db="high"), "snr_db"),
        (dict(damping_amplitude=-1.0), "damping_amplitude"),
        (dict(random_state="x"), "random_state"),
        (dict(double_hit=(0.3, 0.5), pre_trigger=0.5), "end after the record"),
    ],
)
def test_bad_arguments_are_named(kwargs, match):
    args = dict(frequencies_hz=[100.0, 300.0], damping_ratios=[0.01, 0.02], fs=5000.0, duration=0.5)
    args.update(kwargs)
    with pytest.raises((ValueError, TypeError), match=match):
        impact_record(**args)


def test_bool_is_not_a_dof():
    with pytest.raises(TypeError, match="sensor_dof"):
        impact_record([100.0, 300.0], 0.01, fs=5000.0, duration=0.5, sensor_dof=True)


def test_too_soft_spring_is_refused():
    with pytest.raises(ValueError, match="cubic_stiffness"):
        impact_record(
            50.0, 0.01, [1e-3], fs=1000.0, duration=1.0, sensor="displacement", cubic_stiffness=-1e12
        )


def test_rk4_matches_the_closed_form():
    om, ze = 2 * np.pi * np.array([50.0, 700.0]), np.array([0.002, 0.01])
    s = -ze * om + 1j * om * np.sqrt(1 - ze**2)
    t = np.arange(20000) / 5000.0
    hits = (np.array([0.1, 0.104]), np.array([1.0, 0.3]), 5e-4)
    gain = np.array([1.0, 0.4])
    q, v, _ = linear_modal_response(t, s, gain, *hits)
    Q, V = nonlinear_modal_response(t, om, ze, gain, np.array([0.3, 0.2]), np.zeros(3), *hits)
    np.testing.assert_allclose(Q, q, atol=1e-6 * np.abs(q).max())
    np.testing.assert_allclose(V, v, atol=1e-6 * np.abs(v).max())


def _hilbert_backbone(rec, window=40):
    """Instantaneous (amplitude, damped frequency, decay rate) of a clean single-mode free decay."""
    y = rec.y_clean[rec.free_decay_index :]
    h = hilbert(y)
    amp, phase = np.abs(h), np.unwrap(np.angle(h))
    idx = np.arange(5 * window, y.size - 5 * window, window)
    dt = 1 / rec.fs
    freq = (phase[idx + window] - phase[idx - window]) / (2 * window * dt) / (2 * np.pi)
    decay = -(np.log(amp[idx + window]) - np.log(amp[idx - window])) / (2 * window * dt)
    return amp[idx], freq, decay


@pytest.mark.parametrize("sensor", ["displacement", "acceleration"])
def test_nonlinear_decay_follows_the_true_backbone(sensor):
    f0, z0, a0 = 50.0, 0.002, 1e-3  # a0: initial displacement amplitude
    w0 = 2 * np.pi * f0
    k3 = (1.01**2 - 1) * w0**2 / (0.75 * a0**2)  # 1 % stiffer at a0
    c2 = 12 * z0 * w0 / a0**2  # damping ratio 2.5x at a0
    A0 = a0 * w0 ** (2 if sensor == "acceleration" else 0)
    rec = impact_record(
        f0,
        z0,
        [A0],
        fs=20 * f0,
        duration=400 / f0,
        sensor=sensor,
        cubic_stiffness=k3,
        damping_amplitude=c2,
        pre_trigger=0.0,
    )
    amp, freq, decay = _hilbert_backbone(rec)
    keep = amp > 0.02 * A0
    f_bb, z_bb = rec.true_backbone(amp[keep])
    np.testing.assert_allclose(freq[keep], f_bb * np.sqrt(1 - z_bb**2), rtol=2e-4)
    np.testing.assert_allclose(decay[keep], z_bb * 2 * np.pi * f_bb, rtol=0.03)
    assert z_bb[0] / z_bb[-1] > 1.5 and f_bb[0] / f_bb[-1] > 1.005  # the nonlinearity is visible


def test_quadratic_damping_backbone():
    f0, z0, v0 = 30.0, 0.001, 0.05
    rec = impact_record(
        f0, z0, [v0], fs=600.0, duration=40.0, sensor="velocity", quadratic_damping=15.0, pre_trigger=0.0
    )
    amp, freq, decay = _hilbert_backbone(rec)
    keep = amp > 0.05 * v0
    f_bb, z_bb = rec.true_backbone(amp[keep])
    np.testing.assert_allclose(decay[keep], z_bb * 2 * np.pi * f_bb, rtol=0.03)
    assert rec.true_backbone(v0)[1] > 2 * z0


def test_backbone_converts_sensor_amplitudes():
    rec = impact_record(50.0, 0.01, [1.0], fs=1000.0, duration=0.5, sensor="velocity", cubic_stiffness=1e6)
    bb = rec.true_backbone
    a = bb.displacement_amplitude(2.0)
    w = 2 * np.pi * bb(2.0)[0]
    assert a * w == pytest.approx(2.0, rel=1e-12)
    assert w**2 == pytest.approx((2 * np.pi * 50) ** 2 + 0.75 * 1e6 * a**2, rel=1e-12)


def test_repr_lists_the_modes():
    text = repr(impact_record(F3, Z3, fs=3000.0, duration=0.5))
    assert text.startswith("ImpactRecord(1500 samples at 3000 Hz") and "410.0000" in text


# --- sensor saturation (clip) -----------------------------------------------------------------------


def _clip_record(clip, **kw):
    args = dict(fs=2000.0, duration=0.5, sensor_dof=[0, 2], offset=2.0, snr_db=30, random_state=4)
    args.update(kw)
    return impact_record(F3, Z3, clip=clip, **args)


def test_clip_bounds_the_signal_around_the_offset():
    rec = _clip_record(0.4)
    c = 0.4 * np.abs(rec.y_clean).max(axis=0)
    dev = np.abs(rec.y - rec.offset)
    assert np.all(dev.max(axis=0) <= c * (1 + 1e-12))
    np.testing.assert_allclose(dev.max(axis=0), c, rtol=1e-12)  # it does saturate, in every channel
    free = _clip_record(None)
    inside = dev < c * (1 - 1e-9)
    np.testing.assert_array_equal(rec.y[inside], free.y[inside])  # unsaturated samples are untouched
    np.testing.assert_array_equal(rec.y_clean, free.y_clean)  # a measurement effect: the truth is unchanged
    for name in rec.modes.dtype.names:
        np.testing.assert_array_equal(rec.modes[name], free.modes[name])
    assert rec.params["clip"] == 0.4 and free.params["clip"] is None
    assert "clipped at 0.4 x peak" in repr(rec) and "clipped" not in repr(free)


def test_clip_fraction_grows_as_clip_falls():
    fractions = []
    for clip in (1.0, 0.7, 0.4, 0.2, 0.05):
        rec = impact_record(
            50.0,
            0.01,
            fs=1000.0,
            duration=1.0,
            sensor="displacement",
            offset=0.5,
            snr_db=30,
            random_state=4,
            clip=clip,
        )
        c = clip * np.abs(rec.y_clean).max()
        fractions.append(np.mean(np.abs(rec.y - rec.offset) >= c * (1 - 1e-12)))
    assert fractions[0] < 0.01 and np.all(np.diff(fractions) > 0)


def test_clip_none_is_the_unclipped_record():
    for kw in (dict(), dict(noise="pink", sensor_dof=None, double_hit=(0.01, 0.5)), dict(sensor="velocity")):
        a = _clip_record(None, **kw)
        b = impact_record(
            F3,
            Z3,
            **{
                **dict(fs=2000.0, duration=0.5, sensor_dof=[0, 2], offset=2.0, snr_db=30, random_state=4),
                **kw,
            },
        )
        np.testing.assert_array_equal(a.y, b.y)
        np.testing.assert_array_equal(a.force, b.force)


@pytest.mark.parametrize("clip", [0, 0.0, -0.2, 1.5, np.nan, np.inf, "0.5", True])
def test_bad_clip_is_named(clip):
    with pytest.raises(ValueError, match="clip"):
        impact_record([100.0, 300.0], 0.01, fs=5000.0, duration=0.5, clip=clip)


# --- quadratic stiffness --------------------------------------------------------------------------------

W50, A50 = 2 * np.pi * 50.0, 2e-3


def _spectrum(rec):
    y = rec.y[rec.free_decay_index :]
    Y = np.abs(np.fft.rfft((y - y.mean()) * np.hanning(y.size)))
    return np.fft.rfftfreq(y.size, 1 / rec.fs), Y


def test_quadratic_stiffness_makes_a_second_harmonic():
    k2 = 0.02 * 6 * W50**2 / A50  # second harmonic of 2 % of the fundamental
    kw = dict(fs=1000.0, duration=1.0, sensor="displacement", snr_db=80, random_state=1)
    lin = impact_record(50.0, 0.01, [A50], **kw)
    quad = impact_record(50.0, 0.01, [A50], quadratic_stiffness=k2, **kw)
    f, Y_lin = _spectrum(lin)
    _, Y_quad = _spectrum(quad)
    near2 = np.abs(f - 100.0) <= 2.0
    floor = np.median(Y_lin[(f > 150.0) & (f < 450.0)])
    assert Y_quad[near2].max() > 100 * floor
    assert Y_lin[near2].max() < 10 * floor
    assert quad.params["quadratic_stiffness"] == k2 and "nonlinear" in repr(quad)
    assert quad.true_backbone.quadratic_stiffness == k2
    np.testing.assert_array_equal(quad.modes.frequency_hz, lin.modes.frequency_hz)  # the linear part


def test_quadratic_stiffness_softens_as_the_backbone_says():
    k2 = 0.05 * 6 * W50**2 / A50
    rec = impact_record(
        50.0,
        0.0005,
        [A50],
        fs=5000.0,
        duration=0.3,
        sensor="displacement",
        quadratic_stiffness=-k2,
        force_snr_db=None,
    )
    y, t = rec.y[rec.free_decay_index :], rec.t[rec.free_decay_index :]
    peaks = np.flatnonzero((y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:])) + 1
    f_meas = 1 / np.diff(t[peaks[:6]]).mean()
    f_bb = rec.true_backbone(A50)[0]
    assert f_bb < 0.97 * 50.0  # softening whatever the sign of k2
    assert f_meas == pytest.approx(f_bb, rel=0.005)
    assert rec.true_backbone(1e-9)[0] == pytest.approx(50.0, rel=1e-9)


def test_quadratic_stiffness_default_is_unchanged():
    kw = dict(fs=1000.0, duration=0.5, sensor="displacement", snr_db=40, random_state=2)
    a = impact_record(50.0, 0.01, [A50], cubic_stiffness=1e6, **kw)
    b = impact_record(50.0, 0.01, [A50], cubic_stiffness=1e6, quadratic_stiffness=0.0, **kw)
    np.testing.assert_array_equal(a.y, b.y)
    c = impact_record(F3, Z3, fs=2000.0, duration=0.5, quadratic_stiffness=0.0)
    d = impact_record(F3, Z3, fs=2000.0, duration=0.5)
    np.testing.assert_array_equal(c.y, d.y)
    assert "nonlinear" not in repr(c)


def test_bad_quadratic_stiffness_is_named():
    with pytest.raises(ValueError, match="quadratic_stiffness"):
        impact_record(50.0, 0.01, fs=1000.0, duration=0.5, quadratic_stiffness=np.nan)
    with pytest.raises(ValueError, match="quadratic_stiffness"):  # too soft at the initial amplitude
        impact_record(
            50.0,
            0.01,
            [A50],
            fs=1000.0,
            duration=0.5,
            sensor="displacement",
            quadratic_stiffness=0.6 * W50**2 / A50,
        )

"""Synthetic hammer-impact tests of a spring-mass chain with an exactly known modal table.

The chain (``_chain``): ``n`` masses in a line, mass 0 tied to the ground by a spring, mass ``n - 1``
free, natural frequencies exactly the requested ones. It is built by an inverse eigenvalue construction
(Lanczos on the requested spectrum, then masses from the M-matrix inverse) so that the driving point, the
tapped mass, has the requested modal amplitudes. Damping is modal (classical): each mode keeps its
requested damping ratio. Linear records are computed in closed form (``_response``), nonlinear ones by a
fine fixed-step RK4 in numba.
"""

from __future__ import annotations

import numpy as np

from ._backbone import Backbone
from ._chain import build_chain, scaled
from ._impact_args import check_impact_args
from ._impact_record import ImpactRecord, _nonlinear
from ._measurement import measure
from ._response import (
    accelerations,
    half_sine_force,
    linear_modal_response,
    nonlinear_modal_response,
    pulse_integral,
)

__all__ = ["ImpactRecord", "impact_record"]

_POWER = {"displacement": 0, "velocity": 1, "acceleration": 2}
#: Smallest response of a mode to the hammer, relative to the strongest, that can be scaled up.
_MIN_EXCITATION = 1e-8


def impact_record(
    frequencies_hz,
    damping_ratios,
    amplitudes=None,
    *,
    fs: float = 5000.0,
    duration: float = 2.0,
    sensor: str = "acceleration",
    tap_dof: int | None = None,
    sensor_dof=None,
    pre_trigger: float = 0.1,
    offset: float = 0.0,
    snr_db: float | None = None,
    noise: str = "white",
    contact_time: float | None = None,
    force_amplitude: float = 100.0,
    double_hit: tuple[float, float] | None = None,
    force_snr_db: float | None = 60.0,
    quadratic_stiffness: float = 0.0,
    cubic_stiffness: float = 0.0,
    damping_amplitude: float = 0.0,
    quadratic_damping: float = 0.0,
    clip: float | None = None,
    random_state=None,
) -> ImpactRecord:
    """A synthetic hammer test of an n-DOF spring-mass chain whose modal table is known exactly.

    **The structure.** ``n = len(frequencies_hz)`` masses in a line: mass 0 is tied to the ground by a
    spring, each mass to the next by a spring, mass ``n - 1`` is free. Masses and springs are computed so
    that the undamped natural frequencies are exactly ``frequencies_hz`` and the tapped mass (the driving
    point) responds with exactly ``amplitudes``: an inverse eigenvalue construction of the mass-normalised
    stiffness as a Jacobi matrix, whose spectral weights at the tapped mass are the driving-point residues,
    followed by the masses ``m = (J^-1 e_0)**2`` that make it a grounded chain (all masses and springs
    positive; see ``record.chain``). Damping is modal: each mode decays with its requested damping ratio
    (the damping matrix ``C = M Phi diag(2 zeta omega) Phi^T M`` is not a set of discrete dashpots, which
    could not give arbitrary modal damping with real modes). The response at another mass follows from the
    chain's mode shapes; its amplitudes are in ``record.modes.amplitude``.

    **The hammer.** A half-sine force ``force_amplitude * sin(pi (t - onset_time) / contact_time)`` on the
    tapped mass, optionally followed by a second hit; the force channel is its samples plus white noise at
    ``force_snr_db`` below the peak force.

    **The sensor.** ``y`` is the response plus ``offset`` plus noise; with ``clip`` the sensor saturates:
    ``y = offset + np.clip(y - offset, -c, c)`` per channel, ``c = clip * max|y_clean|``, after the noise is
    added (the noise is clipped too). Clipping is a measurement effect: ``y_clean``, ``modes`` and
    ``true_backbone`` are those of the unclipped record.

    **The response.** Linear records are exact (closed-form modal response to the continuous half-sine,
    vectorised: about 15 ms CPU for 40,000 samples and 4 modes). Nonlinear records add an element between the
    ground and mass 0, with force ``m_0 (k2 x**2 + k3 x**3 + c2 x**2 x' + cq |x'| x')`` (``x`` the
    displacement of mass 0), integrated by classical RK4 in numba on the samples refined so that
    ``omega_max h <= 0.02``, with 64 steps per contact (relative error about 5e-7 over 3,000 periods; about
    0.06 s CPU for a single mode over 3,000 periods at 20 samples per period, plus a one-off compilation of
    a few seconds).

    Parameters
    ----------
    frequencies_hz : float or sequence of float
        Undamped natural frequencies (Hz), distinct, below ``fs / 2``; the table is sorted by them.
    damping_ratios : float or sequence of float
        Modal damping ratios in [0, 1), one per frequency (a scalar applies to all).
    amplitudes : sequence of float, optional
        Initial modal amplitudes at the tapped mass, in sensor units (the amplitude of each mode's
        exponentially decaying cosine extrapolated to ``onset_time``). Their ratios shape the chain, their
        scale sets the masses. Default: 1 for every mode. With the default ``sensor_dof`` (the tapped
        mass) these are the record's amplitudes; a nonlinear record's initial amplitudes are close to them.
    fs, duration : float
        Sampling rate (Hz) and record length (s).
    sensor : {"acceleration", "velocity", "displacement"}
        What the sensor measures (m/s^2, m/s, m).
    tap_dof : int, optional
        The tapped mass (default ``n - 1``, the free end).
    sensor_dof : int or list of int, optional
        The mass the sensor is on (default: the tapped mass); a list gives ``y`` of shape
        (n_samples, n_channels) and per-channel amplitudes and phases in the table.
    pre_trigger : float
        Fraction of the record before the hit, in [0, 0.5].
    offset : float
        Constant added to ``y``, in units of the channel's peak clean amplitude (5.0: five times it).
    snr_db : float, optional
        Noise level: noise std = RMS of the clean signal over the first 10 % of the ring-down (from the
        onset to the end) / ``10**(snr_db / 20)``. None: no noise.
    noise : {"white", "pink"}
        Gaussian white noise, or pink (1/f power) noise scaled to exactly that standard deviation.
    contact_time : float, optional
        Duration of the half-sine (s), at least one sample; default ``max(0.5 ms, 1 / fs)``. Its spectrum
        falls off above about ``1 / contact_time``: shorter contact excites higher modes.
    force_amplitude : float
        Peak force (N).
    double_hit : (float, float), optional
        ``(delay_s, relative_amplitude)``: a second half-sine ``delay_s`` after the first
        (``delay_s >= contact_time``), ``relative_amplitude`` times as strong.
    force_snr_db : float, optional
        Noise of the force channel relative to the peak force (default 60 dB); None: clean.
    quadratic_stiffness, cubic_stiffness, damping_amplitude, quadratic_damping : float
        ``k2`` (1/(m s^2)), ``k3`` (1/(m^2 s^2)), ``c2`` (1/(m^2 s)) and ``cq`` (1/m) of the nonlinear
        element between the ground and mass 0, per unit of its mass. For one mass the equation is
        ``x'' + 2 zeta omega x' + omega**2 x + k2 x**2 + k3 x**3 + c2 x**2 x' + cq |x'| x' = F / m``: a
        Duffing spring (frequency ``sqrt(omega**2 + 3/4 k3 a**2)`` at displacement amplitude ``a``), a
        damper whose damping ratio grows like ``c2 a**2 / (8 omega)`` and a quadratic damper;
        ``record.true_backbone`` gives both against amplitude. The quadratic (asymmetric) spring makes even
        harmonics: a response at ``2 f`` of displacement amplitude ``k2 a**2 / (6 omega**2)`` and a shift of
        the mean by ``-k2 a**2 / (2 omega**2)``; to second order it softens the spring whatever its sign,
        like a cubic one of ``-10/9 k2**2 / omega**2`` (frequency
        ``sqrt(omega**2 + 3/4 (k3 - 10/9 k2**2 / omega**2) a**2)``). A softening spring (``k3 < 0`` or
        ``k2 != 0``) may lower ``omega**2`` by at most a quarter at the initial amplitude.
    clip : float in (0, 1], optional
        Sensor saturation, as a fraction of each channel's peak clean amplitude ``max|y_clean|``: the
        measured signal (noise included) is limited to ``offset -+ clip * max|y_clean|``. None (default):
        no clipping.
    random_state : int, numpy Generator or None
        Seed of the noise.

    Returns
    -------
    ImpactRecord
        ``t``, ``y``, ``force``, ``fs``, ``onset_time``, ``free_decay_index``, ``modes`` (the true modal
        table), ``offset``, ``noise_std``, ``y_clean``, ``true_backbone``, ``chain`` and ``params``.

    Examples
    --------
    Three modes of equal strength at the free end, tapped and measured there:

    >>> rec = impact_record([40.0, 110.0, 250.0], [0.01, 0.005, 0.002], fs=2000.0, duration=3.0,
    ...                     snr_db=40, random_state=0)
    >>> rec.y.shape, rec.modes.frequency_hz.tolist(), bool(np.allclose(rec.modes.amplitude, 1.0))
    ((6000,), [40.0, 110.0, 250.0], True)
    >>> bool(np.all(rec.chain.masses > 0) and np.all(rec.chain.springs > 0))
    True

    A Duffing oscillator whose frequency is 1 % higher at the initial displacement amplitude of 2 mm:

    >>> w0, a0 = 2 * np.pi * 50.0, 2e-3
    >>> k3 = (1.01**2 - 1) * w0**2 / (0.75 * a0**2)
    >>> rec = impact_record(50.0, 0.005, [a0], fs=1000.0, duration=4.0, sensor="displacement",
    ...                     cubic_stiffness=k3)
    >>> f, zeta = rec.true_backbone(a0)
    >>> round(f / 50.0, 4), round(zeta, 5)
    (1.01, 0.00495)

    A sensor that saturates at 30 % of the peak clips the first cycles of the decay:

    >>> rec = impact_record(50.0, 0.01, fs=1000.0, duration=1.0, clip=0.3)
    >>> c = 0.3 * np.abs(rec.y_clean).max()
    >>> bool(np.abs(rec.y).max() <= c), rec.params["clip"]
    (True, 0.3)
    """
    a = check_impact_args(**{k: v for k, v in locals().items()})
    chain, unit_phasor = _design_chain(a)
    t = np.arange(a.n_samples) / a.fs
    y_clean = _simulate(a, chain, unit_phasor, t)
    force_clean = half_sine_force(t, a.starts, a.hit_amplitudes, a.contact_time)
    modes = _modal_table(a, chain, unit_phasor * chain.mode_shapes[a.tap_dof])
    rng = np.random.default_rng(a.random_state)
    y, offset, noise_std = measure(y_clean, t, a.onset, a.offset, a.snr_db, a.noise, rng, a.clip)
    force = force_clean.copy()
    if a.force_snr_db is not None:
        force += rng.standard_normal(force.size) * a.force_amplitude * 10 ** (-a.force_snr_db / 20)
    params = _params(a)
    backbone = None
    if a.frequencies_hz.size == 1:
        backbone = Backbone(
            float(a.frequencies_hz[0]),
            float(a.damping_ratios[0]),
            float(a.cubic_stiffness),
            float(a.damping_amplitude),
            float(a.quadratic_damping),
            a.sensor,
            float(a.quadratic_stiffness),
        )
    squeeze = (lambda v: v) if a.multi_channel else (lambda v: v[..., 0] if np.ndim(v) else v)
    free = int(np.searchsorted(t, a.starts[-1] + a.contact_time, side="right"))
    return ImpactRecord(
        t,
        squeeze(y),
        force,
        float(a.fs),
        float(a.onset),
        free,
        modes,
        squeeze(offset),
        squeeze(noise_std),
        squeeze(y_clean),
        backbone,
        chain,
        params,
    )


def _poles(a):
    omega = 2 * np.pi * a.frequencies_hz
    zeta = a.damping_ratios
    return omega, zeta, -zeta * omega + 1j * omega * np.sqrt(1 - zeta**2)


def _design_chain(a):
    """The scaled chain and each mode's free-decay phasor per unit driving-point gain."""
    omega, zeta, s = _poles(a)
    G = pulse_integral(s, np.array(a.contact_time), a.contact_time)
    unit = sum(h * np.exp(-s * (t0 - a.starts[0])) for t0, h in zip(a.starts, a.hit_amplitudes)) * G
    response = np.abs(s ** _POWER[a.sensor] * unit) / s.imag  # sensor amplitude per unit residue
    weak = response < _MIN_EXCITATION * response.max()
    if np.any(weak):
        f = a.frequencies_hz[weak][0]
        raise ValueError(
            f"the hammer hardly excites the mode at {f:g} Hz (its force spectrum is near zero there): "
            "change contact_time or double_hit"
        )
    residues = a.amplitudes / response  # driving-point phi_p**2
    chain = build_chain(omega, zeta, residues / residues.sum(), a.tap_dof)
    return scaled(chain, 1.0 / residues.sum()), unit


def _simulate(a, chain, unit, t):
    """Clean sensor signals (n_samples, n_channels)."""
    omega, zeta, s = _poles(a)
    Phi = chain.mode_shapes
    gain, phi_g = Phi[a.tap_dof], Phi[0]
    coefs = chain.masses[0] * np.array(
        [a.cubic_stiffness, a.damping_amplitude, a.quadratic_damping, a.quadratic_stiffness]
    )
    hits = (a.starts, a.hit_amplitudes, a.contact_time)
    if _nonlinear(vars(a)):
        if a.cubic_stiffness < 0 or a.quadratic_stiffness:
            x0 = np.sum(np.abs(phi_g * gain * unit) / s.imag)  # bound on the displacement of mass 0
            # a quadratic spring softens like a cubic one of -10/9 k2**2 / omega**2 (second order)
            k3 = a.cubic_stiffness - 10 / 9 * a.quadratic_stiffness**2 / omega.min() ** 2
            if 0.75 * -k3 * x0**2 > omega.min() ** 2 / 4:
                what = f"cubic_stiffness={a.cubic_stiffness!r} softens"
                if a.quadratic_stiffness:
                    what = (
                        f"quadratic_stiffness={a.quadratic_stiffness!r} (with cubic_stiffness="
                        f"{a.cubic_stiffness!r}) softens"
                    )
                raise ValueError(
                    f"{what} the spring too much at the initial "
                    f"displacement amplitude {x0:.3g} m (omega**2 would drop by more than a quarter)"
                )
        q, v = nonlinear_modal_response(t, omega, zeta, gain, phi_g, coefs, *hits)
        if not np.all(np.isfinite(q)):
            raise ValueError("the nonlinear record diverged; lower the nonlinear coefficients or amplitudes")
    else:
        q, v, _ = linear_modal_response(t, s, gain, *hits)
    modal = (q, v, accelerations(t, q, v, omega, zeta, gain, phi_g, coefs, *hits))[_POWER[a.sensor]]
    return modal @ Phi[list(a.sensor_dofs)].T


def _modal_table(a, chain, phasor) -> np.recarray:
    """The true modal table from each mode's free-decay phasor ``Z`` (``q = Im(Z e^{s tau}) / omega_d``)."""
    omega, zeta, s = _poles(a)
    n, n_ch = s.size, len(a.sensor_dofs)
    coef = chain.mode_shapes[list(a.sensor_dofs)].T * (s ** _POWER[a.sensor] * phasor / s.imag)[:, None]
    shape = (n_ch,) if a.multi_channel else ()
    table = np.zeros(
        n,
        dtype=[
            ("frequency_hz", float),
            ("damped_frequency_hz", float),
            ("damping_ratio", float),
            ("amplitude", float, shape),
            ("phase", float, shape),
            ("band_hz", float, (2,)),
        ],
    ).view(np.recarray)
    table.frequency_hz = a.frequencies_hz
    table.damped_frequency_hz = a.frequencies_hz * np.sqrt(1 - zeta**2)
    table.damping_ratio = zeta
    amp, phase = np.abs(coef), np.angle(coef * -1j)
    table.amplitude = amp if a.multi_channel else amp[:, 0]
    table.phase = phase if a.multi_channel else phase[:, 0]
    root = 2 * zeta * np.sqrt(1 - zeta**2)
    lo, hi = np.maximum(1 - 2 * zeta**2 - root, 0.0), 1 - 2 * zeta**2 + root
    table.band_hz = a.frequencies_hz[:, None] * np.sqrt(np.column_stack([lo, hi]))
    return table


def _params(a) -> dict:
    keys = (
        "fs",
        "duration",
        "sensor",
        "tap_dof",
        "pre_trigger",
        "offset",
        "snr_db",
        "noise",
        "contact_time",
        "force_amplitude",
        "double_hit",
        "force_snr_db",
        "quadratic_stiffness",
        "cubic_stiffness",
        "damping_amplitude",
        "quadratic_damping",
        "clip",
        "random_state",
    )
    out = {
        "frequencies_hz": a.frequencies_hz.tolist(),
        "damping_ratios": a.damping_ratios.tolist(),
        "amplitudes": a.amplitudes.tolist(),
        "sensor_dof": list(a.sensor_dofs) if a.multi_channel else a.sensor_dofs[0],
    }
    out.update({k: getattr(a, k) for k in keys})
    return out

"""Argument checks of :func:`~sindy_impulse.datasets.impact_record`: one clear error per bad argument."""

from __future__ import annotations

import math
from numbers import Integral, Real
from types import SimpleNamespace

import numpy as np

from .._utils.params import Interval, Options, check_param
from .._utils.validation import check_array
from .oscillator import MAX_SAMPLES

__all__ = ["check_impact_args"]

_OWNER = "impact_record"
#: Smallest relative gap between two natural frequencies (closer ones make the chain ill-conditioned).
MIN_GAP = 1e-6
#: Default contact time of the hammer (s), lengthened to one sample at low sampling rates.
CONTACT_TIME = 5e-4


def _num(name, value, lo=None, hi=None, closed="both", kind=Real):
    return check_param(name, value, [Interval(kind, lo, hi, closed)], _OWNER)


def _modal(frequencies_hz, damping_ratios, amplitudes, fs):
    f = check_array(np.atleast_1d(frequencies_hz), "frequencies_hz", ndim=(1,))
    if np.any(f <= 0):
        raise ValueError(f"frequencies_hz must be positive, got {f.tolist()}")
    if np.any(f >= fs / 2):
        bad = float(f[f >= fs / 2][0])
        raise ValueError(
            f"frequencies_hz: {bad:g} Hz is at or above the Nyquist frequency fs / 2 = {fs / 2:g} Hz"
        )
    fsorted = np.sort(f)
    gaps = np.diff(fsorted) / fsorted[1:]
    if np.any(gaps < MIN_GAP):
        i = int(np.argmax(gaps < MIN_GAP))
        raise ValueError(
            f"frequencies_hz must be distinct (relative gap > {MIN_GAP:g}); got {fsorted[i]!r} and "
            f"{fsorted[i + 1]!r}"
        )
    z = check_array(np.atleast_1d(damping_ratios), "damping_ratios", ndim=(1,))
    if z.size == 1:
        z = np.full(f.size, z[0])
    if z.size != f.size:
        raise ValueError(f"damping_ratios has {z.size} entries for {f.size} frequencies")
    if np.any(z < 0):
        raise ValueError(f"damping_ratios must not be negative (negative damping), got {z.tolist()}")
    if np.any(z >= 1):
        raise ValueError(f"damping_ratios must be below 1 (an oscillatory mode), got {z.tolist()}")
    if amplitudes is None:
        a = np.ones(f.size)
    else:
        a = check_array(np.atleast_1d(amplitudes), "amplitudes", ndim=(1,))
        if a.size != f.size:
            raise ValueError(f"amplitudes has {a.size} entries for {f.size} frequencies")
        if np.any(a <= 0):
            raise ValueError(f"amplitudes must be positive, got {a.tolist()}")
    order = np.argsort(f)
    return f[order], z[order], a[order]


def _dof(name, value, n, default):
    if value is None:
        return default
    check_param(name, value, [Interval(Integral, 0, n - 1)], _OWNER)
    return int(value)


def _sensor_dofs(sensor_dof, n, tap):
    if (
        sensor_dof is None
        or isinstance(sensor_dof, (Integral, np.integer))
        and not isinstance(sensor_dof, bool)
    ):
        return (_dof("sensor_dof", sensor_dof, n, tap),), False
    if isinstance(sensor_dof, (str, bytes)) or not hasattr(sensor_dof, "__len__") or len(sensor_dof) == 0:
        raise TypeError(
            f"{_OWNER}: sensor_dof must be an int or a non-empty list of ints; got {sensor_dof!r}"
        )
    dofs = tuple(_dof(f"sensor_dof[{i}]", d, n, tap) for i, d in enumerate(sensor_dof))
    if len(set(dofs)) != len(dofs):
        raise ValueError(f"{_OWNER}: sensor_dof lists a mass twice: {list(dofs)}")
    return dofs, True


def _hammer(contact_time, double_hit, force_amplitude, fs):
    if contact_time is None:
        contact_time = max(CONTACT_TIME, 1.0 / fs)
    _num("contact_time", contact_time, 0, None, "neither")
    if contact_time < (1.0 - 1e-9) / fs:
        raise ValueError(
            f"contact_time must last at least one sample (1 / fs = {1 / fs:.3g} s), got {contact_time!r}"
        )
    _num("force_amplitude", force_amplitude, 0, None, "neither")
    if double_hit is not None:
        if not isinstance(double_hit, (tuple, list)) or len(double_hit) != 2:
            raise TypeError(
                f"{_OWNER}: double_hit must be None or (delay_s, relative_amplitude); got {double_hit!r}"
            )
        delay, rel = double_hit
        _num("double_hit delay", delay, 0, None, "neither")
        _num("double_hit relative amplitude", rel, 0, 10, "right")
        if delay < contact_time:
            raise ValueError(
                f"double_hit delay ({delay!r} s) must be at least the contact_time ({contact_time!r} s): "
                "the hammer leaves the structure before it hits again"
            )
        double_hit = (float(delay), float(rel))
    return float(contact_time), double_hit


def check_impact_args(**kw) -> SimpleNamespace:
    """Validated, normalised arguments (frequencies sorted, dofs resolved, defaults filled in)."""
    fs = _num("fs", kw["fs"], 0, None, "neither")
    duration = _num("duration", kw["duration"], 0, None, "neither")
    n_samples = int(round(duration * fs))
    if n_samples < 16 or n_samples > MAX_SAMPLES:
        raise ValueError(
            f"duration * fs = {duration * fs:.4g} samples; between 16 and {MAX_SAMPLES:.0e} are generated"
        )
    f, z, a = _modal(kw["frequencies_hz"], kw["damping_ratios"], kw["amplitudes"], fs)
    n = f.size
    tap = _dof("tap_dof", kw["tap_dof"], n, n - 1)
    dofs, multi = _sensor_dofs(kw["sensor_dof"], n, tap)
    check_param("sensor", kw["sensor"], [Options({"displacement", "velocity", "acceleration"})], _OWNER)
    check_param("noise", kw["noise"], [Options({"white", "pink"})], _OWNER)
    _num("pre_trigger", kw["pre_trigger"], 0, 0.5)
    _num("offset", kw["offset"])
    for name in ("snr_db", "force_snr_db"):
        check_param(name, kw[name], [None, Interval(Real, None, None)], _OWNER)
    _num("quadratic_stiffness", kw["quadratic_stiffness"])
    _num("cubic_stiffness", kw["cubic_stiffness"])
    _num("damping_amplitude", kw["damping_amplitude"], 0, None, "left")
    _num("quadratic_damping", kw["quadratic_damping"], 0, None, "left")
    check_param("clip", kw["clip"], [None, Interval(Real, 0, 1, "right")], _OWNER)
    check_param("random_state", kw["random_state"], ["random_state"], _OWNER)
    contact_time, double_hit = _hammer(kw["contact_time"], kw["double_hit"], kw["force_amplitude"], fs)
    n_pre = int(round(kw["pre_trigger"] * n_samples))
    onset = (n_pre + math.ceil(contact_time * fs / 2 - 1e-9)) / fs - contact_time / 2
    starts = [onset] if double_hit is None else [onset, onset + double_hit[0]]
    if starts[-1] + contact_time >= (n_samples - 1) / fs:
        raise ValueError(
            f"the hit{'s' if double_hit else ''} (contact_time, double_hit) end after the record "
            f"(duration = {duration!r} s); lengthen the duration or lower pre_trigger"
        )
    hit_amps = [1.0] if double_hit is None else [1.0, double_hit[1]]
    out = dict(kw)
    out.update(
        contact_time=contact_time,
        double_hit=double_hit,
        tap_dof=tap,
        frequencies_hz=f,
        damping_ratios=z,
        amplitudes=a,
        n_samples=n_samples,
        sensor_dofs=dofs,
        multi_channel=multi,
        onset=onset,
        starts=np.array(starts),
        hit_amplitudes=np.array(hit_amps) * kw["force_amplitude"],
    )
    return SimpleNamespace(**out)

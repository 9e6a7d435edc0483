"""The single-mode hammer tests of the nonlinearity benchmarks and the pipeline that fits them.

Shared by ``nonlinearity`` (the test's verdicts) and ``model_backbone`` (the backbones): :func:`record`
draws the hammer test of a row (``linear``, ``cubic`` spring, amplitude-dependent ``damping``) with its
nonlinear coefficient set so that the true backbone shifts by the drawn amount over the kept band signal;
:func:`band` is the mode's band signal (``preprocess``), :func:`states` the band signal and its TVRegDiff
derivative, :func:`fit_and_test` ``ImpulseSINDy(feature_library=MechanicalLibrary())`` and the test for
nonlinearity on them. ``python -m benchmarks nonlinearity`` documents the records' ranges.
"""

from __future__ import annotations

import warnings

import numpy as np

from sindy_impulse import ImpulseSINDy, MechanicalLibrary
from sindy_impulse.analysis import nonlinearity_test
from sindy_impulse.datasets import impact_record
from sindy_impulse.differentiation import TVRegDiff, differentiate
from sindy_impulse.preprocessing import preprocess

ROWS = ("linear", "cubic", "damping")
MAX_PERIODS = 80


def draw(kind: str, seed: int) -> dict:
    """The record's parameters (one random stream per row and seed)."""
    rng = np.random.default_rng([seed, ROWS.index(kind)])
    return dict(
        f0=rng.uniform(20, 200),
        zeta=10 ** rng.uniform(np.log10(0.003), np.log10(0.02)),
        snr=rng.uniform(30, 60),
        spp=rng.uniform(25, 60),
        shift=rng.uniform(0.0035, 0.01),
        ratio=rng.uniform(1.6, 2.5),
    )


def _make(p: dict, seed: int, k3: float = 0.0, c2: float = 0.0):
    decay_db = p["snr"] + 25  # the band's SNR exceeds the wide-band one
    periods = min(MAX_PERIODS, np.log(10 ** (decay_db / 20)) / (2 * np.pi * p["zeta"])) + 25
    return impact_record(p["f0"], p["zeta"], [1.0], fs=p["spp"] * p["f0"], duration=periods / p["f0"] / 0.9,
                         snr_db=p["snr"], cubic_stiffness=k3, damping_amplitude=c2, random_state=seed)


def band(record, scale: float = 1.0, offset: float = 0.0):
    """The mode's band signal of the record in other units (times ``scale``, plus ``offset`` x its peak)."""
    f0 = record.modes.frequency_hz[0]
    y = scale * (record.y + offset * np.max(np.abs(record.y)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pre = preprocess(y, fs=record.fs, force=record.force, bands=[(f0 / 1.5, f0 * 1.5)])
    return pre.bands[0]


def amplitude_range(signal) -> tuple[float, float]:
    """Largest envelope over the first and smallest over the last twentieth of the band signal."""
    e = signal.envelope
    n = max(len(e) // 20, 1)
    return float(np.max(e[:n])), float(np.min(e[-n:]))


def _coefficient(kind: str, p: dict, record) -> dict:
    a_hi, a_lo = amplitude_range(band(record))
    truth = record.true_backbone
    d_hi, d_lo = truth.displacement_amplitude(a_hi), truth.displacement_amplitude(a_lo)
    w0 = 2 * np.pi * p["f0"]
    if kind == "cubic":  # omega(a)^2 = w0^2 + 3/4 k3 a^2
        s = p["shift"]
        return dict(k3=((1 + s) ** 2 - 1) * w0**2 / (0.75 * (d_hi**2 - (1 + s) ** 2 * d_lo**2)))
    r = p["ratio"]  # zeta(a) = zeta0 + c2 a^2 / (8 omega)
    return dict(c2=(r - 1) * p["zeta"] * 8 * w0 / (d_hi**2 - r * d_lo**2))


def record(kind: str, seed: int, **overrides):
    """The hammer test of row ``kind``, number ``seed``, and its drawn parameters (``overrides`` replace
    drawn ones, e.g. ``shift=0.03``).

    The kept amplitude range depends on the nonlinearity: the coefficient is a fixed point (at most eight
    passes, until the true shift over the kept band signal is within 1 % of the drawn one; when a pass
    leaves too short a decay for a band, the previous record is kept: the table reports the true shifts).
    """
    p = {**draw(kind, seed), **overrides}
    rec = _make(p, seed)
    target = p["shift"] if kind == "cubic" else p["ratio"] - 1
    for _ in range(8 if kind != "linear" else 0):
        previous, rec = rec, _make(p, seed, **_coefficient(kind, p, rec))
        try:
            f_shift, z_factor = true_shifts(rec, band(rec))
        except IndexError:  # the drawn shift is out of reach: the decay got too short for a band
            rec = previous
            break
        if abs((f_shift if kind == "cubic" else z_factor - 1) / target - 1) < 0.01:
            break
    return rec, p


def states(signal):
    """``(x, v)``: the band signal and its TVRegDiff derivative (the trimmed ends dropped), and time."""
    t = signal.t - signal.t[0]
    _, (derivative,) = differentiate(TVRegDiff(), [signal.y[:, None]], [t])
    x = np.column_stack([signal.y, derivative[:, 0]])
    keep = np.all(np.isfinite(x), axis=1)
    return x[keep], t[keep]


def true_shifts(rec, signal) -> tuple[float, float]:
    """True frequency shift and damping-ratio factor between the ends of the kept band signal."""
    a_hi, a_lo = amplitude_range(signal)
    (f_hi, z_hi), (f_lo, z_lo) = rec.true_backbone(a_hi), rec.true_backbone(a_lo)
    return f_hi / f_lo - 1, z_hi / z_lo


def fit_and_test(x, t):
    """The identification and the test, as a user runs them (warnings silenced: the budget may run out)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = ImpulseSINDy(feature_library=MechanicalLibrary()).fit(x, t=t, feature_names=["x", "v"])
        return model, nonlinearity_test(model, x, t)

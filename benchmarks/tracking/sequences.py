"""Synthetic test sequences of one structure for the tracker's study (``track_study.py``).

A *sequence* is one structure (a spring-mass chain of :func:`sindy_impulse.impact_record`) tested again
and again: 20 reference tests, then 40 new ones per row. Drawn per sequence (seed ``s``):

- 1-4 modes between 2 and 25 % of the Nyquist frequency, at least 3 % apart with their half-power bands
  apart; damping ratios 0.2-2 % (log-uniform); amplitudes within 20 dB of the strongest; fs 2,048, 5,000
  or 10,000 Hz; 4,000-16,000 samples; a random sensor kind, offset (0-2 x the peak) and pre-trigger;
- the SNR of a hit of nominal strength, 36-44 dB;
- the test-to-test scatter: every frequency of a test moved by one common factor ``1 + e``
  (temperature), ``e`` normal with a standard deviation ``tau`` of 0.02-0.05 %, and every damping ratio
  by ``1 + d``, ``d`` normal with 0-2 %;
- the mode that changes (``target``).

Per test: the hammer's strength ``g`` log-uniform in 0.5-2 (``amplitudes`` and ``force_amplitude``
scaled together, so that the chain is the same), the sensor's noise fixed, so the SNR is the nominal one
plus ``20 log10 g`` (30-50 dB). The rows change the new tests only:

====== =========================================================================================
row    the new tests
====== =========================================================================================
none   as the reference
stiff  the target's stiffness 0.5 % lower (its frequency times ``sqrt(0.995)``)
damp   the target's damping ratio 30 % higher
cubic  a cubic spring at mass 0 raising by 0.3 % the frequency of the mode it moves most (the cubic
       row's target, :func:`cubic_target`) at its amplitude at a nominal hit
drift  the target's frequency lowered 0.05 % more at every new test (test k: ``1 - 0.0005 k``)
====== =========================================================================================
"""

from __future__ import annotations

import numpy as np

from sindy_impulse import impact_record

ROWS = ("none", "stiff", "damp", "cubic", "drift")
SENSORS = ("displacement", "velocity", "acceleration")
N_REFERENCE, N_NEW = 20, 40
CUBIC_SHIFT = 0.003


def _separated(f, z, gap=0.03) -> bool:
    return all(
        f[i + 1] / f[i] - 1 >= gap and f[i + 1] - f[i] > z[i] * f[i] + z[i + 1] * f[i + 1]
        for i in range(len(f) - 1)
    )


def draw_sequence(seed: int) -> dict:
    """The structure and the scatter of one sequence (module docstring)."""
    rng = np.random.default_rng([seed, 38])
    fs = float(rng.choice([2048.0, 5000.0, 10000.0]))
    n_samples = int(rng.integers(4000, 16001))
    n_modes = int(rng.integers(1, 5))
    for _ in range(1000):
        f = np.sort(rng.uniform(0.02, 0.25, n_modes)) * fs / 2
        z = np.exp(rng.uniform(np.log(2e-3), np.log(2e-2), n_modes))
        if _separated(f, z):
            break
    return dict(
        seed=seed,
        fs=fs,
        duration=n_samples / fs,
        frequencies_hz=f.tolist(),
        damping_ratios=z.tolist(),
        amplitudes=(10 ** (-rng.uniform(0, 20, n_modes) / 20)).tolist(),
        sensor=str(rng.choice(SENSORS)),
        pre_trigger=float(rng.uniform(0.02, 0.1)),
        offset=float(rng.uniform(0, 2)),
        snr_db=float(rng.uniform(36, 44)),
        tau=float(rng.uniform(2e-4, 5e-4)),
        tau_damping=float(rng.uniform(0, 0.02)),
        target=int(rng.integers(n_modes)),
    )


def cubic_target(seq: dict) -> tuple[int, float]:
    """The mode a cubic spring at mass 0 moves most, and the ``k3`` that raises its frequency 0.3 % at its
    amplitude at a nominal hit: per mode ``d(w^2) / w^2 = 3/4 m0 phi0^2 k3 a^2 / w^2`` (``a`` its
    displacement at mass 0, ``phi0`` its mass-normalised shape there); the other modes move less."""
    linear = {
        k: seq[k]
        for k in ("frequencies_hz", "damping_ratios", "amplitudes", "fs", "duration", "sensor", "pre_trigger")
    }
    at_mass0 = impact_record(**linear, sensor_dof=0)
    omega = 2 * np.pi * np.asarray(seq["frequencies_hz"])
    a = np.abs(np.atleast_1d(at_mass0.modes.amplitude)) / omega ** SENSORS.index(seq["sensor"])
    per_k3 = 0.75 * at_mass0.chain.masses[0] * at_mass0.chain.mode_shapes[0] ** 2 * a**2 / omega**2
    m = int(np.argmax(per_k3))
    return m, float(((1 + CUBIC_SHIFT) ** 2 - 1) / per_k3[m])


def test_config(seq: dict, row: str, k: int) -> tuple[dict, dict]:
    """``impact_record`` arguments of test ``k`` of ``row`` (``row="reference"``: the reference tests) and
    the truth drawn for it (strength, frequency factor)."""
    rng = np.random.default_rng([seq["seed"], ROWS.index(row) + 1 if row in ROWS else 0, k])
    strength = float(np.exp(rng.uniform(np.log(0.5), np.log(2.0))))
    factor = 1 + seq["tau"] * rng.standard_normal()
    f = np.asarray(seq["frequencies_hz"]) * factor
    z = np.asarray(seq["damping_ratios"]) * (1 + seq["tau_damping"] * rng.standard_normal())
    m, extra = seq["target"], {}
    if row == "stiff":
        f[m] *= np.sqrt(0.995)
    elif row == "damp":
        z[m] *= 1.3
    elif row == "cubic":
        extra["cubic_stiffness"] = cubic_target(seq)[1]
    elif row == "drift":
        f[m] *= 1 - 0.0005 * (k + 1)
    config = dict(
        frequencies_hz=f.tolist(),
        damping_ratios=z.tolist(),
        amplitudes=(np.asarray(seq["amplitudes"]) * strength).tolist(),
        fs=seq["fs"],
        duration=seq["duration"],
        sensor=seq["sensor"],
        pre_trigger=seq["pre_trigger"],
        offset=seq["offset"],
        snr_db=seq["snr_db"] + 20 * np.log10(strength),
        force_amplitude=100.0 * strength,
        random_state=int(rng.integers(2**31)),
        **extra,
    )
    return config, {"strength": strength, "factor": float(factor)}


def records(seq: dict, row: str) -> tuple[list, list]:
    """The records of ``row`` (``"reference"``: 20 tests, else 40) and their truths."""
    n = N_REFERENCE if row == "reference" else N_NEW
    out, truth = [], []
    for k in range(n):
        config, true = test_config(seq, row, k)
        out.append(impact_record(**config))
        truth.append(true)
    return out, truth

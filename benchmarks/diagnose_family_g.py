"""What the nonlinear element of a family-g record does to each of its modes (``bench_modes.py --family g``).

    python benchmarks/diagnose_family_g.py --seed 0 10 13 24 35 37 39 55 58
    python benchmarks/diagnose_family_g.py --seed 0 37 --survey     # also the survey's answer
    python benchmarks/diagnose_family_g.py --seed 0 37 --survey --linear  # and without the element

Family g puts a cubic spring and / or an ``x^2 x'`` damper between the ground and mass 0 of the chain
(``impact_record``), calibrated on the *lowest* mode, and scores every mode on its linear (small-amplitude)
frequency and damping ratio. Mass 0 moves in every mode, so the element couples them. First-order averaging
of the modal equations (``q_i'' + ... + phi_i m0 (k3 x0^3 + c2 x0^2 x0') = 0``, ``x0 = sum_j phi_j q_j``)
gives, with ``X_j`` the displacement amplitude of mode j at mass 0:

- ``omega_i^2`` moves by ``3/4 m0 k3 phi_i^2 (X_i^2 + 2 sum_{j != i} X_j^2)``,
- ``2 zeta_i omega_i`` by ``m0 c2 phi_i^2 (X_i^2 / 4 + sum_{j != i} X_j^2 / 2)``.

The ``X_i`` part (self) is what a mode's own model, fitted on its own band, can see and extrapolate to zero
amplitude; the ``X_j`` part (cross) follows the *other* modes' amplitudes. For each mode the script prints
both at the hit and at the end of the mode's life in the record (where its band SNR reaches 0 dB, or the
record ends): a cross shift still beyond the marks (0.3 % / 10 %) there means the record never shows that
mode at its linear values while the others ring, and no model of its band alone can recover them. It also
lists the third-order combination tones of the other modes (``2 f_a +- f_b``, ``f_a + f_b +- f_c``, ``3 f_a``)
within 2 % of each mode: the cubic element puts them into the mode's band.
"""

from __future__ import annotations

import argparse
import itertools
import sys
import warnings
from pathlib import Path

import numpy as np

from sindy_impulse import identify_modes, impact_record

sys.path.insert(0, str(Path(__file__).resolve().parent))
from mode_families import _displacement_amplitude, band_snr_db, draw  # noqa: E402

NONLINEAR_TERMS = ("cubic_stiffness", "damping_amplitude", "quadratic_stiffness", "quadratic_damping",
                   "snr_db", "clip")


def shifts(config: dict, t: np.ndarray) -> dict:
    """Per mode (columns) and time (rows): relative frequency and damping-ratio shifts, self and cross."""
    linear = {k: v for k, v in config.items() if k not in NONLINEAR_TERMS}
    rec = impact_record(**linear, sensor_dof=0)
    x0 = np.array([_displacement_amplitude(abs(a), f, config["sensor"])
                   for a, f in zip(rec.modes.amplitude, rec.modes.frequency_hz)])
    phi, m0 = rec.chain.mode_shapes[0], rec.chain.masses[0]
    w = 2 * np.pi * np.asarray(config["frequencies_hz"])
    z = np.asarray(config["damping_ratios"])
    k3, c2 = config.get("cubic_stiffness", 0.0), config.get("damping_amplitude", 0.0)
    x2 = (x0 * np.exp(-np.outer(t, z * w))) ** 2
    cross2 = x2.sum(axis=1, keepdims=True) - x2
    return {
        "df_self": 0.375 * m0 * k3 * phi**2 * x2 / w**2,
        "df_cross": 0.375 * m0 * k3 * phi**2 * 2 * cross2 / w**2,
        "dz_self": m0 * c2 * phi**2 * x2 / 4 / (2 * w * z),
        "dz_cross": m0 * c2 * phi**2 * cross2 / 2 / (2 * w * z),
    }


def combination_tones(f: np.ndarray, i: int, within: float = 0.02) -> list[str]:
    """Third-order combinations of the other modes' frequencies within ``within`` of mode ``i``."""
    out = []
    others = [j for j in range(f.size) if j != i]
    for a, b in itertools.product(others + [i], repeat=2):
        for sign in (1, -1):
            if a == b == i:
                continue
            value = 2 * f[a] + sign * f[b]
            if a != b and abs(value / f[i] - 1) <= within:
                out.append(f"2 x {f[a]:.5g} {'+' if sign > 0 else '-'} {f[b]:.5g} = {value:.5g} Hz")
    for a, b, c in itertools.combinations(others, 3) if len(others) >= 3 else []:
        for value, words in ((f[a] + f[b] - f[c], f"{f[a]:.5g} + {f[b]:.5g} - {f[c]:.5g}"),
                             (f[a] - f[b] + f[c], f"{f[a]:.5g} - {f[b]:.5g} + {f[c]:.5g}"),
                             (f[b] + f[c] - f[a], f"{f[b]:.5g} + {f[c]:.5g} - {f[a]:.5g}")):
            if abs(value / f[i] - 1) <= within:
                out.append(f"{words} = {value:.5g} Hz")
    return out


def _survey(rec, f, z, label: str) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        found = identify_modes(rec.y, fs=rec.fs)
    for m in found.modes:
        j = int(np.argmin(np.abs(f / m.frequency_hz - 1)))
        print(f"    {label}: {m.frequency_hz:.6g} Hz (df/f {m.frequency_hz / f[j] - 1:+.1e}), zeta "
              f"{m.damping_ratio:.4g} (dz/z {m.damping_ratio / z[j] - 1:+.2f}), band "
              f"{m.band_hz[0]:.4g}-{m.band_hz[1]:.4g} Hz, {len(m.t)} samples, states {m.states.shape[1]}")
    for r in found.rejected:
        print(f"    {label}: rejected {r.band_hz}: {r.reason[:120]}")


def diagnose(case: dict, survey: bool, linear: bool = False) -> None:
    config = case["config"]
    rec = impact_record(**config)
    f, z = rec.modes.frequency_hz, rec.modes.damping_ratio
    snr = band_snr_db(rec)
    duration = config["duration"] * (1 - config["pre_trigger"])
    life = np.minimum(snr / 20 * np.log(10) / (z * 2 * np.pi * f), duration)
    terms = {k: f"{config[k]:.3g}" for k in ("cubic_stiffness", "damping_amplitude") if k in config}
    print(f"  {len(f)} modes, {config['sensor']}, {duration:.3g} s free decay, {terms}")
    for i in range(f.size):
        s0 = shifts(config, np.array([0.0]))
        s1 = shifts(config, np.array([life[i]]))
        row = {k: (v[0, i], s1[k][0, i]) for k, v in s0.items()}
        (a, b), (c, d) = row["df_self"], row["df_cross"]
        (e, g), (h, k) = row["dz_self"], row["dz_cross"]
        print(f"    {f[i]:9.5g} Hz zeta {z[i]:.4g} band SNR {snr[i]:5.1f} dB, life {life[i]:.3g} s: "
              f"df/f self {a:+.1e} -> {b:+.1e}, cross {c:+.1e} -> {d:+.1e}; "
              f"dz/z self {e:+.2f} -> {g:+.2f}, cross {h:+.2f} -> {k:+.2f}")
        tones = combination_tones(f, i)
        if tones:
            print(f"      combination tones within 2 %: {'; '.join(tones)}")
    if survey:
        _survey(rec, f, z, "survey")
    if linear:  # the same record (same noise seed) without the nonlinear element
        twin = {k: v for k, v in config.items() if k not in NONLINEAR_TERMS[:4]}
        _survey(impact_record(**twin), f, z, "without the element")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("indices", type=int, nargs="+", help="record indices of --family g at this seed")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--survey", action="store_true", help="also run identify_modes on each record")
    parser.add_argument("--linear", action="store_true",
                        help="also survey the record without the nonlinear element (same noise seed)")
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    cases = [draw("g", rng, i) for i in range(max(args.indices) + 1)]
    for i in args.indices:
        print(f"[g #{i}] seed {args.seed}")
        diagnose(cases[i], args.survey, args.linear)


if __name__ == "__main__":
    main()

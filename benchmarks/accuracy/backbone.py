"""Benchmark of the backbone curves (sindy_impulse.analysis.hilbert_backbone and backbone).

Run from the repository root with ``python -m benchmarks backbone [n_seeds]``. On the
free decays of ``tests/test_backbone.py`` (``x'' + (c0 + c2 x^2) x' + w0^2 x + k3 x^3 = 0`` at 10 Hz, 20
samples per period, fine-step RK4, SNR 40 dB), against first-order averaging over the middle 80 % of each
curve's amplitude range, prints the worst over seeds of:

1. hilbert_backbone: frequency and damping-ratio errors and the errors of the total shifts
   (targets 0.5 %, 20 %, 25 %);
2. backbone of the true equations: the same (targets 0.2 %, 10 %, 10 %);
3. linear decays: the shifts a flat backbone shows (its noise level);
4. the time of both on a 60,000-sample record.
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np

from benchmarks.accuracy import backbone_cases as cases
from sindy_impulse.analysis import backbone, hilbert_backbone


def _largest(values) -> float:
    values = [v for v in values if np.isfinite(v)]
    return max(values) if values else np.nan


def _worst(values):
    worst = _largest(values)
    return f"{100 * worst:.3g} %" if np.isfinite(worst) else "-"


def _keyed(errors) -> dict:
    """Worst relative errors of frequency, damping ratio and the two shifts, by name."""
    return dict(zip(("frequency", "damping_ratio", "frequency_shift", "damping_shift"),
                    (_largest(e) for e in errors)))


def data_accuracy(n_seeds: int) -> dict:
    print(f"1. hilbert_backbone, SNR 40 dB, {n_seeds} seeds (start phases alternating cos/sin):")
    out = {}
    for name, cfg in cases.CASES.items():
        rows = []
        for seed in range(n_seeds):
            t, y = cases.noisy(name, seed, phase=np.pi / 2 * (seed % 2))
            e = cases.errors(hilbert_backbone(y, t), cases.truth_of(*cfg[:3]))
            shifts = [e[f"{k}_shift"] if k in cases.SHIFTS[name] else np.nan for k in ("f", "z")]
            rows.append([e["f"], e["z"], *shifts])
        r = np.array(rows).T
        print(
            f"   {name:18s} zeta0={cfg[0]:<6} frequency {_worst(r[0])}, damping ratio {_worst(r[1])}, "
            f"frequency shift {_worst(r[2])}, damping shift {_worst(r[3])}"
        )
        out[name] = _keyed(r)
    return out


def model_accuracy() -> dict:
    print("2. backbone of the true equations:")
    out = {}
    for name, cfg in cases.CASES.items():
        e = cases.errors(backbone(cases.TrueModel(name)), cases.truth_of(*cfg[:3]))
        shifts = [e[f"{k}_shift"] if k in cases.SHIFTS[name] else np.nan for k in ("f", "z")]
        print(
            f"   {name:18s} frequency {_worst([e['f']])}, damping ratio {_worst([e['z']])}, "
            f"frequency shift {_worst(shifts[:1])}, damping shift {_worst(shifts[1:])}"
        )
        out[name] = _keyed([[e["f"]], [e["z"]], shifts[:1], shifts[1:]])
    return out


def linear_flatness(n_seeds: int) -> dict:
    print("3. linear decays, SNR 40 dB: worst |frequency_shift| and |damping_ratio_shift|:")
    out = {}
    for zeta, periods in [(0.001, 3000), (0.002, 1500), (0.005, 600), (0.01, 300), (0.02, 300)]:
        cases.CASES["linear"] = (zeta, 0.0, 1.0, periods)
        cases.decay.cache_clear()
        curves = []
        for seed in range(n_seeds):
            t, y = cases.noisy("linear", seed, phase=np.pi / 2 * (seed % 2))
            curves.append(hilbert_backbone(y, t))
        print(
            f"   zeta={zeta:<6} {periods:5d} periods: {_worst([abs(c.frequency_shift) for c in curves])}, "
            f"{_worst([abs(c.damping_ratio_shift) for c in curves])}"
        )
        out[f"zeta {zeta:g}"] = {"frequency_shift": _largest([abs(c.frequency_shift) for c in curves]),
                                 "damping_shift": _largest([abs(c.damping_ratio_shift) for c in curves])}
    del cases.CASES["linear"]
    return out


def timing() -> dict:
    t, y = cases.noisy("amplitude_damping")
    model = cases.TrueModel("amplitude_damping")
    calls = [("hilbert_backbone", lambda: hilbert_backbone(y, t)), ("backbone", lambda: backbone(model))]
    out = {}
    for label, call in calls:
        call()
        times = []
        for _ in range(5):
            start = time.perf_counter()
            call()
            times.append(time.perf_counter() - start)
        print(f"4. {label} on a {len(y)}-sample record: median {np.median(times):.3f} s")
        out[label] = float(np.median(times))
    return out


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("n_seeds", nargs="?", type=int, default=None, help="noise seeds (default 10)")
    parser.add_argument("--quick", action="store_true", help="3 seeds")
    args = parser.parse_args(argv)
    n = args.n_seeds or (3 if args.quick else 10)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return {"n_seeds": n, "hilbert_backbone": data_accuracy(n), "model_backbone": model_accuracy(),
                "linear_flatness": linear_flatness(n), "seconds": timing()}


if __name__ == "__main__":
    main()

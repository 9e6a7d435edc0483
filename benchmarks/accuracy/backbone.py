"""Benchmark of the backbone curves (sindy_impulse.analysis.hilbert_backbone and backbone).

Run from the repository root with ``PYTHONPATH=. python benchmarks/bench_backbone.py [n_seeds]``. On the
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

import time
import warnings

import numpy as np

from benchmarks.accuracy import backbone_cases as cases
from sindy_impulse.analysis import backbone, hilbert_backbone


def _worst(values):
    values = [v for v in values if np.isfinite(v)]
    return f"{100 * max(values):.3g} %" if values else "-"


def data_accuracy(n_seeds: int) -> None:
    print(f"1. hilbert_backbone, SNR 40 dB, {n_seeds} seeds (start phases alternating cos/sin):")
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


def model_accuracy() -> None:
    print("2. backbone of the true equations:")
    for name, cfg in cases.CASES.items():
        e = cases.errors(backbone(cases.TrueModel(name)), cases.truth_of(*cfg[:3]))
        shifts = [e[f"{k}_shift"] if k in cases.SHIFTS[name] else np.nan for k in ("f", "z")]
        print(
            f"   {name:18s} frequency {_worst([e['f']])}, damping ratio {_worst([e['z']])}, "
            f"frequency shift {_worst(shifts[:1])}, damping shift {_worst(shifts[1:])}"
        )


def linear_flatness(n_seeds: int) -> None:
    print("3. linear decays, SNR 40 dB: worst |frequency_shift| and |damping_ratio_shift|:")
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
    del cases.CASES["linear"]


def timing() -> None:
    t, y = cases.noisy("amplitude_damping")
    model = cases.TrueModel("amplitude_damping")
    calls = [("hilbert_backbone", lambda: hilbert_backbone(y, t)), ("backbone", lambda: backbone(model))]
    for label, call in calls:
        call()
        times = []
        for _ in range(5):
            start = time.perf_counter()
            call()
            times.append(time.perf_counter() - start)
        print(f"4. {label} on a {len(y)}-sample record: median {np.median(times):.3f} s")


if __name__ == "__main__":
    warnings.simplefilter("ignore")
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 10
    data_accuracy(n)
    model_accuracy()
    linear_flatness(n)
    timing()

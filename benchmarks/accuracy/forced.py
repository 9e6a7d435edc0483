"""A forced oscillator identified from its measured force and response (the issue "A true drop-in", item 3).

Run:  python -m benchmarks forced [--seeds 5]

System: x'' + c x' + k x = f(t)/m with k = 64, c = 0.8, m = 1 (8 rad/s, damping ratio 5 %), from rest, 10 s
at dt = 0.01, 40 dB noise on the response [x, v], the force exact
(:func:`sindy_impulse.datasets.forced_oscillator`). Forces: band-limited random (4 Hz, rms 10) and three
half-sine hammer hits (50 ms). Rows:

1. states [x, v] and the force as ``u``, ``ImpulseSINDy()`` (TVRegDiff, polynomial degree 3 on [x, v, f],
   threshold sweep and refinement driven by the force): errors of k, c and 1/m, terms (true 4); then the
   same with a degree-1 library;
2. the same without the force (the model cannot explain the response): k, c errors;
3. displacement only, delay-embedded (tau = 3 samples, m = 2, degree-1 library) with the force aligned by
   ``DelayEmbedding.transform_input`` (``delayed=True``: the force at each delay; ``False``: at the row's
   own time only): natural frequency and damping ratio from the model's eigenvalues.

Prints the median and worst relative error over the seeds and the median fit time.
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np
import pysindy as ps

from sindy_impulse import DelayEmbedding, ImpulseSINDy
from sindy_impulse.datasets import forced_oscillator

K, C, M = 64.0, 0.8, 1.0
WN, ZETA = np.sqrt(K / M), C / (2 * np.sqrt(K * M))


def states_with_force(data, use_force: bool = True, degree: int = 3):
    u = data.u if use_force else None
    model = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=degree))
    model.fit(data.x, t=data.t, u=u, feature_names=["x", "v", "f"][: 2 + use_force])
    names, coef = model.get_feature_names(), model.coefficients()
    k, c = (-coef[1, names.index(n)] if n in names else np.nan for n in ("x", "v"))
    g = coef[1, names.index("f")] if use_force else np.nan
    return {"k": abs(k / K - 1), "c": abs(c / C - 1), "1/m": abs(g * M - 1), "terms": model.complexity}


def embedded_with_force(data, delayed: bool, tau: int = 3):
    emb = DelayEmbedding(tau=tau, dimension=2).fit(data.x[:, 0])
    q, tq = emb.transform(data.x[:, 0]), emb.transform_time(data.t)
    uq = emb.transform_input(data.u, delayed=delayed)
    library = ps.PolynomialLibrary(degree=1, include_bias=False)
    model = ImpulseSINDy(feature_library=library).fit(q, t=tq, u=uq)
    eig = np.linalg.eigvals(model.coefficients()[:, :2])
    wn = float(np.max(np.abs(eig)))
    zeta = float(-eig[np.argmax(np.abs(eig))].real / wn)
    return {"wn": abs(wn / WN - 1), "zeta": abs(zeta / ZETA - 1), "terms": model.complexity}


CASES = {
    "states + force": lambda d: states_with_force(d),
    "states + force, degree-1 library": lambda d: states_with_force(d, degree=1),
    "states, force ignored": lambda d: states_with_force(d, use_force=False),
    "x embedded + force at the delays": lambda d: embedded_with_force(d, delayed=True),
    "x embedded + force at t only": lambda d: embedded_with_force(d, delayed=False),
}


def run(seeds: int) -> dict:
    warnings.simplefilter("ignore")
    print(f"k = {K}, c = {C}, m = {M} (wn = {WN:.3f} rad/s, zeta = {ZETA:.3f}); 40 dB on x, v; {seeds} seeds")
    out = {}
    for force in ("random", "hammer"):
        for label, case in CASES.items():
            rows, times = [], []
            for seed in range(seeds):
                data = forced_oscillator(force=force, snr_db=40, random_state=seed)
                t0 = time.perf_counter()
                rows.append(case(data))
                times.append(time.perf_counter() - t0)
            cells = []
            for key in rows[0]:
                values = np.array([r[key] for r in rows], dtype=float)
                if key == "terms":
                    cells.append(f"terms {int(np.min(values))}-{int(np.max(values))}")
                elif np.all(np.isfinite(values)):
                    med, worst = 100 * np.median(values), 100 * np.max(values)
                    cells.append(f"|d{key}| median {med:.3f}% max {worst:.3f}%")
            print(f"{force:6s} | {label:33s} | " + " | ".join(cells) + f" | {np.median(times):.1f} s")
            out[f"{force}: {label}"] = {
                "median": {k: float(np.median([r[k] for r in rows])) for k in rows[0]},
                "worst": {k: float(np.max([r[k] for r in rows])) for k in rows[0]},
                "median_seconds": float(np.median(times))}
    return out


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=None, help="seeds (default 5, quick 2)")
    parser.add_argument("--quick", action="store_true", help="2 seeds")
    args = parser.parse_args(argv)
    return run(args.seeds or (2 if args.quick else 5))


if __name__ == "__main__":
    main()

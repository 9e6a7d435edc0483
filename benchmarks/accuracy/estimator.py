"""Issue 3 acceptance: ImpulseSINDy on the paper's oscillator (sections 3.1.1, 3.1.2, noise, speed).

Run:  python -m benchmarks estimator [--seeds 20]

Oscillator x1' = x2, x2' = -64 x1 - 3.2 x2, x(0) = (1, 0), t in [0, 4], dt = 0.01, polynomial degree 3.
Prints the tables quoted in the README. Speeds are ratios measured in the same run.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import pysindy as ps

from sindy_impulse import ImpulseSINDy, damped_oscillator

TRUE = {(0, "x1"): 1.0, (1, "x0"): -64.0, (1, "x1"): -3.2}


def structure_ok(coef, names) -> bool:
    support = {(i, names[j]) for i, j in zip(*np.nonzero(coef))}
    return support == set(TRUE)


def k_c_errors(coef, names):
    k = -coef[1, names.index("x0")]
    c = -coef[1, names.index("x1")]
    return abs(k - 64) / 64, abs(c - 3.2) / 3.2


def describe(model) -> str:
    return " | ".join(model.equations(4))


def paper_cases() -> dict:
    t, x, x_dot = damped_oscillator()
    print("== 3.1.1 analytic derivatives (x_dot given)")
    m = ImpulseSINDy().fit(x, t=t, x_dot=x_dot)
    names = m.get_feature_names()
    dk, dc = k_c_errors(m.coefficients(), names)
    out = {"analytic_derivatives": {"terms": m.complexity, "k_error": dk, "c_error": dc, "gamma": m.gamma_}}
    print(f"  {describe(m)}")
    print(f"  terms {m.complexity} (true 3), |dk|/k {dk:.2e}, |dc|/c {dc:.2e}, Gamma {m.gamma_:.3g}")

    print("== 3.1.2 states only, TVRegDiff (paper: spurious cubic term before refinement, Gamma 2.345 after)")
    m = ImpulseSINDy().fit(x, t=t)
    names = m.get_feature_names()
    print(
        f"  selected before refinement ({m.path_.n_terms[m.path_.selected]} terms): "
        f"Gamma {m.gamma_sindy_:.4f}"
    )
    print(f"  after refinement: {describe(m)}")
    dk, dc = k_c_errors(m.coefficients(), names)
    print(
        f"  terms {m.complexity}, |dk|/k {100 * dk:.4f}% (<= 0.2%), |dc|/c {100 * dc:.4f}% (<= 1%), "
        f"Gamma {m.gamma_:.4f} (paper 2.345)"
    )
    m_paper = ImpulseSINDy(selection="min_gamma").fit(x, t=t)
    print(
        f"  selection='min_gamma' (the paper's rule): {m_paper.complexity} terms, Gamma {m_paper.gamma_:.4f}"
    )
    out["tvregdiff"] = {"terms": m.complexity, "k_error": dk, "c_error": dc, "gamma": m.gamma_,
                        "min_gamma_terms": m_paper.complexity, "min_gamma_gamma": m_paper.gamma_}
    return out


def noise_table(n_seeds: int) -> list:
    print(f"\n== noise, both states measured, {n_seeds} seeds per level, degree 3")
    header = (
        f"  {'method':34s} {'SNR':>4s} {'structure':>10s} {'median |dk|/k':>14s} {'median |dc|/c':>14s} "
        f"{'median fit s':>12s}"
    )
    print(header)
    methods = {
        "ImpulseSINDy (auto)": lambda: ImpulseSINDy(),
        "ImpulseSINDy (min_gamma, paper)": lambda: ImpulseSINDy(selection="min_gamma"),
        "PySINDy STLSQ(0.1)+SmoothedFD": lambda: ps.SINDy(
            optimizer=ps.STLSQ(),
            feature_library=ps.PolynomialLibrary(degree=3),
            differentiation_method=ps.SmoothedFiniteDifference(),
        ),
    }
    rows = []
    for snr in (40, 30, 20):
        for label, make in methods.items():
            ok, dks, dcs, times = 0, [], [], []
            for seed in range(n_seeds):
                t, x, _ = damped_oscillator(snr_db=snr, random_state=seed)
                model = make()
                t0 = time.perf_counter()
                model.fit(x, t=t)
                times.append(time.perf_counter() - t0)
                coef = model.coefficients()
                names = model.get_feature_names()
                ok += structure_ok(coef, names)
                dk, dc = k_c_errors(coef, names)
                dks.append(dk)
                dcs.append(dc)
            print(
                f"  {label:34s} {snr:4d} {100 * ok / n_seeds:9.0f}% {100 * np.median(dks):13.3f}% "
                f"{100 * np.median(dcs):13.3f}% {np.median(times):12.3f}"
            )
            rows.append({"method": label, "snr_db": snr, "structure_right": ok / n_seeds,
                         "median_k_error": np.median(dks), "median_c_error": np.median(dcs),
                         "median_fit_seconds": np.median(times)})
    return rows


def speed() -> dict:
    print("\n== speed (ratios in one run)")
    t, x, x_dot = damped_oscillator()
    model = ImpulseSINDy().fit(x, t=t)
    plain = ps.SINDy(feature_library=ps.PolynomialLibrary(degree=3), optimizer=ps.STLSQ(threshold=0.5))
    plain.fit(x, t=t, x_dot=x_dot)
    plain.optimizer.coef_ = model.coefficients().copy()  # the same model in PySINDy
    t0 = time.perf_counter()
    ref = plain.simulate(x[0], t)
    t_pysindy = time.perf_counter() - t0
    model.simulate(x[0], t)
    reps = 200
    t0 = time.perf_counter()
    for _ in range(reps):
        ours = model.simulate(x[0], t)
    t_ours = (time.perf_counter() - t0) / reps
    print(
        f"  simulate 401 samples: PySINDy {t_pysindy * 1e3:.1f} ms, ours {t_ours * 1e6:.1f} us, ratio "
        f"{t_pysindy / t_ours:.0f}x (>= 1000x); max |difference| {np.max(np.abs(ours - ref)):.2e}"
    )
    fits = []
    for seed in range(11):
        _, xn, _ = damped_oscillator(snr_db=40, random_state=seed)
        t0 = time.perf_counter()
        ImpulseSINDy().fit(xn, t=t)
        fits.append(time.perf_counter() - t0)
    t0 = time.perf_counter()
    for _ in range(20):
        np.linalg.lstsq(np.random.default_rng(0).normal(size=(401, 20)), x_dot, rcond=None)
    t_lstsq = (time.perf_counter() - t0) / 20
    print(
        f"  full fit (auto-alpha TVRegDiff, sweep, refinement), 40 dB: median {np.median(fits):.3f} s "
        f"(<= 0.5 s), min {np.min(fits):.3f} s, max {np.max(fits):.3f} s; "
        f"= {np.median(fits) / t_lstsq:.0f}x one 401x20 least-squares solve"
    )
    return {"simulate_pysindy": t_pysindy, "simulate_ours": t_ours, "simulate_ratio": t_pysindy / t_ours,
            "fit_median": np.median(fits), "fit_over_lstsq": np.median(fits) / t_lstsq}


def main(argv=None) -> dict:
    formatter = argparse.RawDescriptionHelpFormatter
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=formatter)
    parser.add_argument("--seeds", type=int, default=None, help="noise seeds per level (default 20, quick 5)")
    parser.add_argument("--quick", action="store_true", help="5 seeds per level")
    args = parser.parse_args(argv)
    seeds = args.seeds or (5 if args.quick else 20)
    return {"paper": paper_cases(), "noise": noise_table(seeds), "seconds": speed()}


if __name__ == "__main__":
    main()

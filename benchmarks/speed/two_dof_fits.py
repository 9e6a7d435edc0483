"""``ImpulseSINDy().fit`` on random 2-DOF systems, 4 measured states: its time and whether it is right.

Issue 36's fifth goal (speed beyond the benchmark's own cases). Each system: two unit masses whose natural
frequencies are drawn in 1-10 Hz and damping ratios in 0.5-5 % (proportional damping, mode shapes at a
random angle), struck on the first mass (initial velocity 1, rest elsewhere), 1,500 samples of the four
states (both displacements and velocities) at 100 Hz and at 500 Hz, 40 dB of white noise. A fit is right
when its model has no nonlinear term and both natural frequencies of its linear part lie within 1 % of the
truth. The baseline, timed in the same run beside every fit: the paper's oscillator (the estimator's own
benchmark case).

Run from the repository root::

    python -m benchmarks two_dof_fits            # 20 systems at each rate
    python -m benchmarks two_dof_fits --quick    # 5
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np
from scipy.integrate import solve_ivp


def system(rng: np.random.Generator) -> dict:
    """One random 2-DOF system: natural frequencies (Hz), damping ratios, stiffness and damping matrices."""
    f = np.sort(rng.uniform(1.0, 10.0, 2))
    while f[1] / f[0] < 1.05:  # two modes the record can tell apart
        f = np.sort(rng.uniform(1.0, 10.0, 2))
    zeta = rng.uniform(0.005, 0.05, 2)
    angle = rng.uniform(0.2, np.pi / 2 - 0.2)  # both masses move in both modes
    phi = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    w = 2 * np.pi * f
    return dict(frequency_hz=f, damping_ratio=zeta, K=phi @ np.diag(w**2) @ phi.T,
                C=phi @ np.diag(2 * zeta * w) @ phi.T)


def free_decay(sys: dict, fs: float, n: int = 1500, snr_db: float = 40.0, seed: int = 0):
    """The struck system's four states ``(x1, v1, x2, v2)`` sampled at ``fs``, with noise."""
    from sindy_impulse.datasets import add_noise

    K, C = sys["K"], sys["C"]

    def rhs(_t, y):
        a = -K @ y[[0, 2]] - C @ y[[1, 3]]
        return [y[1], a[0], y[3], a[1]]

    t = np.arange(n) / fs
    x = solve_ivp(rhs, (0, t[-1]), [0.0, 1.0, 0.0, 0.0], t_eval=t, method="DOP853", rtol=1e-11,
                  atol=1e-13).y.T
    return t, add_noise(x, snr_db, random_state=seed)


def _fit(t, x):
    from sindy_impulse import ImpulseSINDy

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        start = time.perf_counter()
        model = ImpulseSINDy().fit(x, t=t)
        return model, time.perf_counter() - start


def judge(model, sys: dict) -> dict:
    """Terms, nonlinear terms and the natural frequencies' relative errors of a fitted model."""
    from sindy_impulse.analysis import modal_parameters

    names = model.get_feature_names()
    coef = np.asarray(model.coefficients())
    used = np.any(coef != 0, axis=0)
    nonlinear = [n for n, u in zip(names, used) if u and ("^" in n or " " in n.strip())]
    try:
        f, _ = modal_parameters(model)
        f = np.sort(np.asarray(f, float)[np.isfinite(f)])
    except (ValueError, np.linalg.LinAlgError):
        f = np.array([])
    truth = sys["frequency_hz"]
    error = np.abs(f / truth - 1) if f.size == 2 else np.array([np.inf, np.inf])
    return dict(terms=int(np.count_nonzero(coef)), nonlinear_terms=nonlinear,
                frequency_errors=error.tolist(),
                right=bool(not nonlinear and np.all(error <= 0.01)))


def main(argv=None) -> dict:
    formatter = argparse.RawDescriptionHelpFormatter
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=formatter)
    parser.add_argument("--n", type=int, default=None, help="systems per rate (default 20, quick 5)")
    parser.add_argument("--seed", type=int, default=2026)
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args(argv)
    n = args.n or (5 if args.quick else 20)
    from sindy_impulse import damped_oscillator

    paper = damped_oscillator(snr_db=40, random_state=0)
    _fit(paper.t, paper.x)  # compile and warm up once
    rng = np.random.default_rng(args.seed)
    systems = [system(rng) for _ in range(n)]
    out = {"systems": n, "seed": args.seed, "rates": {}}
    for fs in (100.0, 500.0):
        rows = []
        for k, sys in enumerate(systems):
            t, x = free_decay(sys, fs, seed=k)
            model, seconds = _fit(t, x)
            _, baseline = _fit(paper.t, paper.x)
            row = dict(judge(model, sys), seconds=seconds, baseline_seconds=baseline,
                       frequency_hz=sys["frequency_hz"].tolist(),
                       damping_ratio=sys["damping_ratio"].tolist())
            rows.append(row)
            print(f"  {fs:g} Hz #{k}: f {sys['frequency_hz'].round(3).tolist()} Hz, zeta "
                  f"{(100 * sys['damping_ratio']).round(2).tolist()} %: {seconds:.3f} s (paper's case "
                  f"{baseline:.3f} s), {row['terms']} terms, errors "
                  f"{[f'{e:.2%}' for e in row['frequency_errors']]}"
                  + ("" if row["right"] else f"  WRONG {row['nonlinear_terms']}"), flush=True)
        seconds = np.array([r["seconds"] for r in rows])
        base = np.array([r["baseline_seconds"] for r in rows])
        right = sum(r["right"] for r in rows)
        summary = dict(median_s=float(np.median(seconds)), slowest_s=float(seconds.max()),
                       baseline_median_s=float(np.median(base)), right=right, n=len(rows),
                       ratio_median=float(np.median(seconds / base)))
        out["rates"][f"{fs:g}"] = dict(summary, rows=rows)
        print(f"{fs:g} Hz: median {summary['median_s']:.3f} s, slowest {summary['slowest_s']:.3f} s "
              f"(goal 0.3 / 0.6 s; the paper's case {summary['baseline_median_s']:.3f} s in the same run, "
              f"median ratio {summary['ratio_median']:.2f}); right {right} of {len(rows)} (goal 95 %)",
              flush=True)
    return out


if __name__ == "__main__":
    main()

"""Benchmark of sindy_impulse.analysis and SINDyFeatures on the paper's studies (sections 3.3 and 3.4).

Run from the repository root with ``python -m benchmarks analysis``. Prints, with the acceptance criterion of
each:

1. 3.3.2 consensus over the 36 initial conditions of Figure 12 (degree 1, clean data), beside the paper;
2. 3.3.1 parameter dependency along the damping delta in [0.1, 0.3] (c = 2 delta sqrt(k));
3. 3.3.3 the nonlinearity test on k_nl in {0, 10}, deflections 0.5, 1, 2, SNR 40 dB, 10 seeds each;
4. 3.4 the 80-series clustering study with SINDyFeatures, against FFT-magnitude features, with timing;
5. modal parameters at SNR 40 dB from both states and from x1 through the delay embedding.
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np
import pysindy as ps
from sklearn.base import clone
from sklearn.cluster import KMeans
from sklearn.decomposition import PCA
from sklearn.metrics import adjusted_rand_score
from sklearn.pipeline import Pipeline
from sklearn.preprocessing import StandardScaler

from sindy_impulse import DelayEmbedding, ImpulseSINDy, SINDyFeatures, damped_oscillator
from sindy_impulse.analysis import consensus, modal_parameters, nonlinearity_test, parameter_dependency
from sindy_impulse.analysis.consensus import consensus_fit

K, C, DT = 64.0, 3.2, 0.01
F_TRUE, ZETA_TRUE = np.sqrt(K) / (2 * np.pi), C / (2 * np.sqrt(K))


def linear_estimator(**kwargs):
    return ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=1), **kwargs)


def ok(flag: bool) -> str:
    return "PASS" if flag else "FAIL"


def section(title: str) -> None:
    print(f"\n{'=' * 100}\n{title}\n{'=' * 100}")


# ------------------------------------------------------------------------------------------------------
def bench_consensus() -> dict:
    section("3.3.2 Consensus over 36 initial conditions (Figure 12), degree 1, k=64, c=3.2, t in [0, 4]")
    levels = [1, 0.6, 0.2, -0.2, -0.6, -1]
    out = {}
    for snr in (None, 40):
        rings = [
            damped_oscillator(x0=(a, v), snr_db=snr, random_state=i)
            for i, (a, v) in enumerate((a, v) for a in levels for v in levels)
        ]
        t0 = time.perf_counter()
        models = [linear_estimator().fit(r.x, t=r.t) for r in rings]
        fit_time = time.perf_counter() - t0
        mode, median = consensus(models), consensus(models, method="median")
        stacked = consensus_fit(linear_estimator(), [r.x for r in rings], t=DT)
        label = "clean" if snr is None else f"SNR {snr} dB"
        print(f"\n[{label}] 36 fits in {fit_time:.1f} s")
        print(
            f"{'coefficient':<14}{'truth':>9}{'paper':>9}{'mode':>11}{'median':>11}{'stacked':>11}"
            f"{'nonzero':>9}{'IQR':>10}"
        )
        rows = [((0, 2), 1.0, 0.983), ((1, 1), -64.0, -64.6), ((1, 2), -3.2, -3.2)]
        worst = 0.0
        for (i, k), truth, paper in rows:
            name = mode.names()[(i, k)]
            m = mode.coefficients[i, k]
            worst = max(worst, abs(m / truth - 1))
            print(
                f"{name:<14}{truth:>9.3f}{paper:>9.3f}{m:>11.4f}{median.coefficients[i, k]:>11.4f}"
                f"{stacked.coefficients[i, k]:>11.4f}{mode.frequency_nonzero[i, k]:>9.2f}"
                f"{mode.spread[i, k]:>10.2e}"
            )
        others = np.delete(mode.coefficients.ravel(), [2, 4, 5])
        print(f"other coefficients of the consensus: max |xi| = {np.max(np.abs(others)):.3g}")
        crit = worst < 0.01 and np.all(others == 0)
        print(
            f"criterion (clean data): consensus within 1 % of (1, -64, -3.2): worst {worst:.2e} "
            f"-> {ok(crit) if snr is None else '(extra, not a criterion) ' + ok(crit)}"
        )
        out[label] = {"worst_relative_error": worst, "passed": bool(crit), "fit_seconds": fit_time}
    return out


# ------------------------------------------------------------------------------------------------------
def bench_parameters() -> dict:
    section("3.3.1 Parameter dependency: delta in [0.1, 0.3], c = 2 delta sqrt(k), reference delta = 0.2")
    deltas = np.round(np.linspace(0.1, 0.3, 9), 3)
    models = [linear_estimator().fit(damped_oscillator(c=2 * d * np.sqrt(K)).x, t=DT) for d in deltas]
    dep = parameter_dependency(models, deltas, reference=0.2, threshold=0.01)
    names = dep.names()
    print(
        f"{'coefficient':<14}{'ref':>10}" + "".join(f"{d:>8.3f}" for d in dep.values) + f"{'max|d|':>10}"
        f"{'elast.':>8}  varies"
    )
    for i, k in zip(*np.nonzero(np.any(dep.coefficients != 0, axis=0))):
        ratios = "".join(f"{r:>8.3f}" for r in dep.ratio[:, i, k])
        print(
            f"{names[i, k]:<14}{dep.coefficients[dep.reference_index, i, k]:>10.3f}{ratios}"
            f"{dep.max_change[i, k]:>10.2e}{dep.elasticity[i, k]:>8.3f}  {bool(dep.varies[i, k])}"
        )
    print("(columns: xi / xi_ref per delta, as in Figure 11)")
    crit = dep.varying_terms == ["x1' : x1"]
    print(f"varying terms (> 1 %): {dep.varying_terms}; invariant: {dep.invariant_terms}")
    print(f"criterion: only the damping coefficient changes by more than 1 % -> {ok(crit)}")
    return {"varying_terms": dep.varying_terms, "passed": bool(crit)}


# ------------------------------------------------------------------------------------------------------
def bench_nonlinearity() -> dict:
    section(
        "3.3.3 Test for nonlinearity: k_nl in {0, 10}, x0 = (a, 0), a in {0.5, 1, 2}, SNR 40 dB, 10 seeds"
    )
    right = total = 0
    t0 = time.perf_counter()
    print(f"{'k_nl':>5}{'a':>5}{'right':>8}{'growth (min / median / max)':>32}{'cubic coef (median)':>22}")
    for case, (k_nl, a) in enumerate((k, a) for k in (0.0, 10.0) for a in (0.5, 1.0, 2.0)):
        growth, cubic, n_right = [], [], 0
        for seed in range(10):
            ring = damped_oscillator(k_nl=k_nl, x0=(a, 0.0), snr_db=40, random_state=1000 * case + seed)
            model = ImpulseSINDy().fit(ring.x, t=ring.t)
            res = nonlinearity_test(model, ring.x, ring.t)
            n_right += res.nonlinear == (k_nl > 0)
            growth.append(res.relative_growth)
            cubic += [t.coefficient for t in res.terms if t.term == "x0^3" and res.nonlinear]
        right += n_right
        total += 10
        g = np.array(growth)
        c = f"{np.median(cubic):.2f}" if cubic else "-"
        print(
            f"{k_nl:>5.0f}{a:>5.1f}{n_right:>6}/10{np.min(g):>12.3f}{np.median(g):>10.3f}{np.max(g):>10.3f}"
            f"{c:>22}"
        )
    rate = right / total
    print(
        f"(growth = (Gamma_linear - Gamma_nonlinear) / Gamma_nonlinear; decision: significance and amplitude "
        f"dependence, see nonlinearity_test)\n{right}/{total} right ({rate:.1%}) in "
        f"{time.perf_counter() - t0:.1f} s (fit + test)"
    )
    print(f"criterion: right in >= 95 % of cases -> {ok(rate >= 0.95)}")
    return {"right": right, "total": total, "passed": bool(rate >= 0.95)}


# ------------------------------------------------------------------------------------------------------
def fft_features(series: list[np.ndarray], n_bins: int = 40) -> np.ndarray:
    """Generic baseline: magnitudes of the FFT of x1 (first n_bins bins)."""
    return np.array([np.abs(np.fft.rfft(s[:, 0]))[:n_bins] for s in series])


def cluster_ari(X: np.ndarray, labels: np.ndarray) -> float:
    pipe = Pipeline(
        [("scale", StandardScaler()), ("pca", PCA(2)), ("km", KMeans(2, random_state=0, n_init=10))]
    )
    return adjusted_rand_score(labels, pipe.fit_predict(X))


def _spin(n: int) -> int:
    total = 0
    for i in range(n):
        total += i * i
    return total


def cpu_speedup() -> float:
    """Speed-up of 2 joblib processes over 1 on a pure-Python loop: what this machine gives right now."""
    from joblib import Parallel, delayed

    Parallel(n_jobs=2)(delayed(_spin)(10) for _ in range(2))  # start the workers
    t0 = time.perf_counter()
    for _ in range(4):
        _spin(4_000_000)
    serial = time.perf_counter() - t0
    t0 = time.perf_counter()
    Parallel(n_jobs=2)(delayed(_spin)(4_000_000) for _ in range(4))
    return serial / (time.perf_counter() - t0)


def bench_features() -> dict:
    section(
        "3.4 Feature generation: 80 ring-downs, k ~ U[36, 400], k_nl in {0, 50} (40 each), c = 3.2, "
        "x0 = (1, 0), both states, degree 3"
    )
    rng = np.random.default_rng(0)
    ks = rng.uniform(36, 400, 80)
    k_nl = np.repeat([0.0, 50.0], 40)
    labels = (k_nl > 0).astype(int)
    series = [damped_oscillator(k=k, c=C, k_nl=kn).x for k, kn in zip(ks, k_nl)]
    print(f"FFT magnitude baseline (40 bins of x1): ARI = {cluster_ari(fft_features(series), labels):.3f}")

    paper_rule = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=3), selection="min_gamma")
    configs = [
        ("default template ImpulseSINDy() (selection='auto')", None),
        ("paper's rule: ImpulseSINDy(selection='min_gamma')", paper_rule),
    ]
    results = {}
    for label, est in configs:
        feats = SINDyFeatures(estimator=est, dt=DT, n_jobs=2)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            t0 = time.perf_counter()
            X = feats.fit_transform(series)
            elapsed = time.perf_counter() - t0
        cubic = X[:, list(feats.get_feature_names_out()).index("x1' : x0^3")]
        found = (cubic != 0).astype(int)
        ari = cluster_ari(np.nan_to_num(X), labels)
        results[label] = (X, elapsed, ari)
        print(
            f"\n{label}\n  n_jobs=2: {elapsed:.1f} s, failed reconstructions: {feats.n_failed_}, "
            f"x0^3 term found in {found[:40].sum()}/40 linear and {found[40:].sum()}/40 Duffing series; "
            f"ARI = {ari:.3f}"
        )
        missed = np.flatnonzero(found != labels)
        for j in missed[:3]:
            diag_auto = ImpulseSINDy().fit(series[j], t=DT)
            diag_paper = clone(paper_rule).fit(series[j], t=DT)
            print(
                f"  series {j} (k = {ks[j]:.1f}, k_nl = {k_nl[j]:.0f}): "
                f"auto -> {diag_auto.complexity} terms, "
                f"Gamma {diag_auto.gamma_:.3g}; min_gamma -> {diag_paper.complexity} terms, "
                f"Gamma {diag_paper.gamma_:.3g}"
            )

    label = configs[1][0]
    X, t2, ari = results[label]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        t0 = time.perf_counter()
        X1 = SINDyFeatures(estimator=paper_rule, dt=DT, n_jobs=1).fit_transform(series)
        t1 = time.perf_counter() - t0
    same = np.array_equal(np.nan_to_num(X1), np.nan_to_num(X))
    print(
        f"\ncalibration: 2 processes vs 1 on a pure-Python loop give {cpu_speedup():.2f}x on this machine now"
    )
    print(
        f"{label}: n_jobs=1 {t1:.1f} s, n_jobs=2 {t2:.1f} s, speed-up {t1 / t2:.2f}x "
        f"(identical features: {same})"
    )
    print(
        f"criteria ({label}): zero failures, ARI >= 0.95, <= 20 s with n_jobs=2 -> "
        f"ARI {ari:.3f} {ok(ari >= 0.95)}, time {ok(t2 <= 20)}"
    )
    return {"ari": ari, "seconds_n_jobs_1": t1, "seconds_n_jobs_2": t2, "identical_features": bool(same),
            "passed": bool(ari >= 0.95)}


# ------------------------------------------------------------------------------------------------------
def bench_modal() -> dict:
    section(f"Modal parameters at SNR 40 dB (truth {F_TRUE:.4f} Hz, zeta {ZETA_TRUE:.3f}), 10 seeds")
    out = {}
    for label, embed in (("both states", False), ("x1 + delay embedding", True)):
        f_err, z_err = [], []
        for seed in range(10):
            ring = damped_oscillator(snr_db=40, random_state=seed)
            if embed:
                emb = DelayEmbedding().fit(ring.x[:, 0])
                model = ImpulseSINDy().fit(emb.transform(ring.x[:, 0]), t=DT)
            else:
                model = ImpulseSINDy().fit(ring.x, t=ring.t)
            f, z = modal_parameters(model)
            f_err.append(abs(f[0] / F_TRUE - 1) if f.size else np.inf)
            z_err.append(abs(z[0] / ZETA_TRUE - 1) if z.size else np.inf)
        crit = max(f_err) < 0.005 and max(z_err) < 0.05
        print(
            f"{label:<24} max |df/f| = {max(f_err):.2e}, max |dzeta/zeta| = {max(z_err):.2e} "
            f"(criteria 0.5 %, 5 %) -> {ok(crit)}"
        )
        out[label] = {"max_frequency_error": max(f_err), "max_damping_error": max(z_err),
                      "passed": bool(crit)}
    return out


def main(argv=None) -> dict:
    argparse.ArgumentParser(description=__doc__.splitlines()[0]).parse_args(argv)
    start = time.perf_counter()
    result = {"consensus": bench_consensus(), "parameter_dependency": bench_parameters(),
              "nonlinearity_test": bench_nonlinearity(), "features": bench_features(),
              "modal_parameters": bench_modal()}
    print(f"\ntotal {time.perf_counter() - start:.0f} s")
    return result


if __name__ == "__main__":
    main()

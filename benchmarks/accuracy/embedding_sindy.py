"""Benchmark: single-sensor identification, DelayEmbedding + ImpulseSINDy (paper sections 3.1.3 and 3.2).

Run with ``python -m benchmarks embedding_sindy`` from the repository root. Prints:

1. Table 1 of the paper: x1 of the oscillator (x1'' = -64 x1 - 3.2 x1', x(0) = (1, 0), 4 s at dt = 0.01)
   embedded (tau, m estimated), then ImpulseSINDy with PolynomialLibrary degrees p = 1..5: terms, Gamma
   before/after refinement (against the filtered states, the estimator's own), Gamma against the embedded
   trajectories q (the paper's definition), stability over ten times the record, fit time, the equations
   next to the paper's, and the modal parameters implied by the p = 1 model.
2. Figure 10b: s = beta x1 + (1 - beta) x2 for beta = 0, 0.05, .., 1 times p = 1..4 (84 fits) with
   :func:`sindy_impulse.analysis.complexity_error`, serial and with n_jobs=2; the complexity/Gamma summary.
3. Table 1 again on x1 with 40 dB SNR noise (five seeds), with the estimator's selection rule ("auto"),
   the paper's ("min_gamma") and a proposed variant of "auto" with a knee test (see ``proposed_auto``).
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np
import pysindy as ps

from sindy_impulse import DelayEmbedding, ImpulseSINDy
from sindy_impulse.analysis import complexity_error
from sindy_impulse.datasets import add_noise, damped_oscillator
from sindy_impulse.feature_library.terms import term_table
from sindy_impulse.identification.refinement import refine_coefficients
from sindy_impulse.identification.selection import HOPELESS, NOISE_TOL, REL_TOL
from sindy_impulse.simulation import CompiledModel, simulation_gamma
from sindy_impulse.simulation.scoring import gamma_from_arrays

DT = 0.01
K, C = 64.0, 3.2
DEGREES = (1, 2, 3, 4, 5)
SEEDS = range(5)

# Table 1 of the paper as printed (Gamma after refinement, number of non-zero entries, equations). The
# paper's states appear in the other order than ours (its matrix for p = 1 is ours with q1 and q2
# exchanged: see the exact matrices printed below), so its equations are listed as printed.
PAPER = {
    1: (1.88, 5, ["q1' = -0.74 q1 - 5.84 q2", "q2' = -0.0081 + 10.60 q1 - 2.45 q2"]),
    2: (1.82, 6, ["q1' = -0.75 q1 - 5.82 q2 - 0.06 q1 q2", "q2' = -0.0071 + 10.62 q1 - 2.45 q2"]),
    3: (1.63, 7, ["q1' = -0.81 q1 - 5.84 q2 - 0.13 q1 q2 + 0.51 q1^2 q2 + 0.16 q2^3",
                  "q2' = 10.60 q1 - 2.39 q2"]),
    4: (1.64, 7, ["q1' = -0.85 q1 - 5.86 q2 + 0.708 q1^2 q2 - 0.96 q1^3 q2 - 1.44 q1 q2^3",
                  "q2' = 10.54 q1 - 2.36 q2"]),
    5: (159.66, 13, ["failed (Gamma = 159.66, 13 non-zero entries after optimization)"]),
}


def _library(p: int):
    return ps.PolynomialLibrary(degree=p)


def exact_delay_matrix(tau_s: float) -> np.ndarray:
    """The linear system in delay coordinates q = (x1(t - tau), x1(t)): M = T A T^-1."""
    from scipy.linalg import expm

    a = np.array([[0.0, 1.0], [-K, -C]])
    t = np.vstack([expm(-a * tau_s)[0], [1.0, 0.0]])
    return t @ a @ np.linalg.inv(t)


def modal(coef_2x2: np.ndarray) -> tuple[float, float]:
    lam = np.linalg.eigvals(coef_2x2)
    lam = lam[np.argmax(lam.imag)]
    return float(abs(lam)), float(-lam.real / abs(lam))


def linear_block(model) -> np.ndarray:
    names = model.get_feature_names()
    return model.coefficients()[:, [names.index(n) for n in model.feature_names_]]


def long_run_ok(model, q: np.ndarray, factor: int = 10) -> bool:
    """Simulated over ``factor`` times the record from q(0): finite and never beyond the data's peak."""
    t_long = np.arange(factor * len(q)) * DT
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        sim = model.simulate(q[0], t_long)
    return bool(np.all(np.isfinite(sim)) and np.max(np.abs(sim)) <= 1.5 * np.max(np.abs(q)))


def fmt(x: float, width: int = 9) -> str:
    return f"{x:{width}.4f}" if np.isfinite(x) and abs(x) < 1e4 else f"{x:>{width}.4g}"


# ----------------------------------------------------------------------------------------------------------
# 1. Table 1
# ----------------------------------------------------------------------------------------------------------
def table1() -> None:
    ring_down = damped_oscillator()
    x1 = ring_down.x[:, 0]
    emb = DelayEmbedding().fit(x1)
    q = emb.transform(x1)
    print(f"== Table 1: x1 embedded: tau = {emb.tau_} samples ({emb.tau_ * DT:.2f} s), m = {emb.dimension_} "
          f"(paper: tau = 18, m = 2); q = [x1(t - tau), x1(t)], {len(q)} samples")
    res = complexity_error({p: ImpulseSINDy(feature_library=_library(p)) for p in DEGREES}, x1, dt=DT,
                           embedding=DelayEmbedding())
    print(f"{'p':>2} {'terms':>5} {'G_sindy':>9} {'G_refined':>9} {'G(q)':>9} {'stable':>6} {'time s':>6} "
          f"| {'paper G':>7} {'terms':>5}  {'G <= paper':>10}")
    passes = []
    for k, p in enumerate(DEGREES):
        model = res.models[k]
        stable = bool(np.isfinite(res.gamma[k])) and long_run_ok(model, q)
        g_paper, n_paper, _ = PAPER[p]
        ok = stable and res.gamma[k] <= g_paper and res.gamma_filtered[k] <= g_paper
        passes.append(ok)
        print(f"{p:>2} {res.n_terms[k]:>5} {fmt(res.gamma_sindy[k])} {fmt(res.gamma_filtered[k])} "
              f"{fmt(res.gamma[k])} {stable!s:>6} {res.fit_time[k]:6.2f} | {g_paper:7.2f} {n_paper:>5}  "
              f"{'yes' if ok else 'NO':>10}")
    print("   G_sindy / G_refined: against the states filtered by TVRegDiff (ImpulseSINDy.gamma_sindy_ / "
          "gamma_); G(q): the refined model\n   simulated from q(0) against the embedded input q (the "
          "paper's Gamma); stable: finite over the record and bounded over 10x the record")
    print("equations (ours | paper's Table 1 as printed):")
    for k, p in enumerate(DEGREES):
        ours = [f"{n}' = {e}" for n, e in zip(res.models[k].feature_names_, res.equations[k])]
        print(f"  p={p} ours : " + ";  ".join(ours))
        print("       paper: " + ";  ".join(PAPER[p][2]))
    m_ours = exact_delay_matrix(emb.tau_ * DT)
    swap = np.array([[0, 1], [1, 0]])
    print(f"exact delay-coordinate matrix for tau = {emb.tau_ * DT:.2f} s, ours [q1 = x1(t-tau), "
          f"q2 = x1(t)]: {np.round(m_ours, 3).tolist()}")
    print(f"  the same with q1 <-> q2 exchanged: {np.round(swap @ m_ours @ swap, 3).tolist()}; paper p=1: "
          "[[-0.74, -5.84], [10.60, -2.45]] (same trace -3.2 and determinant 64 +- 0.4%)")
    omega, zeta = modal(linear_block(res.models[0]))
    print(f"modal parameters of the p=1 model: omega = {omega:.4f} rad/s (|lambda|/2pi = "
          f"{omega / (2 * np.pi):.4f} Hz), zeta = {zeta:.4f}   (truth: 8 rad/s = 1.2732 Hz, 0.2)")
    print("acceptance: every p stable with Gamma <= paper (p=1..4), p=5 not failed: "
          + ("PASS" if all(passes[:4]) and passes[4] else "FAIL"))
    p5 = res.models[4]
    path = ", ".join(f"{n}:{g:.3g}" for n, g in zip(p5.path_.n_terms, p5.path_.gamma))
    print(f"p=5 sweep path (terms:Gamma_sindy), selected #{p5.path_.selected}: {path}")
    print()


# ----------------------------------------------------------------------------------------------------------
# 2. Figure 10b
# ----------------------------------------------------------------------------------------------------------
def figure10b() -> None:
    ring_down = damped_oscillator()
    x1, x2 = ring_down.x.T
    betas = np.round(np.linspace(0.0, 1.0, 21), 2)
    signals = {float(b): b * x1 + (1 - b) * x2 for b in betas}
    estimators = {p: ImpulseSINDy(feature_library=_library(p)) for p in (1, 2, 3, 4)}
    print("== Figure 10b: s = beta x1 + (1 - beta) x2, beta = 0..1 step 0.05 (21) x p = 1..4 (84 fits)")
    start = time.perf_counter()
    res = complexity_error(estimators, signals, dt=DT, embedding=DelayEmbedding())
    serial = time.perf_counter() - start
    start = time.perf_counter()
    res2 = complexity_error(estimators, signals, dt=DT, embedding=DelayEmbedding(), n_jobs=2)
    parallel = time.perf_counter() - start
    same = np.array_equal(res.n_terms, res2.n_terms)
    print(f"time: serial {serial:.1f} s (mean {1e3 * serial / len(res):.0f} ms per fit incl. embedding; "
          f"fit only {1e3 * np.nanmean(res.fit_time):.0f} ms), n_jobs=2 {parallel:.1f} s (incl. worker "
          f"start); same terms: {same}; acceptance <= 30 s: {'PASS' if serial <= 30 else 'FAIL'} (serial)")
    print(res.summary())
    print(f"{'beta':>5} {'tau':>4} {'m':>2} | terms p=1..4      | G(q) p=1..4")
    n_terms, gam = res.grid("n_terms"), res.grid("gamma")
    taus, dims = res.grid("tau")[0], res.grid("dimension")[0]
    for j, b in enumerate(betas):
        terms = " ".join(f"{n:>3}" for n in n_terms[:, j])
        gs = " ".join(f"{g:8.2e}" for g in gam[:, j])
        print(f"{b:5.2f} {taus[j]:>4} {dims[j]:>2} | {terms}   | {gs}")
    front = res.pareto_front()
    points = [f"({res.estimator_label[i]}, {res.input_label[i]:.2f}, {res.n_terms[i]}, {res.gamma[i]:.2e})"
              for i in front]
    print("Pareto front (p, beta, terms, G(q)): " + "; ".join(points))
    print(f"failed fits: {int((~res.succeeded).sum())}, unstable: {int((~res.stable).sum())}")
    print()


# ----------------------------------------------------------------------------------------------------------
# 3. noisy variant
# ----------------------------------------------------------------------------------------------------------
def proposed_auto(model) -> tuple[np.ndarray, float]:
    """Re-select on ``model.path_`` with a proposed "auto" rule: the present rule plus a knee test.

    The present rule walks the sweep from the sparsest candidate and keeps the first whose *refined*
    Gamma is within ``target = (1 + REL_TOL) * G_best + NOISE_TOL * noise`` of the *unrefined* least
    Gamma. On noisy embedded data that accepts a 3-term model (q2' without its q2 term) whose refined
    Gamma (~1.9) is within the target although the next candidate, the exact 4-term structure, refines
    to ~0.5. The knee test also asks the next denser candidate on the path, refined, not to be better
    by more than the same tolerance, ``G_i <= (1 + REL_TOL) * G_next + NOISE_TOL * noise``. It costs
    at most one more small refinement per step. Returns (coefficients, Gamma against filtered states).
    """
    path = model.path_
    filt = model.x_filtered_
    terms = term_table(model.feature_library_, filt.shape[1])
    cache: dict[int, tuple[np.ndarray, float]] = {}

    def compile_(coef):
        return CompiledModel(coef, terms, reference=filt, divergence_factor=model.divergence_factor)

    def refined(i):
        if i not in cache:
            res = refine_coefficients(compile_(path.coefficients[i]), [filt], [model.t_], model.bound_factor,
                                      model.refine_max_iter)
            g = simulation_gamma(compile_(res.coefficients), [filt], [model.t_])
            cache[i] = (res.coefficients, g) if g <= path.gamma[i] else (path.coefficients[i], path.gamma[i])
        return cache[i]

    usable = np.flatnonzero(np.isfinite(path.gamma) & (path.n_terms > 0))
    best = int(usable[np.lexsort((path.n_terms[usable], path.gamma[usable]))[0]])
    noise = NOISE_TOL * model.noise_gamma_
    target = (1 + REL_TOL) * path.gamma[best] + noise
    order = sorted((int(i) for i in usable if path.n_terms[i] <= path.n_terms[best]),
                   key=lambda i: (path.n_terms[i], path.gamma[i]))
    for k, i in enumerate(order):
        if i == best:
            break
        if path.gamma[i] > HOPELESS * target:
            continue
        coef, g = refined(i)
        if g <= target and g <= (1 + REL_TOL) * refined(order[k + 1])[1] + noise:
            return coef, g
    return refined(best)


def noisy() -> dict:
    ring_down = damped_oscillator()
    x1 = ring_down.x[:, 0]
    print("== Table 1 with 40 dB SNR noise on x1 (information); G(q): against the noisy embedded q (the "
          "paper's Gamma, includes the noise);\n   G(clean): against the noise-free embedding with the same "
          "tau, m (the accuracy); noise: G(clean q, noisy q), the floor of G(q)")
    print(f"{'seed':>4} {'tau':>3} {'m':>2} {'fnn(2)':>6} {'p':>2} | {'auto: terms':>11} {'G_filt':>7} "
          f"{'G(q)':>7} {'G(clean)':>8} | {'min_gamma: terms':>16} {'G(clean)':>8} | {'proposed: terms':>15} "
          f"{'G(clean)':>8} | {'noise':>5} {'omega':>6} {'zeta':>6} {'time':>5}")
    stats = {"auto": [], "min_gamma": [], "proposed": []}
    for seed in SEEDS:
        s = add_noise(x1, 40, random_state=seed)
        emb = DelayEmbedding().fit(s)
        q, q_clean = emb.transform(s), emb.transform(x1)
        floor = gamma_from_arrays(q_clean, q)
        for p in DEGREES:
            names = [f"q{i + 1}" for i in range(emb.dimension_)]
            start = time.perf_counter()
            auto = ImpulseSINDy(feature_library=_library(p), dt=DT).fit(q, feature_names=names)
            elapsed = time.perf_counter() - start
            paper = ImpulseSINDy(feature_library=_library(p), dt=DT, selection="min_gamma").fit(
                q, feature_names=names)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                sim = auto.simulate(q[0], auto.t_)
                sim_paper = paper.simulate(q[0], paper.t_)
                coef_prop, _ = proposed_auto(auto)
                sim_prop = CompiledModel(coef_prop, term_table(auto.feature_library_, emb.dimension_),
                                         reference=auto.x_filtered_).simulate(q[0], auto.t_)
            g_auto, g_paper, g_prop = (gamma_from_arrays(q_clean, z) for z in (sim, sim_paper, sim_prop))
            stats["auto"].append(g_auto)
            stats["min_gamma"].append(g_paper)
            stats["proposed"].append(g_prop)
            if emb.dimension_ == 2:
                omega, zeta = modal(linear_block(auto))
                mod = f"{omega:6.3f} {zeta:6.3f}"
            else:
                mod = f"{'-':>6} {'-':>6}"
            g_q = gamma_from_arrays(q, sim)
            print(f"{seed:>4} {emb.tau_:>3} {emb.dimension_:>2} {emb.fnn_fraction_[1]:6.3f} {p:>2} | "
                  f"{auto.complexity:>11} {auto.gamma_:7.3f} {g_q:7.3f} {g_auto:8.3f} | "
                  f"{paper.complexity:>16} {g_paper:8.3f} | {np.count_nonzero(coef_prop):>15} "
                  f"{g_prop:8.3f} | {floor:5.2f} {mod} {elapsed:5.2f}")
    print("median G(clean) over seeds and p: " + ", ".join(
        f"{k} {np.median(v):.3f} (max {np.max(v):.3f})" for k, v in stats.items()))
    print()
    return {k: {"median": float(np.median(v)), "max": float(np.max(v))} for k, v in stats.items()}


def main(argv=None) -> dict:
    argparse.ArgumentParser(description=__doc__.splitlines()[0]).parse_args(argv)
    t0 = time.perf_counter()
    table1()
    figure10b()
    gamma_clean = noisy()
    print(f"total {time.perf_counter() - t0:.1f} s")
    return {"noisy_gamma_clean_by_rule": gamma_clean}


if __name__ == "__main__":
    main()

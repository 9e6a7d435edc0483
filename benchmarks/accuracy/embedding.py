"""Benchmark of DelayEmbedding: accuracy of tau and m on the paper's oscillator, and speed.

Run with ``python -m benchmarks embedding`` from the repository root. Prints:

1. tau and m on x1 of the paper's oscillator with the defaults (paper: tau = 18, m = 2), with the mutual
   information delay and with Cao's dimension;
2. their spread over noise seeds at 40 and 30 dB SNR, and on the mixed signal s = beta x1 + (1 - beta) x2;
3. the time to estimate tau and m (median of repeats) for 401 and 20,001 samples, next to the time of
   ``np.correlate(s, s, "full")`` on the same signal in the same run.
"""

from __future__ import annotations

import argparse
import time
import warnings
from collections import Counter

import numpy as np

from sindy_impulse.datasets import add_noise, damped_oscillator
from sindy_impulse.embedding import DelayEmbedding

SEEDS = range(20)
METHODS = {
    "acf + fnn (default)": {},
    "mutual_information + fnn": {"delay_method": "mutual_information"},
    "acf + cao": {"dimension_method": "cao"},
}


def _median_time(func, repeats: int) -> float:
    func()  # warm-up
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        func()
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def _fit(s, **params) -> DelayEmbedding:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return DelayEmbedding(**params).fit(s)


def _summary(values) -> str:
    counts = Counter(values)
    return ", ".join(f"{v}:{counts[v]}" for v in sorted(counts))


def accuracy() -> dict:
    ring_down = damped_oscillator()
    x1, x2 = ring_down.x[:, 0], ring_down.x[:, 1]
    print("== x1 of the paper's oscillator (401 samples, dt = 0.01; paper: tau = 18, m = 2)")
    out = {}
    for label, params in METHODS.items():
        emb = _fit(x1, **params)
        extra = ""
        if emb.fnn_fraction_ is not None:
            extra = "FNN fraction d=1..4: " + " ".join(f"{v:.3f}" for v in emb.fnn_fraction_[:4])
        if emb.cao_e1_ is not None:
            extra = "Cao E1 d=1..4: " + " ".join(f"{v:.3f}" for v in emb.cao_e1_[:4])
        if emb.acf_zero_crossing_ is not None:
            extra += f"  (ACF zero at lag {emb.acf_zero_crossing_:.2f})"
        print(f"  {label:<26} tau = {emb.tau_:3d}  m = {emb.dimension_}   {extra}")
        out[label] = {"tau": emb.tau_, "m": emb.dimension_}

    print(f"\n== noisy x1, {len(SEEDS)} noise seeds each (value:count)")
    for snr in (40, 30):
        for label, params in METHODS.items():
            fits = [_fit(add_noise(x1, snr, random_state=seed), **params) for seed in SEEDS]
            print(
                f"  {snr} dB  {label:<26} tau {{{_summary(f.tau_ for f in fits)}}}"
                f"   m {{{_summary(f.dimension_ for f in fits)}}}"
            )

    print("\n== mixed signal s = beta x1 + (1 - beta) x2 (noise-free)")
    for beta in (0.0, 0.1, 0.25, 0.5, 0.75, 0.9, 1.0):
        s = beta * x1 + (1 - beta) * x2
        row = "  ".join(
            f"{label.split(' ')[0]}+{label.split(' ')[2]}: tau={e.tau_:2d} m={e.dimension_}"
            for label, e in ((lab, _fit(s, **p)) for lab, p in METHODS.items())
        )
        print(f"  beta = {beta:4.2f}   {row}")
    return out


def speed() -> dict:
    print("\n== time to estimate tau and m (default acf + fnn), median of repeats")
    short = damped_oscillator().x[:, 0]
    # 20,001 samples: 200 s of a lightly damped ring-down (c = 0.02), about 250 periods
    long = damped_oscillator(c=0.02, t_end=200.0).x[:, 0]
    out = {}
    for s, repeats, limit in ((short, 50, 0.020), (long, 7, 1.0)):
        emb = DelayEmbedding().fit(s)
        t_fit = _median_time(lambda s=s: DelayEmbedding().fit(s), repeats)
        t_mi = _median_time(lambda s=s: DelayEmbedding(delay_method="mutual_information").fit(s), repeats)
        t_cao = _median_time(lambda s=s: DelayEmbedding(dimension_method="cao").fit(s), repeats)
        t_base = _median_time(lambda s=s: np.correlate(s, s, "full"), repeats)
        t_transform = _median_time(lambda s=s, emb=emb: emb.transform(s), repeats)
        print(
            f"  N = {s.size:6d} (tau = {emb.tau_}, m = {emb.dimension_}, {emb.candidate_dimensions_.size} "
            f"dimensions tested): fit {t_fit * 1e3:8.2f} ms (limit {limit * 1e3:.0f} ms: "
            f"{'ok' if t_fit <= limit else 'OVER'}) | np.correlate full {t_base * 1e3:7.2f} ms "
            f"| ratio fit/correlate {t_fit / t_base:6.2f}"
        )
        print(
            f"  {'':10} mutual_information + fnn {t_mi * 1e3:8.2f} ms | acf + cao {t_cao * 1e3:8.2f} ms "
            f"| transform {t_transform * 1e3:6.3f} ms"
        )
        out[f"{s.size} samples"] = {"fit": t_fit, "correlate": t_base, "ratio": t_fit / t_base,
                                    "mutual_information": t_mi, "cao": t_cao, "transform": t_transform}
    return out


def main(argv=None) -> dict:
    argparse.ArgumentParser(description=__doc__.splitlines()[0]).parse_args(argv)
    return {"tau_and_m_of_x1": accuracy(), "seconds": speed()}


if __name__ == "__main__":
    main()

"""Benchmark of the synthetic hammer tests (``datasets.impact_record``) and the ESPRIT baseline.

Run from the repository root with ``python -m benchmarks impact``. Prints:

1. generation time of a linear 40,000-sample 4-mode record and of a nonlinear single-mode record of
   3,000 periods at 20 samples per period (median of 5 runs after a warm-up; wall and CPU time);
2. ESPRIT time and accuracy (RMS and worst relative error of frequency and damping ratio over 10 seeds)
   on 4-mode chain records of 15,000 and 40,000 samples, white and pink noise, 60 to 20 dB.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from sindy_impulse.analysis import esprit
from sindy_impulse.datasets import impact_record

F = np.array([35.0, 120.0, 410.0, 900.0])
Z = np.array([0.01, 0.004, 0.002, 0.003])
AMPS = [1.0, 0.5, 2.0, 1.0]


def timed(fn, repeats=5):
    fn()
    wall, cpu = [], []
    for _ in range(repeats):
        w, c = time.perf_counter(), time.process_time()
        fn()
        wall.append(time.perf_counter() - w)
        cpu.append(time.process_time() - c)
    return np.median(wall), np.median(cpu)


def generation() -> dict:
    print("1. generation (median wall / CPU seconds)")
    w, c = timed(lambda: impact_record(F, Z, AMPS, fs=10000.0, duration=4.0, snr_db=40, random_state=0))
    print(f"   linear, 40,000 samples, 4 modes, noise:         {w:.3f} / {c:.3f}")
    out = {"linear": {"wall": w, "cpu": c}}
    f0, a0 = 50.0, 1e-3
    w0 = 2 * np.pi * f0
    kw = dict(fs=20 * f0, duration=3000 / f0, sensor="displacement", pre_trigger=0.0)
    kw.update(
        cubic_stiffness=(1.01**2 - 1) * w0**2 / (0.75 * a0**2), damping_amplitude=12 * 0.002 * w0 / a0**2
    )
    w, c = timed(lambda: impact_record(f0, 0.002, [a0], **kw))
    print(f"   nonlinear SDOF, 3,000 periods x 20 samples:      {w:.3f} / {c:.3f}")
    out["nonlinear"] = {"wall": w, "cpu": c}
    return out


def accuracy() -> list:
    print("2. ESPRIT on the free decay (10 seeds): CPU s, freq rel err RMS / max, damping rel err RMS / max")
    rows = []
    for duration in (1.5, 4.0):
        for noise in ("white", "pink"):
            for snr in (60, 40, 30, 20):
                df, dz, cpu, missed = [], [], [], 0
                for seed in range(10):
                    rec = impact_record(
                        F, Z, AMPS, fs=10000.0, duration=duration, snr_db=snr, noise=noise, random_state=seed
                    )
                    c = time.process_time()
                    m = esprit(rec.y[rec.free_decay_index :], fs=rec.fs)
                    cpu.append(time.process_time() - c)
                    if m.frequencies_hz.size != F.size:
                        missed += 1
                        continue
                    df.append(m.frequencies_hz / F - 1)
                    dz.append(m.damping_ratios / Z - 1)
                df, dz = np.abs(np.array(df)), np.abs(np.array(dz))
                stats = (
                    "no complete table"
                    if not len(df)
                    else (
                        f"f {np.sqrt(np.mean(df**2)):.1e} / {df.max():.1e}   "
                        f"zeta {np.sqrt(np.mean(dz**2)):.1e} / {dz.max():.1e}"
                    )
                )
                print(
                    f"   n={int(duration * 1e4):6d} {noise:5s} {snr:2d} dB  cpu {np.median(cpu):.3f}  {stats}"
                    + (f"  ({missed} seeds without 4 modes)" if missed else "")
                )
                row = {"samples": int(duration * 1e4), "noise": noise, "snr_db": snr,
                       "cpu": float(np.median(cpu)), "missed": missed}
                if len(df):
                    row.update(frequency_rms=np.sqrt(np.mean(df**2)), frequency_max=df.max(),
                               damping_rms=np.sqrt(np.mean(dz**2)), damping_max=dz.max())
                rows.append(row)
    return rows


def main(argv=None) -> dict:
    argparse.ArgumentParser(description=__doc__.splitlines()[0]).parse_args(argv)
    return {"generation_seconds": generation(), "esprit": accuracy()}


if __name__ == "__main__":
    main()

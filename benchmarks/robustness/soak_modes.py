"""Exception run of the modal-table issue: identify_modes on random impact_record configurations, under the
watchdog of the soak test (:mod:`benchmarks.robustness.watchdog`), counting every exception, hang and caught
failure.

Run:  python -m benchmarks soak_modes [--n 1000] [--seed 0] [--jobs 2] [--timeout 300] [--json out.json]

Each configuration is :func:`families.random_config` (seed = case number): 1-4 modes up to fs / 2.56,
damping ratios 0.05-8 % (log-uniform), amplitudes within 30 dB, 500-40,000 samples, any sensor; in 30 % of
multi-mode records another tapped mass and one or several sensor masses; offset 0-10x the peak, pre-trigger
0-30 %, clipping at 0.3-1 of the peak in 30 %, white or pink noise at 15-60 dB, nonlinear terms (cubic
spring, amplitude-dependent damper, or both) in 30 %. Every other record passes the hammer's force too.

Outcomes: **ok**; **caught** (the survey returned, but with a ``Rejected`` row of band None or carrying an
error in its evidence: a failure caught inside the survey; target at most 1 % of records); **exception**
(identify_modes raised; target 0); **refused** (impact_record refused the configuration: a generator
problem, not the survey's); **crash** / **hang** (the worker died / exceeded the time limit; target 0).
"""

from __future__ import annotations

import argparse
import json
import time
import traceback
import warnings
from collections import Counter

import numpy as np

from benchmarks.accuracy.families import random_config
from benchmarks.robustness.watchdog import run_pool

KINDS = ("ok", "caught", "exception", "refused", "crash", "hang")


def run_config(task: dict) -> dict:
    """identify_modes on the record of ``random_config(task["seed"])``; the outcome (never raises)."""
    from sindy_impulse import identify_modes, impact_record

    seed = task["seed"]
    out = {"seed": seed, "warnings": [], "config": random_config(seed)}
    start = time.perf_counter()
    try:
        rec = impact_record(**out["config"])
    except (ValueError, TypeError) as err:
        out.update(kind="refused", error=f"{type(err).__name__}: {err}", time=time.perf_counter() - start)
        return out
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            survey = identify_modes(rec.y, fs=rec.fs, force=rec.force if seed % 2 else None)
        caught = [r.reason for r in survey.rejected if r.band_hz is None or "error" in r.evidence]
        out.update(kind="caught" if caught else "ok", caught=caught, n_modes=len(survey.modes),
                   n_true=len(rec.modes))
    except Exception as err:  # noqa: BLE001 - the run records every exception
        out.update(kind="exception", error=f"{type(err).__name__}: {err}",
                   traceback=traceback.format_exc(limit=8))
    out["time"] = time.perf_counter() - start
    return out


def report(outcomes: list[dict], timeout: float) -> dict:
    kinds = Counter(o["kind"] for o in outcomes)
    n = len(outcomes)
    print(f"{n} configurations, watchdog {timeout:g} s: "
          + ", ".join(f"{k} {kinds.get(k, 0)}" for k in KINDS))
    for o in outcomes:
        if o["kind"] != "ok":
            what = o.get("error") or "; ".join(o.get("caught", []))
            print(f"  [{o['kind']}] seed {o['seed']}: {what}")
            print(f"      config {json.dumps(o.get('config'))}")
            if "traceback" in o:
                print("      " + o["traceback"].strip().replace("\n", "\n      "))
    times = np.array([o["time"] for o in outcomes if o["kind"] not in ("hang", "crash")])
    if times.size:
        print(f"time per record (s): median {np.median(times):.2f}, p95 {np.percentile(times, 95):.2f}, "
              f"max {times.max():.1f}")
    bad = kinds.get("exception", 0) + kinds.get("crash", 0) + kinds.get("hang", 0)
    return {"failures": bad, "caught_share": kinds.get("caught", 0) / max(n, 1)}


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=None, help="configurations (default 1000, quick 20)")
    parser.add_argument("--quick", action="store_true", help="20 configurations")
    parser.add_argument("--seed", type=int, default=0, help="first configuration seed")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--timeout", type=float, default=300.0, help="hard limit per record (s)")
    parser.add_argument("--json", help="write every outcome to this file")
    args = parser.parse_args(argv)
    start = time.perf_counter()
    tasks = [{"seed": args.seed + i} for i in range(args.n or (20 if args.quick else 1000))]

    def show(out):
        what = f": {out.get('error', out.get('caught'))}" if out["kind"] != "ok" else ""
        print(f"  seed {out['seed']} {out['kind']} {out['time']:.1f} s{what}", flush=True)

    outcomes = run_pool(tasks, "benchmarks.robustness.soak_modes:run_config", args.timeout, args.jobs, "seed",
                        on_result=show)
    for out in outcomes:
        if "config" not in out:  # a crash or hang: the worker's outcome is lost, the configuration is not
            out["config"] = random_config(out["seed"])
    figures = report(outcomes, args.timeout)
    print(f"wall time {time.perf_counter() - start:.0f} s")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(outcomes, fh, default=str)
    return {**figures, "ok": not (figures["failures"] or figures["caught_share"] > 0.01)}


if __name__ == "__main__":
    raise SystemExit(0 if main()["ok"] else 1)

"""The bad-input matrix: hundreds of awkward inputs, each with its stated expectation, run under a watchdog.

Run:  python -m benchmarks bad_inputs [--jobs 2] [--timeout 120] [--group offset] [--verbose]

Every case states what a trustworthy library must do with its input -- the right terms and coefficients
within a tolerance, a named warning, or a named error -- and the run classifies what happened:

============== ===================================================================== ==========
outcome        meaning                                                               counts as
============== ===================================================================== ==========
expected       the stated expectation is met                                         pass
warned         a right answer was expected; the answer is off but a library warning   pass (not
               says so                                                               silent)
refused        a clear ValueError/TypeError where an answer was expected             pass (not
                                                                                     silent)
silent wrong   a wrong answer, a missed warning or a missed error, without any       FAIL
               library warning
crash          any other exception, or a worker that died                            FAIL
hang           over the time limit (the worker is killed)                            FAIL
============== ===================================================================== ==========

Groups: offsets (DC on one or both states, drifts, plain mode), scales (1e-300 to 1e300, per state),
noise only, clipping, steps and glitches, quantisation, redundant channels, strong nonlinearity (Duffing,
Coulomb friction, and their modal parameters), sampling (coarse, dense, short, long), several
trajectories, simulation from far states, SINDyFeatures on noise, plain PySINDy mode, and scikit-learn style
bad inputs (types, shapes, time vectors, parameters, unfitted models). The case definitions are in
:mod:`benchmarks.robustness.bad_input_matrix` (the list) and :mod:`benchmarks.robustness.bad_input_cases`
(data, actions, scikit-learn style calls); ``tests/test_bad_inputs.py`` runs a representative part of them.

Figures (``python -m benchmarks bad_inputs --jobs 2``, 2 shared cores, wall time 2 min, median case 0.2 s,
longest 15 s; hard limit 120 s per case)::

    418 cases: expected 416, warned 0, refused 2, silent wrong 0, crash 0, hang 0

The 2 refusals are records of 10 and 20 samples with the default sweep (a clear ValueError: too few
samples for TVRegDiff or for the library); in plain mode such records are fitted with a warning.
"""

from __future__ import annotations

import argparse
import time
from collections import Counter

import numpy as np

from benchmarks.robustness.bad_input_cases import FAILURES
from benchmarks.robustness.bad_input_matrix import all_cases, fast_cases
from benchmarks.robustness.watchdog import run_pool


def report(outcomes: list[dict]) -> dict:
    """Print the table of outcomes by group; return the counts."""
    kinds = ("expected", "warned", "refused", "silent wrong", "crash", "hang")
    groups = sorted({o["group"] for o in outcomes})
    head = f"{'group':14s}" + "".join(f"{k:>14s}" for k in kinds) + f"{'cases':>8s}"
    print(head)
    print("-" * len(head))
    for g in groups:
        c = Counter(o["outcome"] for o in outcomes if o["group"] == g)
        print(f"{g:14s}" + "".join(f"{c.get(k, 0):14d}" for k in kinds) + f"{sum(c.values()):8d}")
    total = Counter(o["outcome"] for o in outcomes)
    print("-" * len(head))
    print(f"{'all':14s}" + "".join(f"{total.get(k, 0):14d}" for k in kinds) + f"{len(outcomes):8d}")
    for o in outcomes:
        if o["outcome"] in FAILURES or o["outcome"] in ("warned", "refused"):
            print(f"  [{o['outcome']}] {o['id']}: {o['detail']}")
            if "traceback" in o:
                print("    " + o["traceback"].replace("\n", "\n    "))
    times = np.array([o["time"] for o in outcomes])
    print(f"time per case (s): median {np.median(times):.2f}, max {times.max():.2f}, total {times.sum():.0f}")
    return dict(total)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--jobs", type=int, default=2, help="worker processes")
    parser.add_argument("--timeout", type=float, default=120.0, help="hard limit per case (s)")
    parser.add_argument("--group", help="run one group only")
    parser.add_argument("--verbose", action="store_true", help="print every case")
    parser.add_argument("--quick", action="store_true",
                        help="the fast part: every scikit-learn style call and every 25th other case")
    args = parser.parse_args(argv)
    cases = fast_cases() if args.quick else all_cases()
    cases = [c for c in cases if args.group is None or c["group"] == args.group]
    print(f"{len(cases)} cases")
    start = time.perf_counter()

    def show(out):
        if args.verbose or out["outcome"] in FAILURES:
            print(f"[{out['outcome']:12s}] {out['time']:6.2f}s {out['id']}: {out['detail']}", flush=True)

    target = "benchmarks.robustness.bad_input_cases:run_case"
    outcomes = run_pool(cases, target, args.timeout, args.jobs, "id", None, show)
    for o in outcomes:
        o.setdefault("group", next(c["group"] for c in cases if c["id"] == o["id"]))
        o.setdefault("outcome", o.get("kind"))
        o.setdefault("detail", o.get("error", ""))
    counts = report(outcomes)
    print(f"wall time {time.perf_counter() - start:.0f} s")
    return {"cases": len(cases), "outcomes": counts, "ok": not any(counts.get(k, 0) for k in FAILURES)}


if __name__ == "__main__":
    raise SystemExit(0 if main()["ok"] else 1)

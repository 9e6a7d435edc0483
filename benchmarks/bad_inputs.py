"""The bad-input matrix: hundreds of awkward inputs, each with its stated expectation, run under a watchdog.

Run:  python benchmarks/bad_inputs.py [--jobs 2] [--timeout 120] [--group offset] [--verbose]

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
:mod:`bad_input_matrix` (the list) and :mod:`bad_input_cases` (data, actions, scikit-learn style calls);
``tests/test_bad_inputs.py`` runs a representative part of them.

Figures (``python benchmarks/bad_inputs.py --jobs 2``, 2 shared cores, wall time 2 min, median case 0.2 s,
longest 15 s; hard limit 120 s per case)::

    418 cases: expected 416, warned 0, refused 2, silent wrong 0, crash 0, hang 0

The 2 refusals are records of 10 and 20 samples with the default sweep (a clear ValueError: too few
samples for TVRegDiff or for the library); in plain mode such records are fitted with a warning.
"""

from __future__ import annotations

import argparse
import re
import sys
import time
import traceback
import warnings
from collections import Counter

import numpy as np

FAILURES = ("silent wrong", "crash", "hang")


def _caught(record) -> list[tuple[str, str, bool]]:
    from sindy_impulse.exceptions import SindyImpulseWarning

    return [
        (w.category.__name__, str(w.message), issubclass(w.category, SindyImpulseWarning)) for w in record
    ]


def _judge(expect: dict, result, record, error) -> tuple[str, str]:
    """Outcome and detail of one case against its expectation."""
    ours = [c for c in record if c[2]]
    kind = expect["type"]
    if error is not None:
        name, message = type(error).__name__, str(error)
        wanted = expect.get("error")
        if kind == "raise" and _is(error, wanted) and re.search(expect.get("match", ""), message):
            return "expected", f"{name}: {message[:90]}"
        if isinstance(error, (ValueError, TypeError)) and message:
            return "refused", f"{name}: {message[:90]}"
        return "crash", f"{name}: {message[:200]}"
    if kind == "raise":
        return ("warned", _names(ours)) if ours else ("silent wrong", "no error raised")
    if kind == "warn":
        wanted = [
            c
            for c in record
            if _is_name(c[0], expect["warning"]) and re.search(expect.get("match", ""), c[1])
        ]
        if wanted:
            return "expected", _names(wanted)
        return ("warned", f"other warning {_names(ours)}") if ours else ("silent wrong", "no warning")
    ok, detail = result
    if ok:
        return "expected", detail + (f"; warned {_names(ours)}" if ours else "")
    if kind == "right_or_warn" and ours:
        return "expected", f"{detail}; warned {_names(ours)}"
    return ("warned", f"{detail}; {_names(ours)}") if ours else ("silent wrong", detail)


def _is(error, wanted: str | None) -> bool:
    return wanted is not None and any(_is_name(c.__name__, wanted) for c in type(error).__mro__)


def _is_name(name: str, wanted: str) -> bool:
    from sindy_impulse import exceptions

    cls = getattr(exceptions, name, None)
    target = getattr(exceptions, wanted, None)
    if cls is not None and target is not None:
        return issubclass(cls, target)
    return name == wanted


def _names(caught) -> str:
    return ", ".join(sorted({c[0] for c in caught}))


def run_case(spec: dict) -> dict:
    """Build and run one case; never raises. Returns ``{"id", "outcome", "detail", "time", ...}``."""
    from bad_input_cases import run_action

    start = time.perf_counter()
    result, error = None, None
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        try:
            result = run_action(spec)
        except Exception as err:  # noqa: BLE001 - the matrix records everything
            error = err
            tb = traceback.format_exc(limit=8)
    caught = _caught(record)
    outcome, detail = _judge(spec["expect"], result, caught, error)
    out = {"id": spec["id"], "group": spec["group"], "outcome": outcome, "detail": detail}
    out["time"] = time.perf_counter() - start
    out["warnings"] = sorted({c[0] for c in caught})
    if outcome == "crash" and error is not None:
        out["traceback"] = tb
    return out


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


def main(argv=None) -> int:
    sys.path.insert(0, __file__.rsplit("/", 1)[0])
    from _watchdog import run_pool
    from bad_input_matrix import all_cases

    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--jobs", type=int, default=2, help="worker processes")
    parser.add_argument("--timeout", type=float, default=120.0, help="hard limit per case (s)")
    parser.add_argument("--group", help="run one group only")
    parser.add_argument("--verbose", action="store_true", help="print every case")
    args = parser.parse_args(argv)
    cases = [c for c in all_cases() if args.group is None or c["group"] == args.group]
    print(f"{len(cases)} cases")
    start = time.perf_counter()

    def show(out):
        if args.verbose or out["outcome"] in FAILURES:
            print(f"[{out['outcome']:12s}] {out['time']:6.2f}s {out['id']}: {out['detail']}", flush=True)

    outcomes = run_pool(cases, "bad_inputs:run_case", args.timeout, args.jobs, "id", None, show)
    for o in outcomes:
        o.setdefault("group", next(c["group"] for c in cases if c["id"] == o["id"]))
        o.setdefault("outcome", o.get("kind"))
        o.setdefault("detail", o.get("error", ""))
    counts = report(outcomes)
    print(f"wall time {time.perf_counter() - start:.0f} s")
    return 1 if any(counts.get(k, 0) for k in FAILURES) else 0


if __name__ == "__main__":
    sys.exit(main())

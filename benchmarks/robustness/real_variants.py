"""The public real records cut, shifted and clipped: does the survey ever fail, raise or let a NumPy warning
through on them?

    python -m benchmarks real_variants --mirror /path/to/mirrors

The random records of :mod:`.soak_modes` are simulated; a real record breaks the survey in other ways (a
tone, a structure that is never exactly a sum of modes, a quantised sensor). Each record of
:mod:`benchmarks.real_records.survey_speed` is cut to a share of its samples (``--shares``), starting at
a share of them (``--starts``: 0 keeps the hit and pre-trigger, later starts cut into the decay), as
recorded and clipped at half its excursion (:func:`~benchmarks.real_records.clipped_real.clip`), without
the force: a short block that ends while the structure rings, an acquisition started late, a sensor at
its limit. Per variant the outcome is **ok** (modes, or a warning that says why there are none),
**caught** (a row whose evidence holds an error: a fit that failed inside the survey), **exception**
(identify_modes raised; a ``ValueError`` that names the problem is a refusal, counted apart) or
**numpy** (a NumPy ``RuntimeWarning`` reached the user: overflow, invalid value, division by zero). Every
outcome but ok is listed.

Measured (2026-11-30, main at this benchmark's fixes): 240 variants of the 10 records: 239 ok, 1 caught
(pyFRF's second hit, its first 3 % clipped: 768 samples; every candidate model of one band diverged when
simulated), 0 refused, 0 exceptions, 0 NumPy warnings. Its first runs found three failures, all fixed: a
non-decaying neighbour in the averaged equations (pyFRF's first hit cut to a quarter: an
``UnboundLocalError``, no mode), NumPy overflow warnings from a step of the same fit (the Brake-Reuss beam
cut to 15 %), and a clipped record whose unclipped tail was too short for a spectrum (the flutter rig's
second record, 3 % from 0.2 %: refused with "y has 54 samples", a length the user never passed).
"""

from __future__ import annotations

import argparse
import os
import time
import traceback
import warnings
from collections import Counter

import numpy as np

from benchmarks.real_records.clipped_real import clip
from benchmarks.real_records.sources import ENV
from benchmarks.real_records.survey_speed import records
from sindy_impulse import identify_modes

#: NumPy's floating-point warnings (their messages): what must not reach a user of the survey.
NUMPY_MESSAGES = ("overflow encountered", "invalid value encountered", "divide by zero encountered",
                  "underflow encountered")


def variant(y: np.ndarray, share: float, start: float, clipped: bool) -> np.ndarray:
    """``y`` from ``start`` (a share of its samples) for ``share`` of them (at least 50 samples), clipped at
    half its excursion if ``clipped``."""
    n = np.shape(y)[0]
    a = int(start * n)
    out = np.asarray(y, float)[a:a + max(int(share * n), 50)]
    return clip(out, 0.5) if clipped else out


def outcome(y: np.ndarray, fs: float) -> tuple[str, str, float]:
    """``(outcome, detail, seconds)`` of the survey of ``y`` (see the module)."""
    start = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            survey = identify_modes(y, fs=fs)
        except ValueError as err:
            return "refused", f"ValueError: {err}"[:160], time.perf_counter() - start
        except Exception as err:  # noqa: BLE001 - the outcome to count
            detail = f"{type(err).__name__}: {err} | {traceback.format_exc(limit=-2)}"
            return "exception", detail[:400], time.perf_counter() - start
    seconds = time.perf_counter() - start
    numpy = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)
             and str(w.message).startswith(NUMPY_MESSAGES)]
    if numpy:
        return "numpy", "; ".join(sorted(set(numpy)))[:200], seconds
    failed = [r.reason for r in survey.rejected if r.evidence and "error" in r.evidence]
    if failed:
        return "caught", "; ".join(failed)[:200], seconds
    return "ok", f"{len(survey.modes)} mode(s)", seconds


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mirror", default=os.environ.get(ENV), help=f"folder of bare git copies ({ENV})")
    parser.add_argument("--shares", default="0.03,0.06,0.15,0.4", help="shares of the samples kept")
    parser.add_argument("--starts", default="0,0.002,0.01", help="shares of the samples cut from the start")
    args = parser.parse_args(argv)
    try:
        shares = [float(v) for v in args.shares.split(",")]
        starts = [float(v) for v in args.starts.split(",")]
    except ValueError:
        parser.error("--shares and --starts must be numbers separated by commas")
    if not all(0 < s <= 1 for s in shares) or not all(0 <= s < 1 for s in starts):
        parser.error("every share must be in (0, 1] and every start in [0, 1)")
    counts, listed, rows = Counter(), [], []
    for record in records(args.mirror):
        for share in shares:
            for start in starts:
                for clipped in (False, True):
                    y = variant(record["y"], share, start, clipped)
                    kind, detail, seconds = outcome(y, record["fs"])
                    counts[kind] += 1
                    row = {"name": record["name"], "share": share, "start": start, "clipped": clipped,
                           "outcome": kind, "detail": detail, "seconds": seconds}
                    rows.append(row)
                    if kind != "ok":
                        listed.append(row)
                        print(f"  {kind}: {record['name']}, {share:g} from {start:g}"
                              f"{', clipped' if clipped else ''}: {detail}", flush=True)
    slowest = max(rows, key=lambda r: r["seconds"]) if rows else None
    summary = ", ".join(f"{k} {v}" for k, v in sorted(counts.items()))
    if slowest:
        summary += f"; slowest {slowest['seconds']:.1f} s ({slowest['name']}, {slowest['share']:g})"
    print(f"\n{len(rows)} variants: {summary}")
    return {"counts": dict(counts), "listed": listed, "variants": len(rows)}


if __name__ == "__main__":
    main()

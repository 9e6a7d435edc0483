"""Family (d) of the modal-table issue record by record, with CPU time: short, strongly damped records.

    python -m benchmarks short_records --n 30                 # records 0-29 of family d (seed 0)
    python -m benchmarks short_records --n 30 --jobs 2 --json out.json
    python -m benchmarks short_records --records 5 13 17      # only these indices (same draws)
    python -m benchmarks short_records --poles --n 30         # stable poles vs free-decay equations

The records are those of ``python -m benchmarks modes --family d`` (``families.draw("d", rng, i)`` with one
generator seeded ``--seed``, drawn in order, so index i is the same record in both scripts); each is scored
as there (:func:`scoring.run_family_case`: survey and stabilised ESPRIT baseline, 0.5 % / 10 %, no
spurious mode). Time is CPU time of the survey (``time.process_time`` in the worker: the machine is
shared, wall time is not a speed). ``--timeout`` stops a record after that many seconds of wall time (it
is then counted wrong, with its time). The table prints records right, spurious, the baseline's, and the
median / max CPU seconds per record.

Measured (records 0-99, seed 0, 2-core shared machine): the survey 79 right, 2 with a spurious mode, CPU
median 1.21 s, mean 1.85 s, max 23.1 s a record; the baseline 76 right. Main before the short-record path
(286c438): 42 right, 9 with a spurious mode, CPU median 1.22 s, mean 4.05 s, max 37.1 s.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import signal
import time
from pathlib import Path

import numpy as np

from benchmarks.accuracy.families import draw
from benchmarks.accuracy.scoring import run_family_case


class _Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise _Timeout


def _one(args) -> dict:
    index, case, timeout = args
    signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(int(timeout))
    cpu = time.process_time()
    try:
        r = run_family_case(case)
        r = {"index": index, "passed": bool(r["ours"]["passed"]), "spurious": r["ours"]["spurious"],
             "base_passed": bool(r["theirs"]["passed"]), "base_spurious": r["theirs"]["spurious"],
             "problems": r["ours"]["problems"], "found": r["found"], "error": r["error"]}
    except _Timeout:
        r = {"index": index, "passed": False, "spurious": 0, "base_passed": None, "base_spurious": 0,
             "problems": [f"timeout after {timeout} s"], "found": [], "error": "timeout"}
    finally:
        signal.alarm(0)
    r["cpu"] = time.process_time() - cpu
    r["config"] = case["config"]
    return r


def pole_vs_equation(cases: list) -> dict:
    """Per true mode matched (within 1 %) to a stable pole of its record: the error of the pole and of the
    linear mode of the equation fitted on its free decay (``modes._short.fit_free_decay``), medians and
    largest; the share of poles whose equation agrees (is kept)."""
    import warnings

    from sindy_impulse import impact_record
    from sindy_impulse.modes import _short
    from sindy_impulse.modes.band_fit import _linear_mode, default_estimator
    from sindy_impulse.modes.result import Mode, pole_table
    from sindy_impulse.preprocessing import preprocess

    pole_err, eq_err, kept, total = [], [], 0, 0
    for case in cases:
        rec = impact_record(**case["config"])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            pre = preprocess(rec.y, fs=rec.fs)
            stable = _short.stable_modes(pole_table(pre))
            for pole in stable:
                j = int(np.argmin(np.abs(rec.modes.frequency_hz / pole.frequency_hz - 1)))
                f0, z0 = rec.modes.frequency_hz[j], rec.modes.damping_ratio[j]
                if abs(pole.frequency_hz / f0 - 1) > 0.01:
                    continue
                total += 1
                out = _short.fit_free_decay(pre, stable, pole, default_estimator())
                if not isinstance(out, Mode):
                    continue
                kept += 1
                (f, z), _ = _linear_mode(out.model, _short.pole_band(pole))
                pole_err.append((abs(pole.frequency_hz / f0 - 1), abs(pole.damping_ratio / z0 - 1)))
                eq_err.append((abs(f / f0 - 1), abs(z / z0 - 1)))
    for name, e in (("stable pole", np.array(pole_err)), ("free-decay equation", np.array(eq_err))):
        print(f"{name}: |df/f| median {np.median(e[:, 0]):.1e} max {e[:, 0].max():.1e}; |dz/z| median "
              f"{np.median(e[:, 1]):.1e} max {e[:, 1].max():.1e} ({len(e)} modes)")
    print(f"true modes with a stable pole: {total}; its equation agrees (kept): {kept}")
    return {"true_modes_with_a_stable_pole": total, "kept": kept,
            "pole_median_errors": np.median(pole_err, axis=0),
            "equation_median_errors": np.median(eq_err, axis=0)}


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=None, help="records 0..N-1 (default 30, quick 5)")
    parser.add_argument("--quick", action="store_true", help="records 0-4")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--records", type=int, nargs="*", default=None)
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--timeout", type=float, default=600.0)
    parser.add_argument("--json", default=None)
    parser.add_argument("--poles", action="store_true",
                        help="instead: errors of the stable poles and the free-decay equations' modes")
    args = parser.parse_args(argv)
    args.n = args.n or (5 if args.quick else 30)
    rng = np.random.default_rng(args.seed)
    n = max(args.n, 1 + max(args.records or [0]))
    cases = [draw("d", rng, i) for i in range(n)]
    if args.poles:
        chosen = args.records if args.records is not None else range(args.n)
        return pole_vs_equation([cases[i] for i in chosen])
    wanted = args.records if args.records is not None else range(args.n)
    work = [(i, cases[i], args.timeout) for i in wanted]
    results = []
    with mp.Pool(args.jobs, maxtasksperchild=1) as pool:
        for r in pool.imap(_one, work):
            results.append(r)
            c = r["config"]
            print(f"  [d #{r['index']}] {'right' if r['passed'] else 'WRONG'} (baseline "
                  f"{'right' if r['base_passed'] else 'wrong'}), {len(c['frequencies_hz'])} modes, "
                  f"{r['cpu']:.1f} s CPU" + (f": {'; '.join(r['problems'])}" if not r["passed"] else ""),
                  flush=True)
    m = len(results)
    right = sum(r["passed"] for r in results)
    spurious = sum(r["spurious"] > 0 for r in results)
    base = sum(bool(r["base_passed"]) for r in results)
    cpu = np.array([r["cpu"] for r in results])
    print(f"family d, {m} records (seed {args.seed}): survey right {right}, with a spurious mode {spurious}; "
          f"baseline right {base}; CPU s/record median {np.median(cpu):.2f}, mean {cpu.mean():.2f}, "
          f"max {cpu.max():.1f}")
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=1, default=float))
    return {"seed": args.seed, "records": m, "right": right, "spurious": spurious, "baseline_right": base,
            "cpu_median": np.median(cpu), "cpu_mean": cpu.mean(), "cpu_max": cpu.max(),
            "per_record": [{k: r[k] for k in ("index", "passed", "spurious", "base_passed", "cpu",
                                              "problems")} for r in results]}


if __name__ == "__main__":
    main()

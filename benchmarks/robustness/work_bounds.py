"""The work bounds of issue 25: the adaptive integrator's real cost per work unit, and the records that hung
or ran out of memory, each timed with its peak memory (one fresh process per record).

    OMP_NUM_THREADS=1 python -m benchmarks work_bounds                  # cost ratio + the slow records
    OMP_NUM_THREADS=1 python -m benchmarks work_bounds --mirror /work/.mirror   # + pyFRF measurements_1
    OMP_NUM_THREADS=1 python -m benchmarks work_bounds --only cost
    # another checkout's package: run outside this tree (the working folder comes first on the path)
    cd /tmp && PYTHONPATH=OLD_CHECKOUT:THIS_TREE python -m benchmarks work_bounds --records d0,d21

The records: family d records 0 and 21 of ``python -m benchmarks modes --family d`` (seed 0; 394 s and 209 s
before), the exception run's seeds 20 and 25 (``benchmarks/robustness/soak_modes.py``, over 300 s there), and
pyFRF measurements_1 (25,600 samples at 25.6 kHz with force; killed at 21.3 GB before; read as
``benchmarks/real_records/real_records.py`` does).
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import resource
import time
import warnings
from pathlib import Path

import numpy as np

from benchmarks.accuracy.families import draw, random_config
from benchmarks.real_records.sources import pyfrf_records


def cost_ratio() -> dict:
    """Seconds per work unit through the RK4 kernel and through the adaptive integrator (same model)."""
    from sindy_impulse.simulation import CompiledModel, TermTable

    model = CompiledModel([[0.0, 1.0], [-64.0, -3.2]], TermTable.polynomial([[1, 0], [0, 1]]),
                          reference=[[1.0, 0.0], [0.0, 8.0]])
    t = np.arange(20001) * 0.01
    out = {}
    runs = {"kernel": lambda: model.simulate([1.0, 0.0], t),
            "adaptive": lambda: model._adaptive(np.array([1.0, 0.0]), t[:2001], None, model.coef)}
    for name, run in runs.items():
        run()  # compiled / warmed
        before, start = model.work_done, time.perf_counter()
        for _ in range(3):
            run()
        out[name] = (time.perf_counter() - start) / (model.work_done - before)
    return out


def family_d_record(index: int):
    from sindy_impulse.datasets import impact_record

    rng = np.random.default_rng(0)
    for i in range(index + 1):
        case = draw("d", rng, i)
    rec = impact_record(**case["config"])
    return rec.y, rec.fs, None


def soak_record(seed: int):
    from sindy_impulse.datasets import impact_record

    rec = impact_record(**random_config(seed))
    return rec.y, rec.fs, rec.force if seed % 2 else None


def pyfrf_record(mirror: str):
    rec = pyfrf_records(Path(mirror))[0]
    return rec["y"], rec["fs"], rec["force"]


def _survey(task, results) -> None:
    from sindy_impulse import identify_modes

    kind, arg = task
    y, fs, force = {"d": family_d_record, "soak": soak_record, "pyfrf": pyfrf_record}[kind](arg)
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        survey = identify_modes(y, fs=fs, force=force)
    elapsed = time.perf_counter() - start
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    modes = ", ".join(f"{m.frequency_hz:.5g} Hz / {m.damping_ratio:.3g}" for m in survey.modes)
    results.put((len(y), elapsed, peak, len(survey.modes), len(survey.rejected), modes))


def run_one(task, timeout: float) -> tuple | None:
    ctx = mp.get_context("spawn")
    results = ctx.Queue()
    process = ctx.Process(target=_survey, args=(task, results))
    process.start()
    process.join(timeout)
    if process.is_alive():
        process.kill()
        return None
    return results.get() if not results.empty() else None


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mirror", help="folder of bare git copies (pyFRF); without it pyFRF is skipped")
    parser.add_argument("--only", choices=("cost", "records"), default=None)
    parser.add_argument("--timeout", type=float, default=900.0)
    parser.add_argument("--records", default="d0,d21,soak20,soak25",
                        help="comma-separated subset of d0, d21, soak20, soak25 (pyFRF: --mirror)")
    args = parser.parse_args(argv)
    out = {}
    if args.only != "records":
        ratio = out["seconds_per_work_unit"] = cost_ratio()
        print(f"seconds per work unit: kernel {ratio['kernel']:.3g}, adaptive {ratio['adaptive']:.3g} "
              f"(adaptive / kernel = {ratio['adaptive'] / ratio['kernel']:.2f})")
    if args.only == "cost":
        return out
    out["records"] = {}
    named = {"d0": ("d", 0), "d21": ("d", 21), "soak20": ("soak", 20), "soak25": ("soak", 25)}
    tasks = [named[k] for k in args.records.split(",") if k]
    tasks += [("pyfrf", args.mirror)] if args.mirror else []
    print("| record | samples | time (s) | peak memory (MB) | modes | rejected |")
    print("|---|---|---|---|---|---|")
    for task in tasks:
        label = f"{task[0]} {task[1]}" if task[0] != "pyfrf" else "pyFRF measurements_1"
        out = run_one(task, args.timeout)
        if out is None:
            print(f"| {label} | | over {args.timeout:g} s or crashed | | | |")
            out["records"][label] = None
            continue
        n, elapsed, peak, n_modes, n_rejected, modes = out
        row = f"| {label} | {n} | {elapsed:.1f} | {peak:.0f} | {n_modes} ({modes}) | {n_rejected} |"
        print(row, flush=True)
        out["records"][label] = {"samples": n, "seconds": elapsed, "peak_memory_mb": peak, "modes": n_modes,
                                 "rejected": n_rejected}
    return out


if __name__ == "__main__":
    main()

"""CPU time of ``identify_modes`` on one of issue 26's speed records, this tree beside another checkout.

    git archive main | tar -x -C /tmp/main_tree
    python benchmarks/perf_beside.py --other /tmp/main_tree --case nonlinear --rounds 5

Each round runs one subprocess per tree (``PYTHONPATH`` set to it), alternating, so both see the same load;
each subprocess surveys the record once to warm up (numba, caches), then ``--repeat`` times, and reports
the median CPU time of those runs (this process, all threads: on a shared machine the wall time follows
the load, the CPU time much less) and the first mode's frequency, damping ratio and nonlinearity verdict
(read after the timing). Printed: each tree's median over the rounds and the ratio this / other.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent

_CHILD = """
import json, sys, time, warnings
import numpy as np
sys.path.insert(0, {bench!r})
from perf_cases import issue26_records
from sindy_impulse import identify_modes
rec = issue26_records()[{case!r}]
def run():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return identify_modes(rec.y, fs=rec.fs)
run()
cpu = []
for _ in range({repeat}):
    start = time.process_time()
    survey = run()
    cpu.append(time.process_time() - start)
m = survey.modes[0]
print(json.dumps(dict(cpu=float(np.median(cpu)), f=m.frequency_hz, zeta=m.damping_ratio,
                      nonlinear=bool(m.nonlinear))))
"""


def measure(tree: Path, case: str, repeat: int) -> dict:
    """One subprocess on ``tree``: median CPU seconds and the first mode's values."""
    code = _CHILD.format(bench=str(tree / "benchmarks"), case=case, repeat=repeat)
    env = dict(os.environ, PYTHONPATH=str(tree))
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--other", type=Path, required=True, help="the other checkout (a source tree)")
    parser.add_argument("--case", default="nonlinear")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    trees = {"this": HERE.parent, "other": args.other.resolve()}
    rows = {name: [] for name in trees}
    for r in range(args.rounds):
        for name, tree in trees.items():
            rows[name].append(measure(tree, args.case, args.repeat))
            print(f"round {r} {name}: {rows[name][-1]}", flush=True)
    this, other = (float(np.median([x["cpu"] for x in rows[k]])) for k in ("this", "other"))
    print(f"{args.case}: CPU median this {this:.3f} s, other {other:.3f} s, ratio {this / other:.3f}; "
          f"nonlinear: this {rows['this'][-1]['nonlinear']}, other {rows['other'][-1]['nonlinear']}")


if __name__ == "__main__":
    main()

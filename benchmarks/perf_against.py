"""CPU time of a survey in this tree beside another checkout of the package, in the same run.

Each round runs a fresh process per tree (alternating, so a change of the machine's load shifts both): the
record of ``perf_cases.issue26_records()`` named by ``--record``, surveyed once to warm up, then
``--repeat`` times, the median CPU time of the process kept. The figure is the ratio of the medians over
the rounds (this tree / the other).

    python benchmarks/perf_against.py --against /work/main --record "two modes" --rounds 3
    python benchmarks/perf_against.py --against /work/main --family a --n 10 --rounds 2 --repeat 1

Measured for the weak modes of family b (``modes/_weak.py``, against main at 3dfa1d6): see
docs/modal-families-results.md.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

RUN = r'''
import json, sys, time, warnings
import numpy as np
sys.path.insert(0, {benchmarks!r})
from perf_cases import issue26_records
from mode_families import draw
from sindy_impulse import identify_modes, impact_record
if {family!r}:
    rng = np.random.default_rng(0)
    records = [impact_record(**draw({family!r}, rng, i)["config"]) for i in range({n})]
else:
    records = [issue26_records()[{record!r}]]
def run():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return [identify_modes(rec.y, fs=rec.fs) for rec in records]
run()
cpu = []
for _ in range({repeat}):
    start = time.process_time()
    surveys = run()
    cpu.append(time.process_time() - start)
print(json.dumps(dict(cpu=float(np.median(cpu)), modes=sum(len(s.modes) for s in surveys))))
'''


def _measure(tree: Path, record: str, repeat: int, family: str = "", n: int = 0) -> dict:
    """One fresh process surveying ``record`` (or the first ``n`` records of ``family``) with the package
    of ``tree``."""
    env = dict(os.environ, PYTHONPATH=str(tree), PYTHONDONTWRITEBYTECODE="1")
    code = RUN.format(benchmarks=str(Path(__file__).resolve().parent), record=record, repeat=repeat,
                      family=family, n=n)
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", type=Path, required=True, help="the other checkout's folder")
    parser.add_argument("--record", default="two modes")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--family", default="", help="instead of --record: the first --n records of a family "
                        "of mode_families.py (seed 0), surveyed together")
    parser.add_argument("--n", type=int, default=10)
    args = parser.parse_args()
    here = Path(__file__).resolve().parent.parent
    ours, theirs = [], []
    for r in range(args.rounds):
        a, b = (_measure(tree, args.record, args.repeat, args.family, args.n)
                for tree in (here, args.against))
        ours.append(a["cpu"])
        theirs.append(b["cpu"])
        print(f"round {r}: this tree {a['cpu']:.3f} s {a['modes']}, other {b['cpu']:.3f} s {b['modes']}")
    mine, other = statistics.median(ours), statistics.median(theirs)
    what = f"family {args.family}, {args.n} records" if args.family else args.record
    print(f"{what}: CPU median {mine:.3f} s here, {other:.3f} s there: ratio {mine / other:.3f}")


if __name__ == "__main__":
    main()

"""Do two checkouts give the same numbers? A refactoring's check (results must not move).

Runs the same cases in this tree and in another checkout of the package (its folder given by ``--against``,
e.g. ``git worktree add /tmp/base ae41a9d``), each in a fresh process, and compares every number exactly:
the paper's oscillator at 30 dB (coefficients and the nonlinearity verdict, seeds 0-2), two-mode linear
hammer surveys (frequency, damping ratio, fit error of every mode, seeds 0-2) and a nonlinear survey with
its nonlinearity verdict.

    python benchmarks/same_results.py --against /tmp/base

Measured for the layout change of issue 28 (against ae41a9d): identical, every number to the last digit.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

CASES = r'''
import json, warnings
import numpy as np
warnings.simplefilter("ignore")
from sindy_impulse import ImpulseSINDy, damped_oscillator, identify_modes, impact_record
from sindy_impulse.analysis import nonlinearity_test
out = {}
for s in range(3):
    t, x, _ = damped_oscillator(snr_db=30, random_state=s)
    model = ImpulseSINDy().fit(x, t=t)
    out[f"oscillator seed {s}"] = model.coef_.tolist()
    verdict = nonlinearity_test(model, x, t=t)
    out[f"nonlinearity seed {s}"] = [bool(verdict.nonlinear), float(verdict.statistic)]
for s in range(3):
    rec = impact_record([88.6, 156.7], [0.002, 0.004], fs=2048, duration=2, snr_db=50, random_state=s)
    survey = identify_modes(rec.y, fs=rec.fs)
    out[f"survey seed {s}"] = [(m.frequency_hz, m.damping_ratio, m.fit_error) for m in survey.modes]
rec = impact_record(122.4, 0.002, [1e-4], fs=2000, duration=2, sensor="displacement", snr_db=50,
                    cubic_stiffness=5e5, random_state=5)
survey = identify_modes(rec.y, fs=rec.fs)
out["nonlinear survey"] = [(m.frequency_hz, m.damping_ratio, bool(m.nonlinear)) for m in survey.modes]
print(json.dumps(out))
'''


def _run(root: Path) -> dict:
    env = dict(os.environ, PYTHONPATH=str(root))
    done = subprocess.run([sys.executable, "-c", CASES], env=env, cwd=root, capture_output=True, text=True)
    if done.returncode:
        raise SystemExit(f"the cases failed in {root}:\n{done.stderr[-2000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", required=True, type=Path, help="folder of the other checkout")
    args = parser.parse_args(argv)
    if not (args.against / "sindy_impulse" / "__init__.py").is_file():
        raise SystemExit(f"{args.against} holds no sindy_impulse package")
    here, there = _run(Path(__file__).resolve().parent.parent), _run(args.against.resolve())
    differ = [k for k in here if here[k] != there.get(k)]
    for key in differ:
        print(f"{key}:\n  this tree: {here[key]}\n  {args.against}: {there.get(key)}")
    print("identical" if not differ else f"{len(differ)} of {len(here)} cases differ")
    return 1 if differ else 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Exact gradients against forward differences in the refinement: CPU time of ``identify_modes``.

    OPENBLAS_NUM_THREADS=1 python benchmarks/perf_gradients.py [--repeat 3]

On issue 26's records (``perf_cases.issue26_records``) each survey runs with
``refinement.EXACT_GRADIENTS`` off and on, alternating in one process (the same load for both), and the
median CPU time of each is printed with the modes found. Measured on a shared 2-core machine (load 24):
two modes 1.07 s (differences) against 1.25 s (exact), three modes 1.27 s against 1.73 s, the nonlinear
record 2.22 s against 2.45 s (its work budget runs out either way); ESPRIT on the same records 0.06 s.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path[:0] = [str(Path(__file__).resolve().parent), str(Path(__file__).resolve().parents[1])]

from perf_cases import issue26_records  # noqa: E402

from sindy_impulse import identify_modes  # noqa: E402
from sindy_impulse.identification import refinement  # noqa: E402


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    for name, rec in issue26_records().items():
        times = {False: [], True: []}
        found = {}
        for exact in (False, True):  # warm both paths
            refinement.EXACT_GRADIENTS = exact
            identify_modes(rec.y, fs=rec.fs)
        for _ in range(args.repeat):
            for exact in (False, True):
                refinement.EXACT_GRADIENTS = exact
                start = time.process_time()
                survey = identify_modes(rec.y, fs=rec.fs)
                times[exact].append(time.process_time() - start)
                modes = survey.modes
                found[exact] = ", ".join(f"{m.frequency_hz:.3f} Hz / {m.damping_ratio:.5f}" for m in modes)
        print(f"{name}: differences {np.median(times[False]):.2f} s CPU ({found[False]}); exact "
              f"{np.median(times[True]):.2f} s CPU ({found[True]})", flush=True)
    refinement.EXACT_GRADIENTS = False
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

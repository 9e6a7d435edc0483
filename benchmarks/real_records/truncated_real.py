"""Real records cut before their decay reaches the noise: the survey's modes against the whole record's, and
its time beside the classical chart's on the cut record.

    python -m benchmarks truncated_real --mirror /path/to/mirrors [--keep 0.25,0.1] [--repeats 3]

A short acquisition block, or a shock record of a few thousand samples, ends while the structure still
rings: its modes are still tens of dB over the noise at the last sample. Every record of
:mod:`benchmarks.real_records.survey_speed` (the shipped flutter rig, and with the mirror folder pyFRF's
five hits, case1, the Dataset-4 cantilever and the Brake-Reuss beam) is cut to its first ``--keep`` share
of samples (each channel, the force too), hit and pre-trigger kept. Per record and share: the whole
record's modes paired with the nearest mode of the cut one within 1 % (``kept`` where the two frequencies
agree within 3 combined standard deviations, ``moved`` beyond), the whole record's modes ``lost`` and the
cut record's ``new`` ones (as :mod:`.clipped_real` pairs them), and the median times (``--repeats``, warm)
of the survey and of the baseline of :mod:`.survey_speed` on the cut record. A cut record holds less of
each decay: weak or lightly damped modes may be lost, and a mode whose damping changes with amplitude
reads the damping of its louder start; ``new`` modes are the ones to read.
"""

from __future__ import annotations

import argparse
import os

import numpy as np

from benchmarks.real_records.clipped_real import compare
from benchmarks.real_records.sources import ENV
from benchmarks.real_records.survey_speed import records, time_record


def cut(record: dict, share: float) -> dict:
    """``record`` with its samples (and force) cut to the first ``share`` of them."""
    n = max(int(share * np.shape(record["y"])[0]), 1)
    force = record.get("force")
    force = None if force is None else np.asarray(force)[:n]
    return {**record, "y": np.asarray(record["y"])[:n], "force": force}


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mirror", default=os.environ.get(ENV), help=f"folder of bare git copies ({ENV})")
    parser.add_argument("--keep", default="0.25,0.1", help="shares of each record kept, comma-separated")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    try:
        shares = [float(v) for v in args.keep.split(",")]
    except ValueError:
        parser.error(f"--keep must be numbers separated by commas, got {args.keep!r}")
    if not all(0 < s < 1 for s in shares):
        parser.error(f"every --keep share must be between 0 and 1, got {args.keep}")
    if args.repeats < 1:
        parser.error(f"--repeats must be at least 1, got {args.repeats}")
    print(f"load average before: {os.getloadavg()[0]:.2f}; median of {args.repeats}")
    rows = []
    for record in records(args.mirror):
        reference = time_record(record, 1)["survey"]  # (the whole record, its modes only)
        for share in shares:
            short = cut(record, share)
            timed = time_record(short, args.repeats)
            survey, survey_s, base_s = timed["survey"], timed["survey_s"], timed["baseline_s"]
            row = {"name": record["name"], "share": share, "samples": int(np.shape(short["y"])[0]),
                   "modes": len(reference.modes), "cut_modes": len(survey.modes), "survey_s": survey_s,
                   "baseline_s": base_s, "ratio": survey_s / base_s, **compare(reference, survey)}
            rows.append(row)
            print(f"\n{row['name']}, first {share:g} ({row['samples']} samples): {row['modes']} modes whole, "
                  f"{row['cut_modes']} cut; {survey_s:.2f} s vs baseline {base_s:.2f} s "
                  f"({row['ratio']:.1f}x)")
            for key in ("kept", "moved", "lost", "new"):
                print(f"  {key:5s} {len(row[key]):3d}  {', '.join(f'{f:.5g}' for f in row[key])}")
    totals = {key: sum(len(r[key]) for r in rows) for key in ("kept", "moved", "lost", "new")}
    ratios = [r["ratio"] for r in rows]
    print(f"\nall records: {totals}; survey / baseline time: median {np.median(ratios):.1f}x, largest "
          f"{max(ratios):.1f}x; load average after: {os.getloadavg()[0]:.2f}")
    return {"rows": rows, "totals": totals, "shares": shares}


if __name__ == "__main__":
    main()

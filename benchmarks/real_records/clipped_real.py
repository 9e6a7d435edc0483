"""Real records clipped as a saturating sensor would clip them: the survey's modes against the same record's
unclipped modes, and its time beside the classical chart's on the clipped record.

    python -m benchmarks clipped_real --mirror /path/to/mirrors [--clip 0.6] [--repeats 1]

Every record of :mod:`benchmarks.real_records.survey_speed` (the shipped flutter rig, and with the mirror
folder pyFRF's five hits, case1, the Dataset-4 cantilever and the Brake-Reuss beam) is clipped per channel
at ``--clip`` times its largest excursion from its offset (the median of its last tenth), as an ADC or a
sensor at its limit does: the samples beyond are set to the limit, the others stay. A quantised record
(pyFRF's) keeps its steps; a clip level between two steps is one more level, as a sensor's limit is.

Per record: the unclipped survey's modes paired with the nearest clipped one within 1 % (``kept`` where the
two frequencies agree within 3 combined standard deviations, ``moved`` beyond), the modes ``lost`` (no
partner), the clipped survey's modes with no unclipped one within 1 % (``new``), what the survey did with
the clipped samples (its warning), and the median times (``--repeats``, warm) of the survey and of the
baseline of :mod:`.survey_speed` on the clipped record. A clipped stretch holds the decay's first, loudest
part: weak modes that have died out by its end are expected to be lost, and the modes of a nonlinear
structure (the jointed beam, the flutter rig) move with the amplitude the decay starts from. ``new`` modes
are the ones to read: a mode the structure does not have is a wrong answer that looks right.
"""

from __future__ import annotations

import argparse
import os
import time
import warnings

import numpy as np

from benchmarks.real_records.sources import ENV
from benchmarks.real_records.survey_speed import baseline, records
from sindy_impulse import identify_modes

#: Largest relative distance between an unclipped mode and its clipped partner.
PAIR = 0.01


def clip(y: np.ndarray, fraction: float) -> np.ndarray:
    """``y`` clipped per channel at ``fraction`` of its largest excursion from its offset (last tenth's
    median)."""
    y = np.asarray(y, float)
    offset = np.median(y[-max(len(y) // 10, 1):], axis=0)
    reach = fraction * np.max(np.abs(y - offset), axis=0)
    return np.clip(y, offset - reach, offset + reach)


def _survey(y, record):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        survey = identify_modes(y, fs=record["fs"], force=record["force"])
    said = [str(w.message) for w in caught if "saturated" in str(w.message)]
    return survey, said


def _timed(y, record, repeats: int) -> tuple:
    survey, said = _survey(y, record)  # warm
    baseline(y, record["fs"])
    survey_s, base_s = [], []
    for _ in range(repeats):
        start = time.perf_counter()
        survey, said = _survey(y, record)
        survey_s.append(time.perf_counter() - start)
        start = time.perf_counter()
        baseline(y, record["fs"])
        base_s.append(time.perf_counter() - start)
    return survey, said, float(np.median(survey_s)), float(np.median(base_s))


def compare(reference, clipped) -> dict:
    """Unclipped modes kept, moved or lost in the clipped survey, and its new modes (frequencies, Hz)."""
    out = {"kept": [], "moved": [], "lost": [], "new": []}
    for mode in reference.modes:
        near = min(clipped.modes, key=lambda m: abs(m.frequency_hz - mode.frequency_hz), default=None)
        if near is None or abs(near.frequency_hz / mode.frequency_hz - 1) > PAIR:
            out["lost"].append(mode.frequency_hz)
            continue
        sigma = np.hypot(mode.frequency_std_hz, near.frequency_std_hz)
        moved = not abs(near.frequency_hz - mode.frequency_hz) <= 3 * sigma
        out["moved" if moved else "kept"].append(mode.frequency_hz)
    for mode in clipped.modes:
        if all(abs(mode.frequency_hz / m.frequency_hz - 1) > PAIR for m in reference.modes):
            out["new"].append(mode.frequency_hz)
    return out


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mirror", default=os.environ.get(ENV), help=f"folder of bare git copies ({ENV})")
    parser.add_argument("--clip", type=float, default=0.6, help="the limit, a fraction of the excursion")
    parser.add_argument("--repeats", type=int, default=1)
    args = parser.parse_args(argv)
    if not 0 < args.clip < 1:
        parser.error(f"--clip must be between 0 and 1, got {args.clip}")
    print(f"load average before: {os.getloadavg()[0]:.2f}; clipped at {args.clip:g} of each channel's "
          f"excursion; median of {args.repeats}")
    rows = []
    for record in records(args.mirror):
        reference, _ = _survey(record["y"], record)
        y = clip(record["y"], args.clip)
        survey, said, survey_s, base_s = _timed(y, record, args.repeats)
        row = {"name": record["name"], "modes": len(reference.modes), "clipped_modes": len(survey.modes),
               "survey_s": survey_s, "baseline_s": base_s, "ratio": survey_s / base_s,
               "handling": said[-1] if said else "no saturation found", **compare(reference, survey)}
        rows.append(row)
        print(f"\n{row['name']}: {row['modes']} modes unclipped, {row['clipped_modes']} clipped; "
              f"{survey_s:.2f} s vs baseline {base_s:.2f} s ({row['ratio']:.1f}x)\n  {row['handling']}")
        for key in ("kept", "moved", "lost", "new"):
            print(f"  {key:5s} {len(row[key]):3d}  {', '.join(f'{f:.5g}' for f in row[key])}")
    totals = {key: sum(len(r[key]) for r in rows) for key in ("kept", "moved", "lost", "new")}
    print(f"\nall records: {totals}; load average after: {os.getloadavg()[0]:.2f}")
    return {"rows": rows, "totals": totals, "clip": args.clip}


if __name__ == "__main__":
    main()

"""The modes' standard deviations against the spread over repeated hits of one structure (real records).

    python -m benchmarks repeat_hits --mirror /path/to/mirrors

pyFRF's five hammer hits (``ladisk/pyFRF``, ``data/measurements_1..5.npy``: the same driving point, force
and acceleration at 25,600 Hz, nothing changed between the hits) each go through ``identify_modes`` with
their force. The modes of the first hit are paired with the nearest mode of every other hit (within 0.2 %);
for each mode found in all five, the sample standard deviation of its frequency and damping ratio over the
hits is compared with the median of the five reported standard deviations (``frequency_std_hz``,
``damping_ratio_std``). Where the ratio is about 1 or below, the ± says how far a repeated test moves the
value (what ``track`` needs to tell a change from the test-to-test scatter); well above 1, the hits differ
by more than their noise explains (a mode that moves with the hit's force, or a ± too small). Five hits make
each spread uncertain by about 35 % (the spread of a sample standard deviation of five values).
"""

from __future__ import annotations

import argparse
import os
import warnings
from pathlib import Path

import numpy as np

from benchmarks.real_records.sources import ENV, pyfrf_records
from sindy_impulse import identify_modes

#: Largest relative distance between a mode of the first hit and its partner in another hit.
PAIR = 2e-3


def paired(surveys: list) -> list[dict]:
    """The modes of the first survey found in every other one (nearest within :data:`PAIR`), each with its
    values and standard deviations over the surveys."""
    rows = []
    for mode in surveys[0].modes:
        partners = []
        for survey in surveys:
            near = min(survey.modes, key=lambda m: abs(m.frequency_hz - mode.frequency_hz), default=None)
            if near is None or abs(near.frequency_hz / mode.frequency_hz - 1) > PAIR:
                break
            partners.append(near)
        if len(partners) < len(surveys):
            continue
        values = {name: np.array([getattr(m, name) for m in partners], float)
                  for name in ("frequency_hz", "frequency_std_hz", "damping_ratio", "damping_ratio_std")}
        rows.append({
            "frequency_hz": float(np.mean(values["frequency_hz"])),
            "damping_ratio": float(np.mean(values["damping_ratio"])),
            "frequency_spread_hz": float(np.std(values["frequency_hz"], ddof=1)),
            "frequency_std_hz": float(np.median(values["frequency_std_hz"])),
            "damping_spread": float(np.std(values["damping_ratio"], ddof=1)),
            "damping_std": float(np.median(values["damping_ratio_std"])),
            "sources": sorted({m.source for m in partners}),
        })
    for row in rows:
        row["frequency_ratio"] = row["frequency_spread_hz"] / row["frequency_std_hz"]
        row["damping_ratio_ratio"] = row["damping_spread"] / row["damping_std"]
    return rows


def main(argv=None) -> dict:
    formatter = argparse.RawDescriptionHelpFormatter
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=formatter)
    parser.add_argument("--mirror", default=os.environ.get(ENV), help=f"folder of bare git copies ({ENV})")
    args = parser.parse_args(argv)
    if args.mirror is None:
        raise SystemExit(f"pyFRF's records are read from a bare git copy: give --mirror DIR or set {ENV}")
    records = pyfrf_records(Path(args.mirror))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        surveys = [identify_modes(r["y"], fs=r["fs"], force=r["force"]) for r in records]
    rows = paired(surveys)
    print(f"pyFRF, five hits: {[len(s.modes) for s in surveys]} modes; {len(rows)} found in all five")
    print(f"{'f [Hz]':>10} {'spread':>9} {'median std':>10} {'ratio':>6} | {'zeta':>9} {'spread':>8} "
          f"{'median std':>10} {'ratio':>6}  source")
    for r in rows:
        print(f"{r['frequency_hz']:10.2f} {r['frequency_spread_hz']:9.3g} {r['frequency_std_hz']:10.3g} "
              f"{r['frequency_ratio']:6.2f} | {r['damping_ratio']:9.3g} {r['damping_spread']:8.2g} "
              f"{r['damping_std']:10.2g} {r['damping_ratio_ratio']:6.2f}  {', '.join(r['sources'])}")
    summary = {}
    for key, label in (("frequency_ratio", "frequency"), ("damping_ratio_ratio", "damping ratio")):
        ratios = np.array([r[key] for r in rows])
        summary[label] = {"median": float(np.median(ratios)), "above_3": int(np.sum(ratios > 3)),
                          "n": int(ratios.size)}
        print(f"{label}: spread over the hits / median std: median {np.median(ratios):.2f}, "
              f"above 3 for {np.sum(ratios > 3)} of {ratios.size} modes")
    return {"modes": rows, "summary": summary}


if __name__ == "__main__":
    main()

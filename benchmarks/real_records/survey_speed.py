"""The survey's time on real records beside the classical stabilisation diagram's, and the modes it finds.

    python -m benchmarks survey_speed --mirror /path/to/mirrors [--repeats 3] [--trace case1]

Every record of :mod:`benchmarks.real_records.real_records` (the shipped flutter rig, pyFRF's five hits,
vibration_toolbox's case1, the Dataset-4 cantilever) and, when its bare git copy is under the mirror folder,
the Brake-Reuss beam's hammer record (``mattiacenedese/BRBtesting``, ``HammerImpact.mat``, three
accelerometers at 12.8 kHz; GPL-3.0: read here, never shipped), each timed ``--repeats`` times (median, warm:
one untimed survey first) through ``identify_modes`` and through the baseline, alternately so a busy
machine shifts both: :func:`sindy_impulse.poles.stabilisation` on at most 20,000 samples of each channel's
free decay (the classical chart the package already draws; per channel for several channels). Printed per
record: both medians, their ratio, the modes (frequency and damping ratio with standard deviations, where
the values come from) and, for case1, whether its 579 Hz mode is found. ``--trace NAME`` prints the
survey's trace (each stage's time and decisions) for the records whose name contains NAME. The 1-minute
load average is printed before and after.
"""

from __future__ import annotations

import argparse
import io
import os
import time
import warnings
from pathlib import Path

import numpy as np
import scipy.io

from benchmarks.accuracy.scoring import esprit_start
from benchmarks.real_records.sources import (
    ENV,
    MissingRepository,
    beam_record,
    case1_record,
    flutter_records,
    git_file,
    pyfrf_records,
)
from sindy_impulse import identify_modes
from sindy_impulse.poles import stabilisation

BRB = ("mattiacenedese/BRBtesting", "2d42d3a618206da58642674d3287ae34dfc7d5e5")
BASELINE_SAMPLES = 20_000


def brb_record(mirror: Path) -> list[dict]:
    """The Brake-Reuss beam's hammer impact: three accelerometers (m/s^2), 65,536 samples at 12.8 kHz."""
    raw = git_file(mirror, BRB, "HammerImpact.mat")
    data = scipy.io.loadmat(io.BytesIO(raw), squeeze_me=True, struct_as_record=False)["HIdata"]
    fs = 1.0 / float(np.mean(np.diff(data.time)))
    y = np.column_stack([data.acc1, data.acc2, data.acc3])
    return [{"name": "BRBtesting HammerImpact (3 accelerometers)", "set": "BRB", "y": y, "force": None,
             "fs": round(fs, 3)}]


def baseline(y: np.ndarray, fs: float) -> list:
    """The classical chart per channel (from the detected onset plus 2 ms): its stable modes, all channels."""
    y = y.reshape(len(y), -1)
    found = []
    for channel in y.T:
        onset = esprit_start(channel, fs)
        found += stabilisation(channel[onset: onset + BASELINE_SAMPLES], fs=fs).modes()
    return found


def _survey(record):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return identify_modes(record["y"], fs=record["fs"], force=record["force"])


def time_record(record: dict, repeats: int) -> dict:
    """Median times of the survey and the baseline (alternated), and the survey."""
    survey = _survey(record)  # warm: kernels compiled, caches filled
    baseline(np.asarray(record["y"], float), record["fs"])
    survey_s, base_s = [], []
    for _ in range(repeats):
        start = time.perf_counter()
        survey = _survey(record)
        survey_s.append(time.perf_counter() - start)
        start = time.perf_counter()
        baseline(np.asarray(record["y"], float), record["fs"])
        base_s.append(time.perf_counter() - start)
    return {"survey_s": float(np.median(survey_s)), "baseline_s": float(np.median(base_s)), "survey": survey}


def records(mirror) -> list:
    """The real records: the shipped flutter rig's, and those of the repositories under ``mirror``."""
    out = flutter_records()
    for load in (pyfrf_records, case1_record, beam_record, brb_record):
        if mirror is None:
            continue
        try:
            out += load(Path(mirror))
        except MissingRepository as err:
            print(f"  (skipped: {err})")
    return out


def _row(record: dict, timed: dict) -> dict:
    survey = timed["survey"]
    modes = [dict(frequency_hz=m.frequency_hz, frequency_std_hz=m.frequency_std_hz,
                  damping_ratio=m.damping_ratio, damping_ratio_std=m.damping_ratio_std, source=m.source)
             for m in survey.modes]
    row = dict(name=record["name"], samples=int(len(record["y"])), fs=record["fs"],
               survey_s=timed["survey_s"], baseline_s=timed["baseline_s"],
               ratio=timed["survey_s"] / timed["baseline_s"], modes=modes,
               without_std=sum(1 for m in modes if not np.isfinite(m["frequency_std_hz"])))
    if record["set"] == "case1":
        row["finds_579_hz"] = any(abs(m["frequency_hz"] / 579.0 - 1) < 0.005 for m in modes)
    return row


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mirror", default=os.environ.get(ENV), help=f"folder of bare git copies ({ENV})")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--trace", default=None, help="print the trace of the records whose name contains it")
    parser.add_argument("--quick", action="store_true", help="one repeat")
    args = parser.parse_args(argv)
    repeats = 1 if args.quick else args.repeats
    load_before = os.getloadavg()[0]
    print(f"load average before: {load_before:.2f} ({os.cpu_count()} cores); median of {repeats}")
    rows = []
    print(f"{'record':<44s} {'samples':>8s} {'survey s':>9s} {'baseline s':>10s} {'ratio':>6s}  modes")
    for record in records(args.mirror):
        timed = time_record(record, repeats)
        row = _row(record, timed)
        rows.append(row)
        extra = "" if "finds_579_hz" not in row else f"  579 Hz found: {row['finds_579_hz']}"
        print(f"{row['name'][:44]:<44s} {row['samples']:>8d} {row['survey_s']:>9.2f} "
              f"{row['baseline_s']:>10.2f} {row['ratio']:>6.1f}  {len(row['modes'])}{extra}")
        for m in row["modes"]:
            print(f"      {m['frequency_hz']:11.5g} +- {m['frequency_std_hz']:.2g} Hz   zeta "
                  f"{m['damping_ratio']:.4g} +- {m['damping_ratio_std']:.2g}   ({m['source']})")
        if args.trace and args.trace in record["name"]:
            print(timed["survey"].trace)
    load_after = os.getloadavg()[0]
    print(f"load average after: {load_after:.2f}")
    return {"rows": rows, "load_before": load_before, "load_after": load_after, "repeats": repeats}


if __name__ == "__main__":
    main()

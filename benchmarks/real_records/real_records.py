"""Real impact and ring-down records through identify_modes, each mode beside the stabilised ESPRIT baseline.

    python -m benchmarks real_records --mirror /path/to/mirrors
    SINDY_IMPULSE_MIRROR=/path/to/mirrors python -m benchmarks real_records

The shipped flutter-rig free decays (:func:`sindy_impulse.datasets.load_flutter_rig`, 2 records, heave and
pitch at 500 Hz) and three public record sets (docs/real-records.md has their provenance, licences and the
values their authors publish), read from bare git copies of their repositories under the mirror folder
(``owner+name/repo``, as a ``git clone --bare`` of the repository or the search tool's ``fetch`` leaves
them), at the pinned commits below:

=====================================================  =========================================  ==========
repository (folder)                                    files (commit)                             licence
=====================================================  =========================================  ==========
ladisk/pyFRF (``ladisk+pyFRF``)                        ``data/measurements_1..5.npy`` (55431fd)   MIT
vibrationtoolbox/vibration_toolbox                     ``vibration_toolbox/data/case1.mat``       MIT
(``vibrationtoolbox+vibration_toolbox``)               (1bec7f1)
PujaChowdhury/Dataset-4-Univariate-signal-with-        ``modal_analysis/data/timeseries_data.lvm``  CC BY-SA
non-stationarity (``PujaChowdhury+Dataset-4-...``)     (42c970f)                                  4.0
=====================================================  =========================================  ==========

pyFRF: five hammer hits on one driving point (force and acceleration, 25,600 Hz, 1 s); case1.mat: one hit
(force and response, 1,280 Hz, 3.2 s, no pre-trigger); Dataset-4: a cantilever beam tapped once, one
accelerometer, 1,651.6 Hz (51,200 / 31; the file's rounded Delta_X is not used), 49.6 s. A missing
repository is reported with how to get it, and the others still run.

Every record is surveyed (``identify_modes(y, fs=..., force=...)``; an exception is printed, not raised) and
the baseline is the stabilisation diagram (:func:`sindy_impulse.poles.stabilisation`: ESPRIT over model
orders 10-60, a pole kept when it recurs within 0.5 % in frequency and 10 % in damping ratio at 5 orders)
on at most 20,000 samples from the detected onset (plus 2 ms, as in benchmarks/accuracy/modes.py). Each mode
is printed beside the baseline's nearest stable pole (frequency, damping ratio, their relative differences),
then the baseline's poles no mode is near (within 1 %), the rejected peaks and the survey's notes.
"""

from __future__ import annotations

import argparse
import os
import time
import warnings
from pathlib import Path

import numpy as np

from benchmarks.accuracy.scoring import MATCH, esprit_start
from benchmarks.real_records.sources import (
    ENV,
    MissingRepository,
    beam_record,
    case1_record,
    flutter_records,
    pyfrf_records,
)
from sindy_impulse import identify_modes
from sindy_impulse.poles import stabilisation

BASELINE_SAMPLES = 20_000
#: What the sources (or docs/real-records.md's checks) say each set shows.
REFERENCE = {
    "flutter rig": "heave and pitch modes near the rig's nominal frequencies (datasets/flutter_rig.py)",
    "pyFRF": "no published table; FFT/H1 peaks 899.9, 2640.4, 3669.0, 3689.5, 4128, 4163.5, 4391.9, 5969.6, "
             "6077.5 Hz, zeta about 2-16e-4 (docs/real-records.md)",
    "case1": "f_n = 212.0925 Hz (the toolbox's own sdof_cf doctest), zeta about 9e-4; other peaks 34.0 and "
             "579 Hz",
    "beam": "6.62, 41.4, 117.5 Hz (the authors' README); zeta about 3.8e-3, 1.5e-3, 2.4e-3 (envelope)",
}


def baseline(y: np.ndarray, fs: float) -> list:
    ref = y if y.ndim == 1 else y[:, int(np.argmax(np.std(y, axis=0)))]
    onset = esprit_start(ref, fs)
    return stabilisation(ref[onset: onset + BASELINE_SAMPLES], fs=fs).modes()


def survey_record(record: dict) -> dict:
    print(f"\n== {record['name']}: {len(record['y'])} samples at {record['fs']:.6g} Hz"
          + (", with force" if record["force"] is not None else ""))
    start = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            survey = identify_modes(record["y"], fs=record["fs"], force=record["force"])
    except Exception as exc:  # noqa: BLE001 - every record is surveyed; a failure is printed
        print(f"   survey EXCEPTION {type(exc).__name__}: {exc}")
        survey = None
    elapsed = time.perf_counter() - start
    start = time.perf_counter()
    try:
        poles = baseline(np.asarray(record["y"], float), record["fs"])
    except Exception as exc:  # noqa: BLE001
        print(f"   baseline EXCEPTION {type(exc).__name__}: {exc}")
        poles = []
    base_time = time.perf_counter() - start
    print(f"   survey {elapsed:.1f} s, baseline {base_time:.1f} s")
    if survey is not None:
        _print_modes(survey, poles)
    return {"name": record["name"], "samples": len(record["y"]), "fs": record["fs"],
            "modes": None if survey is None else [(m.frequency_hz, m.damping_ratio) for m in survey.modes],
            "baseline": [(p.frequency_hz, p.damping_ratio) for p in poles], "seconds": elapsed,
            "baseline_seconds": base_time}


def _print_modes(survey, poles) -> None:
    pf = np.array([p.frequency_hz for p in poles])
    print(f"   {'mode f (Hz)':>12} {'zeta':>9} | {'baseline f':>11} {'zeta':>9} {'df/f':>9} {'dz/z':>7}")
    near = set()
    for m in survey.modes:
        if pf.size:
            j = int(np.argmin(np.abs(pf / m.frequency_hz - 1)))
            p = poles[j]
            near.add(j) if abs(p.frequency_hz / m.frequency_hz - 1) <= MATCH else None
            print(f"   {m.frequency_hz:12.5g} {m.damping_ratio:9.3e} | {p.frequency_hz:11.5g} "
                  f"{p.damping_ratio:9.3e} {p.frequency_hz / m.frequency_hz - 1:+9.1e} "
                  f"{p.damping_ratio / m.damping_ratio - 1:+7.2f}")
        else:
            print(f"   {m.frequency_hz:12.5g} {m.damping_ratio:9.3e} | (no stable pole)")
    rest = [poles[j] for j in range(len(poles)) if j not in near]
    if rest:
        print("   baseline poles with no mode near: "
              + ", ".join(f"{p.frequency_hz:.5g} Hz / {p.damping_ratio:.2e}" for p in rest))
    for r in survey.rejected:
        band = "record" if r.band_hz is None else f"{r.band_hz[0]:.5g}-{r.band_hz[1]:.5g} Hz"
        print(f"   rejected {band}: {r.reason[:160]}")
    for note in survey.notes:
        print(f"   note: {note[:160]}")


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mirror", default=os.environ.get(ENV),
                        help=f"folder of the bare git copies (or set {ENV})")
    parser.add_argument("--sets", default="flutter rig,pyFRF,case1,beam",
                        help="comma-separated: flutter rig, pyFRF, case1, beam")
    args = parser.parse_args(argv)
    wanted = [s.strip() for s in args.sets.split(",")]
    loaders = {"flutter rig": lambda m: flutter_records(), "pyFRF": pyfrf_records, "case1": case1_record,
               "beam": beam_record}
    missing, surveyed = 0, []
    for name in wanted:
        if name != "flutter rig" and not args.mirror:
            print(f"\n{name}: no mirror folder given: pass --mirror DIR or set {ENV} to the folder holding "
                  "the bare git copies (owner+name/repo; see this script's docstring)")
            missing += 1
            continue
        try:
            records = loaders[name](Path(args.mirror) if args.mirror else None)
        except MissingRepository as err:
            print(f"\n{name}: {err}")
            missing += 1
            continue
        print(f"\n#### {name}: what the records show: {REFERENCE[name]}")
        surveyed += [survey_record(record) for record in records]
    return {"records": surveyed, "sets_missing": missing, "ok": not missing}


if __name__ == "__main__":
    raise SystemExit(0 if main()["ok"] else 1)

"""Issue 27's round trip: a synthetic 3-channel hammer test written to every file format the package reads
gives the same modes from each file as from the arrays.

Run from the repository root::

    python -m benchmarks file_round_trip            # seeds 0-4
    python -m benchmarks file_round_trip --seeds 2

For each seed, a 3-sensor, 3-mode ``impact_record`` with its force channel is surveyed from the arrays, then
written with :func:`sindy_impulse.io.write_record` to UFF 58 (ASCII and binary), LabVIEW ``.lvm``, TDMS,
MATLAB ``.mat``, ``.npz`` and CSV, read back with :func:`sindy_impulse.io.read_record` and surveyed again.
Printed per format: the largest relative frequency and damping-ratio differences against the arrays' modes
over all seeds, and whether every seed met the issue's bounds (1e-4 in frequency, 1 % in damping ratio).
Needs the ``io`` extra (pyuff, npTDMS, lvm-read, h5py).
"""

from __future__ import annotations

import argparse
import tempfile
import warnings
from pathlib import Path

import numpy as np

from sindy_impulse import identify_modes, impact_record
from sindy_impulse.io import Record, read_record, write_record

#: (label, suffix, write_record keywords)
FORMATS = [
    ("UFF 58 ASCII", ".uff", {}),
    ("UFF 58 binary", ".uff", {"binary": True}),
    ("LabVIEW lvm", ".lvm", {}),
    ("TDMS", ".tdms", {}),
    ("MATLAB mat", ".mat", {}),
    ("NumPy npz", ".npz", {}),
    ("CSV", ".csv", {}),
]
FREQUENCY_BOUND, DAMPING_BOUND = 1e-4, 1e-2


def hammer_test(seed: int) -> Record:
    """Three accelerometers and the hammer's force of a 3-mode structure."""
    rec = impact_record([90.0, 210.0, 335.0], [0.005, 0.008, 0.006], fs=2048, duration=1.5, snr_db=50,
                        sensor_dof=[0, 1, 2], sensor="acceleration", random_state=seed)
    data = np.column_stack([rec.y, rec.force])
    return Record(data, rec.fs, channel_names=("a1", "a2", "a3", "hammer"), units=("m/s^2",) * 3 + ("N",),
                  force_channel=3)


def modes_of(record: Record) -> np.ndarray:
    """(frequency_hz, damping_ratio) per mode of the record's survey."""
    keep = [i for i in range(record.data.shape[1]) if i != record.force_channel]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        force = record.data[:, record.force_channel]
        survey = identify_modes(record.data[:, keep], fs=record.fs, force=force)
    return np.array([[m.frequency_hz, m.damping_ratio] for m in survey.modes])


def differences(seeds, folder: Path) -> dict:
    """{format: list of (max rel. frequency difference, max rel. damping difference) per seed}."""
    out = {label: [] for label, _, _ in FORMATS}
    for seed in seeds:
        record = hammer_test(seed)
        reference = modes_of(record)
        for label, suffix, kwargs in FORMATS:
            path = folder / f"s{seed}_{label.replace(' ', '_')}{suffix}"
            write_record(record, path, **kwargs)
            found = modes_of(read_record(path))
            if found.shape != reference.shape:
                out[label].append((np.inf, np.inf))
                continue
            rel = np.abs(found - reference) / np.abs(reference)
            out[label].append((rel[:, 0].max(), rel[:, 1].max()))
    return out


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=None, help="seeds 0..N-1 (default 5, quick 1)")
    parser.add_argument("--quick", action="store_true", help="seed 0 only")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        table = differences(range(args.seeds or (1 if args.quick else 5)), Path(tmp))
    print(f"| format | seeds | max rel. frequency difference | max rel. damping difference | "
          f"within {FREQUENCY_BOUND:g} / {DAMPING_BOUND:.0%} |")
    print("|---|---|---|---|---|")
    ok, worst = True, {}
    for label, rows in table.items():
        df, dz = (max(r[i] for r in rows) for i in (0, 1))
        good = df <= FREQUENCY_BOUND and dz <= DAMPING_BOUND
        ok &= good
        print(f"| {label} | {len(rows)} | {df:.1e} | {dz:.1e} | {'yes' if good else 'NO'} |")
        worst[label] = {"frequency": df, "damping_ratio": dz, "within_bounds": good}
    return {"formats": worst, "ok": ok}


if __name__ == "__main__":
    raise SystemExit(0 if main()["ok"] else 1)

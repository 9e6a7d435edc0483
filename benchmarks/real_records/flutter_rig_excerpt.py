"""Rebuild ``sindy_impulse/data/flutter_rig_free_decay.npz`` from the source records.

Source: the public GitHub repository ``Kyounghyunlee/System_ID_flutter`` (MIT licence, Copyright (c) 2019
Kyoung Hyun Lee), commit 0a20f217e61a145e6992aeda7944b4a7f6453920, folder ``Linear_system_Identification``:
the MATLAB files ``Measured_data.mat`` ("model-1") and ``Measured_data2.mat`` ("model-2"). Each holds
``data`` (2 x 80000): row 0 the pitch angle (rad), row 1 the heave sensor voltage (V; ``sen`` = 0.18 m/V),
sampled at ``fs`` = 5000 Hz (16 s): one still-air free decay of a pitch-and-heave aerofoil rig per file.

The excerpt keeps every 10th sample of the whole record (rows 0, 10, ..., 79990: 8000 samples at 500 Hz).
The kept values are copied unchanged (float32 holds every source value exactly; the script checks it). No
filtering: the rig's content is below 10 Hz, the few sensor tones above 250 Hz fold back at < -75 dB.
The archive is written with a fixed time stamp, so the same source gives the same bytes (sha256 printed).

Run (from the repository root):
    python -m benchmarks flutter_rig_excerpt PATH/TO/System_ID_flutter/Linear_system_Identification
    python -m benchmarks flutter_rig_excerpt SOURCE_DIR -o other.npz
"""

from __future__ import annotations

import argparse
import hashlib
import io
import zipfile
from pathlib import Path

import numpy as np
from scipy.io import loadmat

SOURCES = {  # record name -> (file, sha256 of the file at commit 0a20f21)
    "model-1": ("Measured_data.mat", "e66ffbe8f11657dc1985e24fdc101cb7ec941d94105473cdac66152d019172a9"),
    "model-2": ("Measured_data2.mat", "b7d310d9d023c5c285b51fa288326832c995d1f27bc50bf7c85435178c1bdd1d"),
}
STRIDE = 10
SOURCE_FS = 5000.0
OUT = Path(__file__).resolve().parents[2] / "sindy_impulse" / "data" / "flutter_rig_free_decay.npz"


def sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def read_record(path: Path) -> dict:
    """Pitch (rad) and heave (V) rows, kept every STRIDE-th sample, plus the scalars the excerpt carries."""
    m = loadmat(path)
    data = np.asarray(m["data"], dtype=np.float64)
    if data.shape != (2, 80000) or float(m["fs"].squeeze()) != SOURCE_FS:
        raise ValueError(f"{path}: expected data (2, 80000) at 5000 Hz, got {data.shape} at {m['fs']}")
    kept = data[:, ::STRIDE]
    as32 = kept.astype(np.float32)
    if not np.array_equal(as32.astype(np.float64), kept):
        raise ValueError(f"{path}: float32 would change some values; keep float64")
    return {
        "pitch": as32[0],
        "heave": as32[1],
        "sen": float(m["sen"].squeeze()),
        "w_h": float(m["w_h"].squeeze()),
        "w_a": float(m["w_a"].squeeze()),
    }


def build_arrays(source_dir: Path, check_hash: bool = True) -> dict:
    records, digests = [], []
    for fname, expected in SOURCES.values():
        path = source_dir / fname
        digest = sha256(path)
        if check_hash and digest != expected:
            raise ValueError(f"{path}: sha256 {digest} differs from the commit's {expected}")
        records.append(read_record(path))
        digests.append(digest)
    sens = {r["sen"] for r in records}
    if len(sens) != 1:
        raise ValueError(f"the records disagree on the heave sensitivity: {sens}")
    return {
        "pitch_rad": np.stack([r["pitch"] for r in records]),
        "heave_volts": np.stack([r["heave"] for r in records]),
        "heave_sensitivity_m_per_volt": np.float64(sens.pop()),
        "fs": np.float64(SOURCE_FS / STRIDE),
        "source_fs": np.float64(SOURCE_FS),
        "stride": np.int64(STRIDE),
        "record_names": np.array(list(SOURCES)),
        "source_files": np.array([f for f, _ in SOURCES.values()]),
        "source_sha256": np.array(digests),
        "nominal_heave_frequency_hz": np.array([r["w_h"] / (2 * np.pi) for r in records]),
        "nominal_pitch_frequency_hz": np.array([r["w_a"] / (2 * np.pi) for r in records]),
    }


def write_npz(arrays: dict, out: Path) -> str:
    """A standard ``.npz`` (read by ``np.load``) with fixed time stamps and order, so it is byte-stable."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        for key in sorted(arrays):
            member = io.BytesIO()
            np.lib.format.write_array(member, np.asarray(arrays[key]), allow_pickle=False)
            info = zipfile.ZipInfo(key + ".npy", date_time=(1980, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED
            zf.writestr(info, member.getvalue(), compresslevel=9)
    out.write_bytes(buf.getvalue())
    return hashlib.sha256(buf.getvalue()).hexdigest()


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("source_dir", type=Path, help="folder with Measured_data.mat and Measured_data2.mat")
    parser.add_argument("-o", "--out", type=Path, default=OUT, help=f"output file (default {OUT})")
    parser.add_argument("--no-hash-check", action="store_true", help="accept source files of other commits")
    args = parser.parse_args(argv)
    arrays = build_arrays(args.source_dir, check_hash=not args.no_hash_check)
    digest = write_npz(arrays, args.out)
    print(f"wrote {args.out} ({args.out.stat().st_size} bytes), sha256 {digest}")
    for key in sorted(arrays):
        print(f"  {key}: {np.asarray(arrays[key]).dtype} {np.asarray(arrays[key]).shape}")
    return {"out": str(args.out), "bytes": args.out.stat().st_size, "sha256": digest}


if __name__ == "__main__":
    main()

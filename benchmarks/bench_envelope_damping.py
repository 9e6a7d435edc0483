"""The records of a family scored with and without the small-amplitude damping step (``modes/_envelope.py``).

    python benchmarks/bench_envelope_damping.py --family g --seed 1          # 60 records
    python benchmarks/bench_envelope_damping.py --family a --n 60

One survey per record (``bench_modes.py``'s draw and scoring): the step's input and output are recorded, so
the answer without the step is the same survey's modes before it. Printed: every record where the step
changed a mode (its damping ratio before -> after against the truth), and per answer the records right,
the records with a spurious mode and the median errors, as ``bench_modes.py --family X`` reports them.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

from sindy_impulse import identify_modes, impact_record
from sindy_impulse.modes import survey as _survey

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_modes import FAMILY_SIZES, judge  # noqa: E402
from mode_families import band_snr_db, draw  # noqa: E402


def one(case: dict) -> dict:
    """Survey one record, recording the step's modes before and after; both answers judged."""
    seen = []
    step = _survey.small_amplitude_damping

    def spy(modes):
        out = step(modes)
        seen.append((list(modes), list(out[0])))
        return out

    _survey.small_amplitude_damping = spy
    try:
        rec = impact_record(**case["config"])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            found = identify_modes(rec.y, fs=rec.fs)
    finally:
        _survey.small_amplitude_damping = step
    after = [(m.frequency_hz, m.damping_ratio) for m in found.modes]
    swap = {id(a): b for before, out in seen for a, b in zip(before, out) if a is not b}
    undo = {id(b): a for before, out in seen for a, b in zip(before, out) if a is not b}
    before = [(m.frequency_hz, undo[id(m)].damping_ratio if id(m) in undo else m.damping_ratio)
              for m in found.modes]
    f, z = rec.modes.frequency_hz, rec.modes.damping_ratio
    counted = np.ones(f.size, bool)
    if "min_band_snr_db" in case:
        counted = band_snr_db(rec) >= case["min_band_snr_db"]
    return {"with": judge(case, f, z, counted, after, found.rejected),
            "without": judge(case, f, z, counted, before, found.rejected),
            "changed": [(b.frequency_hz, a.damping_ratio, b.damping_ratio) for a, b in
                        ((undo[id(m)], m) for m in found.modes if id(m) in undo)],
            "truth": (f, z), "n_changed": len(swap)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--family", default="g")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--n", type=int, default=None)
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    rows = []
    for i in range(args.n or FAMILY_SIZES[args.family]):
        r = one(draw(args.family, rng, i))
        rows.append(r)
        for g, z_before, z_after in r["changed"]:
            f, z = r["truth"]
            j = int(np.argmin(np.abs(f / g - 1)))
            print(f"  [{args.family} #{i}] {g:.6g} Hz: damping ratio {z_before:.4g} -> {z_after:.4g} "
                  f"(dz/z {z_before / z[j] - 1:+.3f} -> {z_after / z[j] - 1:+.3f}); record right "
                  f"{r['without']['passed']} -> {r['with']['passed']}", flush=True)
    for who in ("without", "with"):
        right = sum(r[who]["passed"] for r in rows)
        spurious = sum(r[who]["spurious"] > 0 for r in rows)
        e = np.array([x for r in rows for x in r[who]["errors"] if np.all(np.isfinite(x))]).reshape(-1, 2)
        mf, mz = np.median(e, axis=0) if e.size else (np.nan, np.nan)
        print(f"family {args.family}, seed {args.seed}, {len(rows)} records, {who} the step: {right} right, "
              f"{spurious} with a spurious mode, median df/f {mf:.1e}, dz/z {mz:.1e}")


if __name__ == "__main__":
    main()

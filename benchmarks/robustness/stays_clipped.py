"""Records that stay clipped, and modes that may be harmonics: what the survey names, and what it loses.

    python -m benchmarks stays_clipped                 # 120 clipped records, families at seed 241
    python -m benchmarks stays_clipped --seed 3 --n 120 --family-seed 239 --family-n 100
    python -m benchmarks stays_clipped --quick         # 30 records, 20 per family

**Records that stay clipped** (the impact's ``clipping`` is ``"kept"``: no repair fits and nothing
unclipped follows the clipping): random records of 2-4 modes at 1 kHz (displacement), a dominant one
of 40-80 Hz and the others at 100-450 Hz with 0.2-0.5 of its amplitude, damping ratios 0.1-0.5 %, 0.2-0.3 s
long, clipped at 0.2-0.4 of the peak, SNR 30-60 dB; those that stay clipped are surveyed. Per record:
the true modes found (within 0.3 %), the true modes named clipping products (what must not happen), the
products named, and the modes left that are no true mode (the clipping's other products, which the
warning says may remain).

**The may-be-harmonic note** (a mode the harmonic test left undecided whose numbers fit a harmonic of a
lower mode): over the records of families a, b, e, f and g of :mod:`benchmarks.accuracy.families` at
``--family-seed``, the notes standing on a true mode (a false doubt) and on a mode that is none (a right
one); and how many of those records stay clipped (none is expected: the families' clipped records are
repaired or start after the clipping).

Measured (2026-11-30, main at 9cc3f61; ``--family-seed 239``): 11 of the 120 records stay clipped; their
true modes found 12 of 26 (a record clipped to its end keeps little of its decay); 61 products named; 1 true
mode named a product (#115: a 421.6 Hz mode 0.27 % from the dominant 46.85 Hz mode's ninth harmonic, within
its half-power half-width: where the sensor clips to the end, nothing in the record tells the two apart);
33 modes left that are no true mode (the warning says products may remain). Families at seed 239: the note
on 2 modes, both no true mode (e #54, a quadratic spring's 18 dB second harmonic, and g #32), on no true
mode; no record of them stays clipped. At seed 241 (e, f and g): no note.
"""

from __future__ import annotations

import argparse
import re
import warnings

import numpy as np

from benchmarks.accuracy.families import draw
from sindy_impulse import identify_modes, impact_record
from sindy_impulse.modes.kinds import Reason
from sindy_impulse.preprocessing import preprocess

#: A found mode is a true one within this relative distance.
MATCH = 3e-3
NOTE = re.compile(r"the mode at ([0-9.]+) Hz may be harmonic")


def _survey(y, fs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return preprocess(y, fs=fs).impact.clipping, identify_modes(y, fs=fs)


def _true(f: float, f_true) -> bool:
    return bool(np.any(np.abs(np.asarray(f_true, float) / f - 1) < MATCH))


def clipped_record(rng: np.random.Generator, index: int):
    """One random record clipped to near its end (see the module), or None when the generator refuses it."""
    n = int(rng.integers(2, 5))
    f = np.r_[rng.uniform(40, 80), np.sort(rng.uniform(100, 450, n - 1))]
    z = rng.uniform(0.001, 0.005, n)
    clip, duration = float(rng.uniform(0.2, 0.4)), float(rng.uniform(0.2, 0.3))
    amplitudes = [1.0, *rng.uniform(0.2, 0.5, n - 1)]
    snr = float(rng.uniform(30, 60))
    try:
        return impact_record(list(f), list(z), amplitudes, fs=1000.0, duration=duration, pre_trigger=0.01,
                             clip=clip, snr_db=snr, random_state=index, sensor="displacement")
    except ValueError:
        return None


def stays_clipped(seed: int, n: int) -> dict:
    rng = np.random.default_rng(seed)
    rows = []
    for i in range(n):
        rec = clipped_record(rng, i)
        if rec is None:
            continue
        how, survey = _survey(rec.y, rec.fs)
        if how != "kept":
            continue
        f_true = rec.modes.frequency_hz
        products = [r.evidence["frequency_hz"] for r in survey.rejected
                    if r.code is Reason.CLIPPING_PRODUCT and "combination" in r.evidence]
        found = [m.frequency_hz for m in survey.modes]
        row = {"index": i, "true": len(f_true), "found": sum(any(abs(g / f - 1) < MATCH for g in found)
                                                               for f in f_true),
               "true_named_products": sum(_true(p, f_true) for p in products), "products": len(products),
               "spurious_left": sum(not _true(g, f_true) for g in found)}
        rows.append(row)
        print(f"  #{i}: true {np.round(f_true, 1).tolist()}, found {np.round(found, 1).tolist()}; "
              f"{row['products']} product(s) named, {row['true_named_products']} of them a true mode",
              flush=True)
    total = {k: sum(r[k] for r in rows) for k in ("true", "found", "true_named_products", "products",
                                                  "spurious_left")}
    print(f"{len(rows)} of {n} records stay clipped: true modes found {total['found']} of {total['true']}; "
          f"true modes named products {total['true_named_products']}; products named {total['products']}; "
          f"modes left that are none {total['spurious_left']}")
    return {"records": rows, "total": total}


def harmonic_notes(seed: int, n: int) -> dict:
    out = {}
    for family in ("a", "b", "e", "f", "g"):
        rng = np.random.default_rng(seed)
        right = false = kept = 0
        for i in range(n):
            case = draw(family, rng, i)
            try:
                rec = impact_record(**case["config"])
            except ValueError:
                continue
            y = rec.y if rec.y.ndim == 1 else rec.y[:, 0]
            how, survey = _survey(y, rec.fs)
            kept += how == "kept"
            for note in survey.notes:
                m = NOTE.search(note)
                if m:
                    on_true = _true(float(m.group(1)), rec.modes.frequency_hz)
                    false += on_true
                    right += not on_true
                    print(f"  [{family} #{i}] {'FALSE DOUBT' if on_true else 'right doubt'}: {note[:120]}",
                          flush=True)
        out[family] = {"right": right, "false": false, "stay_clipped": kept}
        print(f"family {family}: the note on {right} mode(s) that are none, on {false} true mode(s); "
              f"{kept} record(s) stay clipped", flush=True)
    return out


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seed", type=int, default=3, help="seed of the clipped records")
    parser.add_argument("--n", type=int, default=120, help="clipped records drawn")
    parser.add_argument("--family-seed", type=int, default=241)
    parser.add_argument("--family-n", type=int, default=100, help="records per family")
    parser.add_argument("--quick", action="store_true", help="30 clipped records, 20 per family")
    args = parser.parse_args(argv)
    if args.quick:
        args.n, args.family_n = 30, 20
    if args.n < 1 or args.family_n < 1:
        parser.error("--n and --family-n must be at least 1")
    print(f"records that stay clipped (seed {args.seed}):")
    clipped = stays_clipped(args.seed, args.n)
    print(f"\nthe may-be-harmonic note (families at seed {args.family_seed}):")
    notes = harmonic_notes(args.family_seed, args.family_n)
    return {"stays_clipped": clipped, "harmonic_notes": notes}


if __name__ == "__main__":
    main()

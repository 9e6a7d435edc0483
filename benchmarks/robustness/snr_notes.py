"""The survey's signal-to-noise notes against the generator's SNR: how often a record is called noisy.

    python -m benchmarks snr_notes                     # families d and a, 40 records each, seed 5
    python -m benchmarks snr_notes --family d --n 100 --seed 7
    python -m benchmarks snr_notes --quick             # family d, 10 records

Each record of a family of :mod:`benchmarks.accuracy.families` goes through ``identify_modes``; the notes
about the record's noise ("no signal above the noise", "low signal-to-noise ratio") are counted with the
generator's ``snr_db`` beside them (the noise's standard deviation under the RMS of the ring-down's first
tenth; every family draws it from 30-60 dB). The survey's SNR is the documented one
(:func:`~sindy_impulse.preprocessing.ringdown_snr_db`: the mean square of the whole ring-down over the
noise), so a strongly damped mode in a record far longer than its decay reads lower than the generator's
figure; a note on a record whose noise the survey could not measure (no pre-trigger) is the one to read.
A record the generator refuses is left out.
"""

from __future__ import annotations

import argparse
import warnings

import numpy as np

from benchmarks.accuracy.families import FAMILIES, draw
from sindy_impulse import identify_modes, impact_record


def _noise_notes(survey) -> list[str]:
    return [n for n in survey.notes if "signal above the noise" in n or "signal-to-noise" in n]


def count(family: str, n: int, seed: int) -> dict:
    """Per family: records, records with a noise note, and those of them without a pre-trigger to measure
    the noise by."""
    rng = np.random.default_rng(seed)
    records = noted = unmeasured = 0
    for index in range(n):
        case = draw(family, rng, index)
        try:
            rec = impact_record(**case["config"])
        except ValueError:
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            survey = identify_modes(rec.y, fs=rec.fs)
        records += 1
        notes = _noise_notes(survey)
        if notes:
            noted += 1
            pre = survey.preprocessing[0]
            # (a tree before the quality report said so: a pre-trigger of 32 samples measures the noise)
            measured = getattr(pre.quality, "noise_measured", pre.impact.onset_index >= 32)
            unmeasured += not measured
            print(f"  [{family} #{index}] generator {case['config']['snr_db']:.1f} dB; {notes[0]}")
    return {"family": family, "records": records, "noted": noted, "noted_without_pre_trigger": unmeasured}


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--family", choices=FAMILIES, action="append", help="a family (repeatable)")
    parser.add_argument("--n", type=int, default=None, help="records per family (default 40, quick 10)")
    parser.add_argument("--seed", type=int, default=5)
    parser.add_argument("--quick", action="store_true", help="family d, 10 records")
    args = parser.parse_args(argv)
    families = args.family or (["d"] if args.quick else ["d", "a"])
    n = args.n or (10 if args.quick else 40)
    rows = [count(f, n, args.seed) for f in families]
    print("| family | records | with a noise note | of them without a pre-trigger |")
    print("|---|---|---|---|")
    for r in rows:
        print(f"| {r['family']} | {r['records']} | {r['noted']} | {r['noted_without_pre_trigger']} |")
    return {"seed": args.seed, "rows": rows}


if __name__ == "__main__":
    main()

"""What the survey's ``coupling`` stage changes: a family's records scored with the survey's values before
that stage and after it, record by record.

The stage (:mod:`sindy_impulse.modes.coupling`) reads every decaying mode of a record with a nonlinear one
together under one element's first-order coupling and takes the reading's values where they move beyond its
standard deviations (or knows them better) and it leaves nothing but noise in every mode's band. Here each
record runs through the survey's stages once: the modes before the last stage and after it are scored with
the modes benchmark's marks (:func:`~benchmarks.accuracy.scoring.judge`), and every record whose verdict
changes is listed with what the stage decided.

    python -m benchmarks coupling_stage --seed 131 --n 100
    python -m benchmarks coupling_stage --family e --seed 223

Measured, family g (records right before / after the stage; records gained, lost): seed 131 (the seed the
band test was read on) 85 / 90 (5, 0); held out 197 88 / 90 of 99 (3, 1), 199 88 / 91 (3, 0), 211 94 / 95
(1, 0), 223 (fresh) 90 / 91 of 99 (1, 0), 227 (fresh) 93 / 99 (6, 0).
"""

from __future__ import annotations

import argparse
import warnings

import numpy as np

from benchmarks.accuracy.families import FAMILIES, draw
from benchmarks.accuracy.scoring import judge
from sindy_impulse import impact_record
from sindy_impulse.modes.band_fit import default_estimator
from sindy_impulse.modes.pipeline import Pipeline, SurveyOptions, SurveyState
from sindy_impulse.modes.survey import SURVEY

STAGE = "coupling"


def before_and_after(rec) -> tuple[list, list, list]:
    """``(frequency_hz, damping_ratio)`` of each mode of ``rec`` before the survey's last stage and after
    it, and that stage's decisions."""
    if SURVEY[-1].name != STAGE:
        raise RuntimeError(f"the survey's last stage is {SURVEY[-1].name!r}, not {STAGE!r}")
    state = SurveyState(0, np.asarray(rec.y, float).reshape(len(rec.y), -1), None, rec.fs, None,
                        SurveyOptions(template=default_estimator()))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        Pipeline(SURVEY[:-1])(state)
        before = [(m.frequency_hz, m.damping_ratio) for m in state.modes]
        Pipeline(SURVEY[-1:])(state)
    after = [(m.frequency_hz, m.damping_ratio) for m in state.modes]
    return before, after, state.trace[-1].decisions


def right(case: dict, found: list) -> bool:
    """Every mode within the case's marks and no spurious one (the modes benchmark's :func:`judge`)."""
    f_true, z_true = case["config"]["frequencies_hz"], case["config"]["damping_ratios"]
    return judge(case, f_true, z_true, np.ones(len(f_true), bool), found)["passed"]


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--family", default="g", choices=FAMILIES)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--n", type=int, default=100, help="records (default 100)")
    parser.add_argument("--quick", action="store_true", help="10 records")
    args = parser.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    records, before_right, after_right, gained, lost, read, refused = 0, 0, 0, [], [], 0, 0
    for index in range(10 if args.quick else args.n):
        case = draw(args.family, rng, index)
        try:
            rec = impact_record(**case["config"])
        except ValueError:  # as the modes benchmark: a record the generator refuses is left out
            continue
        before, after, decisions = before_and_after(rec)
        a, b = right(case, before), right(case, after)
        records, before_right, after_right = records + 1, before_right + a, after_right + b
        read += any("modes read together" in d for d in decisions)
        refused += any(d.startswith("the coupling reading") for d in decisions)
        if a != b:
            (gained if b else lost).append(index)
            print(f"  [{args.family} #{index}] {'WRONG' if not a else 'right'} before the stage, "
                  f"{'right' if b else 'WRONG'} after: {'; '.join(decisions)}", flush=True)
    print(f"family {args.family}, seed {args.seed}: {records} records, {read} read together by the stage "
          f"({refused} more readings turned down); "
          f"right before it {before_right}, after it {after_right} (gained {len(gained)}, lost {len(lost)})")
    return {"family": args.family, "seed": args.seed, "records": records, "read_together": read,
            "turned_down": refused, "right_before": before_right, "right_after": after_right,
            "gained": gained, "lost": lost}


if __name__ == "__main__":
    main()

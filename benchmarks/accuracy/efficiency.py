"""How close the survey's and the baselines' errors come to the Cramer-Rao bound on a linear family.

The modal-families table compares median errors: the survey's against a baseline's, over the modes both
found. On a linear family both readings are close to efficient, and the ratio of two such medians over a
few hundred modes moves by several per cent from seed to seed: a median over ``n`` modes has a relative
standard error near ``1.25 / sqrt(n)``. This benchmark says where each estimator stands and how sure the
ratio is.

Per record of ``--family`` (the same draws as ``python -m benchmarks modes --family X --seed S``), it runs
the survey, single-order ESPRIT (:func:`sindy_impulse.analysis.esprit`, the ``a`` / ``high`` table's
baseline) and the stabilised ESPRIT (:func:`sindy_impulse.poles.stabilisation`, the other families'), and
computes each mode's Cramer-Rao standard deviations (``benchmarks.accuracy.bounds.bound``: the free decay
in its known white noise, the offset a nuisance parameter). For the counted modes all three found it
prints

- the median relative errors ``|df/f|`` and ``|dz/z|`` of each, and the survey's over each baseline's with a
  95 % bootstrap interval over the records (a ratio whose interval holds 1 is no measured difference);
- the median of the errors over the bound (``|df| / sd_f``, ``|dz| / sd_zeta``): an efficient unbiased
  estimator's is 0.674 (the median of ``|N(0, 1)|``); nothing unbiased does better on average.

    python -m benchmarks efficiency --family high --n 100 --seed 241
    python -m benchmarks efficiency --family b --n 100 --seed 233 --quick   # 20 records
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from benchmarks.accuracy.bounds import bound
from benchmarks.accuracy.families import band_snr_db, draw
from benchmarks.accuracy.scoring import baseline_answer, esprit_answer, judge, survey_answer
from sindy_impulse import impact_record

FAMILIES = ("a", "high", "b", "f")
#: Bootstrap resamples of the records for the ratio's interval.
RESAMPLES = 2000
#: The median of |N(0, 1)|: an efficient unbiased estimator's median error over its bound.
EFFICIENT = 0.674


def record_errors(case: dict) -> dict | None:
    """One record's counted modes: truth, Cramer-Rao standard deviations and the three readings' errors
    (None where the generator refuses the record)."""
    try:
        rec = impact_record(**case["config"])
    except ValueError:
        return None
    f = np.asarray(rec.modes.frequency_hz, float)
    z = np.asarray(rec.modes.damping_ratio, float)
    counted = np.ones(f.size, bool)
    if "min_band_snr_db" in case:  # family b: modes under 20 dB of band SNR are not counted
        counted = band_snr_db(rec) >= case["min_band_snr_db"]
    sd_f, sd_z = bound(rec)
    answers = {"survey": survey_answer(rec)[0], "esprit": esprit_answer(rec),
               "stabilised": baseline_answer(rec)[0]}
    # per counted mode, |df/f| and |dz/z| (inf where nothing was paired with it), as the families score
    out = {who: np.array(judge(case, f, z, counted, found)["errors"], float).reshape(-1, 2)
           for who, found in answers.items()}
    return {"f": f[counted], "z": z[counted], "sd_f": sd_f[counted], "sd_z": sd_z[counted], **out}


def _pooled(records: list, who: str, scale: bool) -> np.ndarray:
    rows = []
    for r in records:
        e = np.abs(r[who])
        if scale:  # in units of the bound's standard deviations
            e = e * np.column_stack([r["f"], r["z"]]) / np.column_stack([r["sd_f"], r["sd_z"]])
        rows.append(e)
    return np.concatenate(rows) if rows else np.empty((0, 2))


def _both(records: list, baseline: str) -> list:
    """The records restricted to the modes the survey and ``baseline`` both found."""
    out = []
    for r in records:
        keep = np.isfinite(r["survey"]).all(axis=1) & np.isfinite(r[baseline]).all(axis=1)
        out.append({k: v[keep] for k, v in r.items()})
    return out


def ratio_interval(records: list, baseline: str, rng: np.random.Generator) -> np.ndarray:
    """The survey's median relative errors over ``baseline``'s ``(f, zeta)`` and their 95 % bootstrap
    interval over the records: ``[[ratio_f, low_f, high_f], [ratio_z, low_z, high_z]]``."""
    def ratios(sample):
        ours, theirs = _pooled(sample, "survey", False), _pooled(sample, baseline, False)
        return np.median(ours, axis=0) / np.median(theirs, axis=0)

    point = ratios(records)
    boot = np.array([ratios([records[i] for i in rng.integers(len(records), size=len(records))])
                     for _ in range(RESAMPLES)])
    low, high = np.nanpercentile(boot, [2.5, 97.5], axis=0)
    return np.column_stack([point, low, high])


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--family", default="high", choices=FAMILIES)
    parser.add_argument("--n", type=int, default=100, help="records (default 100)")
    parser.add_argument("--quick", action="store_true", help="20 records")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    n = 20 if args.quick else args.n
    records, start = [], time.perf_counter()
    for i in range(n):
        r = record_errors(draw(args.family, rng, i))
        if r is not None:
            records.append(r)
        if (i + 1) % 10 == 0:
            print(f"  {i + 1} / {n} records ({time.perf_counter() - start:.0f} s)", flush=True)
    boot_rng = np.random.default_rng(0)
    result = {"family": args.family, "seed": args.seed, "records": len(records)}
    print(f"family {args.family}, seed {args.seed}, {len(records)} records; errors on the counted modes both "
          f"found; 'over the bound': the median of |error| / its Cramer-Rao standard deviation (efficient: "
          f"{EFFICIENT})")
    print("| baseline | modes | median df/f survey / baseline | ratio (95 % interval) | median dz/z survey "
          "/ baseline | ratio (95 % interval) | over the bound f: survey / baseline | zeta: survey / "
          "baseline |")
    print("|---|---|---|---|---|---|---|---|")
    for baseline in ("esprit", "stabilised"):
        both = _both(records, baseline)
        ours, theirs = _pooled(both, "survey", False), _pooled(both, baseline, False)
        if not len(ours):
            continue
        ratio = ratio_interval(both, baseline, boot_rng)
        scaled = [np.median(_pooled(both, who, True), axis=0) for who in ("survey", baseline)]
        mo, mt = np.median(ours, axis=0), np.median(theirs, axis=0)
        print(f"| {baseline} | {len(ours)} | {mo[0]:.2e} / {mt[0]:.2e} | {ratio[0, 0]:.2f} "
              f"({ratio[0, 1]:.2f}-{ratio[0, 2]:.2f}) | {mo[1]:.2e} / {mt[1]:.2e} | {ratio[1, 0]:.2f} "
              f"({ratio[1, 1]:.2f}-{ratio[1, 2]:.2f}) | {scaled[0][0]:.3f} / {scaled[1][0]:.3f} | "
              f"{scaled[0][1]:.3f} / {scaled[1][1]:.3f} |")
        result[baseline] = {"modes": len(ours), "median_errors": mo.tolist(),
                            "baseline_median_errors": mt.tolist(), "ratio": ratio.tolist(),
                            "over_bound": scaled[0].tolist(), "baseline_over_bound": scaled[1].tolist()}
    return result


if __name__ == "__main__":
    main()

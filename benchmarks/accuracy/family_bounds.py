"""How many records of a family any unbiased estimator can get right: the Cramer-Rao bound.

Each record of ``benchmarks/accuracy/modes.py``'s families (same draws: ``--seed``, record ``i`` of the
family) is a free decay of damped sinusoids in white Gaussian noise of known standard deviation
(``ImpactRecord.noise_std``) from the end of the hit (``free_decay_index``) on. Its parameters per mode are
the natural frequency, the damping ratio and the cosine and sine amplitudes; a constant offset is a nuisance
parameter (the record's offset is unknown to every estimator). The Fisher information ``J^T J / sigma^2``
(``J``: derivatives of the clean free decay by the parameters, by central differences) gives the smallest
standard deviation an unbiased estimator can have for each mode's frequency and damping ratio.

Per record, the chance that an efficient unbiased estimator puts every counted mode within the family's
tolerances (0.3 % / 10 %, family d 0.5 % / 10 %) is the product over modes of
``erf(tol_f f / (sqrt 2 sd_f)) erf(tol_z zeta / (sqrt 2 sd_zeta))`` (errors taken as independent normal
ones); their sum is the expected number of records right: a ceiling for the survey and the baseline alike
(a biased estimator can beat it on some records, not on average over the family). A record is also counted
"resolvable" when twice the bound's standard deviations are inside the tolerances for every mode.

Family g's records are not sums of damped sinusoids: a nonlinear element moves every mode's frequency and
decay rate with the modes' amplitudes. Their parameters are the generator's own (each mode's linear natural
frequency, damping ratio and amplitude, the element's cubic stiffness and amplitude-dependent damping, where
drawn, and the offset), and ``J`` is the derivative of the simulated record (:func:`impact_record`, the same
hit) by them. An estimator given the rest (the hit's time and shape, hence each mode's phase, and the
element's place and kind) knows more than any survey of the raw record does, so this bound is lower than the
survey's: a record it leaves unresolvable is unresolvable for every unbiased estimator.

    python -m benchmarks family_bounds --family d --n 100          # the issue's family (d)
    python -m benchmarks family_bounds --family b --n 60 --list    # one line per record
    python -m benchmarks family_bounds --family g --n 100 --seed 131 --list   # the nonlinear family
"""

from __future__ import annotations

import argparse
from math import erf, sqrt

import numpy as np

from benchmarks.accuracy.bounds import bound, nonlinear_bound
from benchmarks.accuracy.families import FAMILY_SIZES, band_snr_db, draw
from sindy_impulse import impact_record

LINEAR_FAMILIES = ("a", "high", "b", "d", "f")
#: The families whose bound this module computes: the linear ones, and g (its generator's parameters).
FAMILIES = (*LINEAR_FAMILIES, "g")


def record_chance(case: dict) -> dict:
    rec = impact_record(**case["config"])
    f = np.asarray(rec.modes.frequency_hz, float)
    z = np.asarray(rec.modes.damping_ratio, float)
    counted = np.ones(f.size, bool)
    if "min_band_snr_db" in case:  # family b: modes under 20 dB of band SNR are not counted
        counted = band_snr_db(rec) >= case["min_band_snr_db"]
    sd_f, sd_z = nonlinear_bound(case["config"]) if case["family"] == "g" else bound(rec)
    tol_f, tol_z = case["f_tol"] * f, case["z_tol"] * z
    chance = [erf(a / (sqrt(2) * b)) * erf(c / (sqrt(2) * d)) if b > 0 and d > 0 else 1.0
              for a, b, c, d in zip(tol_f, sd_f, tol_z, sd_z)]
    ok = counted
    return {"chance": float(np.prod(np.where(ok, chance, 1.0))),
            "resolvable": bool(np.all(~ok | ((2 * sd_f <= tol_f) & (2 * sd_z <= tol_z)))),
            "worst_z": float(np.max(np.where(ok, sd_z / z, 0.0))), "f": f, "z": z}


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--family", default="d", choices=FAMILIES)
    parser.add_argument("--n", type=int, default=None, help="records (default: the family's size; quick 10)")
    parser.add_argument("--quick", action="store_true", help="10 records")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--list", action="store_true", help="one line per record")
    args = parser.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    n = args.n or (10 if args.quick else FAMILY_SIZES[args.family])
    rows = []
    for i in range(n):
        case = draw(args.family, rng, i)
        try:
            rows.append(record_chance(case))
        except ValueError as err:  # as the modes benchmark: a record the generator refuses is left out
            print(f"  [{args.family} #{i}] left out: the generator refused the record ({err})", flush=True)
            continue
        if args.list:
            r = rows[-1]
            print(f"  [{args.family} #{i}] chance {r['chance']:.3f}, resolvable {r['resolvable']}, worst "
                  f"sd(zeta)/zeta {r['worst_z']:.3f}, f {np.round(r['f'], 2).tolist()}, "
                  f"zeta {np.round(r['z'], 4).tolist()}", flush=True)
    expected = sum(r["chance"] for r in rows)
    resolvable = sum(r["resolvable"] for r in rows)
    n = len(rows)
    print(f"family {args.family}, {n} records (seed {args.seed}): an efficient unbiased estimator gets "
          f"{expected:.1f} right on average ({100 * expected / n:.1f} %); {resolvable} records "
          f"({100 * resolvable / n:.1f} %) have every mode within the tolerances at twice the bound")
    return {"family": args.family, "seed": args.seed, "records": n, "expected_right": expected,
            "resolvable": resolvable, "chances": [r["chance"] for r in rows]}


if __name__ == "__main__":
    main()

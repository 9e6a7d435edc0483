"""Benchmark of ``analysis.nonlinearity_test`` on synthetic single-mode hammer tests.

Run from the repository root with ``python -m benchmarks nonlinearity [--quick]
[--records N] [--jobs J]``. Three rows of single-mode hammer tests (``impact_record``, accelerometer,
pre-trigger and hammer force as in a laboratory record), N records each (default 100; ``--quick``: 8):

``linear``
    Viscous damping only: must be called linear.
``cubic``
    A Duffing spring whose natural frequency rises by 0.35-1 % from the end to the start of the kept
    decay: must be called nonlinear.
``damping``
    A damper ``x^2 x'`` (damping ratio ``zeta0 + c2 a^2 / (8 omega)``) whose damping ratio is 1.5-2.5 times
    higher at the start of the kept decay than at its end, natural frequency constant: must be called
    nonlinear.

Per record: natural frequency 20-200 Hz, damping ratio 0.3-2 % (log-uniform), SNR 30-60 dB (white noise,
relative to the first tenth of the ring-down), 25-60 samples per period, the decay down to the noise floor
or at most 80 periods after the filter's transient. The nonlinear coefficient is a fixed point: the true
backbone (``record.true_backbone``) has the drawn shift between the largest and the smallest envelope of the
kept band signal.

The pipeline (the states are the band signal and its derivative): ``preprocess`` (onset from the force,
offset from the pre-trigger, one band ``(f0 / 1.5, 1.5 f0)`` around the mode, zero-phase band-pass, the
filter transient trimmed, stop at the noise floor, decimation to about 16 samples per period), ``x`` = the
band signal, ``v`` = its TVRegDiff derivative (``differentiate``), ``ImpulseSINDy(feature_library=
MechanicalLibrary())`` on ``(x, v)``, then ``nonlinearity_test``. The same record multiplied by 1e-6 and by
1e6, each plus an offset of three times its peak, goes through the whole pipeline again; the table counts
the records whose three verdicts agree. Results per record are written to ``--out`` (JSON lines).

Why the signal and its derivative as states, not a delay embedding: with ``(x, v)`` every library term keeps
its mechanical meaning (``x^3`` a spring, ``x^2 v`` or ``|x| v`` a damper growing with amplitude), the model
is a second-order oscillator whose backbone is that of the measured coordinate, and the test's verdict names
the physical term. A delay embedding ``(y(t - tau), y(t))`` is exactly linear for a linear mode but turns a
cubic spring or an amplitude-dependent damper into a mixture of delay-coordinate terms. The band signal of
an accelerometer is, for one mode, ``-omega^2`` times the displacement to first order, so the same terms
describe it (a Duffing spring in displacement is ``x^3`` and ``x v^2`` in acceleration coordinates).
"""

from __future__ import annotations

import argparse
import json
import os
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path

import numpy as np

from benchmarks.accuracy.nonlinear_records import ROWS, band, fit_and_test, record, states, true_shifts
from sindy_impulse.analysis import modal_parameters

UNITS = (1.0, 1e-6, 1e6)
#: In other units the record also gets an offset of this many times its peak (removed by preprocess).
OFFSET = 3.0


def run_one(job) -> dict:
    """One record through the pipeline in each of ``units``: verdicts, and the details in units of 1."""
    kind, seed, units = job
    rec, p = record(kind, seed)
    out = dict(kind=kind, seed=seed, **{k: float(v) for k, v in p.items()})
    for scale in units:
        start = time.process_time()
        signal = band(rec, scale, OFFSET if scale != 1.0 else 0.0)
        x, t = states(signal)
        model, res = fit_and_test(x, t)
        out["verdict" + ("" if scale == 1.0 else f"_{scale:g}")] = bool(res.nonlinear)
        if scale != 1.0:
            continue
        f_true, z_true = true_shifts(rec, signal)
        out.update(
            periods=float(signal.n_periods), samples=int(len(t)), true_frequency_shift=float(f_true),
            true_damping_factor=float(z_true), statistic=res.statistic, significance=res.significance,
            amplitude_dependence=res.amplitude_dependence, relative_growth=res.relative_growth,
            frequency_shift=res.frequency_shift, damping_ratio_shift=res.damping_ratio_shift,
            data_frequency_shift=res.data_frequency_shift,
            data_damping_ratio_shift=res.data_damping_ratio_shift,
            term=res.terms[0].term if res.terms else "", cpu_s=time.process_time() - start,
            model_terms=[n for n, c in zip(model.get_feature_names(), model.coefficients()[1]) if c != 0],
        )
    return out


def _truth_range(kind: str, sel: list[dict]) -> str:
    if kind == "cubic":
        v = [100 * r["true_frequency_shift"] for r in sel]
        return f"frequency +{min(v):.2f}-{max(v):.2f} %"
    v = [r["true_damping_factor"] for r in sel]
    return "-" if kind == "linear" else f"damping x{min(v):.2f}-{max(v):.2f}"


def table(rows: list[dict]) -> None:
    """The acceptance table: verdicts per row, agreement across units, the statistic's extremes."""
    others = sorted({k for r in rows for k in r if k.startswith("verdict_")})
    same_in = "same in " + ", ".join(o[8:] for o in others)
    print(f"{'row':8s} {'records':>7s} {'nonlinear':>9s} {'right':>6s} {same_in:>22s} {'cycles':>8s} "
          f"{'statistic':>16s}  truth over the decay")
    for kind in ROWS:
        sel = [r for r in rows if r["kind"] == kind]
        if not sel:
            continue
        n, called = len(sel), sum(r["verdict"] for r in sel)
        right = n - called if kind == "linear" else called
        same = sum(all(r.get(k) == r["verdict"] for k in others) for r in sel)
        cycles = [r["periods"] for r in sel]
        stat = [r["statistic"] for r in sel]
        print(f"{kind:8s} {n:7d} {called:9d} {100 * right / n:5.0f}% {same:>17d} of {n:<3d} "
              f"{min(cycles):3.0f}-{max(cycles):<4.0f} {min(stat):7.3g}-{max(stat):<8.3g}  "
              f"{_truth_range(kind, sel)}")
    print(f"CPU per record and unit: median {np.median([r['cpu_s'] for r in rows]):.1f} s (fit and test)")


def rounding(n: int) -> None:
    """A record and the same record rounded to 8 significant digits: model, modal parameters, verdict."""
    print(f"\nRounding to 8 significant digits ({n} records per row; worst relative differences):")
    print(f"{'row':8s} {'same terms':>10s} {'coefficients':>13s} {'frequency':>10s} {'damping':>9s} "
          f"{'verdict':>8s}")
    for kind in ROWS:
        worst, same_terms, same_verdict = np.zeros(3), 0, 0
        for seed in range(n):
            rec, _ = record(kind, seed)
            fits = []
            for y in (rec.y, np.array([float(f"{v:.7e}") for v in rec.y])):
                x, t = states(band(replace(rec, y=y)))
                model, res = fit_and_test(x, t)
                fits.append((model.coefficients(), modal_parameters(model), res.nonlinear))
            (c0, (f0, z0), v0), (c1, (f1, z1), v1) = fits
            same_terms += bool(np.array_equal(c0 != 0, c1 != 0))
            same_verdict += v0 == v1
            rel = np.max(np.abs(c1 - c0)[c0 != 0] / np.abs(c0[c0 != 0]))
            worst = np.maximum(worst, [rel, abs(f1[0] / f0[0] - 1), abs(z1[0] / z0[0] - 1)])
        print(f"{kind:8s} {same_terms:>6d}/{n:<3d} {worst[0]:13.1e} {worst[1]:10.1e} {worst[2]:9.1e} "
              f"{same_verdict:>5d}/{n}")


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="8 records per row, units 1 and 1e6, rounding 2")
    parser.add_argument("--records", type=int, default=None, help="records per row (default 100, quick 8)")
    parser.add_argument("--first", type=int, default=0, help="first seed")
    parser.add_argument("--jobs", type=int, default=1, help="worker processes")
    parser.add_argument("--units", default=None, help="scales, comma-separated (default 1,1e-6,1e6)")
    parser.add_argument("--rounding", type=int, default=None, help="records per row, rounding check (10)")
    parser.add_argument("--out", default=None, help="write one JSON line per record here")
    parser.add_argument("--table", default=None, help="print the table of an --out file and stop")
    args = parser.parse_args(argv)
    if args.table:
        rows = [json.loads(line) for line in Path(args.table).read_text().splitlines()]
        table(rows)
        return {"rows": rows}
    n = args.records or (8 if args.quick else 100)
    units = (1.0, 1e6) if args.quick else UNITS
    if args.units:
        units = tuple(float(u) for u in args.units.split(","))
    jobs = [(kind, seed, units) for seed in range(args.first, args.first + n) for kind in ROWS]
    start = time.perf_counter()
    rows = []
    with ProcessPoolExecutor(args.jobs) as pool, open(args.out or os.devnull, "w") as out:
        for row in pool.map(run_one, jobs):
            rows.append(row)
            out.write(json.dumps(row) + "\n")
            out.flush()
    elapsed = time.perf_counter() - start
    print(f"{len(rows)} records in units {', '.join(f'{u:g}' for u in units)}: {elapsed:.0f} s")
    table(rows)
    rounding(args.rounding if args.rounding is not None else (2 if args.quick else 10))
    return {"units": units, "seconds": elapsed, "rows": rows}


if __name__ == "__main__":
    main()

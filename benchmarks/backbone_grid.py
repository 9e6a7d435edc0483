"""The mechanical rows of ``bench_model_backbone.py`` for one record, on amplitude ranges given by hand.

``bench_model_backbone.py`` compares every curve of a record on the amplitudes all of them cover (the mode's
backbone, the mechanical model's and the Hilbert curve's), so a change of the mode's curve moves the grid
the mechanical rows are scored on, though their fit is untouched. This script scores one record's
mechanical models on the ranges you give, e.g. the ranges two checkouts used::

    python benchmarks/backbone_grid.py --kind cubic --seed 31 --range 0.0338 0.6601 --range 0.0338 0.5239

Found with it at the stop that restored the mode backbones (main at e724f17): cubic seed 31 is the one
record whose mechanical rows changed since 722c74e, and on 722c74e's range (0.0338-0.6601) both pass there
and here; on this stop's (0.0338-0.5239, the mode's curve ending lower) both miss on the shift (10.4 %,
11.1 %), there and here alike.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE), str(HERE.parent)]


def main(argv=None) -> int:
    import bench_model_backbone as bench
    import bench_nonlinearity as nl

    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--kind", choices=("cubic", "damping"), default="cubic")
    parser.add_argument("--seed", type=int, required=True)
    parser.add_argument("--range", type=float, nargs=2, action="append", required=True,
                        metavar=("LOW", "HIGH"), help="the amplitudes compared (repeat for several)")
    args = parser.parse_args(argv)
    bench._set_options((None, None, None, None))
    shift = 0.02 * 2 ** np.random.default_rng(args.seed).uniform()  # as bench_model_backbone.run_one
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rec, _ = nl.record(args.kind, args.seed, **({"shift": shift} if args.kind == "cubic" else {}))
        x, t = nl.states(nl.band(rec))
        model, test = nl.fit_and_test(x, t)
        curves = {"mechanical": bench._backbone_or_none(model),
                  "mech., tested": test.backbone_model if test.nonlinear else bench._backbone_or_none(model)}
    for lo, hi in args.range:
        grid = np.linspace(lo + 0.1 * (hi - lo), hi - 0.1 * (hi - lo), bench.N_GRID)
        for name, curve in curves.items():
            errors = bench._errors(curve, rec.true_backbone, grid, args.kind) if curve else (np.inf,) * 3
            verdict = "pass" if np.all(np.array(errors) <= np.array(bench.MARKS[name])) else "MISS"
            print(f"{lo:.4g}-{hi:.4g}  {name:13s} frequency {100 * errors[0]:.3g} %, damping "
                  f"{100 * errors[1]:.3g} %, shift {100 * errors[2]:.3g} %: {verdict}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

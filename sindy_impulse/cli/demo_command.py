"""``sindy-impulse demo``: the paper's oscillator case 3.1.2 end to end."""

from __future__ import annotations

import argparse

from ._options import integer, real
from .files import check_outputs, write_figure

__all__ = ["add_parser", "run"]


def add_parser(sub) -> argparse.ArgumentParser:
    about = ("The paper's damped oscillator (Stender, Oberst & Hoffmann 2019, case 3.1.2): the threshold "
             "sweep, the refined model, its stiffness, damping and modal parameters, and a figure.")
    demo = sub.add_parser("demo", help="run the paper's oscillator case 3.1.2 end to end", description=about)
    demo.add_argument("--snr", type=real, default=None, metavar="DB", help="add noise at this SNR in dB")
    demo.add_argument("--seed", type=integer, default=0, help="noise seed (default: 0)")
    demo.add_argument(
        "--plot",
        default="sindy_impulse_demo.png",
        metavar="OUT.png",
        help="figure file (default: sindy_impulse_demo.png, replaced when it exists; '' for none)",
    )
    demo.set_defaults(func=run)
    return demo


def _print_sweep(model) -> None:
    path = model.path_
    print(f"\nThreshold sweep: {len(path)} distinct models from {path.n_terms[0]} terms to none.")
    print(
        f"Selected before refinement ({path.n_terms[path.selected]} terms), Gamma = {model.gamma_sindy_:.4f}:"
    )
    names = model.get_feature_names()
    for lhs, row in zip(model.feature_names_, path.coefficients[path.selected]):
        terms = " + ".join(f"{c: .4f} {n}" for c, n in zip(row, names) if c != 0) or "0"
        print(f"  ({lhs})' = {terms}")


def run(args) -> int:
    from ..analysis import modal_parameters
    from ..datasets import damped_oscillator
    from ..identification.estimator import ImpulseSINDy

    check_outputs({"--plot": args.plot}, figures=["--plot"])
    print("sindy-impulse demo: the paper's case 3.1.2 (Stender, Oberst & Hoffmann 2019)")
    print("  x1' = x2, x2' = -64 x1 - 3.2 x2, x(0) = (1, 0), t in [0, 4], dt = 0.01; states only,")
    print(f"  derivatives by TVRegDiff, polynomial library of degree 3, SNR = {args.snr or 'no noise'}")
    t, x, _ = damped_oscillator(snr_db=args.snr, random_state=args.seed)
    model = ImpulseSINDy().fit(x, t=t, feature_names=["x1", "x2"])
    _print_sweep(model)
    print(f"After refinement ({model.complexity} terms), Gamma = {model.gamma_:.3g} (the paper: 2.345):")
    model.print(precision=4, lhs=[f"  ({n})'" for n in model.feature_names_])
    coef, names = model.coefficients(), model.get_feature_names()
    k, c = -coef[1, names.index("x1")], -coef[1, names.index("x2")]
    print(f"\nStiffness k = {k:.4f} (true 64), damping c = {c:.4f} (true 3.2)")
    frequencies, ratios = modal_parameters(model)
    for f, zeta in zip(frequencies, ratios):
        print(f"Natural frequency {f:.4f} Hz (true 1.2732), damping ratio {100 * zeta:.2f} % (true 20 %)")
    if not len(frequencies):
        print("No oscillatory mode in the linear part of the model")
    if args.plot:
        from ..plotting import plot_reconstruction

        write_figure(args.plot, lambda: plot_reconstruction(model)[0].figure)
        print(f"Figure of input vs reconstruction written to {args.plot}")
    return 0

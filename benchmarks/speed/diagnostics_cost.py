"""Cost of the diagnostics that run at the end of every fit (diagnostics_), measured in one run.

Run:  python -m benchmarks diagnostics_cost [--repeats 10]

Times the paper's oscillator fit (``damped_oscillator``, 40 dB) and ``identify_modes`` on a three-mode
impact record, alternately with the diagnostics and with ``diagnose_fit`` replaced by a no-op, and prints
the median times and their ratio. The ratio is what the diagnostics add; the absolute times depend on the
machine.
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np


def _timed(fn) -> float:
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fn()
    return time.perf_counter() - start


def measure(fn, repeats: int) -> tuple[float, float]:
    """Median time of ``fn`` with the diagnostics and without them (interleaved)."""
    import sindy_impulse.identification.estimator as estimator

    real = estimator.diagnose_fit
    on, off = [], []
    fn()  # warm up (kernels, caches)
    for _ in range(repeats):
        on.append(_timed(fn))
        estimator.diagnose_fit = lambda est, stacklevel=2: None
        try:
            off.append(_timed(fn))
        finally:
            estimator.diagnose_fit = real
    return float(np.median(on)), float(np.median(off))


def main(argv=None) -> dict:
    from sindy_impulse import ImpulseSINDy, damped_oscillator, identify_modes, impact_record

    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=None, help="timed runs each (default 10, quick 3)")
    parser.add_argument("--quick", action="store_true", help="3 timed runs each")
    args = parser.parse_args(argv)
    args.repeats = args.repeats or (3 if args.quick else 10)
    ring = damped_oscillator(snr_db=40, random_state=0)
    rec = impact_record(
        [120.0, 240.0, 410.0], [0.005, 0.01, 0.02], fs=5000, duration=1.0, snr_db=40, random_state=0
    )
    cases = {
        "paper's oscillator fit (40 dB)": lambda: ImpulseSINDy().fit(ring.x, t=ring.t),
        "identify_modes, 3 modes": lambda: identify_modes(rec.y, fs=rec.fs),
    }
    print(f"{'case':34s} {'with [s]':>10s} {'without [s]':>12s} {'ratio':>7s}")
    out = {}
    for name, fn in cases.items():
        on, off = measure(fn, args.repeats)
        print(f"{name:34s} {on:10.3f} {off:12.3f} {on / off:7.2f}")
        out[name] = {"with": on, "without": off, "ratio": on / off}
    return out


if __name__ == "__main__":
    main()

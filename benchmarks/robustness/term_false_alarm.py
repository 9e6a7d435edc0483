"""Calibration of the diagnostics' add test ("the data ask for term(s) the model lacks").

Run from the repository root::

    python -m benchmarks.robustness.term_false_alarm            # 100 linear records, the power grid
    python -m benchmarks.robustness.term_false_alarm --quick    # 20 records, a smaller grid

**False alarms.** Linear three-mode hammer tests (``impact_record``: frequencies drawn in 30-400 Hz at
least 15 % apart, damping ratios 0.2-2 %, SNR 30-60 dB, 2 s at 2048 Hz, one seed per record) are surveyed
by ``identify_modes``; every mode's model is linear, so a mode whose diagnostics list a missing term is a
false alarm. The test's nominal level is ``diagnostics.terms.FALSE_ALARM`` per fit (all the terms tried
together).

**Power.** The paper's oscillator made a Duffing oscillator (``damped_oscillator(k_nl=...)``, initial
deflection 10, the cubic force ``share`` of the linear one at that deflection), fitted in plain mode with
a threshold that keeps ``x0``, ``x1`` and drops the cubic term: the model lacks a term the data hold, and
the test should say so once the cubic force is well above the noise.
"""

from __future__ import annotations

import argparse
import warnings

import numpy as np


def _linear_record(seed: int):
    from sindy_impulse import impact_record

    rng = np.random.default_rng(seed)
    freqs = np.sort(rng.uniform(30.0, 400.0, 3))
    while np.min(np.diff(freqs) / freqs[1:]) < 0.15:
        freqs = np.sort(rng.uniform(30.0, 400.0, 3))
    zetas = rng.uniform(0.002, 0.02, 3)
    snr = float(rng.uniform(30.0, 60.0))
    return impact_record(list(freqs), list(zetas), fs=2048.0, duration=2.0, snr_db=snr, random_state=seed)


def false_alarms(n_records: int) -> dict:
    """Modes of linear records whose diagnostics ask for a missing term."""
    from sindy_impulse import identify_modes
    from sindy_impulse.diagnostics.terms import FALSE_ALARM

    n_modes, alarms, examples = 0, 0, []
    for seed in range(n_records):
        rec = _linear_record(seed)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            survey = identify_modes(rec.y, fs=rec.fs)
            for mode in survey.modes:
                n_modes += 1
                missing = list(mode.diagnostics.missing_terms)
                if missing:
                    alarms += 1
                    examples.append({"seed": seed, "frequency_hz": mode.frequency_hz, "missing": missing})
    return {
        "records": n_records,
        "modes": n_modes,
        "false_alarms": alarms,
        "rate": alarms / max(n_modes, 1),
        "nominal": FALSE_ALARM,
        "examples": examples[:10],
    }


def power(shares, snrs, seeds: int) -> list[dict]:
    """How often a linear model of Duffing data is told it lacks a term, per cubic share and SNR."""
    import pysindy as ps

    from sindy_impulse import ImpulseSINDy, damped_oscillator

    rows = []
    for share in shares:
        for snr in snrs:
            flagged = 0
            for seed in range(seeds):
                ring = damped_oscillator(
                    k_nl=share * 64.0 / 100.0, x0=(10.0, 0.0), snr_db=snr, random_state=seed
                )
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    model = ImpulseSINDy(
                        feature_library=ps.PolynomialLibrary(degree=3),
                        optimizer=ps.STLSQ(threshold=0.5),
                        sweep=False,
                        refine=False,
                    ).fit(ring.x, t=ring.t)
                    flagged += bool(model.diagnostics_.missing_terms)
            rows.append({"cubic_share": share, "snr_db": snr, "flagged": flagged, "fits": seeds})
    return rows


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="20 records and a smaller power grid")
    args = parser.parse_args(argv)
    alarms = false_alarms(20 if args.quick else 100)
    print(
        f"linear records: {alarms['records']}, modes: {alarms['modes']}, false alarms: "
        f"{alarms['false_alarms']} (rate {alarms['rate']:.3g}, nominal {alarms['nominal']:g} per fit)"
    )
    for example in alarms["examples"]:
        print(f"  seed {example['seed']}, {example['frequency_hz']:.5g} Hz: {', '.join(example['missing'])}")
    shares = (0.0, 0.01, 0.03, 0.1) if not args.quick else (0.0, 0.03, 0.1)
    rows = power(shares, (40, 30), 5 if args.quick else 10)
    print(f"{'cubic share':>12s} {'SNR [dB]':>9s} {'flagged':>9s}")
    for row in rows:
        print(f"{row['cubic_share']:12.2f} {row['snr_db']:9d} {row['flagged']:5d} / {row['fits']}")
    return {"false_alarms": alarms, "power": rows}


if __name__ == "__main__":
    main()

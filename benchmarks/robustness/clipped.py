"""Clipped records through ``identify_modes``: the modes and the CPU time of issue 26's clipped shock record
(``impact_record([804, 2400, 4800], [0.01, 0.005, 0.006], fs=50000, duration=0.11, pre_trigger=0.005,
sensor="acceleration", snr_db=40, clip=0.6)``) over seeds, each beside the same record unclipped (same seed,
same noise) in the same run, and what was done with the clipped samples (also runs on versions before the
repair, from outside this tree so that the other package comes first on the path:
``cd /tmp && PYTHONPATH=OLD_CHECKOUT:THIS_TREE python -m benchmarks clipped``).

    python -m benchmarks clipped              # seeds 0-4, 3 warm runs each (median CPU time)
    python -m benchmarks clipped --seeds 10   # seeds 0-9

CPU time (``time.process_time``), so a shared machine's load does not count; a mode is right within 0.3 % in
frequency and 10 % in damping ratio. Family (h) of ``benchmarks/accuracy/modes.py`` (``--family h``) is the
accuracy study.
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np

from sindy_impulse import identify_modes, impact_record

F_TRUE, Z_TRUE = np.array([804.0, 2400.0, 4800.0]), np.array([0.01, 0.005, 0.006])
RECORD = dict(fs=50000, duration=0.11, pre_trigger=0.005, sensor="acceleration", snr_db=40)


def _cpu(y, fs, repeat):
    """Median CPU time of ``repeat`` warm surveys, and the last survey."""
    times = []
    for _ in range(repeat):
        start = time.process_time()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            survey = identify_modes(y, fs=fs)
        times.append(time.process_time() - start)
    return float(np.median(times)), survey


def _right(survey) -> bool:
    f = np.array([m.frequency_hz for m in survey.modes])
    z = np.array([m.damping_ratio for m in survey.modes])
    return (f.size == F_TRUE.size and np.all(np.abs(f / F_TRUE - 1) <= 3e-3)
            and np.all(np.abs(z / Z_TRUE - 1) <= 0.1))


def survey_seeds(seeds: int, repeat: int) -> dict:
    """The table over seeds: the clipped record's modes and CPU time beside the unclipped one's."""
    identify_modes(impact_record(F_TRUE, Z_TRUE, random_state=0, **RECORD).y, fs=RECORD["fs"])  # warm
    print("| seed | clipped: modes (Hz / damping ratio) | right | clipped samples | CPU s clipped "
          "| CPU s unclipped | ratio |")
    print("|---|---|---|---|---|---|---|")
    ratios, right = [], []
    for seed in range(seeds):
        clipped = impact_record(F_TRUE, Z_TRUE, clip=0.6, random_state=seed, **RECORD)
        plain = impact_record(F_TRUE, Z_TRUE, random_state=seed, **RECORD)
        t_clip, survey = _cpu(clipped.y, clipped.fs, repeat)
        t_plain, _ = _cpu(plain.y, plain.fs, repeat)
        ratios.append(t_clip / t_plain)
        right.append(_right(survey))
        impact = survey.preprocessing[0].impact
        modes = ", ".join(f"{m.frequency_hz:.1f} / {m.damping_ratio:.4f}" for m in survey.modes)
        clipped_note = f"{getattr(impact, 'saturated', '-')} {getattr(impact, 'clipping', '') or '-'}"
        print(f"| {seed} | {modes} | {'yes' if _right(survey) else 'NO'} | {clipped_note} "
              f"| {t_clip:.2f} | {t_plain:.2f} | {ratios[-1]:.2f} |")
    print(f"median CPU ratio clipped / unclipped: {np.median(ratios):.2f}")
    return {"seeds": seeds, "right": right, "cpu_ratios": ratios, "median_cpu_ratio": np.median(ratios)}


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=None, help="seeds 0..N-1 (default 5, quick 2)")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="2 seeds")
    args = parser.parse_args(argv)
    return survey_seeds(args.seeds or (2 if args.quick else 5), args.repeat)


if __name__ == "__main__":
    main()

"""The tracker's acceptance study (issue 38): synthetic test sequences, the statistics alone, real records.

Run from the repository root::

    python -m benchmarks.tracking.track_study                       # the full study (hours: the surveys)
    python -m benchmarks.tracking.track_study --sequences 8 --quick # a small one
    python -m benchmarks.tracking.track_study --only statistics     # the tests alone, by simulation

**Sequences** (``sequences.py``): per sequence 20 reference tests shared by the rows and 40 new tests per
row (no change, stiffness -0.5 %, damping +30 %, a cubic spring of +0.3 % at the hit, a drift of -0.05 %
per test), each surveyed by :func:`sindy_impulse.survey_many`; the surveys' values
(:class:`sindy_impulse.tracking.SurveyValues`) are cached as JSON under ``--cache`` (default
``benchmarks/results/cache/track_study/<fingerprint of the package's source>``, not committed: surveys of
other code are never read), one file per sequence and row, so that the
statistics rerun in seconds and an interrupted run resumes. Then :func:`sindy_impulse.tracking.track` on
each (reference + row) sequence at the default 1 % rate: the fraction of new surveys flagged, the right
mode, the term named, the trend; and how often today's survey gives the target mode of the cubic row a
cubic coefficient.

**Statistics** (no survey): the prediction test against 20 reference values drawn with the fit's ±
right, missing, 3 and 10 times too small, 3 times too large, with and without a scatter beyond them; the
false-alarm rate at 1 % and at 0.0625 % (one test of a family of 16), and the power against a shift of
5 standard deviations beside the textbook prediction interval's.

**Real records**: pyFRF's five repeated hits (``--pyfrf DIR`` with ``measurements_1..5.npy``).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import time
import warnings
from pathlib import Path

import numpy as np

from benchmarks.tracking import sequences as seqs

ROOT = Path(__file__).resolve().parents[2]
CACHE = ROOT / "benchmarks" / "results" / "cache" / "track_study"


def source_cache(root: Path = CACHE) -> Path:
    """The default cache folder: ``root`` / a fingerprint of the package's source (the sha256 of every
    ``sindy_impulse`` module's bytes, in path order), so that surveys cached by other code are never read
    as this code's."""
    digest = hashlib.sha256()
    package = ROOT / "sindy_impulse"
    for path in sorted(package.rglob("*.py")):
        digest.update(str(path.relative_to(package)).encode())
        digest.update(path.read_bytes())
    return root / digest.hexdigest()[:12]


# ----------------------------------------------------------------------------------------------------
# surveys, computed once
# ----------------------------------------------------------------------------------------------------
def _survey(records: list, n_jobs: int) -> list[dict]:
    from sindy_impulse import survey_many
    from sindy_impulse.tracking import survey_values

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        surveys = survey_many(
            [r.y for r in records], fs=[r.fs for r in records], n_jobs=n_jobs, progress=False
        )
    out = []
    for i, survey in enumerate(surveys):
        try:
            out.append(survey_values(survey).to_dict())
        except Exception as err:  # noqa: BLE001 - one survey's values must not lose the others
            print(f"    survey {i}: its values could not be read: {type(err).__name__}: {err}", flush=True)
            out.append({"label": "", "failed": f"values: {type(err).__name__}: {err}", "modes": []})
    return out


def cached_row(seed: int, row: str, cache: Path, n_jobs: int) -> dict:
    """The surveys of one sequence's row (``"reference"`` or one of :data:`sequences.ROWS`), from the
    cache or computed and cached: ``{"sequence", "row", "truth", "surveys", "seconds"}``."""
    path = cache / f"seq{seed:04d}" / f"{row}.json"
    if path.exists():
        return json.loads(path.read_text())
    seq = seqs.draw_sequence(seed)
    records, truth = seqs.records(seq, row)
    start = time.perf_counter()
    surveys = _survey(records, n_jobs)
    out = {
        "sequence": seq,
        "row": row,
        "truth": truth,
        "surveys": surveys,
        "seconds": time.perf_counter() - start,
    }
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(out))
    tmp.replace(path)
    return out


def compute(seeds, rows, cache: Path, n_jobs: int) -> None:
    """Survey every (sequence, row) not yet cached, printing progress."""
    for seed in seeds:
        for row in ("reference",) + tuple(rows):
            if not (cache / f"seq{seed:04d}" / f"{row}.json").exists():
                got = cached_row(seed, row, cache, n_jobs)
                print(
                    f"  sequence {seed} {row}: {len(got['surveys'])} surveys in {got['seconds']:.0f} s",
                    flush=True,
                )


def speed(n_surveys: int = 200, repeats: int = 3) -> dict:
    """Seconds of :func:`sindy_impulse.tracking.track` on 20 reference + 180 new surveys of 4 modes (their
    values given: the surveys themselves are not timed), without change and with every new survey changed
    (then every alarm's terms are tested too); median of ``repeats``, and of the table and JSON after."""
    from benchmarks.tracking.study_stats import synthetic_survey
    from sindy_impulse.tracking import track

    rng = np.random.default_rng(3)
    f0 = (90.0, 210.0, 340.0, 515.0)
    same = [synthetic_survey(rng, f0, 1.0, False, 1 + 3e-4 * rng.standard_normal()) for _ in range(n_surveys)]
    changed = same[:20] + [
        synthetic_survey(rng, (90.0, 209.0, 340.0, 515.0), 1.0, False, 1 + 3e-4 * rng.standard_normal())
        for _ in range(n_surveys - 20)
    ]
    from sindy_impulse import identify_modes, impact_record

    record = impact_record(list(f0), [0.01, 0.005, 0.004, 0.003], fs=5000.0, duration=1.0, snr_db=40,
                           random_state=0)
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        identify_modes(record.y, fs=record.fs)
    one_survey = time.perf_counter() - start  # the baseline: one survey of one such record, same run
    out = {}
    for name, surveys in (("no change", same), ("every new survey changed", changed)):
        times, extra = [], []
        for _ in range(repeats):
            start = time.perf_counter()
            result = track(surveys, reference=20)
            times.append(time.perf_counter() - start)
            start = time.perf_counter()
            result.to_frame(), result.to_dict()
            extra.append(time.perf_counter() - start)
        out[name] = {
            "one_survey_s": one_survey,
            "track_s": float(np.median(times)),
            "frame_and_json_s": float(np.median(extra)),
            "alarms": len(result.alarms),
        }
    return out


def _print_real(real: dict, indent: str = "  ") -> None:
    for key, val in real.items():
        if isinstance(val, dict) and "lines" in val:
            closest = [round(c, 3) if c else c for c in val["smallest_p_times_tests"]]
            print(f"{indent}{key}: {val['changed']} of {val['new']} new surveys changed "
                  f"({val['tests_per_survey']} tests; smallest p x tests {closest}: an alarm needs it "
                  f"below the rate); modes tested {val['tested_modes']}")
            for line in val["lines"] + [f"note: {n}" for n in val["notes"]]:
                print(f"{indent}  {line}")
        elif isinstance(val, dict):
            print(f"{indent}{key}:")
            _print_real(val, indent + "  ")
        else:
            print(f"{indent}{key}: {json.dumps(val)[:3000]}")


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sequences", type=int, default=50)
    parser.add_argument("--first", type=int, default=0, help="first sequence seed")
    parser.add_argument("--rows", default=",".join(seqs.ROWS))
    parser.add_argument("--cache", type=Path, default=None,
                        help="where the surveys are cached (default: a folder per source fingerprint)")
    parser.add_argument("--n-jobs", type=int, default=1)
    parser.add_argument("--alpha", type=float, default=0.01)
    parser.add_argument(
        "--only", choices=("surveys", "sequences", "statistics", "real", "speed"), default=None
    )
    parser.add_argument("--no-surveys", action="store_true", help="track only the sequences already cached")
    parser.add_argument("--mirror", default=None, help="folder of bare git copies (real records)")
    parser.add_argument("--quick", action="store_true", help="fewer draws in the statistics part")
    parser.add_argument("--json", type=Path, default=None, help="also write the results as JSON there")
    args = parser.parse_args(argv)
    if args.cache is None:
        args.cache = source_cache()
        print(f"surveys cached in {args.cache} (this source's fingerprint)")
    rows = [r for r in args.rows.split(",") if r]
    seeds = range(args.first, args.first + args.sequences)
    results = {}
    if args.only in (None, "surveys") and not args.no_surveys:
        compute(seeds, rows, args.cache, args.n_jobs)
    if args.only in (None, "sequences"):
        from benchmarks.tracking import study_rows

        results["sequences"] = study_rows.summary(study_rows.analyse(seeds, rows, args.cache, args.alpha))
        print(f"synthetic sequences at a {100 * args.alpha:g} % false-alarm rate (95 % Wilson intervals):")
        study_rows.print_summary(results["sequences"])
    if args.only in (None, "statistics"):
        from benchmarks.tracking import study_stats

        reps = 20_000 if args.quick else 100_000
        one = study_stats.one_test(reps)
        whole = study_stats.whole_track(40 if args.quick else 200)
        results["statistics"] = {"one_test": one, "track": whole}
        print("the tests by simulation:")
        study_stats.print_tables(one, whole)
    if args.only in (None, "real"):
        from benchmarks.tracking import study_real

        mirror = study_real.mirror_folder(args.mirror)
        if mirror is None:
            print("real records: give --mirror DIR or set SINDY_IMPULSE_MIRROR (bare git copies)")
        else:
            results["real"] = {
                "pyFRF": study_real.pyfrf(mirror, args.cache),
                "Vibration-Tester beam": study_real.beam(mirror, args.cache),
            }
            print("real records:")
            _print_real(results["real"])
    if args.only in (None, "speed"):
        results["speed"] = speed()
        print("speed of track() on 200 surveys of 4 modes (median of 3):")
        for name, v in results["speed"].items():
            print(
                f"  {name}: track {v['track_s']:.3f} s, then table and JSON {v['frame_and_json_s']:.3f} s "
                f"({v['alarms']} alarms); one survey of a 4-mode record in the same run "
                f"{v['one_survey_s']:.2f} s (track = {v['track_s'] / v['one_survey_s']:.2f} of it)"
            )
    if args.json is not None:
        args.json.write_text(json.dumps(results, indent=1, default=float))
    return results


if __name__ == "__main__":
    main()

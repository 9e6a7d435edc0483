"""The modal-table acceptance study: random hammer-test records through identify_modes and through ESPRIT.

    python -m benchmarks modes            # 200 records + 50 noise-only records (a few minutes)
    python -m benchmarks modes --quick    # 30 + 10
    python -m benchmarks modes --seed 3 --n 50
    python -m benchmarks modes --output-error-cost 20   # time of the output-error fit (see below)
    python -m benchmarks modes --family high --n 60      # family (c): modes between fs/8 and fs/2.56
    python -m benchmarks modes --family e --show-failures   # one family of the modal-table issue
    python -m benchmarks modes --family all --show-failures # every family (a, high, b, d, e, f, g, h)

Each record (``sindy_impulse.datasets.impact_record``): 1-4 modes between 2 and 25 % of the Nyquist
frequency (>= 8 samples per period), at least 3 % apart with non-overlapping half-power bands, damping
ratios 0.1-3 % (log-uniform), every mode's initial amplitude within 20 dB of the strongest, SNR 30-60 dB
(noise std against the RMS of the first 10 % of the ring-down), offset up to 5x the amplitude, pre-trigger
0-10 % of the record, displacement / velocity / acceleration sensor, 2,000-40,000 samples.

Pass marks (per record): every true mode found with frequency within 0.3 % and damping ratio within 10 %;
no spurious mode (an identified mode farther than 1 % from every true mode). Noise-only records (white and
pink): no mode. The classical baseline is :func:`sindy_impulse.analysis.esprit` on the same records from the
same detected onset, its median errors reported beside ours (the ratio is the aim: at least as accurate).

``--family high`` draws family (c) of the modal-table issue instead: 1-3 modes between 2 % and 78 % of the
Nyquist frequency (up to fs / 2.56), at least one of them above fs / 8 (fewer than 8 samples per period:
its band is resampled), the other constraints as above; the baseline there is also the stabilisation
diagram (:func:`sindy_impulse.poles.stabilisation`: ESPRIT over orders 10-60, poles recurring within 0.5 %
/ 10 % at 5 orders), from the same onset. Measured (``--family high --n 60``, seed 0): 59 of 60 records
with every mode within the marks (ESPRIT 59, stabilised ESPRIT 59), none with a spurious mode, noise-only
50 of 50 without a mode; median errors 5.1e-6 in frequency and 1.0e-3 in damping ratio (ESPRIT 1.7e-6 and
3.7e-4); 0.88 s a record (ESPRIT 0.05 s). The miss: a mode 3 % from its neighbour at 3.4 samples per
period (604 Hz at 2,048 Hz). Before the bands were resampled, every mode above fs / 8 was refused.

``--family b|d|e|f|g|h|all`` draws the other families of the modal-table issue from
:mod:`benchmarks.accuracy.families` (its docstring gives every generator's ranges): (b) weak modes 20-40 dB
below the strongest, scored where their own band SNR is >= 20 dB; (d) short, strongly damped records (3-15
periods, damping 2-25 %, marks 0.5 % / 10 %) plus the paper's oscillator on seeds 0-99 at 40 dB
(:mod:`benchmarks.accuracy.short_decays`); (e) 1:2 and 1:3 near-resonant pairs (two modes) against the
harmonics of single quadratic and cubic oscillators (one mode and a rejected row naming ``harmonic 2`` /
``harmonic 3``); (f) close pairs 1-3 half-power bandwidths apart; (g) 1-4 modes with a nonlinear element; (h)
clipped records. Default sizes: a 200, high 60, b 60, d 100 (+ 100 oscillator records), e 80, f 60, g 60, h 60
(740). These runs (and ``--table`` for a / high) score both answers alike: true and found modes paired one to
one (closest first, within 1 %), a record right when every counted mode is within the marks and no found mode
is left unpaired (spurious); the baseline is the stabilised ESPRIT above, unchanged. Per family the table
gives n, records right (survey, baseline), records with a spurious mode, exceptions raised by
``identify_modes``, records with a failure caught inside the survey (a ``Rejected`` row of band None or with
an error in its evidence), median errors of the paired modes and the median seconds per record;
``--show-failures`` lists each record the survey got wrong with its index, its ``impact_record`` config
(a reproducer: ``impact_record(**config)``) and what went wrong.

``--output-error-cost N`` instead times ``identify_modes`` on the first N records with the modes' output-error
fit (bands of at most ``modes._fit.OUTPUT_ERROR_PERIODS`` periods) and without it (the threshold set to 0),
alternating, three times each, and prints the median time ratio with / without.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings

import numpy as np

from benchmarks.accuracy.families import FAMILY_SIZES, draw, random_case
from benchmarks.accuracy.scoring import (
    F_TOL,
    Z_TOL,
    RecordRefused,
    esprit_answer,
    esprit_start,
    judge,
    match,
    run_family_case,
)
from benchmarks.accuracy.short_decays import F_TRUE, Z_TRUE, run
from sindy_impulse import identify_modes, impact_record
from sindy_impulse.poles import stabilisation

NEW_FAMILIES = ("b", "d", "e", "f", "g", "h")


def run_case(case: dict) -> dict:
    rec = impact_record(**case)
    f_true, z_true = rec.modes.frequency_hz, rec.modes.damping_ratio
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        survey = identify_modes(rec.y, fs=rec.fs)
    elapsed = time.perf_counter() - start
    ours, spurious = match(
        f_true, z_true, [m.frequency_hz for m in survey], [m.damping_ratio for m in survey]
    )
    onset = esprit_start(rec.y, rec.fs)
    start = time.perf_counter()
    es = esprit_answer(rec, onset)
    es_time = time.perf_counter() - start
    theirs, es_spurious = match(f_true, z_true, [f for f, _ in es], [z for _, z in es])
    start = time.perf_counter()
    stable = stabilisation(rec.y[onset:], fs=rec.fs).modes()
    st_time = time.perf_counter() - start
    found = [m.frequency_hz for m in stable], [m.damping_ratio for m in stable]
    stabilised, st_spurious = match(f_true, z_true, *found)
    passed = all(ef <= F_TOL and ez <= Z_TOL for ef, ez in ours)
    es_passed = all(ef <= F_TOL and ez <= Z_TOL for ef, ez in theirs)
    return dict(
        case=case,
        ours=ours,
        theirs=theirs,
        spurious=spurious,
        es_spurious=es_spurious,
        passed=passed,
        es_passed=es_passed,
        time=elapsed,
        es_time=es_time,
        st_time=st_time,
        st_passed=all(ef <= F_TOL and ez <= Z_TOL for ef, ez in stabilised),
        st_spurious=st_spurious,
    )


def noise_case(rng: np.random.Generator, kind: str) -> int:
    fs = 5000.0
    n = int(rng.integers(2000, 40001))
    white = rng.standard_normal(n)
    if kind == "pink":
        spectrum = np.fft.rfft(white)
        f = np.fft.rfftfreq(n, 1 / fs)
        spectrum[1:] /= np.sqrt(f[1:])
        spectrum[0] = 0
        white = np.fft.irfft(spectrum, n)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return len(identify_modes(white + 3.0, fs=fs))


def _summary(results: list[dict]) -> dict:
    n = len(results)
    passed = sum(r["passed"] for r in results)
    clean = sum(r["spurious"] == 0 for r in results)
    print(
        f"records: {n}; all modes within 0.3 % / 10 %: {passed} ({100 * passed / n:.1f} %); "
        f"no spurious mode: {clean} ({100 * clean / n:.1f} %)"
    )
    es_passed = sum(r["es_passed"] for r in results)
    es_clean = sum(r["es_spurious"] == 0 for r in results)
    print(
        f"ESPRIT baseline: {es_passed} ({100 * es_passed / n:.1f} %) within the marks, "
        f"{es_clean} ({100 * es_clean / n:.1f} %) without spurious poles"
    )
    st_passed = sum(r["st_passed"] for r in results)
    st_clean = sum(r["st_spurious"] == 0 for r in results)
    print(
        f"stabilised ESPRIT baseline (orders 10-60, 5 recurrences): {st_passed} "
        f"({100 * st_passed / n:.1f} %) within the marks, {st_clean} ({100 * st_clean / n:.1f} %) "
        "without spurious modes"
    )
    ours = np.array([e for r in results for e in r["ours"]])
    theirs = np.array([e for r in results for e in r["theirs"]])
    ok = np.all(np.isfinite(ours), axis=1) & np.all(np.isfinite(theirs), axis=1)
    mf, mz = np.median(ours[ok], axis=0)
    ef, ez = np.median(theirs[ok], axis=0)
    print(
        f"median |df|/f: ours {mf:.2e}, ESPRIT {ef:.2e}, ratio {mf / ef:.2f}; "
        f"median |dzeta|/zeta: ours {mz:.2e}, ESPRIT {ez:.2e}, ratio {mz / ez:.2f} (modes found by both)"
    )
    t = np.array([r["time"] for r in results])
    te = np.array([r["es_time"] for r in results])
    ts = np.array([r["st_time"] for r in results])
    print(f"time per record: median {np.median(t):.2f} s (ESPRIT {np.median(te):.2f} s, stabilised ESPRIT "
          f"{np.median(ts):.2f} s), max {t.max():.1f} s")
    return {"records": n, "right": passed, "no_spurious": clean, "esprit_right": es_passed,
            "esprit_no_spurious": es_clean, "stabilised_right": st_passed, "stabilised_no_spurious": st_clean,
            "median_frequency_error": mf, "median_damping_error": mz, "esprit_median_frequency_error": ef,
            "esprit_median_damping_error": ez, "median_seconds": np.median(t),
            "esprit_median_seconds": np.median(te), "stabilised_median_seconds": np.median(ts)}


def _bin_label(bins, v) -> str:
    k = np.searchsorted(bins, v, side="right")
    return f"{bins[k - 1]:g}-{bins[k]:g}"


def _misses(results: list[dict]) -> None:
    print("misses by category (failed / total):")
    for key, bins in (("sensor", None), ("snr_db", [30, 40, 50, 60.1]), ("n_modes", None)):
        values = [len(r["case"]["frequencies_hz"]) if key == "n_modes" else r["case"][key] for r in results]
        labels = (
            [str(v) for v in values]
            if bins is None
            else [_bin_label(bins, v) for v in values]
        )
        for label in sorted(set(labels)):
            group = [r for r, lab in zip(results, labels) if lab == label]
            print(f"  {key} {label}: {sum(not r['passed'] for r in group)} / {len(group)}")
    zetas = np.array([z for r in results for z in r["case"]["damping_ratios"]])
    errs = np.array([e[1] for r in results for e in r["ours"]])
    for lo, hi in ((1e-3, 3e-3), (3e-3, 1e-2), (1e-2, 3e-2)):
        sel = (zetas >= lo) & (zetas < hi)
        off = int(np.sum(errs[sel] > Z_TOL))
        print(f"  damping {lo:g}-{hi:g}: {off} of {int(sel.sum())} modes off by > 10 %")


def output_error_cost(n: int, rng: np.random.Generator) -> dict:
    """Median time ratio of ``identify_modes`` with / without the modes' output-error fit (same run)."""
    from sindy_impulse.modes import band_fit as _fit

    default = _fit.OUTPUT_ERROR_PERIODS
    ratios = []
    for _ in range(n):
        rec = impact_record(**random_case(rng))
        times = {default: [], 0: []}
        for _ in range(3):
            for periods in (default, 0):
                _fit.OUTPUT_ERROR_PERIODS = periods
                start = time.perf_counter()
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    identify_modes(rec.y, fs=rec.fs)
                times[periods].append(time.perf_counter() - start)
        ratios.append(np.median(times[default]) / np.median(times[0]))
    _fit.OUTPUT_ERROR_PERIODS = default
    print(f"identify_modes with / without the output-error fit, {n} records: median time ratio "
          f"{np.median(ratios):.3f} (range {min(ratios):.3f}-{max(ratios):.3f})")
    return {"records": n, "median_time_ratio": np.median(ratios), "ratios": ratios}


# --------------------------------------------------------------------------------------------------------
# the families of the modal-table issue (b, d, e, f, g, h; a and high scored alike in the table)
# --------------------------------------------------------------------------------------------------------
def oscillator_results(seeds: int = 100, snr_db: float = 40.0) -> list[dict]:
    """Family d's second part: the paper's oscillator (``python -m benchmarks short_decays``) as family
    rows."""
    out = run(seeds, snr_db)
    case = {"family": "d", "f_tol": 0.005, "z_tol": 0.10, "config": {"damped_oscillator": True}}
    results = []
    for seed, (ours, base, t, tb) in enumerate(zip(out["rows"]["survey"], out["rows"]["baseline"],
                                                   out["times"]["survey"], out["times"]["baseline"])):
        c = dict(case, config={"damped_oscillator": {"snr_db": snr_db, "random_state": seed}})
        one = (np.array([F_TRUE]), np.array([Z_TRUE]), np.array([True]))
        results.append({"case": c, "ours": judge(c, *one, ours), "theirs": judge(c, *one, base), "time": t,
                        "base_time": tb, "error": None, "caught": 0, "counted": 1, "found": ours,
                        "baseline": base})
    return results


def _median_errors(results, who) -> tuple:
    e = np.array([x for r in results for x in r[who]["errors"] if np.all(np.isfinite(x))]).reshape(-1, 2)
    return tuple(np.median(e, axis=0)) if e.size else (np.nan, np.nan)


def _paired_median_errors(results) -> tuple:
    """Median errors of the survey and of the baseline on the modes both found (each record's counted modes
    are listed in one order for both), and the share of those modes where the survey's error is the smaller:
    ``((df/f, dz/z) survey, (df/f, dz/z) baseline, (share f, share zeta))``. The medians over each one's own
    finds compare different modes: the one that finds more weak modes adds larger errors."""
    pairs = np.array([(*a, *b) for r in results for a, b in zip(r["ours"]["errors"], r["theirs"]["errors"])
                      if np.all(np.isfinite(a)) and np.all(np.isfinite(b))]).reshape(-1, 4)
    if not pairs.size:
        return (np.nan, np.nan), (np.nan, np.nan), (np.nan, np.nan)
    m = np.median(pairs, axis=0)
    closer = np.mean(pairs[:, 0] < pairs[:, 2]), np.mean(pairs[:, 1] < pairs[:, 3])
    return (m[0], m[1]), (m[2], m[3]), closer


def family_row(results: list[dict]) -> dict:
    """One family's figures: n, survey right, baseline right, spurious, failures, median errors (over each
    one's finds, and over the modes both found), s/record."""
    (mf, mz), (bf, bz) = _median_errors(results, "ours"), _median_errors(results, "theirs")
    (pf, pz), (qf, qz), (cf, cz) = _paired_median_errors(results)
    return {"n": len(results), "right": sum(r["ours"]["passed"] for r in results),
            "baseline_right": sum(r["theirs"]["passed"] for r in results),
            "spurious": sum(r["ours"]["spurious"] > 0 for r in results),
            "baseline_spurious": sum(r["theirs"]["spurious"] > 0 for r in results),
            "exceptions": sum(r["error"] is not None for r in results),
            "caught": sum(r["caught"] > 0 for r in results),
            "median_frequency_error": mf, "baseline_median_frequency_error": bf,
            "median_damping_error": mz, "baseline_median_damping_error": bz,
            "paired_median_frequency_error": pf, "paired_baseline_median_frequency_error": qf,
            "paired_median_damping_error": pz, "paired_baseline_median_damping_error": qz,
            "survey_closer_frequency": cf, "survey_closer_damping": cz,
            "median_seconds": np.median([r["time"] for r in results]),
            "baseline_median_seconds": np.median([r["base_time"] for r in results])}


def family_table(rows: dict) -> None:
    """The per-family table: n, survey right, baseline right, spurious, failures, median errors, s/record."""
    print("| family | n | survey right | baseline right | survey spurious | baseline spurious | exceptions "
          "| caught failures | median df/f (survey / baseline) | median dz/z (survey / baseline) "
          "| on modes both found: median df/f, dz/z (survey / baseline); survey closer (f, zeta) "
          "| s/record (survey / baseline) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, results in rows.items():
        r = family_row(results)
        n, right, base = r["n"], r["right"], r["baseline_right"]
        print(f"| {name} | {n} | {right} ({100 * right / n:.1f} %) | {base} ({100 * base / n:.1f} %) "
              f"| {r['spurious']} | {r['baseline_spurious']} | {r['exceptions']} | {r['caught']} "
              f"| {r['median_frequency_error']:.1e} / {r['baseline_median_frequency_error']:.1e} "
              f"| {r['median_damping_error']:.1e} / {r['baseline_median_damping_error']:.1e} "
              f"| {r['paired_median_frequency_error']:.1e} / "
              f"{r['paired_baseline_median_frequency_error']:.1e}"
              f", {r['paired_median_damping_error']:.1e} / {r['paired_baseline_median_damping_error']:.1e}; "
              f"{100 * r['survey_closer_frequency']:.0f} %, {100 * r['survey_closer_damping']:.0f} % "
              f"| {r['median_seconds']:.2f} / {r['baseline_median_seconds']:.2f} |")


def show_failures(name: str, results: list[dict], seed: int) -> None:
    """Every record the survey got wrong: its index (the draw's, as the progress lines give it), the
    reproducer config and what went wrong."""
    bad = [(r.get("index", i), r) for i, r in enumerate(results) if not r["ours"]["passed"]]
    print(f"failures of family {name} (seed {seed}): {len(bad)} of {len(results)}")
    for i, r in bad:
        extra = {k: v for k, v in r["case"].items() if k not in ("config", "family")}
        print(f"  [{name} #{i}] {'; '.join(r['ours']['problems'])}")
        print(f"      baseline {'right' if r['theirs']['passed'] else 'wrong'}; scoring {extra}")
        print(f"      config {json.dumps(r['case']['config'])}")


def run_families(names: list[str], n: int | None, seed: int, failures: bool, budget: float = np.inf) -> dict:
    """Each family in turn: its records (at most ``budget`` seconds of drawing new ones; Ctrl-C also stops
    the family early), then its failures and its table row."""
    rows = {}
    for name in names:
        rng = np.random.default_rng(seed)
        count = n or FAMILY_SIZES[name]
        rows[name] = []
        start = time.perf_counter()
        for i in range(count):
            if time.perf_counter() - start > budget:
                print(f"  family {name}: time budget spent after {i} of {count} records")
                break
            try:
                r = dict(run_family_case(draw(name, rng, i)), index=i)
            except KeyboardInterrupt:
                print(f"  family {name}: interrupted after {i} of {count} records")
                break
            except RecordRefused as err:  # the generator's, not the survey's: the record is left out
                print(f"  [{name} #{i}] left out: the generator refused the record ({err})", flush=True)
                continue
            rows[name].append(r)
            print(f"  [{name} #{i}] survey {'right' if r['ours']['passed'] else 'WRONG'}, baseline "
                  f"{'right' if r['theirs']['passed'] else 'wrong'}, "
                  f"{r['time']:.1f} s / {r['base_time']:.1f} s"
                  + (f": {'; '.join(r['ours']['problems'])}" if not r["ours"]["passed"] else ""), flush=True)
        if failures:
            show_failures(name, rows[name], seed)
        if name == "d":
            rows["d oscillator"] = oscillator_results(100 if n is None or n >= 20 else n)
            if failures:
                show_failures("d oscillator", rows["d oscillator"], seed)
        family_table({k: v for k, v in rows.items() if k.startswith(name)})
        sys.stdout.flush()
    if len(rows) > 1:
        print("all families:")
        family_table(rows)
    return {name: family_row(results) for name, results in rows.items() if results}


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--n", type=int, default=None)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--output-error-cost", type=int, default=0, metavar="N")
    parser.add_argument("--family", choices=("a", "high", *NEW_FAMILIES, "all"), default="a")
    parser.add_argument("--show-failures", action="store_true",
                        help="list every record the survey got wrong (index, config, what went wrong)")
    parser.add_argument("--budget", type=float, default=np.inf, metavar="SECONDS",
                        help="per family: draw no new record after this long (the table covers those done)")
    parser.add_argument("--table", action="store_true",
                        help="family a / high: also the per-family table (one-to-one matching, as b-h)")
    args = parser.parse_args(argv)
    if args.family not in ("a", "high") or args.table:
        names = [*FAMILY_SIZES] if args.family == "all" else [args.family]
        return {"families": run_families(names, args.n or (5 if args.quick else None), args.seed,
                                         args.show_failures, args.budget)}
    if args.output_error_cost:
        cost = output_error_cost(args.output_error_cost, np.random.default_rng(args.seed))
        return {"output_error_cost": cost}
    n = args.n or (30 if args.quick else 200)
    rng = np.random.default_rng(args.seed)
    results = []
    for i in range(n):
        r = run_case(random_case(rng, args.family))
        results.append(r)
        if not r["passed"] or r["spurious"]:
            c = r["case"]
            print(
                f"  miss {i}: f={np.round(c['frequencies_hz'], 2).tolist()} "
                f"z={np.round(c['damping_ratios'], 4).tolist()} "
                f"{c['sensor']} snr={c['snr_db']:.0f} n={int(c['duration'] * c['fs'])} fs={c['fs']:g}: "
                f"errors {[(f'{a:.1e}', f'{b:.2f}') for a, b in r['ours']]} spurious {r['spurious']}",
                flush=True,
            )
    summary = _summary(results)
    _misses(results)
    n_noise = 10 if args.quick else 50
    found = [noise_case(rng, kind) for kind in ("white", "pink") for _ in range(n_noise // 2)]
    print(f"noise-only records: {sum(f == 0 for f in found)} of {len(found)} give no mode")
    return {"family": args.family, "seed": args.seed, **summary, "noise_only_records": len(found),
            "noise_only_without_mode": sum(f == 0 for f in found)}


if __name__ == "__main__":
    main()

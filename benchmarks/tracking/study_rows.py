"""The acceptance rows of the tracker's study: each cached sequence tracked, the rates counted.

For a sequence and a row, :func:`sindy_impulse.tracking.track` runs on its 20 reference surveys and the
row's 40 new ones at the rate asked. The *target* is the mode the row changes (for the cubic row the mode
the spring moves most), matched to the track nearest its nominal frequency. Counted per row:

- ``flagged``: the share of new surveys flagged (``changed``);
- ``right mode``: of the flagged ones, those whose most significant alarm is on the target;
- ``term``: of the flagged ones, those whose alarm on the target names the row's term (``y`` the linear
  stiffness, ``y'`` the linear damping, ``y^3`` the cubic stiffness); for the cubic row also those with
  an alarm on any mode naming the cubic stiffness (the spring at mass 0 moves every mode that moves it),
  and those naming the linear stiffness and nowhere the cubic one;
- ``cubic found``: the share of surveys whose target mode has a cubic coefficient at all (the survey's
  part of naming the cubic term), in the row and in its reference;
- ``trend``: the share of sequences with a significant trend (any, for the row without change; on the
  target's frequency for the drift), and for the drift the new survey at which the trend over the new
  surveys so far first reaches the trend threshold beside the first single-test alarm on the target.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from benchmarks.tracking import sequences as seqs

EXPECTED_TERM = {"stiff": "y", "damp": "y'", "cubic": "y^3"}


def wilson(k: int, n: int) -> tuple[float, float]:
    """95 % Wilson interval of a proportion k / n."""
    if n == 0:
        return math.nan, math.nan
    z, p = 1.96, k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return centre - half, centre + half


def load(cache: Path, seed: int, row: str):
    """``(sequence, reference surveys, new surveys, truth of the new tests)`` from the cache, or None when
    not computed."""
    from sindy_impulse.tracking import SurveyValues

    ref_path, row_path = cache / f"seq{seed:04d}" / "reference.json", cache / f"seq{seed:04d}" / f"{row}.json"
    if not (ref_path.exists() and row_path.exists()):
        return None
    ref, new = json.loads(ref_path.read_text()), json.loads(row_path.read_text())
    return (
        ref["sequence"],
        [SurveyValues.from_dict(d) for d in ref["surveys"]],
        [SurveyValues.from_dict(d) for d in new["surveys"]],
        new["truth"],
    )


def _target(seq: dict, row: str, tracks) -> int | None:
    m = seqs.cubic_target(seq)[0] if row == "cubic" else seq["target"]
    f = seq["frequencies_hz"][m]
    best = min(range(len(tracks)), key=lambda j: abs(tracks[j].frequency_hz / f - 1), default=None)
    return best if best is not None and abs(tracks[best].frequency_hz / f - 1) < 0.03 else None


def _first(flags) -> float:
    hit = np.flatnonzero(flags)
    return float(hit[0]) if hit.size else math.nan


def _drift_timing(result, j: int, alpha: float) -> tuple[float, float]:
    """First new survey (index from 0) where the running trend of the target's frequency passes the
    trend family's threshold, and the first single-test alarm on the target."""
    from sindy_impulse.tracking.statistics import running_trend

    n_tests = max(len(result.trends), 1)
    x = result.series["value"]["frequency_hz"][result.new, j]
    return _first(running_trend(x) < alpha / n_tests), _first(result.changed_modes[result.new, j])


def sequence_row(seq, reference, new, truth, row: str, alpha: float) -> dict:
    """The counts of one sequence's row."""
    from sindy_impulse.tracking import track

    result = track(reference + new, reference=len(reference), alpha=alpha)
    j = _target(seq, row, result.tracks)
    flagged = result.changed[result.new]
    out = {
        "n_new": int(flagged.size),
        "flagged": int(flagged.sum()),
        "target_tracked": j is not None,
        "trend_any": bool(result.trend_alarms),
        "events_any": bool(result.event_alarms),
    }
    lead = {}
    for a in result.alarms:
        if a.survey not in lead or a.p < lead[a.survey].p:
            lead[a.survey] = a
    on_target = {a.survey: a for a in result.alarms if a.mode == j}
    out["right_mode"] = sum(1 for s, a in lead.items() if a.mode == j)
    expected = EXPECTED_TERM.get(row)
    out["term"] = sum(
        1 for a in on_target.values() if expected and a.term is not None and a.term.key == expected
    )
    named = {}
    for a in result.alarms:
        named.setdefault(a.survey, set()).add(a.term.key if a.term is not None else None)
    out["term_any_mode"] = sum(1 for keys in named.values() if expected in keys)
    out["term_linear_stiffness"] = sum(1 for keys in named.values() if "y" in keys and expected not in keys)
    if j is not None:
        has_cubic = [
            result.slot[s, j] >= 0 and "y^3" in result.values[s].modes[result.slot[s, j]].terms
            for s in range(len(result.values))
        ]
        out["cubic_found_new"] = int(sum(has_cubic[len(reference) :]))
        # per new survey found with its mode: the cubic spring's shift at that hit (0.3 % x strength^2)
        out["cubic_by_shift"] = [
            (seqs.CUBIC_SHIFT * t["strength"] ** 2, bool(h))
            for t, h, s in zip(truth, has_cubic[len(reference) :], result.new)
            if result.slot[s, j] >= 0
        ]
        out["cubic_found_reference"] = int(sum(has_cubic[: len(reference)]))
        out["target_found_new"] = int((result.slot[result.new, j] >= 0).sum())
        out["trend_target"] = any(t.mode == j and t.quantity == "frequency_hz" for t in result.trend_alarms)
        if row == "drift":
            out["first_trend"], out["first_single"] = _drift_timing(result, j, alpha)
    return out


def analyse(seeds, rows, cache: Path, alpha: float) -> dict:
    """Per row, the counts summed over the cached sequences."""
    table = {}
    for row in rows:
        per = []
        for seed in seeds:
            got = load(cache, seed, row)
            if got is not None:
                per.append(sequence_row(*got, row, alpha))
        table[row] = per
    return table


def _rate(k, n) -> str:
    lo, hi = wilson(k, n)
    return f"{100 * k / n:.1f} % [{100 * lo:.1f}, {100 * hi:.1f}] ({k}/{n})" if n else "-"


def summary(table: dict) -> dict:
    """The acceptance rows as numbers and printable lines."""
    out = {}
    for row, per in table.items():
        if not per:
            continue
        n_new, flagged = sum(p["n_new"] for p in per), sum(p["flagged"] for p in per)
        s = {
            "sequences": len(per),
            "new_surveys": n_new,
            "flagged": flagged,
            "flagged_rate": flagged / n_new if n_new else math.nan,
            "right_mode": sum(p["right_mode"] for p in per),
            "term": sum(p["term"] for p in per),
            "term_any_mode": sum(p["term_any_mode"] for p in per),
            "term_linear_stiffness": sum(p["term_linear_stiffness"] for p in per),
            "trend_sequences": sum(p["trend_any"] for p in per),
            "event_sequences": sum(p["events_any"] for p in per),
            "trend_target_sequences": sum(p.get("trend_target", False) for p in per),
            "cubic_found_new": sum(p.get("cubic_found_new", 0) for p in per),
            "cubic_found_reference": sum(p.get("cubic_found_reference", 0) for p in per),
            "target_found_new": sum(p.get("target_found_new", 0) for p in per),
            "target_untracked": sum(not p["target_tracked"] for p in per),
        }
        if row == "cubic":
            pairs = [pair for p in per for pair in p.get("cubic_by_shift", [])]
            edges = (0.0, 0.0015, 0.003, 0.006, 0.013)
            s["cubic_found_by_shift"] = [
                {
                    "shift_from": lo,
                    "shift_to": hi,
                    "surveys": sum(lo <= x < hi for x, _ in pairs),
                    "found": sum(lo <= x < hi and f for x, f in pairs),
                }
                for lo, hi in zip(edges, edges[1:])
            ]
        if row == "drift":
            s["first_trend_median"] = float(
                np.nanmedian([p.get("first_trend", np.nan) for p in per] or [np.nan])
            )
            s["first_single_median"] = float(
                np.nanmedian([p.get("first_single", np.nan) for p in per] or [np.nan])
            )
        out[row] = s
    return out


def print_summary(s: dict) -> None:
    for row, v in s.items():
        n, f = v["new_surveys"], v["flagged"]
        print(f"  {row:6s} {v['sequences']:3d} sequences: flagged {_rate(f, n)}", end="")
        if row in EXPECTED_TERM:
            print(f"; right mode {_rate(v['right_mode'], f)}; term {_rate(v['term'], f)}", end="")
        if row == "cubic":
            print(
                f"; cubic named on any mode {_rate(v['term_any_mode'], f)}; linear stiffness named and no "
                f"cubic {_rate(v['term_linear_stiffness'], f)}; cubic coefficient in the target's survey "
                f"{_rate(v['cubic_found_new'], v['target_found_new'])}, in its reference "
                f"{v['cubic_found_reference']}",
                end="",
            )
        if row == "cubic":
            bins = ", ".join(
                f"{100 * b['shift_from']:.2g}-{100 * b['shift_to']:.2g} %: {b['found']}/{b['surveys']}"
                for b in v["cubic_found_by_shift"]
            )
            print(f"; cubic coefficient found by the shift at the hit: {bins}", end="")
        if row == "none":
            print(
                f"; trend in {v['trend_sequences']} of {v['sequences']} sequences; a mode gone or new beyond "
                f"chance in {v['event_sequences']}",
                end="",
            )
        if row == "drift":
            print(
                f"; trend on the target {v['trend_target_sequences']} of {v['sequences']} sequences, first "
                f"at new survey {v['first_trend_median']:.0f} (median) vs first single alarm "
                f"{v['first_single_median']:.0f}",
                end="",
            )
        print(f"; target not tracked in {v['target_untracked']}")

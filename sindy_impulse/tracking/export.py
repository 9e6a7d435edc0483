"""A :class:`~sindy_impulse.tracking.TrackResult` as a table (pandas) and as JSON-ready data."""

from __future__ import annotations

import math

import numpy as np

from .result import QUANTITIES

__all__ = ["track_frame", "track_dict", "frame_rows", "row_note"]


def _num(x):
    x = float(x)
    return x if math.isfinite(x) else None


def row_note(result, s: int, j: int) -> str:
    """Why a value of this row has no ± of its own (the reference scatter then carries it)."""
    if result.slot[s, j] < 0:
        return "mode not found in this survey"
    if not result.testable[j]:
        return "not tested: too few reference surveys have this mode" if result.tracks[j].in_reference \
            else "not tested: the mode is not in the reference"
    missing = [q for q in QUANTITIES[:2] if not math.isfinite(result.series["std"][q][s, j])]
    if missing:
        return ("no ± from the fit for " + " and ".join(m.replace("_hz", "") for m in missing)
                + ": the reference scatter carries the uncertainty")
    return ""


def frame_rows(result) -> list[dict]:
    """One dict per survey and mode (the rows of :func:`track_frame`)."""
    alarms = {(a.survey, a.mode): a for a in result.alarms}
    keys = sorted({k for v in result.values for m in v.modes for k in m.terms})
    rows = []
    role = np.array(["new"] * len(result.values), dtype=object)
    role[result.reference] = "reference"
    for s in range(len(result.values)):
        for j, tr in enumerate(result.tracks):
            if result.slot[s, j] < 0 and not tr.in_reference:
                continue
            row = {"survey": s, "label": result.labels[s], "role": role[s], "mode": j,
                   "mode_frequency_hz": tr.frequency_hz, "found": bool(result.slot[s, j] >= 0)}
            for q in QUANTITIES + ("backbone_frequency_hz", "backbone_damping_ratio", "amplitude"):
                row[q] = result.series["value"][q][s, j]
                if q != "amplitude":
                    row[q + "_std"] = result.series["std"][q][s, j]
                if q in QUANTITIES:
                    row[q + "_t"], row[q + "_p"] = result.t[q][s, j], result.p[q][s, j]
            row["backbone_amplitude"] = result.amplitudes[j]
            mode = result.values[s].modes[result.slot[s, j]] if result.slot[s, j] >= 0 else None
            for k in keys:
                value, std = mode.terms.get(k, (0.0, math.nan)) if mode is not None else (math.nan, math.nan)
                row[f"coef[{k}]"], row[f"coef[{k}]_std"] = value, std
            alarm = alarms.get((s, j))
            row["changed"] = alarm is not None
            row["quantity"] = alarm.quantity if alarm else ""
            row["term"] = alarm.term.name if alarm and alarm.term is not None else ""
            row["term_significant"] = bool(alarm.term_significant) if alarm else False
            row["term_frequency_shift_hz"] = alarm.term.frequency_shift_hz if alarm and alarm.term else math.nan
            row["note"] = row_note(result, s, j)
            rows.append(row)
    return rows


def track_frame(result):
    """One row per survey and mode: role (reference or new), found, each quantity's value, ±, test
    statistic and p-value, the backbone at the common amplitude with its ±, every equation coefficient
    (``coef[y^3]``) with its ± (``coef[y^3]_std``), changed or not, the quantity and the term named, and a
    note where a ± is missing. Needs pandas."""
    try:
        import pandas as pd
    except ImportError:  # pragma: no cover - pandas is a test dependency
        raise ImportError("TrackResult.to_frame needs pandas: pip install pandas") from None
    return pd.DataFrame(frame_rows(result))


def track_dict(result) -> dict:
    """JSON-ready: the settings, the modes, the per-survey verdicts, the alarms with their terms, the
    trends and the events."""
    return {
        "alpha": result.alpha,
        "reference": [int(i) for i in result.reference],
        "modes": [{"mode": j, "frequency_hz": tr.frequency_hz, "in_reference": tr.in_reference,
                   "tested": bool(result.testable[j]), "backbone_amplitude": _num(result.amplitudes[j]),
                   "reference_mean": {q: _num(result.reference_mean(q, j)) for q in QUANTITIES},
                   "reference_scatter": {q: _num(result.reference_std(q, j)) for q in QUANTITIES}}
                  for j, tr in enumerate(result.tracks)],
        "surveys": [{"survey": s, "label": result.labels[s], "changed": bool(result.changed[s]),
                     "failed": result.values[s].failed or None} for s in range(len(result.values))],
        "alarms": [{"survey": a.survey, "label": result.labels[a.survey], "mode": a.mode,
                    "quantity": a.quantity, "quantities": list(a.quantities), "value": _num(a.value),
                    "t": _num(a.t), "p": _num(a.p), "text": a.text(result),
                    "term": a.term.name if a.term is not None else None,
                    "term_significant": a.term_significant,
                    "terms": [{"term": c.key, "name": c.name, "status": c.status, "value": _num(c.value),
                               "std": _num(c.std), "reference": _num(c.reference),
                               "reference_scatter": _num(c.reference_std), "t": _num(c.t), "p": _num(c.p),
                               "significant": c.significant,
                               "frequency_shift_hz": _num(c.frequency_shift_hz),
                               "damping_shift": _num(c.damping_shift)} for c in a.terms]}
                   for a in result.alarms],
        "trends": [{"mode": tr.mode, "quantity": tr.quantity, "z": _num(tr.z), "p": _num(tr.p),
                    "significant": tr.significant, "slope_per_survey": _num(tr.slope),
                    "text": tr.text(result)} for tr in result.trends],
        "events": result.events(),
    }

"""A :class:`~sindy_impulse.tracking.TrackResult` as a table (pandas) and as JSON-ready data."""

from __future__ import annotations

import math

__all__ = ["track_frame", "track_dict", "frame_rows", "row_note"]


def _num(x):
    x = float(x)
    return x if math.isfinite(x) else None


def row_note(result, s: int, j: int) -> str:
    """Why a value of this row has no ± of its own (the reference scatter then carries it)."""
    if result.slot[s, j] < 0:
        return "mode not found in this survey"
    if not result.testable[j]:
        return (
            "not tested: too few reference surveys have this mode"
            if result.tracks[j].in_reference
            else "not tested: the mode is not in the reference"
        )
    missing = [q for q in result.quantities[:2] if not math.isfinite(result.series["std"][q][s, j])]
    if missing:
        return (
            "no ± from the fit for "
            + " and ".join(m.replace("_hz", "") for m in missing)
            + ": the reference scatter carries the uncertainty"
        )
    return ""


def _values(result, s: int, j: int, keys: list) -> dict:
    """A row's quantities (value, ±, T, p), backbone and coefficients."""
    row = {}
    for q in result.quantities + ("backbone_frequency_hz", "backbone_damping_ratio", "amplitude"):
        row[q] = result.series["value"][q][s, j]
        if q != "amplitude":
            row[q + "_std"] = result.series["std"][q][s, j]
        if q in result.quantities:
            row[q + "_t"], row[q + "_p"] = result.t[q][s, j], result.p[q][s, j]
    row["backbone_amplitude"] = result.amplitudes[j]
    mode = result.values[s].modes[result.slot[s, j]] if result.slot[s, j] >= 0 else None
    for k in keys:
        value, std = mode.terms.get(k, (0.0, math.nan)) if mode is not None else (math.nan, math.nan)
        row[f"coef[{k}]"], row[f"coef[{k}]_std"] = value, std
    return row


def _verdict(alarm) -> dict:
    """A row's verdict: changed, the quantity and the term named."""
    term = alarm.term if alarm is not None else None
    return {
        "changed": alarm is not None,
        "quantity": alarm.quantity if alarm else "",
        "term": term.name if term is not None else "",
        "term_significant": bool(alarm.term_significant) if alarm else False,
        "term_frequency_shift_hz": term.frequency_shift_hz if term is not None else math.nan,
    }


def frame_rows(result) -> list[dict]:
    """One dict per survey and mode (the rows of :func:`track_frame`)."""
    alarms = {(a.survey, a.mode): a for a in result.alarms}
    keys = sorted({k for v in result.values for m in v.modes for k in m.terms})
    reference = set(int(i) for i in result.reference)
    rows = []
    for s in range(len(result.values)):
        for j, tr in enumerate(result.tracks):
            if result.slot[s, j] < 0 and not tr.in_reference:
                continue
            row = {"survey": s, "label": result.labels[s], "role": "reference" if s in reference else "new",
                   "mode": j, "mode_frequency_hz": tr.frequency_hz, "found": bool(result.slot[s, j] >= 0)}
            row.update(_values(result, s, j, keys))
            row.update(_verdict(alarms.get((s, j))))
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


def _term_dict(c) -> dict:
    return {"term": c.key, "name": c.name, "status": c.status, "value": _num(c.value), "std": _num(c.std),
            "reference": _num(c.reference), "reference_scatter": _num(c.reference_std), "t": _num(c.t),
            "p": _num(c.p), "significant": c.significant, "frequency_shift_hz": _num(c.frequency_shift_hz),
            "damping_shift": _num(c.damping_shift)}


def _alarm_dict(a, result) -> dict:
    return {"survey": a.survey, "label": result.labels[a.survey], "mode": a.mode, "quantity": a.quantity,
            "quantities": list(a.quantities), "value": _num(a.value), "t": _num(a.t), "p": _num(a.p),
            "text": a.text(result), "term": a.term.name if a.term is not None else None,
            "term_significant": a.term_significant, "terms": [_term_dict(c) for c in a.terms]}


def _mode_dict(j: int, tr, result) -> dict:
    return {"mode": j, "frequency_hz": tr.frequency_hz, "in_reference": tr.in_reference,
            "tested": bool(result.testable[j]), "backbone_amplitude": _num(result.amplitudes[j]),
            "reference_mean": {q: _num(result.reference_mean(q, j)) for q in result.quantities},
            "reference_scatter": {q: _num(result.reference_std(q, j)) for q in result.quantities}}


def track_dict(result) -> dict:
    """JSON-ready: the settings, the modes, the per-survey verdicts, the alarms with their terms, the
    trends and the events."""
    return {
        "alpha": result.alpha,
        "reference": [int(i) for i in result.reference],
        "modes": [_mode_dict(j, tr, result) for j, tr in enumerate(result.tracks)],
        "surveys": [{"survey": s, "label": result.labels[s], "changed": bool(result.changed[s]),
                     "failed": result.values[s].failed or None} for s in range(len(result.values))],
        "alarms": [_alarm_dict(a, result) for a in result.alarms],
        "trends": [{"mode": tr.mode, "quantity": tr.quantity, "z": _num(tr.z), "p": _num(tr.p),
                    "significant": tr.significant, "slope_per_survey": _num(tr.slope),
                    "text": tr.text(result)} for tr in result.trends],
        "events": [{"mode": e.mode, "kind": e.kind, "found_reference": e.found_reference,
                    "n_reference": e.n_reference, "found_new": e.found_new, "n_new": e.n_new, "p": _num(e.p),
                    "significant": e.significant, "text": e.text(result)} for e in result.mode_events],
    }

"""Repeated hits of one structure: the same mode in every record, combined by consensus (section 3.3.2)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..analysis.consensus import consensus
from ..poles.modal import modal_parameters

__all__ = ["merge_hits", "MATCH_TOLERANCE"]

#: Two modes of different hits are the same mode when their frequencies differ by less than this fraction.
MATCH_TOLERANCE = 0.01


def _groups(per_record: list[list]) -> list[list]:
    """Modes grouped across records by frequency, at most one per record in a group."""
    groups: list[list] = []
    for mode in sorted((m for modes in per_record for m in modes), key=lambda m: m.frequency_hz):
        for group in groups:
            centre = float(np.median([g.frequency_hz for g in group]))
            if abs(mode.frequency_hz / centre - 1) <= MATCH_TOLERANCE and all(
                g.record != mode.record for g in group
            ):
                group.append(mode)
                break
        else:
            groups.append([mode])
    return groups


def _iqr(values) -> float:
    q1, q3 = np.percentile(values, [25, 75])
    return float(q3 - q1)


def _combined_std(stds) -> float:
    """Standard deviation of a combined value from the hits' own: of their mean, and ``sqrt(pi / 2)``
    times that for three hits or more, whose combination is a median (or the consensus, a median of the
    coefficients): the large-sample variance of the median of normal values."""
    stds = np.asarray(stds, dtype=float)
    factor = np.sqrt(np.pi / 2) if stds.size >= 3 else 1.0
    return float(factor * np.sqrt(np.mean(stds**2) / stds.size))


def _combined(group: list):
    """One mode from its hits: the consensus model's linear values, their standard deviations, the hits'
    spread."""
    best = max(group, key=lambda m: m.snr_db)
    frequency = float(np.median([m.frequency_hz for m in group]))
    zeta = float(np.median([m.damping_ratio for m in group]))
    if len(group) >= 3:  # a histogram consensus of the coefficients needs a few models
        f, z = modal_parameters(consensus([m.model for m in group]))
        near = np.flatnonzero(np.abs(f / frequency - 1) <= MATCH_TOLERANCE) if f.size else []
        if len(near) and z[near[0]] > 0:
            frequency, zeta = float(f[near[0]]), float(z[near[0]])
    return replace(
        best,
        frequency_hz=frequency,
        damping_ratio=zeta,
        frequency_std_hz=_combined_std([m.frequency_std_hz for m in group]),
        damping_ratio_std=_combined_std([m.damping_ratio_std for m in group]),
        hits=sorted(group, key=lambda m: m.record),
        frequency_spread_hz=_iqr([m.frequency_hz for m in group]),
        damping_ratio_spread=_iqr([m.damping_ratio for m in group]),
    )


def merge_hits(per_record: list[list]) -> list:
    """Modes of several hits matched by frequency and combined; a mode seen in one hit only is kept as is
    (with ``hits`` of length 1)."""
    return [_combined(group) for group in _groups(per_record)]

"""The same mode across surveys: modes matched by frequency and, where both have a shape, by MAC.

Each survey's modes are assigned one-to-one to the *tracks* (the modes of the structure) by the Hungarian
method on the cost ``|ln(f / f_track)| / tolerance + (1 - MAC) / (1 - min_mac)``; a pair further apart
than ``tolerance`` (relative) or less alike than ``min_mac`` is never matched. The tracks come from the
reference surveys: seeded by the survey with the most modes, every reference mode that matches none
starts a track, then the reference is assigned again to the tracks' median frequencies. New surveys are
assigned to them in order; a new mode that matches no track starts one that is not in the reference (a
mode that appeared), and a track a survey does not fill is a mode that survey missed or that vanished.
Nothing is forced into a match.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import linear_sum_assignment

__all__ = ["ModeTrack", "match_modes"]

_NO = 1e9


@dataclass(eq=False)
class ModeTrack:
    """One mode of the structure followed over the surveys.

    Attributes
    ----------
    frequency_hz : float
        Median frequency of its modes in the reference (in the new surveys for a track that is not in the
        reference).
    in_reference : bool
        Whether the reference surveys have it (else it appeared in the new ones).
    shape : ndarray or None
        The shape of its first mode with one.
    """

    frequency_hz: float
    in_reference: bool
    shape: np.ndarray | None = None
    members: list = field(default_factory=list, repr=False)

    def label(self, index: int) -> str:
        """``"mode 2 (412.3 Hz)"``."""
        return f"mode {index} ({self.frequency_hz:.5g} Hz)"


def _mac(a, b) -> float:
    if a is None or b is None or len(a) != len(b) or len(a) < 2:
        return np.nan
    num = abs(np.vdot(a, b)) ** 2
    den = np.vdot(a, a).real * np.vdot(b, b).real
    return float(num / den) if den > 0 else np.nan


def _assign(modes: list, tracks: list, tolerance: float, min_mac: float) -> dict:
    """``{mode index: track index}`` of one survey's modes."""
    if not modes or not tracks:
        return {}
    cost = np.full((len(modes), len(tracks)), _NO)
    for i, m in enumerate(modes):
        for j, tr in enumerate(tracks):
            rel = abs(np.log(m.frequency_hz / tr.frequency_hz))
            mac = _mac(m.shape, tr.shape)
            if rel > tolerance or (np.isfinite(mac) and mac < min_mac):
                continue
            cost[i, j] = rel / tolerance + (
                0.0 if not np.isfinite(mac) else (1 - mac) / max(1 - min_mac, 1e-9)
            )
    rows, cols = linear_sum_assignment(cost)
    return {int(i): int(j) for i, j in zip(rows, cols) if cost[i, j] < _NO}


def _fill(values, order, tracks, slots, tolerance, min_mac, in_reference: bool) -> None:
    """Assign the surveys ``order`` to ``tracks`` (new tracks for modes that match none); a track not in
    the reference follows the median of its modes."""
    for s in order:
        index = [i for i, m in enumerate(values[s].modes) if m.frequency_hz > 0]
        modes = [values[s].modes[i] for i in index]
        got = _assign(modes, tracks, tolerance, min_mac)
        for i, m in enumerate(modes):
            if i not in got:
                tracks.append(ModeTrack(m.frequency_hz, in_reference, m.shape))
                got[i] = len(tracks) - 1
            tr = tracks[got[i]]
            tr.members.append(m.frequency_hz)
            if tr.shape is None and m.shape is not None:
                tr.shape = m.shape
            if not tr.in_reference:
                tr.frequency_hz = float(np.median(tr.members))
            slots.setdefault(s, {})[got[i]] = index[i]


def match_modes(values: list, reference, tolerance: float = 0.03, min_mac: float = 0.8):
    """Tracks over the surveys and, per survey and track, the index of its mode (module docstring).

    Parameters
    ----------
    values : list of SurveyValues
    reference : sequence of int
        The reference surveys.
    tolerance : float
        Largest relative frequency difference of a match.
    min_mac : float
        Smallest MAC of a match where both modes have a shape.

    Returns
    -------
    tracks : list of ModeTrack
        Reference tracks first, by frequency; then the tracks that appeared.
    slot : ndarray of int (n_surveys, n_tracks)
        The index of the track's mode in each survey's ``modes``, -1 where the survey has none.

    Examples
    --------
    >>> from sindy_impulse.tracking.values import ModeValues, SurveyValues
    >>> def survey(*fs):
    ...     return SurveyValues([ModeValues(f, 0.0, 0.01, 0.0, 1.0) for f in fs])
    >>> tracks, slot = match_modes([survey(100.0, 250.0), survey(100.2, 249.0), survey(250.5, 400.0)], [0, 1])
    >>> [round(t.frequency_hz, 1) for t in tracks], [t.in_reference for t in tracks]
    ([100.1, 249.5, 400.0], [True, True, False])
    >>> slot.tolist()
    [[0, 1, -1], [0, 1, -1], [-1, 0, 1]]
    """
    reference = [int(i) for i in reference]
    seeds: list = []  # the tracks, seeded by the richest survey, then at their median frequencies
    _fill(
        values, sorted(reference, key=lambda s: -len(values[s].modes)), seeds, {}, tolerance, min_mac, False
    )
    tracks = sorted(
        (ModeTrack(float(np.median(t.members)), True, t.shape) for t in seeds), key=lambda t: t.frequency_hz
    )
    slots: dict = {}
    _fill(values, reference, tracks, slots, tolerance, min_mac, True)
    new = [s for s in range(len(values)) if s not in set(reference)]
    _fill(values, new, tracks, slots, tolerance, min_mac, False)
    slot = np.full((len(values), len(tracks)), -1, dtype=int)
    for s, got in slots.items():
        for j, i in got.items():
            slot[s, j] = i
    return tracks, slot

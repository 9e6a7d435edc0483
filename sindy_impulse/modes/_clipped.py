"""What a survey says about a record whose sensor saturated: a note on what was done with the clipped
samples (:func:`~sindy_impulse.preprocessing.preprocess` repairs them from the unclipped ones, or starts
the free decay after them), and one :class:`~.result.Rejected` row per spectral peak of the clipped record
that its unclipped samples do not hold (a product of the clipping, dropped by the repair), with the
combination of the record's modes it sits at as evidence.
"""

from __future__ import annotations

import itertools

import numpy as np

from .result import Rejected

__all__ = ["clipping_report", "nearest_combination"]

#: Largest multiple of one mode, and of each of two modes, searched for a clipping product.
_ORDER = {1: 40, 2: 12}


def nearest_combination(frequency_hz: float, modes_hz) -> tuple[str, float]:
    """The combination ``n f_a + m f_b`` of the (up to two strongest) modes closest to a frequency, in
    words, and its distance relative to the frequency.

    Examples
    --------
    >>> nearest_combination(31.9, [10.6])
    ('3 x 10.6 Hz', 0.0031...)
    >>> nearest_combination(413.0, [119.0, 147.0])[0]
    '2 x 147 Hz + 1 x 119 Hz'
    """
    f = [float(v) for v in modes_hz][:2]
    best = (np.inf, 0, "")
    top = _ORDER[len(f)]
    for counts in itertools.product(range(-top, top + 1), repeat=len(f)):
        pairs = list(zip(counts, f))
        value = sum(k * g for k, g in pairs)
        if value <= 0 or all(k == 0 for k, _ in pairs):
            continue
        terms = sorted((p for p in pairs if p[0]), key=lambda p: -abs(p[0] * p[1]))
        words = " ".join(f"{'+' if k > 0 else '-'} {abs(k)} x {g:.4g} Hz" for k, g in terms).lstrip("+ ")
        order = sum(abs(k) for k, _ in pairs)  # the lowest order among equally close ones
        best = min(best, (round(abs(value - frequency_hz) / frequency_hz, 9), order, words))
    return best[2], best[0]


def clipping_report(pre, index: int) -> tuple[list, list]:
    """The note and the :class:`~.result.Rejected` rows of one preprocessed record's clipping (see the
    module): (notes, rejected), both empty when the sensor never saturated after the contact."""
    impact = pre.impact
    if not impact.saturated:
        return [], []
    if impact.clipping == "repaired":
        note = (f"record {index}: the sensor saturated on {impact.saturated} samples of the free decay; they "
                "were repaired from the unclipped samples (damped sinusoids fitted to them)")
    else:
        note = (f"record {index}: the sensor saturated on {impact.saturated} samples; the free decay starts "
                f"after the last one, at {impact.ringdown_time:.6g} s")
    repair = pre.declipped
    if repair is None or not len(repair.dropped_hz):
        return [note], []
    kept = repair.frequency_hz[np.argsort(-repair.amplitude)]
    rows = []
    for f in repair.dropped_hz:
        words, off = nearest_combination(f, kept)
        half = 0.01 * f
        rows.append(Rejected(
            (float(f - half), float(f + half)),
            f"a peak of the clipped record at {f:.5g} Hz that its unclipped samples do not hold: a product "
            f"of the clipping ({words}, {off:.1%} off), not a mode",
            index,
            {"frequency_hz": float(f), "clipping_product": True, "combination": words,
             "combination_offset": float(off)},
        ))
    return [note], rows

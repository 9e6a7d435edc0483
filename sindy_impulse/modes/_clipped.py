"""What a survey says about a record whose sensor saturated: a note on what was done with the clipped
samples (:func:`~sindy_impulse.preprocessing.preprocess` repairs them from the unclipped ones, or starts
the free decay after them, or, when neither can be done, keeps them), and one :class:`~.result.Rejected`
row per spectral peak of the clipped record that its unclipped samples do not hold (a product of the
clipping, dropped by the repair), with the combination of the record's modes it sits at as evidence. Where
the clipped samples are kept, the clipping's products are still in the free decay: :func:`clipping_product`
tells a component on a harmonic of a stronger one, or on a combination of two (the survey names it,
:mod:`.classify`).
"""

from __future__ import annotations

import itertools

import numpy as np

from .kinds import Reason
from .result import Rejected

__all__ = ["clipping_report", "nearest_combination", "clipping_product"]

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
        order = sum(abs(k) for k, _ in pairs)  # the lowest order among equally close ones
        best = min(best, (round(abs(value - frequency_hz) / frequency_hz, 9), order, _words(pairs)))
    return best[2], best[0]


def _words(pairs) -> str:
    """``n f_a + m f_b`` in words, the larger term first: ``[(2, 147.0), (1, 119.0)]`` -> '2 x 147 Hz + 1 x
    119 Hz'."""
    terms = sorted((p for p in pairs if p[0]), key=lambda p: -abs(p[0] * p[1]))
    return " ".join(f"{'+' if k > 0 else '-'} {abs(k)} x {g:.5g} Hz" for k, g in terms).lstrip("+ ")


def clipping_report(pre, index: int) -> tuple[list, list]:
    """The note and the :class:`~.result.Rejected` rows of one preprocessed record's clipping (see the
    module): (notes, rejected), both empty when the sensor never saturated after the contact."""
    impact = pre.impact
    if not impact.saturated:
        return [], []
    if impact.clipping == "repaired":
        note = (f"record {index}: the sensor saturated on {impact.saturated} samples of the free decay; they "
                "were repaired from the unclipped samples (damped sinusoids fitted to them)")
    elif impact.clipping == "kept":
        note = (f"record {index}: the sensor saturated on {impact.saturated} samples of the free decay and "
                "they could not be repaired (too few unclipped samples follow them, and no damped sinusoids "
                "fit the unclipped ones): peaks on the clipping's products of stronger modes (harmonics, "
                "intermodulation) are named as such, others may remain, and the damping ratios are those "
                "of the clipped signal, lower than the structure's while it clipped; hit softer, or set the "
                "sensor's range higher")
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
            Reason.CLIPPING_PRODUCT,
        ))
    return [note], rows


#: Clipping a sum of sinusoids puts at ``n f_a + m f_b`` a product at most ``1 / (|n| + |m|)`` of the weaker
#: one involved (of a lone sinusoid, harmonic ``k`` at most ``1 / k`` of it: a square wave's, the limit of
#: clipping); a component at most this many times that bound may be one (amplitudes read from a decay fit
#: are not exact).
_PRODUCT_MARGIN = 1.5
#: Highest order ``|n| + |m|`` of a product of two components that names a component (the grid of their
#: combinations thickens with the order until any frequency lies near one).
_PAIR_ORDER = 6


def clipping_product(frequency_hz: float, tolerance_hz: float, amplitude: float, parents,
                     fs: float) -> tuple[str, float] | None:
    """The lowest-order product of clipping one or two stronger components on which a component lies: a
    harmonic ``k f_a`` (``2 <= k <=`` :data:`_ORDER` ``[1]``) of one, or ``|n f_a + m f_b|`` (``n, m``
    non-zero, ``|n| + |m| <=`` :data:`_PAIR_ORDER`) of two, folded about the Nyquist frequency as sampling
    folds it; within ``tolerance_hz`` plus three standard deviations of the combination (``|n|`` times a
    parent's, summed), and no stronger than clipping makes it (:data:`_PRODUCT_MARGIN`). ``parents``: one or
    two ``(frequency_hz, frequency_std_hz, amplitude)``. ``(the combination in words, its distance in Hz)``,
    or None when there is none.

    Examples
    --------
    >>> clipping_product(149.99, 0.5, 0.1, [(50.0, 0.001, 1.0)], fs=1000.0)[0]  # the third harmonic
    '3 x 50 Hz'
    >>> clipping_product(447.3, 3.0, 0.01, [(50.0, 0.001, 1.0)], fs=1000.0)[0]  # 450 Hz: the ninth
    '9 x 50 Hz'
    >>> clipping_product(447.3, 3.0, 0.5, [(50.0, 0.001, 1.0)], fs=1000.0) is None  # too strong for it
    True
    >>> clipping_product(167.0, 1.0, 0.05, [(255.0, 0.01, 1.0), (44.0, 0.01, 0.8)], fs=1000.0)[0]
    '1 x 255 Hz - 2 x 44 Hz'
    """
    f = np.array([p[0] for p in parents], float)
    std = np.array([p[1] for p in parents], float)
    amplitudes = np.array([p[2] for p in parents], float)
    if f.size == 1:
        counts = np.arange(2, _ORDER[1] + 1)[:, None]
    else:
        top = np.arange(-_PAIR_ORDER, _PAIR_ORDER + 1)
        counts = np.array([(n, m) for n in top for m in top if n and m and abs(n) + abs(m) <= _PAIR_ORDER])
    order = np.abs(counts).sum(axis=1)
    folded = np.abs((counts @ f + fs / 2) % fs - fs / 2)
    off = np.abs(folded - frequency_hz)
    bound = _PRODUCT_MARGIN / order * np.min(np.where(counts != 0, amplitudes, np.inf), axis=1)
    fits = (off <= tolerance_hz + 3 * np.abs(counts) @ std) & (amplitude <= bound)
    if not fits.any():
        return None
    value = counts @ f  # (of -n, -m and n, m, the one that is positive is said)
    best = min(np.flatnonzero(fits), key=lambda i: (order[i], off[i], value[i] < 0))
    return _words(list(zip(counts[best].tolist(), f.tolist()))), float(off[best])

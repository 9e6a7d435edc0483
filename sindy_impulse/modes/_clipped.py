"""What a survey says about a record whose sensor saturated: a note on what was done with the clipped
samples (:func:`~sindy_impulse.preprocessing.preprocess` repairs them from the unclipped ones, or starts
the free decay after them, or, when neither can be done, keeps them), and one :class:`~.result.Rejected`
row per spectral peak of the clipped record that its unclipped samples do not hold (a product of the
clipping, dropped by the repair), with the combination of the record's modes it sits at as evidence. Where
the clipped samples are kept, the clipping's products are still in the free decay: :func:`harmonic_order`
tells a component on a harmonic of a stronger one (the survey names it, :mod:`.classify`).
"""

from __future__ import annotations

import itertools

import numpy as np

from .kinds import Reason
from .result import Rejected

__all__ = ["clipping_report", "nearest_combination", "harmonic_order"]

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
    elif impact.clipping == "kept":
        note = (f"record {index}: the sensor saturated on {impact.saturated} samples of the free decay and "
                "they could not be repaired (too few unclipped samples follow them, and no damped sinusoids "
                "fit the unclipped ones): peaks on harmonics of a stronger mode are named as the clipping's "
                "products, and the damping ratios are those of the clipped signal, lower than the "
                "structure's while it clipped; hit softer, or set the sensor's range higher")
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


#: A clipped sinusoid's harmonic ``k`` is at most ``1 / k`` of its fundamental (a square wave's, the limit
#: of clipping); a component at most this many times that bound may be one (amplitudes read from a decay
#: fit are not exact).
_HARMONIC_MARGIN = 1.5


def harmonic_order(frequency_hz: float, tolerance_hz: float, parent_hz: float, parent_std_hz: float,
                   fs: float, share: float = 0.0) -> tuple[int, float] | None:
    """The lowest harmonic ``k f_p`` (``2 <= k <=`` :data:`_ORDER` ``[1]``, folded about the Nyquist
    frequency as sampling folds it) of a parent at ``parent_hz`` on which a component at ``frequency_hz``
    lies, within ``tolerance_hz`` plus three times ``k`` parent standard deviations, and that clipping can
    make as strong as the component (its amplitude a ``share`` of the parent's: at most
    :data:`_HARMONIC_MARGIN` ``/ k``), and its distance (Hz); None when there is none.

    Examples
    --------
    >>> order, off = harmonic_order(149.99, 0.5, 50.0, 0.001, fs=1000.0)  # the third
    >>> order, round(off, 6)
    (3, 0.01)
    >>> harmonic_order(447.3, 3.0, 50.0, 0.001, fs=1000.0)[0]  # 450 Hz: the ninth
    9
    >>> harmonic_order(447.3, 3.0, 50.0, 0.001, fs=1000.0, share=0.5) is None  # too strong for the ninth
    True
    >>> harmonic_order(130.0, 3.0, 50.0, 0.001, fs=1000.0) is None
    True
    """
    k = np.arange(2, _ORDER[1] + 1)
    folded = np.abs((k * parent_hz + fs / 2) % fs - fs / 2)
    off = np.abs(folded - frequency_hz)
    fits = (off <= tolerance_hz + 3 * k * parent_std_hz) & (share <= _HARMONIC_MARGIN / k)
    if not fits.any():
        return None
    first = int(np.argmax(fits))
    return int(k[first]), float(off[first])

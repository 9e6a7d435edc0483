"""Data-quality checks of a hammer-test record, for diagnostics: each returns numbers, not verdicts;
:func:`check_quality` gathers them and words the problems against documented limits.

=====================  ==============================================================  =================
check                  measure                                                         flagged when
=====================  ==============================================================  =================
offset                 ``|offset|`` over the ring-down's largest excursion              > 0.1
clipping               samples in runs of >= 3 equal to the record's max or min        any
quantisation           ADC step over the ring-down amplitude                           > 0.005
signal-to-noise        ``10 log10(P_signal / P_noise)`` over the ring-down              < 20 dB
                       (noise from the pre-trigger, else from the peaks' floor;         or no signal
                       ``-inf`` when the ring-down is no louder than the noise)         above the noise
no ring-down           no significant spectral peak and no decay (first over last      both
                       quarter of the ring-down, RMS)
=====================  ==============================================================  =================

A step of 0.005 of the amplitude (about 400 levels across the ring-down) limits the SNR to about 54 dB
(quantisation noise ``step / sqrt(12)``). The SNR is defined as in :func:`sindy_impulse.datasets.add_noise`
(signal and noise power over the whole ring-down). Without a pre-trigger the noise power is an upper
bound (:func:`ringdown_snr_db`), so the SNR is a lower bound. A heavily oversampled,
coarsely quantised peak can sit 3 samples on one level: clipping and quantisation are then flagged
together.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from numbers import Integral, Real

import numpy as np

from .._utils.params import Interval, check_param
from .._utils.robust import robust_std
from ._record import check_fs, check_signal_1d
from .offset import estimate_offset
from .peaks import SpectralPeaks, spectral_peaks
from .saturation import clipping_mask
from .spectrum import Spectrum, ringdown_spectrum

__all__ = [
    "LIMITS",
    "clipping_mask",
    "clipping_end",
    "saturated_mask",
    "MIN_AT_LIMIT",
    "quantisation_step",
    "ringdown_snr_db",
    "decay_db",
    "QualityReport",
    "check_quality",
]

#: Limits past which :func:`check_quality` words a problem.
LIMITS = {"offset": 0.1, "quantisation": 0.005, "snr_db": 20.0, "decay_db": 6.0}


#: Samples at exactly one extreme of a record that is not quantised that make it saturated, with no run.
MIN_AT_LIMIT = 5


def saturated_mask(y, *, min_run: int = 3) -> np.ndarray:
    """Every sample at a level the sensor saturated at.

    The record saturated when :func:`clipping_mask` finds a run of ``min_run`` samples at one of its
    extremes, or when :data:`MIN_AT_LIMIT` samples sit exactly at one extreme, more than a smooth crest
    puts there (:func:`_piled_up`: a continuous signal with noise reaches its maximum once, a finely
    quantised one rarely more often than the levels just inside it; a sum of modes sampled a few times
    per period touches its limit one sample at a time); a side saturated
    then when ``min_run`` samples sit at its extreme, and every sample at that level counts, also alone
    (the contacts with the limit as the decay leaves it, and many on the side a sensor clips less, are one
    or two samples).

    Examples
    --------
    >>> y = np.clip(np.exp(-np.arange(300) / 60) * np.sin(np.arange(300) / 3), -0.5, 0.5)
    >>> int(saturated_mask(y).sum()), int(clipping_mask(y).sum())
    (18, 18)
    """
    arr = check_signal_1d(y, "y", 1)
    out = np.zeros(arr.size, bool)
    if np.ptp(arr) == 0:
        return out
    tol = 1e-12 * np.ptp(arr)
    sides = (arr >= arr.max() - tol, arr <= arr.min() + tol)
    many = False
    if max(side.sum() for side in sides) >= MIN_AT_LIMIT:  # (the step only where it can matter)
        step = quantisation_step(arr)
        many = any(_piled_up(arr, side, step) for side in sides)
    if not (many or clipping_mask(arr, min_run=min_run).any()):
        return out
    for at_extreme in sides:
        if at_extreme.sum() >= min_run:
            out |= at_extreme
    return out


#: Quantisation levels just inside an extreme that :func:`_piled_up` compares the extreme's count with.
_LEVELS_BELOW = 4


def _piled_up(arr: np.ndarray, at_extreme: np.ndarray, step: float) -> bool:
    """Whether at least :data:`MIN_AT_LIMIT` samples sit at one extreme more often than a smooth crest
    puts them there.

    A continuous record with noise reaches its extreme once. A quantised one (``step`` > 0) reaches its
    top level on every crest within a step of its peak, but a crest passes the :data:`_LEVELS_BELOW`
    levels inside it for longer than it stays in the top one (about 1.2 times as long, a cosine's crest),
    so the extreme is a limit the signal piled up against when it holds more than twice as many samples
    as those levels.
    """
    count = int(at_extreme.sum())
    if count < MIN_AT_LIMIT:
        return False
    if step == 0:
        return True
    level = arr[at_extreme][0]
    inside = np.abs(arr - level)
    below = int(np.count_nonzero((inside > 0.5 * step) & (inside < (_LEVELS_BELOW + 0.5) * step)))
    return count > 2 * below


def clipping_end(y, *, min_run: int = 3) -> int:
    """Index after the last saturated sample (:func:`saturated_mask`; 0 when the sensor never saturated).
    After it the record is the sensor's true signal: clipping distorts only the samples it flattens.

    Examples
    --------
    >>> y = np.clip(np.exp(-np.arange(300) / 60) * np.sin(np.arange(300) / 3), -0.5, 0.5)
    >>> end = clipping_end(y)
    >>> end, bool(np.abs(y[end:]).max() < 0.5), clipping_end(np.sin(np.arange(100) / 5))
    (35, True, 0)
    """
    found = np.flatnonzero(saturated_mask(y, min_run=min_run))
    return int(found[-1]) + 1 if found.size else 0


def quantisation_step(y) -> float:
    """The ADC step of a quantised record (0.0 when its values are not on a regular grid).

    The step is the smallest gap between distinct values; the record is quantised when 99 % of the gaps
    between its sorted distinct values are whole multiples of it (to 1 %). Values exported with a fixed
    number of significant digits lie on such a grid too, with a step far below the signal.

    Examples
    --------
    >>> y = np.round(np.sin(np.arange(1000) / 7) / 0.05) * 0.05
    >>> round(quantisation_step(y), 6), quantisation_step(np.sin(np.arange(1000) / 7))
    (0.05, 0.0)
    """
    arr = check_signal_1d(y, "y", 1)
    levels = np.unique(arr)
    if levels.size < 3:
        return float(np.ptp(arr))
    gaps = np.diff(levels)
    step = float(gaps.min())
    ratio = gaps / step
    return step if np.mean(np.abs(ratio - np.round(ratio)) < 0.01) >= 0.99 else 0.0


def ringdown_snr_db(y, fs: float, *, noise_rms: float | None = None,
                    spectrum: Spectrum | None = None) -> float:
    """``10 log10(P_signal / P_noise)`` of a ring-down (from the onset, offset removed).

    ``P_noise`` is ``noise_rms**2`` when given (e.g. from the pre-trigger), else the smaller of the
    spectrum's noise floor integrated over frequency and the mean square of the last tenth of the
    ring-down (both upper bounds of the noise: the first under the skirts of strong modes, the second
    while the modes still ring at the end); ``spectrum``: the ring-down's
    :func:`~sindy_impulse.preprocessing.ringdown_spectrum` when already computed. ``P_signal`` is the mean
    square minus ``P_noise``; ``-inf`` when the mean square does not exceed ``P_noise`` (no signal above
    the noise).

    Examples
    --------
    >>> from sindy_impulse.datasets import add_noise
    >>> t = np.arange(10000) / 5000
    >>> x = np.exp(-2 * np.pi * 0.005 * 120 * t) * np.sin(2 * np.pi * 120 * t)
    >>> round(ringdown_snr_db(add_noise(x, 20, random_state=0), 5000.0))
    20
    """
    arr = check_signal_1d(y, "y")
    rate = check_fs(fs)
    check_param("noise_rms", noise_rms, [None, Interval(Real, 0, None, "neither")], "ringdown_snr_db")
    if spectrum is not None and not isinstance(spectrum, Spectrum):
        raise TypeError(f"ringdown_snr_db: spectrum must be None or the ring-down's Spectrum "
                        f"(ringdown_spectrum), got {type(spectrum).__name__}")
    if noise_rms is None:
        spectrum = ringdown_spectrum(arr, rate) if spectrum is None else spectrum
        floor = float(np.sum(spectrum.floor) * (spectrum.frequency_hz[1] - spectrum.frequency_hz[0]))
        noise = min(floor, float(np.mean(arr[int(0.9 * arr.size) :] ** 2)))
    else:
        noise = float(noise_rms) ** 2
    signal = float(np.mean(arr**2)) - noise
    if signal <= 0:
        return float("-inf")
    return float(10.0 * np.log10(signal / noise)) if noise > 0 else float("inf")


def decay_db(y) -> float:
    """How much a ring-down decays: RMS of its first quarter over its last quarter, in dB.

    Examples
    --------
    >>> round(decay_db(np.exp(-np.arange(400) / 100) * np.sin(np.arange(400))), 1)
    26.0
    """
    arr = check_signal_1d(y, "y", 8)
    q = arr.size // 4
    first, last = np.sqrt(np.mean(arr[:q] ** 2)), np.sqrt(np.mean(arr[-q:] ** 2))
    return float(20.0 * np.log10(max(first, np.finfo(float).tiny) / max(last, np.finfo(float).tiny)))


@dataclass(frozen=True)
class QualityReport:
    """The checks of :func:`check_quality` and the problems they show.

    Attributes
    ----------
    offset_ratio : float
        ``|offset|`` over the ring-down's largest excursion from it.
    clipped : ndarray of bool
        Mask of the clipped samples (see :func:`clipping_mask`).
    quantisation_step, relative_step : float
        ADC step (0 if none found) and the step over the ring-down amplitude.
    snr_db, decay_db : float
        See :func:`ringdown_snr_db` and :func:`decay_db`.
    n_peaks : int
        Significant spectral peaks.
    problems : dict
        One sentence per check past its limit (:data:`LIMITS`), saying what to do, keyed by check:
        ``"offset"``, ``"clipping"``, ``"quantisation"``, ``"snr"``, ``"no_ringdown"``.
    noise_measured : bool
        Whether the SNR's noise was measured (on a pre-trigger of :data:`PRE_TRIGGER_SAMPLES` samples or
        more, or given: :meth:`with_snr`); False where it is an upper bound read off the ring-down itself
        (its spectrum's floor, its last tenth), which on a short record of strong modes stands on the modes
        and makes the SNR too low.
    """

    offset_ratio: float
    clipped: np.ndarray
    quantisation_step: float
    relative_step: float
    snr_db: float
    decay_db: float
    n_peaks: int
    problems: dict
    noise_measured: bool = True

    def with_snr(self, snr_db: float) -> QualityReport:
        """The report with the SNR measured against a better noise estimate (e.g. the residual of the
        modes fitted to the ring-down), its problems worded again.

        Examples
        --------
        >>> t = np.arange(150) / 1000
        >>> noise = 1e-4 * np.random.default_rng(0).normal(size=150)
        >>> y = np.exp(-40 * t) * np.sin(2 * np.pi * 60 * t) + noise
        >>> report = check_quality(y, 1000.0)
        >>> report.noise_measured, "snr" in report.with_snr(45.0).problems
        (False, False)
        """
        if isinstance(snr_db, bool) or not isinstance(snr_db, Real):
            raise TypeError(f"QualityReport.with_snr: snr_db must be a number in dB; got {snr_db!r}")
        if np.isnan(snr_db):
            raise ValueError("QualityReport.with_snr: snr_db must be a number in dB (-inf: no signal above "
                             "the noise), got nan")
        problems = _problems(self.offset_ratio, self.clipped, self.relative_step, snr_db, self.decay_db,
                             self.n_peaks)
        return replace(self, snr_db=float(snr_db), problems=problems, noise_measured=True)

    @property
    def ringdown_found(self) -> bool:
        """A significant spectral peak or a decaying envelope."""
        return self.n_peaks > 0 or self.decay_db > LIMITS["decay_db"]

    def __repr__(self) -> str:
        head = (
            f"QualityReport(offset {self.offset_ratio:.3g} x amplitude, {int(self.clipped.sum())} clipped "
            f"sample(s), quantisation step {self.relative_step:.3g} x amplitude, SNR {self.snr_db:.1f} dB, "
            f"decay {self.decay_db:.1f} dB, {self.n_peaks} peak(s))"
        )
        return "\n".join([head, *(f"  - {p}" for p in self.problems.values())])


def _problems(offset, clipped, relative_step, snr, decay, n_peaks) -> dict:
    out = {}
    if offset > LIMITS["offset"]:
        out["offset"] = f"offset of {offset:.3g} x the ring-down amplitude: remove it (estimate_offset)"
    if clipped.any():
        out["clipping"] = (
            f"{int(clipped.sum())} sample(s) clipped: the sensor saturated; hit softer or drop them"
        )
    if relative_step > LIMITS["quantisation"]:
        out["quantisation"] = (
            f"coarse quantisation: step {relative_step:.3g} x the amplitude; use a finer input range"
        )
    if not snr > 0:  # (-inf: a mean square at most the noise's; under 0 dB: the ring-down is quieter)
        out["snr"] = "no signal above the noise: the ring-down is no louder than the noise; hit harder"
    elif snr < LIMITS["snr_db"]:
        out["snr"] = f"low signal-to-noise ratio ({snr:.1f} dB): expect scattered models; hit harder"
    if n_peaks == 0 and decay <= LIMITS["decay_db"]:
        out["no_ringdown"] = "no ring-down found: no spectral peak and no decay; the record looks like noise"
    return out


#: Fewest pre-trigger samples whose spread measures the noise.
PRE_TRIGGER_SAMPLES = 32


def _noise_rms(pre: np.ndarray) -> float | None:
    """Noise standard deviation measured on the pre-trigger (robust; :data:`PRE_TRIGGER_SAMPLES` samples or
    more), or None (:func:`ringdown_snr_db` then bounds it from the ring-down itself)."""
    if pre.size < PRE_TRIGGER_SAMPLES:
        return None
    return robust_std(pre) or None


def check_quality(y, fs: float, *, onset_index: int = 0, peaks: SpectralPeaks | None = None) -> QualityReport:
    """Run every check on a raw record (any offset) and word the problems.

    Parameters
    ----------
    y : array-like (n,)
        The raw record.
    fs : float
        Sampling rate (Hz).
    onset_index : int
        First sample of the hit (the ring-down is ``y[onset_index:]``).
    peaks : SpectralPeaks, optional
        Already found peaks of the ring-down (saves a spectrum).

    Returns
    -------
    QualityReport

    Examples
    --------
    >>> t = np.arange(10000) / 5000
    >>> x = np.exp(-2 * np.pi * 0.002 * 150 * t) * np.sin(2 * np.pi * 150 * t)
    >>> y = np.clip(x + 1e-3 * np.random.default_rng(0).standard_normal(t.size), -0.8, 0.8) + 0.5
    >>> report = check_quality(y, 5000.0)
    >>> for check, problem in report.problems.items():
    ...     print(check, "->", problem)
    offset -> offset of 0.625 x the ring-down amplitude: remove it (estimate_offset)
    clipping -> 160 sample(s) clipped: the sensor saturated; hit softer or drop them
    """
    arr = check_signal_1d(y, "y")
    rate = check_fs(fs)
    check_param("onset_index", onset_index, [Interval(Integral, 0, arr.size - 64)], "check_quality")
    offset = estimate_offset(arr, rate, onset_index=onset_index)
    ring = arr[onset_index:] - offset.trend(arr.size, rate)[onset_index:]
    amplitude = max(float(np.max(np.abs(ring))), np.finfo(float).tiny)
    clipped = clipping_mask(arr)
    step = quantisation_step(arr)
    noise = _noise_rms(arr[:onset_index])
    spectrum = peaks.spectrum if peaks is not None and np.isfinite(peaks.threshold_db) else None
    snr, decay = ringdown_snr_db(ring, rate, noise_rms=noise, spectrum=spectrum), decay_db(ring)
    n_peaks = len(spectral_peaks(ring, rate) if peaks is None else peaks)
    problems = _problems(offset.relative, clipped, step / amplitude, snr, decay, n_peaks)
    return QualityReport(offset.relative, clipped, step, step / amplitude, snr, decay, n_peaks, problems,
                         noise is not None)

"""One peak's band signal with the other peaks removed: a strongly damped mode next to lightly damped ones.

A peak's own band (:mod:`.partition`) ends half-way to its neighbours. A strongly damped mode needs a
wide band: a band-pass filter's transient lasts about the inverse of its bandwidth, and a mode with a
damping ratio of 2 % loses an e-fold of amplitude every 8 periods, so in a narrow band the transient
swallows it. When lightly damped neighbours ring inside the wide band they are removed first:

1. every peak of the ring-down is a damped sinusoid with the frequency and decay rate the detection
   fitted (:mod:`.detection`); their amplitudes, phases and a constant are fitted together by linear
   least squares (:func:`.sinusoids.fit_amplitudes`) over the first ``n_efolds`` decay times of the
   target peak (at least 50 periods of the lowest peak);
2. every component but the target's, and the constant, are subtracted: what remains is the target
   mode's response, the noise and whatever the components miss (a small share of each neighbour, as
   their poles are estimates);
3. the remainder is extracted as any band (:func:`.band.extract_band`: zero-phase band-pass, transient
   trimmed, stop at the noise floor, decimation) in a band ``widen`` half-power widths wide on each side
   of the peak, at least ``min_width`` of its frequency, up to ``top_hz`` (default: the highest frequency
   with ``min_samples_per_period``).

The mode is then identified on that band signal like on any other (its frequency and damping come from
its model, not from step 1): measured on ``benchmarks/accuracy/modes.py`` records whose strongly damped mode
(damping ratio 1-3 %) sits 5-10 % from lightly damped ones, the identified damping ratio is within 1-3 %
where the mode's own band gave none.
"""

from __future__ import annotations

from numbers import Integral, Real

import numpy as np

from .._utils.params import Interval, check_param
from .band import BandSignal, band_noise_rms, extract_band
from .pipeline import Preprocessed, _noise_spectrum
from .sinusoids import fit_amplitudes

__all__ = ["deflated_band"]

#: Fewest periods of the lowest peak in the window the amplitudes are fitted on.
_MIN_WINDOW_PERIODS = 50


def _decay_rates(pre: Preprocessed) -> np.ndarray:
    zeta = pre.peaks.damping_ratio
    return zeta * 2.0 * np.pi * pre.peaks.frequency_hz / np.sqrt(1.0 - zeta**2)


def deflated_band(
    pre: Preprocessed,
    peak: int,
    *,
    n_efolds: float = 30.0,
    widen: float = 8.0,
    min_width: float = 0.1,
    top_hz: float | None = None,
    **options,
) -> BandSignal:
    """The band signal of peak ``peak`` of ``pre`` with the other peaks subtracted (see the module).

    Parameters
    ----------
    pre : Preprocessed
        A record through :func:`~sindy_impulse.preprocessing.preprocess` (its peaks fitted as damped
        sinusoids).
    peak : int
        Index of the target peak in ``pre.peaks``.
    n_efolds : float, default=30
        Length of the window whose amplitudes are fitted, in decay times of the target.
    widen : float, default=8
        Half-width of the band around the peak, in half-power half-widths (damping ratios) of the peak.
    min_width : float, default=0.1
        Smallest half-width of the band relative to the peak's frequency.
    top_hz : float, optional
        Highest frequency of the band; default: the highest with ``min_samples_per_period`` (8) at the
        record's rate (a band above it would be resampled by
        :func:`~sindy_impulse.preprocessing.extract_band`; a higher ``top_hz`` lets it).
    **options
        Passed to :func:`~sindy_impulse.preprocessing.extract_band` (``samples_per_period``,
        ``min_samples_per_period``, ``end_snr_db``, ``min_periods``, ...).

    Returns
    -------
    BandSignal
        Raises ``ValueError`` (from :func:`~sindy_impulse.preprocessing.extract_band`) when too few
        periods remain.

    Examples
    --------
    A 2.5 %-damped mode at 105 Hz between lightly damped ones at 100 and 112 Hz:

    >>> from sindy_impulse.preprocessing import preprocess
    >>> t = np.arange(8000) / 2000
    >>> y = sum(a * np.exp(-2 * np.pi * z * f * t) * np.sin(2 * np.pi * f * t)
    ...         for a, f, z in ((1.0, 100.0, 0.002), (1.0, 105.0, 0.025), (1.0, 112.0, 0.003)))
    >>> y = np.concatenate([np.zeros(200), y]) + 1e-4 * np.random.default_rng(0).standard_normal(8200)
    >>> pre = preprocess(y, fs=2000.0)
    >>> band = deflated_band(pre, 1)
    >>> [round(b) for b in band.band_hz], band.n_periods > 10
    ([88, 126], True)
    """
    check_param("peak", peak, [Interval(Integral, 0, len(pre.peaks) - 1)], "deflated_band")
    for name, value, low in (("n_efolds", n_efolds, 1), ("widen", widen, 1), ("min_width", min_width, 0)):
        check_param(name, value, [Interval(Real, low, None, "neither")], "deflated_band")
    start = pre.impact.ringdown_index
    ring = pre.y[start:]
    frequency, decay = pre.peaks.frequency_hz, _decay_rates(pre)
    if not np.all(np.isfinite(decay)):
        raise ValueError(
            "deflated_band needs the peaks fitted as damped sinusoids (preprocess without bands=): "
            f"the decay rates are {np.round(decay, 4).tolist()}"
        )
    window = max(n_efolds / max(decay[peak], 1e-12), _MIN_WINDOW_PERIODS / frequency.min())
    n = int(min(ring.size, np.ceil(window * pre.fs)))
    fit = fit_amplitudes(ring[:n], pre.fs, frequency, decay)
    rest = np.zeros_like(pre.y)  # the record's indices; past the window the target is far under the noise
    rest[start : start + n] = fit.residual + fit.component(peak, n, pre.fs)
    half = max(widen * pre.peaks.damping_ratio[peak], min_width)
    top = pre.fs / options.get("min_samples_per_period", 8.0) * (1 - 1e-9) if top_hz is None else top_hz
    band = (float(frequency[peak] / (1 + half)), float(min(frequency[peak] * (1 + half), top)))
    noise = band_noise_rms(_noise_spectrum(pre.y, pre.impact, pre.fs, pre.peaks), band)
    return extract_band(rest, pre.fs, band, start=start, t0=pre.t0, noise_rms=noise, **options)

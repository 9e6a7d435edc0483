"""A record whose sensor saturated, repaired from the samples it did not clip (:func:`declip`).

While a sensor clips, the record is a memoryless distortion of the response: flat tops whose spectrum holds
harmonics and intermodulation products of the strong modes, and a ring-down that seems to decay faster
than it does. The samples between the flat tops are exact. The repair fits the free decay's modes as
damped sinusoids (:func:`~sindy_impulse.preprocessing.sinusoids.fit_damped_sinusoids`) to the unclipped
samples of a window from the start of the free decay to past the last clipped sample, and puts the
fitted model in place of the clipped samples only:

1. the modes of the unclipped tail (``frequency_hz``, ``decay_rate``: e.g. its spectral peaks) start the
   fit; they are refined on the window's unclipped samples;
2. a mode that decays while the sensor still clips (a strongly damped mode beside a lightly damped one
   that holds the sensor at its limit) is absent from the tail: the largest peak of the fit residual's
   spectrum (zero at the clipped samples) that stands above its floor by the detection threshold
   (:func:`~sindy_impulse.preprocessing.spectrum.detection_threshold_db`) is added and everything refitted,
   while the residual's energy on the unclipped samples drops by more than :data:`MIN_GAIN` times the
   noise variance (a peak made by clipping has nothing on the unclipped samples and is not added);
3. the model must agree with what the sensor showed: at least :data:`MIN_CONSISTENT` of the clipped
   samples must lie beyond the limit they were clipped at (within 3 noise standard deviations), and its
   residual between the clipped samples must be no larger than :data:`_MAX_MISFIT` times its residual
   after them, and no component found in the clipped stretch may decay faster than a damping ratio of
   :data:`_TRANSIENT` (the hit still under way), else the record is not repaired (None);
4. a repaired sample is off by about the fit's residual on the unclipped ones: where the record's noise is
   known (``noise_rms``, e.g. the standard deviation of its last samples), a residual above
   :data:`MAX_RESIDUAL` times it (a model that does not describe the decay: too few components, or a
   nonlinear one) would put its error into every repaired sample, a broadband distortion that reads as
   spurious modes, and the record is not repaired either.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from numbers import Integral, Real

import numpy as np

from .._utils.params import Interval, check_param
from ._record import check_fs, check_signal_1d
from .sinusoids import fit_damped_sinusoids
from .spectrum import (
    candidate_peaks,
    detection_threshold_db,
    half_power_width,
    ringdown_spectrum,
    search_range,
)

__all__ = ["Declipped", "declip", "declip_attempt", "MIN_GAIN", "MIN_CONSISTENT", "MAX_RESIDUAL"]

#: A component found only in the clipped stretch is kept when it lowers the residual's energy on the
#: unclipped samples by this many noise variances.
MIN_GAIN = 100.0
#: Least share of the clipped samples the repair must put beyond the limit they were clipped at.
MIN_CONSISTENT = 0.9
#: Largest ratio of the fit's residual (standard deviation) on the unclipped samples to the record's noise:
#: an order of magnitude (the repaired samples' error, about that residual, must stay near the noise).
MAX_RESIDUAL = 10.0
_MAX_EXTRA = 4  # components added from the clipped stretch at most
#: Largest ratio of the fit's residual (standard deviation) between the clipped samples to its residual after
#: them: a model that holds after the clipping but not while it lasts (a hit still under way) repairs nothing.
_MAX_MISFIT = 3.0
#: A component found only in the clipped stretch that decays faster than this damping ratio is the hit
#: still under way, not a mode: the window starts too early.
_TRANSIENT = 0.1
#: The window reaches past the last clipped sample by this many times the clipped stretch (and 256 samples).
_TAIL = 2.0


@dataclass(frozen=True)
class Declipped:
    """A repaired record and the model that repaired it.

    Attributes
    ----------
    y : ndarray
        The record with its clipped samples (from ``start`` on) replaced by the fitted model.
    repaired : int
        How many samples were replaced.
    frequency_hz, decay_rate : ndarray
        Damped frequencies (Hz) and decay rates (1/s) of the fitted components.
    extra_hz : ndarray
        The components found only in the clipped stretch (modes that decayed while the sensor clipped).
    consistent : float
        Share of the clipped samples the model puts beyond their limit.
    noise_rms : float
        Standard deviation of the fit's residual on the unclipped samples.
    dropped_hz : ndarray
        Start components the unclipped samples do not need (``prune``): clipping products.
    amplitude : ndarray
        Amplitudes of the fitted components at the window's first sample.
    """

    y: np.ndarray = field(repr=False)
    repaired: int
    frequency_hz: np.ndarray
    decay_rate: np.ndarray
    extra_hz: np.ndarray
    consistent: float
    noise_rms: float
    dropped_hz: np.ndarray = field(default_factory=lambda: np.empty(0))
    amplitude: np.ndarray = field(default_factory=lambda: np.empty(0))


def _fit(w, fs, keep, f, sigma):
    tol = np.maximum(3.0 * sigma / (2 * np.pi), 2.0 * fs / w.size) + 1e-3 * f
    fit = fit_damped_sinusoids(w, fs, f, sigma, frequency_tol_hz=tol, keep=keep)
    return fit, float(np.sum(fit.residual[keep] ** 2))


def _extra_peak(residual, fs, keep, found):
    """The strongest significant peak of the residual's spectrum (clipped samples zeroed) away from the
    components ``found``: (frequency, decay rate) or None."""
    spectrum = ringdown_spectrum(np.where(keep, residual, 0.0), fs)
    lo, hi = search_range(spectrum)
    threshold = detection_threshold_db(max(int((hi - lo) / spectrum.resolution_hz), 1))
    idx, height = candidate_peaks(spectrum, lo, hi, threshold, 3.0)
    for i in idx[np.argsort(height)[::-1]]:
        f = float(spectrum.frequency_hz[i])
        if np.all(np.abs(found - f) > 2.0 * spectrum.resolution_hz):
            return f, np.pi * half_power_width(spectrum, int(i))
    return None


def _with_extras(w, fs, keep, fit, rss):
    """The fit with the components found only in the clipped stretch added (module, step 2): (fit, rss,
    their frequencies), or None when one decays like the hit still under way."""
    extra = []
    for _ in range(_MAX_EXTRA):
        noise = rss / max(keep.sum() - 4 * fit.frequency_hz.size - 1, 1)
        peak = _extra_peak(fit.residual, fs, keep, fit.frequency_hz)
        if peak is None:
            break
        trial, trial_rss = _fit(w, fs, keep, np.append(fit.frequency_hz, peak[0]),
                                np.append(fit.decay_rate, peak[1]))
        if rss - trial_rss < MIN_GAIN * noise:
            break
        if trial.damping_ratio[-1] > _TRANSIENT:  # the window starts too early
            return None
        fit, rss = trial, trial_rss
        extra.append(float(trial.frequency_hz[-1]))
    return fit, rss, extra


def _pruned(w, fs, keep, f, sigma):
    """The start components without those the unclipped samples do not need (their removal raises the
    residual's energy by less than :data:`MIN_GAIN` noise variances: peaks of the clipping's harmonics and
    intermodulation products), weakest first, decided with the poles held: linear least squares on the
    unclipped samples, every subset from one Gram matrix. (frequencies, decay rates, dropped frequencies)."""
    t = np.flatnonzero(keep) / fs
    envelope = np.exp(-np.minimum(np.outer(t, sigma), 300.0))
    phase = 2 * np.pi * np.outer(t, f)
    design = np.column_stack([envelope * np.cos(phase), envelope * np.sin(phase), np.ones(t.size)])
    y = w[keep]
    gram, moment, total = design.T @ design, design.T @ y, float(y @ y)
    k = f.size

    def energy(kept):
        cols = np.flatnonzero(np.concatenate([kept, kept, [True]]))
        coef = np.linalg.lstsq(gram[np.ix_(cols, cols)], moment[cols], rcond=None)[0]
        return max(total - float(moment[cols] @ coef), 0.0), coef

    kept = np.ones(k, bool)
    rss, coef = energy(kept)
    for j in np.argsort(np.hypot(coef[:k], coef[k : 2 * k])):
        if kept.sum() == 1:
            break
        trial = kept.copy()
        trial[j] = False
        trial_rss = energy(trial)[0]
        if trial_rss - rss < MIN_GAIN * rss / max(t.size - 4 * kept.sum() - 1, 1):
            kept, rss = trial, trial_rss
    return f[kept], sigma[kept], [float(v) for v in f[~kept]]


def _consistent(arr, model, clipped, start, noise_rms) -> float:
    """Share of the clipped samples that the model puts beyond the limit they were clipped at."""
    centre = np.median(arr[start:])
    top = arr[clipped] >= centre
    beyond = np.where(top, model[clipped - start] >= arr[clipped] - 3 * noise_rms,
                      model[clipped - start] <= arr[clipped] + 3 * noise_rms)
    return float(np.mean(beyond))


def declip(y, fs: float, saturated, start: int, frequency_hz, decay_rate, *,
           prune: bool = False, noise_rms: float | None = None) -> Declipped | None:
    """Repair the clipped samples of a free decay from its unclipped ones (see the module).

    Parameters
    ----------
    y : array-like (n,)
        The record (any offset).
    fs : float
        Sampling rate (Hz).
    saturated : array-like of bool (n,)
        The clipped samples (:func:`~sindy_impulse.preprocessing.quality.saturated_mask`).
    start : int
        First sample of the free decay (end of the hammer contact); clipped samples before it stay.
    frequency_hz, decay_rate : array-like (k,)
        Start values of the modes of the unclipped tail: damped frequencies (Hz), decay rates (1/s).
    prune : bool, default=False
        Drop the start components the unclipped samples do not need (``dropped_hz``): for start values
        taken from the clipped record itself (a sensor that clips to the record's end has no unclipped
        tail), whose peaks include the clipping's harmonics.
    noise_rms : float, optional
        The record's noise (standard deviation; an upper bound will do, e.g. that of its last samples):
        the repair is refused when the fit's residual exceeds :data:`MAX_RESIDUAL` times it.

    Returns
    -------
    Declipped or None
        None when the record is not clipped after ``start`` or the model disagrees with the clipped
        samples.

    Examples
    --------
    A 40 Hz mode holds the sensor at its limit while a 310 Hz mode (damping ratio 2 %) decays:

    >>> t = np.arange(4000) / 2000
    >>> clean = (np.exp(-2 * t) * np.sin(2 * np.pi * 40 * t)
    ...          + 0.3 * np.exp(-39 * t) * np.sin(2 * np.pi * 310 * t))
    >>> y = np.clip(clean + 1e-3 * np.random.default_rng(0).standard_normal(t.size), -0.6, 0.6)
    >>> out = declip(y, 2000.0, np.abs(y) >= 0.6, 0, [40.0], [2.0])
    >>> out.extra_hz.round().tolist(), out.repaired, bool(np.abs(out.y - clean).max() < 0.01)
    ([310.0], 205, True)
    """
    return declip_attempt(y, fs, saturated, start, frequency_hz, decay_rate, prune=prune,
                          noise_rms=noise_rms)[0]


def declip_attempt(y, fs: float, saturated, start: int, frequency_hz, decay_rate, *,
                   prune: bool = False, noise_rms: float | None = None) -> tuple[Declipped | None, str]:
    """:func:`declip` (the same parameters), and why it gave no repair: ``(repair, "repaired")``, or ``(None,
    why)`` with ``why`` one of ``"nothing to repair"``, ``"transient"`` (a component found in the clipped
    stretch decays like the hit still under way), ``"inconsistent"`` (the model does not pass the limits
    where the sensor clipped), ``"misfit"`` (the model holds after the clipping, not while it lasts) and
    ``"unexplained"`` (its residual is far above ``noise_rms``: no start of the window fixes that).

    Examples
    --------
    >>> t = np.arange(4000) / 2000
    >>> noise = 1e-3 * np.random.default_rng(0).standard_normal(t.size)
    >>> y = np.clip(np.exp(-2 * t) * np.sin(2 * np.pi * 40 * t) + noise, -0.6, 0.6)
    >>> out, why = declip_attempt(y, 2000.0, np.abs(y) >= 0.6, 0, [40.0], [2.0], noise_rms=1e-3)
    >>> why, out.repaired
    ('repaired', 207)
    >>> declip_attempt(y, 2000.0, np.abs(y) >= 0.6, 0, [40.0], [2.0], noise_rms=1e-5)[1]  # 100x too low
    'unexplained'
    """
    arr, fs = check_signal_1d(y, "y"), check_fs(fs)
    check_param("start", start, [Interval(Integral, 0, arr.size - 1)], "declip")
    if noise_rms is not None:
        check_param("noise_rms", noise_rms, [Interval(Real, 0, None)], "declip")
    mask = np.asarray(saturated, bool)
    if mask.shape != arr.shape:
        raise ValueError(f"saturated has shape {mask.shape}, y {arr.shape}: one flag per sample")
    clipped = np.flatnonzero(mask[start:]) + start
    f = np.asarray(frequency_hz, float).reshape(-1)
    if clipped.size == 0 or f.size == 0:
        return None, "nothing to repair"
    end = int(clipped[-1]) + 1
    stop = min(arr.size, end + int(_TAIL * (end - start)) + 256)
    w, keep = arr[start:stop], ~mask[start:stop]
    sigma = np.maximum(np.asarray(decay_rate, float).reshape(-1), 1e-3)
    f, sigma, dropped = _pruned(w, fs, keep, f, sigma) if prune else (f, sigma, [])
    fit, rss = _fit(w, fs, keep, f, sigma)
    if prune:  # once more with the refined poles: a harmonic may have stood in for a pole's error
        f, sigma, more = _pruned(w, fs, keep, fit.frequency_hz, fit.decay_rate)
        if more:
            fit, rss = _fit(w, fs, keep, f, sigma)
            dropped += more
    found = _with_extras(w, fs, keep, fit, rss)
    if found is None:
        return None, "transient"
    fit, rss, extra = found
    residual_rms = float(np.sqrt(rss / max(keep.sum() - 4 * fit.frequency_hz.size - 1, 1)))
    consistent = _consistent(arr[:stop], w - fit.residual, clipped, start, residual_rms)
    before, after = fit.residual[: end - start][keep[: end - start]], fit.residual[end - start :]
    misfit = after.size >= 16 and np.std(before) > _MAX_MISFIT * max(np.std(after), 1e-300)
    if consistent < MIN_CONSISTENT:
        return None, "inconsistent"
    if misfit:
        return None, "misfit"
    if noise_rms is not None and residual_rms > MAX_RESIDUAL * noise_rms:
        return None, "unexplained"
    repaired = arr.copy()
    repaired[clipped] = (w - fit.residual)[clipped - start]
    return Declipped(repaired, int(clipped.size), fit.frequency_hz, fit.decay_rate, np.array(extra),
                     consistent, residual_rms, np.array(dropped), fit.amplitude), "repaired"

"""A raw hammer-test record to one band signal per mode, recording every choice (:func:`preprocess`)."""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace
from numbers import Integral, Real

import numpy as np

from .._utils.params import Interval, Options, check_param
from ..exceptions import DataWarning
from ._record import MIN_SAMPLES, as_record
from .band import band_noise_rms, extract_band
from .declipping import declip_attempt
from .offset import OffsetEstimate, estimate_offset, remove_offset
from .onset import Impact, find_impact
from .peaks import SpectralPeaks, no_peaks, spectral_peaks
from .quality import QualityReport, check_quality, saturated_mask
from .saturation import runs as _runs
from .spectrum import ringdown_spectrum

__all__ = ["Preprocessed", "preprocess", "prepare_record", "warn_quality"]

#: Fewest pre-trigger samples whose spectrum gives the noise in each band.
_MIN_NOISE_SAMPLES = 256


@dataclass(frozen=True)
class Preprocessed:
    """What :func:`preprocess` found and did.

    Attributes
    ----------
    y : ndarray
        The record with the offset (and drift) removed.
    fs, t0 : float
        Sampling rate (Hz) and time of the first sample.
    impact : Impact
        Onset, start of the free ring-down, force pulses.
    offset : OffsetEstimate
        The offset removed and how it was estimated.
    peaks : SpectralPeaks
        The spectral peaks and their bands.
    bands : list of BandSignal
        One per band that could be extracted, in the order of ``peaks``.
    skipped : list of (tuple, str)
        Bands that could not be extracted and why.
    quality : QualityReport
        The data-quality checks of the raw record.
    declipped : Declipped or None
        The repair of a clipped record (:func:`~sindy_impulse.preprocessing.declipping.declip`: its
        model's components, those found only while the sensor clipped, and the clipping products
        dropped); None when nothing was repaired (see ``impact.clipping``).
    groups : list of (tuple of int, BandSignal)
        For each group of peaks too close for their damping (``peaks.groups``) that could be extracted:
        the peaks' indices and the signal of their joint band (``peaks.group_band_hz``), which holds
        all of them: identify them together there (their own bands are in ``bands`` too; a joint band
        that cannot be extracted is left out).
    """

    y: np.ndarray = field(repr=False)
    fs: float
    t0: float
    impact: Impact
    offset: OffsetEstimate
    peaks: SpectralPeaks
    bands: list
    skipped: list
    quality: QualityReport
    groups: list = field(default_factory=list)
    declipped: object = None

    def __repr__(self) -> str:
        lines = [
            f"Preprocessed({self.y.size} samples at {self.fs:.6g} Hz from t = {self.t0:.6g} s)",
            f"  {self.impact!r}",
            f"  {self.offset!r}",
            f"  {len(self.peaks)} peak(s), threshold {self.peaks.threshold_db:.1f} dB over the noise floor",
        ]
        for f, h, band in zip(self.peaks.frequency_hz, self.peaks.height_db, self.peaks.band_hz):
            done = [b for b in self.bands if b.band_hz == tuple(band)]
            what = repr(done[0]) if done else "skipped: " + dict(self.skipped).get(tuple(band), "")
            lines.append(f"  {f:.5g} Hz (+{h:.0f} dB): {what}")
        lines += [f"  peaks {', '.join(map(str, g))} together: {b!r}" for g, b in self.groups]
        lines += [f"  problem: {p}" for p in self.quality.problems.values()]
        return "\n".join(lines)


def _impact(y, fs, t0, force, onset) -> Impact:
    if isinstance(onset, str):
        return find_impact(y, fs, force=force, t0=t0)
    if onset >= y.size - 1:
        raise ValueError(f"onset={onset} is beyond the record ({y.size} samples)")
    return Impact(int(onset), t0 + onset / fs, int(onset), t0 + onset / fs, "given", (), fs)


#: The free decay starts after the last clipped sample when at least this share of the ring-down remains.
_MIN_UNCLIPPED = 0.25
#: The record's noise for the repair's check (:func:`~.declipping.declip`): the standard deviation of the
#: last 1 / _NOISE_SHARE of the unclipped tail (an upper bound while the modes still ring there).
_NOISE_SHARE = 5


#: Clipped runs after whose end a repair is tried when the free decay does not fit from the contact's end.
_RETRIES = 3


def _decay_starts(mask: np.ndarray, start: int, end: int) -> list[int]:
    """Where the free decay may start in a clipped record: the contact's end, then the ends of the first
    :data:`_RETRIES` clipped runs after it (a clipped contact hides its own end), up to mid-way to ``end``."""
    runs = [int(last) + 1 for _, last in _runs(mask[start:end])][:_RETRIES]
    return [start] + [start + r for r in runs if start + r < (start + end) / 2]


def _unclipped(y: np.ndarray, fs: float, impact: Impact) -> tuple[np.ndarray, Impact, object]:
    """A record whose sensor saturated after the contact, and its impact, made free of the clipping: the
    clipped samples repaired from the unclipped ones (:func:`~.declipping.declip`, started from the
    spectral peaks of the unclipped tail; from the contact's end, or from the end of one of the first
    clipped runs when the free decay's model does not hold there yet; refused, and no later start tried,
    where the model's residual is far above the noise of the tail's last samples), or else the free
    ring-down started after the last clipped sample. When less than :data:`_MIN_UNCLIPPED` of the
    ring-down is past the last clipped sample (or fewer samples than a spectrum needs), the repair starts
    from the clipped ring-down's own peaks, those the unclipped samples do not need dropped (the clipping's
    harmonics), and without a repair the record stays as it is (its impact says so: ``clipping="kept"``); a
    ring-down too short for a spectrum stays as it is. (record, impact, the repair or None)."""
    mask = saturated_mask(y)
    found = np.flatnonzero(mask[impact.ringdown_index :])
    ring = y.size - impact.ringdown_index
    if not found.size or ring < MIN_SAMPLES:
        return y, impact, None
    end = impact.ringdown_index + int(found[-1]) + 1
    short = y.size - end < max(_MIN_UNCLIPPED * ring, MIN_SAMPLES)
    tail = y[impact.ringdown_index if short else end :]
    peaks = spectral_peaks(tail - np.mean(tail), fs, refine=False)
    noise = None if short else float(np.std(tail[-max(tail.size // _NOISE_SHARE, 16) :]))
    t0 = impact.onset_time - impact.onset_index / impact.fs
    for start in _decay_starts(mask, impact.ringdown_index, end):
        repaired, why = declip_attempt(y, fs, mask, start, peaks.frequency_hz,
                                       np.pi * peaks.half_power_width_hz, prune=short, noise_rms=noise)
        if why == "unexplained":  # a model far from the decay: a later start leaves it as far
            break
        if repaired is not None and np.abs(repaired.y - y).max() <= 3 * repaired.noise_rms:
            return y, impact, None  # the samples at the limits are the signal's own peaks (within the noise)
        if repaired is not None:
            return repaired.y, replace(impact, ringdown_index=start, ringdown_time=t0 + start / fs,
                                       saturated=repaired.repaired, clipping="repaired"), repaired
    if short:  # nothing to start after: the record stays clipped, and says so
        return y, replace(impact, saturated=int(found.size), clipping="kept"), None
    return y, replace(impact, ringdown_index=end, ringdown_time=t0 + end / impact.fs,
                      saturated=int(found.size), clipping="skipped"), None


def _noise_spectrum(y: np.ndarray, impact: Impact, fs: float, peaks: SpectralPeaks):
    """The spectrum whose floor gives the noise in each band: the pre-trigger's (pure noise) when long
    enough, else the peaks' (the floor of the residual of the modes' fit)."""
    if impact.onset_index < _MIN_NOISE_SAMPLES:
        return peaks.spectrum
    return ringdown_spectrum(y[: impact.onset_index], fs)


def _extract(y, fs, t0, impact, band, noise_spectrum, options):
    """The BandSignal of one band, or why it cannot be extracted."""
    noise = band_noise_rms(noise_spectrum, band, method=options["method"])
    try:
        return extract_band(y, fs, band, start=impact.ringdown_index, t0=t0, noise_rms=noise, **options)
    except ValueError as err:
        return str(err)


def _extract_all(y, fs, t0, impact, peaks, noise_spectrum, options) -> tuple[list, list, list]:
    """The band signals, the skipped bands with the reason, and the groups' joint band signals (those
    that cannot be extracted are left out: the group's own bands stay)."""
    bands, skipped = [], []
    for band in peaks.band_hz:
        out = _extract(y, fs, t0, impact, band, noise_spectrum, options)
        if isinstance(out, str):
            skipped.append((tuple(band), out))
            warnings.warn(f"band skipped: {out}", DataWarning, stacklevel=3)
        else:
            bands.append(out)
    joint = [(g, _extract(y, fs, t0, impact, b, noise_spectrum, options))
             for g, b in zip(peaks.groups, peaks.group_band_hz)]
    return bands, skipped, [(g, out) for g, out in joint if not isinstance(out, str)]


def preprocess(y, t=None, *, fs: float | None = None, force=None, n_modes: int | None = None, bands=None,
               onset="auto", offset="auto", samples_per_period: float = 16.0,
               min_samples_per_period: float = 8.0, method: str = "fft", end_snr_db: float | None = 10.0,
               threshold_db: float | None = None, quality_warnings: bool = True) -> Preprocessed:
    """Prepare a raw hammer-test record for per-mode identification.

    Impact (onset, end of contact, double hits; a sensor that saturated: its clipped samples repaired from the
    unclipped ones, or else the free ring-down started after the last clipped sample) -> offset removal ->
    spectral peaks and bands of the free ring-down -> per band: zero-phase band-pass, transient trim, end
    at the noise floor, decimation. The noise in each band comes from the pre-trigger's spectrum when it
    has at least 256 samples, else from the noise floor of the peaks' spectrum. Peaks too close for their
    damping are also extracted together, in their joint band (``groups``). Every automatic choice can be
    overridden.

    Parameters
    ----------
    y : array-like (n,)
        The raw response (any offset).
    t : array-like (n,) or float, optional
        Time vector (uniform) or step; or give ``fs``.
    fs : float, optional
        Sampling rate (Hz).
    force : array-like (n,), optional
        The force channel: onset and end of contact from it, double hits reported.
    n_modes : int, optional
        Keep the strongest ``n_modes`` peaks.
    bands : sequence of (low, high), optional
        The bands (Hz), instead of the detected ones.
    onset : "auto" or int
        First sample of the hit (then also the start of the ring-down, clipped or not). With "auto" the
        ring-down starts after the contact, clipped samples repaired (see ``impact.clipping``).
    offset : "auto", "pre_trigger", "tail", "linear" or float
        See :func:`~sindy_impulse.preprocessing.offset.estimate_offset`.
    samples_per_period, min_samples_per_period, method, end_snr_db
        See :func:`~sindy_impulse.preprocessing.band.extract_band`.
    threshold_db : float, optional
        Peak detection threshold (see :func:`~sindy_impulse.preprocessing.peaks.spectral_peaks`).
    quality_warnings : bool
        Warn (:class:`~sindy_impulse.exceptions.DataWarning`) for each quality problem found but the
        offset (which is removed).

    Returns
    -------
    Preprocessed

    Examples
    --------
    >>> t = np.arange(15000) / 5000
    >>> ring = sum(np.exp(-2 * np.pi * 0.004 * f * (t - 0.2)) * np.sin(2 * np.pi * f * (t - 0.2) + 1)
    ...            for f in (120.0, 410.0))
    >>> y = 0.3 + np.where(t >= 0.2, ring, 0.0) + 1e-3 * np.random.default_rng(0).standard_normal(t.size)
    >>> pre = preprocess(y, fs=5000.0)
    >>> pre.impact.onset_index, pre.offset.method, pre.peaks.frequency_hz.round(1).tolist()
    (1000, 'pre_trigger', [120.0, 410.0])
    >>> [(b.decimation, round(b.samples_per_period, 1)) for b in pre.bands]
    [(2, 20.8), (1, 12.2)]
    """
    check_param("quality_warnings", quality_warnings, ["boolean"], "preprocess")
    check_param("threshold_db", threshold_db, [None, Real], "preprocess")
    pre, raw = prepare_record(y, t, fs=fs, force=force, onset=onset, offset=offset)
    clean, rate, t0, impact = pre.y, pre.fs, pre.t0, pre.impact
    ring = clean[impact.ringdown_index :]
    peaks = spectral_peaks(ring, rate, n_modes=n_modes, bands=bands, threshold_db=threshold_db)
    quality = check_quality(raw, rate, onset_index=impact.onset_index, peaks=peaks)
    if quality_warnings:
        warn_quality(quality)
    options = dict(samples_per_period=samples_per_period, min_samples_per_period=min_samples_per_period,
                   method=method, end_snr_db=end_snr_db)
    noise = _noise_spectrum(clean, impact, rate, peaks)
    extracted, skipped, groups = _extract_all(clean, rate, t0, impact, peaks, noise, options)
    return replace(pre, peaks=peaks, bands=extracted, skipped=skipped, quality=quality, groups=groups)


def warn_quality(quality: QualityReport, stacklevel: int = 3) -> None:
    """One :class:`~sindy_impulse.exceptions.DataWarning` per quality problem but the offset (which the
    preparation removes)."""
    for check, problem in quality.problems.items():
        if check != "offset":
            warnings.warn(problem, DataWarning, stacklevel=stacklevel)


def prepare_record(y, t=None, *, fs: float | None = None, force=None, onset="auto", offset="auto"
                   ) -> tuple[Preprocessed, np.ndarray]:
    """The record-level steps of :func:`preprocess`: the impact (onset, end of contact, double hits), a
    saturated sensor's clipped samples repaired (or the free ring-down started after them), the offset
    removed. Returns the :class:`Preprocessed` record without peaks and bands (``peaks`` empty,
    ``quality`` None) and the raw record as an array.

    Examples
    --------
    >>> t = np.arange(5000) / 5000
    >>> y = 0.3 + np.where(t >= 0.1, np.exp(-3 * (t - 0.1)) * np.sin(2 * np.pi * 120 * (t - 0.1)), 0.0)
    >>> pre, raw = prepare_record(y + 1e-4 * np.random.default_rng(0).standard_normal(t.size), fs=5000.0)
    >>> pre.impact.onset_index, round(pre.offset.value, 3), len(pre.peaks)
    (501, 0.3, 0)
    """
    arr, rate, t0 = as_record(y, t, fs)
    check_param("onset", onset, [Options({"auto"}), Interval(Integral, 0, None)], "preprocess")
    impact = _impact(arr, rate, t0, force, onset)
    raw, declipped = arr, None
    if isinstance(onset, str):
        arr, impact, declipped = _unclipped(arr, rate, impact)
    estimate = estimate_offset(arr, rate, onset_index=impact.onset_index, method=offset)
    clean = remove_offset(arr, rate, estimate)
    return Preprocessed(clean, rate, t0, impact, estimate, no_peaks(rate), [], [], None, [], declipped), raw

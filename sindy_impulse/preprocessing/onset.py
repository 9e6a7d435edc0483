"""Impact onset, end of hammer contact and double hits, from the response or from the force channel.

The pre-trigger noise band is ``median +- n_sigma * sigma`` of the quiet stretch before the hit, with
``sigma = 1.4826 * MAD`` (robust to an offset, to hum and to a few spikes). The onset is the first sample
leaving that band and followed by another within 16 samples (a lone spike is skipped), walked back to the
last sample inside ``+- 2 sigma`` (the start of the rise). A record whose first samples are already as
loud as the hit has no pre-trigger: its onset is 0.

Force pulses are the stretches where the force (sign taken from its largest excursion) exceeds
``max(n_sigma * sigma, level * peak)``; their edges are walked out to ``max(2 sigma, 1e-3 * peak)``.
Every pulse after the first is a double hit; the free ring-down starts after the last contact. Without a
force channel the end of the contact is found in the response (:func:`~.contact.contact_end`).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from numbers import Real

import numpy as np

from .._utils.params import Interval, check_param
from .._utils.robust import robust_std
from ..exceptions import DataWarning
from ._record import MIN_SAMPLES, check_fs, check_signal_1d
from .contact import contact_end
from .saturation import runs as _runs

__all__ = ["ForcePulse", "Impact", "response_onset", "force_pulses", "find_impact"]

_N_SIGMA = [Interval(Real, 1, None, "left")]
_LEVEL = [Interval(Real, 0, 1, "neither")]
#: A quiet stretch shorter than this (samples) is not a pre-trigger.
_MIN_PRE = 16


def _noise_band(x: np.ndarray) -> tuple[float, float]:
    """Centre (median) and robust standard deviation (1.4826 MAD) of a stretch."""
    centre = float(np.median(x))
    return centre, robust_std(x, centre=centre)


def _first_sustained(exceeds: np.ndarray) -> int:
    """First exceedance followed by another within ``_MIN_PRE`` samples (a lone spike is not a hit)."""
    count = np.cumsum(exceeds)
    ahead = count[np.minimum(np.arange(exceeds.size) + _MIN_PRE, exceeds.size - 1)] - count
    return int(np.argmax(exceeds & (ahead > 0)))


def _quiet_stretch(dev: np.ndarray, n_sigma: float) -> tuple[int, float, float] | None:
    """First exceedance after the quiet stretch before the largest excursion of ``dev``, the stretch's
    centre and noise sigma; None without a quiet stretch.

    Starts from the first half before the peak and shrinks to the samples before the first exceedance
    until stable, so a response that began well before its peak does not inflate the noise estimate.
    """
    magnitude = np.abs(dev)
    peak = int(np.argmax(magnitude))
    while peak + 1 < dev.size and magnitude[peak + 1] == magnitude[peak]:  # a clipped peak: its run's end
        peak += 1
    end = peak // 2
    for _ in range(4):
        if end < _MIN_PRE:
            return None
        centre, sigma = _noise_band(dev[:end])
        sigma = max(sigma, 1e-12 * abs(dev[peak]))
        if n_sigma * sigma >= 0.5 * abs(dev[peak] - centre):
            return None  # the "pre-trigger" is as loud as the hit: there is none
        first = _first_sustained(np.abs(dev - centre) > n_sigma * sigma)
        if first >= end - 1:
            return first, centre, sigma
        end = max(first - 2, 0)
    return None


def response_onset(y, *, n_sigma: float = 6.0) -> int:
    """Index of the first sample where the response leaves the pre-trigger noise band.

    Parameters
    ----------
    y : array-like (n,)
        The response (any offset).
    n_sigma : float
        Half-width of the noise band in robust standard deviations. 6 gives about one false exceedance in
        1e9 Gaussian samples.

    Returns
    -------
    int
        The onset index (0 when the record has no pre-trigger).

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> t = np.arange(3000) / 5000
    >>> y = 2.0 + 1e-3 * rng.standard_normal(3000)
    >>> y[1000:] += np.exp(-5 * t[:2000]) * np.sin(2 * np.pi * 120 * t[:2000] + 1)
    >>> response_onset(y)
    1000
    >>> response_onset(y[1000:])  # no pre-trigger
    0
    """
    arr = check_signal_1d(y, "y")
    check_param("n_sigma", n_sigma, _N_SIGMA, "response_onset")
    dev = arr - np.median(arr)
    found = _quiet_stretch(dev, n_sigma)
    if found is None:
        return 0
    first, centre, sigma = found
    inside = np.flatnonzero(np.abs(dev[: first + 1] - centre) <= 2.0 * sigma)
    return int(inside[-1]) + 1 if inside.size else 0


@dataclass(frozen=True)
class ForcePulse:
    """One hammer contact: sample indices of its start, peak and end, and its peak over the largest."""

    start: int
    peak: int
    end: int
    relative_amplitude: float


def force_pulses(force, *, level: float = 0.05, n_sigma: float = 6.0) -> list[ForcePulse]:
    """The hammer contacts in a force record: stretches above ``max(n_sigma sigma, level * peak)``.

    Runs closer than half the first contact's duration are one contact (noise at the threshold).

    Parameters
    ----------
    force : array-like (n,)
        The force channel (any offset and sign).
    level : float in (0, 1)
        Threshold as a fraction of the largest force excursion.
    n_sigma : float
        Threshold in robust standard deviations of the pre-trigger force noise.

    Returns
    -------
    list of ForcePulse
        In time order; more than one means a double hit.

    Examples
    --------
    >>> f = np.zeros(400)
    >>> f[100:111] = np.sin(np.pi * np.arange(11) / 10)        # the hit
    >>> f[200:211] = 0.3 * np.sin(np.pi * np.arange(11) / 10)  # a bounce
    >>> [(p.start, p.end, round(p.relative_amplitude, 2)) for p in force_pulses(f)]
    [(101, 109, 1.0), (201, 209, 0.3)]
    """
    arr = check_signal_1d(force, "force")
    check_param("level", level, _LEVEL, "force_pulses")
    check_param("n_sigma", n_sigma, _N_SIGMA, "force_pulses")
    dev = arr - np.median(arr)
    found = _quiet_stretch(dev, n_sigma)
    centre, sigma = (0.0, 0.0) if found is None else found[1:]
    dev = dev - centre
    dev = dev * np.sign(dev[np.argmax(np.abs(dev))])
    peak = float(dev.max())
    runs = _runs(dev > max(n_sigma * sigma, level * peak))
    merged = [list(runs[0])]
    for first, last in runs[1:]:
        if first - merged[-1][1] <= max(2, (runs[0][1] - runs[0][0] + 1) // 2):
            merged[-1][1] = last
        else:
            merged.append([first, last])
    edge = max(2.0 * sigma, 1e-3 * peak)
    pulses = []
    for first, last in merged:
        while first > 0 and dev[first - 1] > edge:
            first -= 1
        while last < arr.size - 1 and dev[last + 1] > edge:
            last += 1
        top = first + int(np.argmax(dev[first : last + 1]))
        pulses.append(ForcePulse(int(first), int(top), int(last), float(dev[top] / peak)))
    return pulses


@dataclass(frozen=True)
class Impact:
    """Where the hit is in a record.

    Attributes
    ----------
    onset_index, onset_time : int, float
        First sample of the hit (of the first contact when there is a force channel).
    ringdown_index, ringdown_time : int, float
        First sample of the free decay: after the last contact (from the force channel, else from the
        response by :func:`~sindy_impulse.preprocessing.contact.contact_end`).
    source : str
        ``"force"``, ``"response"``, ``"no pre-trigger"`` or ``"given"``.
    pulses : tuple of ForcePulse
        The contacts found in the force channel (empty without one).
    fs : float
        Sampling rate (Hz) of the record.
    saturated : int
        Clipped samples after the contact (the sensor saturated; :func:`~sindy_impulse.preprocessing.
        preprocess`).
    clipping : str
        What was done with them: ``"repaired"`` (replaced by the modes fitted to the unclipped samples),
        ``"skipped"`` (the free ring-down starts after the last one) or ``"kept"`` (neither could be done:
        too few unclipped samples follow them and no repair fits; the free decay stays clipped); empty when
        none.
    """

    onset_index: int
    onset_time: float
    ringdown_index: int
    ringdown_time: float
    source: str
    pulses: tuple = ()
    fs: float = float("nan")
    saturated: int = 0
    clipping: str = ""

    @property
    def double_hit(self) -> bool:
        """More than one contact in the force channel."""
        return len(self.pulses) > 1

    @property
    def hits(self) -> list[tuple[float, float]]:
        """``(start time, amplitude relative to the largest)`` of every contact."""
        t0 = self.onset_time - self.onset_index / self.fs
        return [(t0 + p.start / self.fs, p.relative_amplitude) for p in self.pulses]

    def __repr__(self) -> str:
        hits = ""
        if self.double_hit:
            hits = ", double hit: " + ", ".join(f"{p.relative_amplitude:.2f}" for p in self.pulses[1:])
        clipped = f", {self.saturated} clipped samples {self.clipping}" if self.saturated else ""
        return (
            f"Impact(onset {self.onset_index} at {self.onset_time:.6g} s from the {self.source}, "
            f"ring-down from {self.ringdown_index} at {self.ringdown_time:.6g} s{clipped}{hits})"
        )


def find_impact(y, fs: float, *, force=None, t0: float = 0.0, n_sigma: float = 6.0, level: float = 0.05):
    """Onset of the hit and start of the free ring-down, from the force channel when given.

    A double hit (a second contact) is reported with a :class:`~sindy_impulse.exceptions.DataWarning`.

    Parameters
    ----------
    y : array-like (n,)
        The response.
    fs : float
        Sampling rate (Hz).
    force : array-like (n,), optional
        The force channel, sampled with ``y``.
    t0 : float
        Time of the first sample.
    n_sigma, level : float
        See :func:`response_onset` and :func:`force_pulses`.

    Returns
    -------
    Impact

    Examples
    --------
    >>> f = np.zeros(1000); f[300:311] = np.sin(np.pi * np.arange(11) / 10)
    >>> y = np.zeros(1000); y[301:] = np.sin(np.arange(699) / 4) * np.exp(-np.arange(699) / 300)
    >>> find_impact(y, 1000.0, force=f)
    Impact(onset 301 at 0.301 s from the force, ring-down from 310 at 0.31 s)
    """
    rate = check_fs(fs)
    arr = check_signal_1d(y, "y")
    if force is None:
        onset = response_onset(arr, n_sigma=n_sigma)
        source = "response" if onset > 0 else "no pre-trigger"
        free = onset + (contact_end(arr[onset:]) if arr.size - onset >= MIN_SAMPLES else 0)
        return Impact(onset, t0 + onset / rate, free, t0 + free / rate, source, (), rate)
    if np.shape(force)[:1] != arr.shape:
        raise ValueError(f"force has shape {np.shape(force)}, y has {arr.size} samples; record them together")
    pulses = force_pulses(force, level=level, n_sigma=n_sigma)
    onset, end = pulses[0].start, pulses[-1].end + 1
    if len(pulses) > 1:
        hits = ", ".join(
            f"{t0 + p.start / rate:.6g} s ({p.relative_amplitude:.0%} of the largest)" for p in pulses[1:]
        )
        warnings.warn(
            f"double hit: {len(pulses) - 1} more contact(s) after the first, at {hits}; the ring-down "
            "starts after the last one. Repeat the hit or check that the bands still decay freely",
            DataWarning,
            stacklevel=2,
        )
    return Impact(onset, t0 + onset / rate, end, t0 + end / rate, "force", tuple(pulses), rate)

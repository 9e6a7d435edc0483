"""A mode's own signal: the record with every other component of the decay fit removed, in the mode's band.

The decay fit (:mod:`sindy_impulse.poles.decay_fit`) gives every candidate's damped sinusoid from the free
decay's first sample on. A mode's own signal is the record less all the others (:func:`deflated`): its
neighbours' skirts and the filter transient they would cause are gone, so its band can be wide and the
band-pass transient short. Its band (:func:`mode_bands`) is cut among the modes alone (tones, harmonics and
merged pieces are removed or belong to their mode): a linear mode's among all modes, a nonlinear mode's
among the nonlinear ones only (its linear neighbours are removed exactly, its nonlinear ones are not) and
never up to its second harmonic's sweep: its top stays under twice its lowest piece's frequency by the
harmonic window (:data:`~sindy_impulse.preprocessing.partition.HARMONIC_NEAR`; its harmonics are not
removed, and three broad pieces of a quadratic spring's 672 Hz mode had spread its band over its own 1316
Hz harmonic, and its equation, fitted to both, was 1.2 % off).
Where even that band keeps too few periods (a short, strongly damped record), the mode's free decay is used
without band-pass (:func:`free_decay`).
"""

from __future__ import annotations

import numpy as np

from ..preprocessing.band import band_noise_rms, extract_band
from ..preprocessing.filters import bandpass, transient_samples
from ..preprocessing.partition import HARMONIC_NEAR, peak_bands
from .kinds import Kind

__all__ = ["component", "deflated", "analytic", "band_signal", "free_decay", "mode_bands", "END_SNR_DB",
           "MIN_PERIODS"]

#: The free decay of a mode without band-pass ends where its envelope falls to this many dB over the noise,
#: as a band signal ends at the noise floor; at least :data:`MIN_PERIODS` of its periods are kept.
END_SNR_DB, MIN_PERIODS = 10.0, 2.0
#: ... and at least this many samples (a smoothing window's worth).
MIN_SAMPLES = 24
_MODES = (Kind.LINEAR, Kind.NONLINEAR)


def component(cand, n: int, fs: float, t: np.ndarray | None = None) -> np.ndarray:
    """A candidate's damped sinusoid over ``n`` samples of the free decay (reference channel); ``t``:
    their times ``arange(n) / fs`` when already computed.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> c = SimpleNamespace(decay_rate=1.0, damped_frequency_hz=10.0, amplitude=np.array([2.0 + 0j]))
    >>> component(c, 3, 100.0).round(3).tolist()
    [2.0, 1.602, 0.606]
    """
    t = np.arange(n) / fs if t is None else t
    s = -cand.decay_rate + 2j * np.pi * cand.damped_frequency_hz
    return np.real(cand.amplitude[0] * np.exp(s * t))


def _members(state, k: int) -> list:
    """Candidate ``k`` and the pieces merged into it."""
    return [j for j, c in enumerate(state.candidates) if j == k or (c.kind is Kind.MERGED and c.parent == k)]


def deflated(state, k: int, keep=()) -> np.ndarray:
    """The prepared record with every candidate but ``k`` (and its merged pieces) removed from the free
    decay on, and the hidden components under the detection threshold (``state.hidden``); once per set of
    members (:func:`_kept`: read-only). ``keep``: other candidates left in it with their merged pieces (the
    pieces of one chirping signal)."""
    members = [m for j in (k, *keep) for m in _members(state, j)]
    return _kept(state, "_deflated", frozenset(members), lambda: _deflate(state, members))


def _deflate(state, members: list) -> np.ndarray:
    pre, start = state.pre, state.start
    n = pre.y.size - start
    if "_all_components" not in state.cache:
        t = np.arange(n) / pre.fs
        parts = [component(c, n, pre.fs, t) for c in state.candidates]
        every = parts + [component(c, n, pre.fs, t) for c in state.hidden]
        state.cache["_all_components"] = parts, (np.sum(every, axis=0) if every else np.zeros(n))
    parts, total = state.cache["_all_components"]
    out = pre.y.copy()
    out[start:] -= total - sum((parts[j] for j in set(members)), np.zeros(n))
    return out


#: Most bytes of signals a record's survey keeps for reuse (:func:`_kept`): its candidates' own signals and
#: their analytic band-passes, each computed once while they fit.
CACHE_BYTES = 64 * 2**20


def _kept(state, kind: str, key, compute) -> np.ndarray:
    """``compute()``, kept in ``state.cache[kind][key]`` (read-only) while the signals kept stay within
    :data:`CACHE_BYTES`: the stages ask for the same candidate's signal, or the same band of it, several
    times (the classification's tests, then the mode's identification)."""
    store = state.cache.setdefault(kind, {})
    if key in store:
        return store[key]
    value = compute()
    used = state.cache.get("_kept_bytes", 0)
    if used + value.nbytes <= CACHE_BYTES:
        value.flags.writeable = False
        store[key] = value
        state.cache["_kept_bytes"] = used + value.nbytes
    return value


def _own_analytic(state, k: int, band_hz) -> np.ndarray:
    """Candidate ``k``'s own signal (:func:`deflated`) from the decay's start as an analytic signal in
    ``band_hz`` (zero-phase FFT band-pass, untrimmed); once per set of members and band."""
    band = tuple(float(b) for b in band_hz)
    key = (frozenset(_members(state, k)), band)
    return _kept(state, "_analytic", key,
                 lambda: bandpass(deflated(state, k)[state.start:], state.pre.fs, band, analytic=True))


def _noise_spectrum(state):
    """The spectrum whose floor gives the noise in a band (the pre-trigger's when long enough, else the
    decay fit's floor), once per record."""
    from ..preprocessing.pipeline import _noise_spectrum as spectrum

    if "_noise_spectrum" not in state.cache:
        pre = state.pre
        state.cache["_noise_spectrum"] = spectrum(pre.y, pre.impact, pre.fs, pre.peaks)
    return state.cache["_noise_spectrum"]


def band_signal(state, k: int, max_periods):
    """Candidate ``k``'s own signal (:func:`deflated`) in its band, band-passed from the decay's start
    (:func:`~sindy_impulse.preprocessing.extract_band`; the noise from the pre-trigger's or the spectrum's
    floor), its first ``max_periods`` periods; a ValueError when the band cannot keep enough."""
    pre, band_hz = state.pre, state.candidates[k].band_hz
    noise = band_noise_rms(_noise_spectrum(state), band_hz)
    y = deflated(state, k)
    z = _own_analytic(state, k, band_hz) if 0 < band_hz[0] < band_hz[1] < pre.fs / 2 else None
    return extract_band(y, pre.fs, band_hz, start=state.start, t0=pre.t0,
                        samples_per_period=state.options.samples_per_period, noise_rms=noise,
                        max_periods=max_periods, analytic_signal=z)


def analytic(state, k: int, band_hz) -> tuple[np.ndarray, int]:
    """Candidate ``k``'s own signal (:func:`deflated`) from the decay's start as an analytic signal in
    ``band_hz`` (zero-phase FFT band-pass), the filter's transient trimmed at both ends: ``(z, first)``,
    ``first`` the sample of the free decay ``z`` starts at."""
    pre, start = state.pre, state.start
    size = pre.y.size - start
    trim = transient_samples(pre.fs, band_hz)
    if size <= 2 * trim + 16:
        return np.empty(0, complex), trim
    return _own_analytic(state, k, band_hz)[trim: size - trim], trim


def free_decay(state, k: int) -> tuple[np.ndarray, np.ndarray]:
    """Candidate ``k``'s free decay without band-pass (:func:`deflated`), up to where its envelope falls to
    :data:`END_SNR_DB` over the noise (at least :data:`MIN_PERIODS` periods): ``(y, t)``."""
    pre, start, cand = state.pre, state.start, state.candidates[k]
    y = deflated(state, k)[start:]
    stop = y.size
    amplitude = float(np.abs(cand.amplitude[0]))
    if cand.noise_std > 0 and amplitude > 0 and cand.decay_rate > 0:
        floor = cand.noise_std * 10 ** (END_SNR_DB / 20)
        seconds = np.log(max(amplitude / floor, 1.0)) / cand.decay_rate
        least = max(MIN_PERIODS * pre.fs / cand.frequency_hz, MIN_SAMPLES)
        stop = int(min(y.size, max(least, seconds * pre.fs)))
    return y[:stop], pre.t0 + (start + np.arange(stop)) / pre.fs


def mode_bands(state) -> None:
    """Each mode's band (``band_hz`` of the linear and nonlinear candidates and their merged pieces): cut
    among all modes for a linear one, among the nonlinear ones for a nonlinear one (see the module); a
    mode's half-power width spans its merged pieces."""
    cands = state.candidates
    heads = [k for k, c in enumerate(cands) if c.kind in _MODES]
    if not heads:
        return
    f = np.array([cands[k].damped_frequency_hz for k in heads])
    width = np.array([_width(state, k) for k in heads])
    every = peak_bands(f, width, state.pre.fs)
    nonlinear = [i for i, k in enumerate(heads) if cands[k].kind is Kind.NONLINEAR]
    wide = peak_bands(f[nonlinear], width[nonlinear], state.pre.fs) if nonlinear else []
    for i, k in enumerate(heads):
        cands[k].band_hz = tuple(float(b) for b in every[i])
    for i, band in zip(nonlinear, wide):
        lowest = min(cands[j].damped_frequency_hz for j in _members(state, heads[i]))
        top = 2 * (1 - HARMONIC_NEAR) * lowest  # (a nonlinear mode's band never holds its harmonic's sweep)
        cands[heads[i]].band_hz = (float(band[0]), float(min(band[1], top)))
    for c in cands:
        if c.kind is Kind.MERGED:
            c.band_hz = cands[c.parent].band_hz


def _width(state, k: int) -> float:
    """Half-power width (Hz) of candidate ``k`` widened to span its merged pieces."""
    cands = state.candidates
    own = cands[k].decay_rate / np.pi
    f = [cands[j].damped_frequency_hz for j in _members(state, k)]
    return float(max(own, max(f) - min(f) + own))

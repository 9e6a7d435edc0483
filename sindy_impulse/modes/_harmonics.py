"""Harmonics decided from the data: is a mode near 2 or 3 times another that mode's harmonic, or a mode?

A harmonic made by a term of power ``p`` of a mode (``x^2``: p = 2 at 2 f; ``x^3`` or ``x^2 x'``: p = 3 at 3
f; a ``|x'| x'`` damper: p = 2 at 3 f) is **phase-locked** to its mode: its instantaneous phase is exactly
``n`` times the mode's at every instant, so their instantaneous frequency ratio is ``n`` even while the mode's
frequency follows its backbone; and its **amplitude goes as the mode's amplitude to the power p** (``p >=
2``), so its envelope decays ``p`` times as fast. A true mode near ``n f`` (a 1:2 internal-resonance rig, a
beam's second mode 0.56 % below twice the first) keeps its own frequency: the phase ``phi_2 - n phi_1`` drifts
at ``2 pi (f_2 - n f_1)``. (With equal damping ratios such a mode's envelope also decays about ``n`` times as
fast as its parent's: only the phase tells them apart.)

:func:`harmonic_evidence` measures both: each mode's analytic signal in its own band (zero-phase FFT band-
pass, :func:`~sindy_impulse.preprocessing.filters.bandpass`), over the stretch after both filters' transients
where both envelopes stand :data:`MIN_SNR_DB` over their band's noise; the frequency ratio ``n + (d/dt (phi_2
- n phi_1)) / (2 pi f_1)`` from a weighted straight-line fit of the phase difference, its standard error from
the residual with one independent sample per ``1 / bandwidth``; the exponent ``p`` from a straight-line fit of
``log a_2`` against ``log a_1`` weighted as the phases (each envelope less the noise's power). A candidate is
a harmonic (:func:`_evidence`, which the survey's classification calls on each candidate's own signal) when it
is locked (over the whole stretch and over each of its :data:`_SEGMENTS` pieces the ratio within
:data:`SIGMAS` standard errors of ``n`` -- a Student-t quantile for pieces of few independent samples -- or
within :data:`RATIO_TOL`, for a parent that moves only, and only where its movement over the stretch explains
the offset or an amplitude exponent is a whole power, :func:`_loosely_locked`; resolved: the whole stretch's
relative standard error at most :data:`RESOLVED`) and whose exponent is at least :data:`MIN_EXPONENT` and at
most ``n + 0.5`` (a term of power at most ``n`` makes harmonic ``n``), the numbers kept as evidence. When the
record cannot resolve the locking (a harmonic a few dB over the noise, or seen only just after the hit) and
the parent is a nonlinear mode, the candidate is its harmonic when it lies at ``n`` times a frequency of the
parent's fitted backbone (:func:`_on_backbone`; ``by_backbone`` in the evidence), unless its measured ratio
lies outside the window a harmonic is looked for in, beyond its standard errors (:func:`_contradicted`: the
data then say no, and no backbone overrules them). So is a candidate whose resolved test names nothing while
its parent's frequency moves and its ratio strays from ``n`` no farther than that movement explains
(:func:`_strays_with_sweep`): a piece of the harmonic's sweep, whose band-passed envelope and phase are the
piece's, not the harmonic's. Harmonics of a nonlinear mode too weak to be candidates are named where a
spectral peak stands phase-locked at their place (:func:`_unseen_harmonics`).
"""

from __future__ import annotations

import warnings
from types import SimpleNamespace

import numpy as np
from scipy.special import ndtr as normal_cdf
from scipy.special import stdtrit

from .._utils.validation import check_signal
from ..preprocessing._record import check_fs
from ..preprocessing.band import band_noise_rms
from ..preprocessing.filters import bandpass, transient_samples
from ..preprocessing.partition import HARMONIC_NEAR, peak_bands
from .result import Rejected

__all__ = ["harmonic_evidence", "product_evidence", "SIGMAS", "RATIO_TOL", "RESOLVED", "MIN_EXPONENT",
           "MIN_SNR_DB"]

#: Harmonic orders tested.
ORDERS = (2, 3)
#: A mode is tested as harmonic ``n`` of another when its frequency is within this relative distance of
#: ``n`` times the other's (a nonlinear mode's frequency moves with amplitude; its harmonic is strongest
#: where the amplitude is largest). The distance at which the peak steps leave a peak whole for this test.
NEAR = HARMONIC_NEAR
#: Envelopes used down to this height over their band's noise (dB).
MIN_SNR_DB = 10.0
#: A locked pair's frequency ratio lies within this many standard errors of ``n`` ...
SIGMAS = 3.0
#: ... or within this relative distance of it (half the smallest offset of a true mode the study draws:
#: 0.5 %; a beam's second mode sat 0.56 % off twice its first) ...
RATIO_TOL = 2.5e-3
#: ... and the whole stretch's ratio has a relative standard error at most this (else nothing is decided).
RESOLVED = 1e-3
#: Smallest amplitude exponent of a harmonic (``a_2 ~ a_1^p``; a term of power 2 or 3 gives p = 2 or 3).
MIN_EXPONENT = 1.5
#: A harmonic of order n comes from a term of power at most n (``x^2`` at 2 f; ``x^3``, ``x^2 x'``,
#: ``|x'| x'`` at 3 f): an exponent above ``n`` by more than this is a mode that decays faster (two linear
#: modes at exactly 120 and 240 Hz with damping ratios 0.5 and 1 % are locked, with p = 4).
_EXPONENT_MARGIN = 0.5
#: ... and the exponent lies within this of a whole power ``k`` with ``2 <= k <= n`` (a term of power k makes
#: its harmonic's amplitude go as the mode's to the power k): two linear modes at exactly 2400 and 4800 Hz
#: with damping ratios 0.5 and 0.6 % are locked with p = 2.4, and are two modes. Measured harmonics: 1.90
#: (quadratic spring, 2 f), 2.81-2.85 (cubic spring, 3 f).
_EXPONENT_TOL = 0.3
#: The filters' transients are trimmed down to this share of their peak (not 1e-3 as for the bands: a
#: harmonic decays p times as fast as its mode and its largest amplitudes would be lost with them).
_TRANSIENT_TOL = 1e-2
#: The stretch is cut into this many pieces, each locked too (a chirping parent crossing ``f_2 / n``
#: halfway would give ``n`` on average).
_SEGMENTS = 4
#: Fewest periods of the candidate in the stretch measured.
_MIN_PERIODS = 5.0


def _line(x: np.ndarray, y: np.ndarray, w: np.ndarray) -> tuple[float, float, np.ndarray]:
    """Weighted straight line ``y = a + b x``: (a, b, residual)."""
    xm, ym = np.average(x, weights=w), np.average(y, weights=w)
    b = float(np.sum(w * (x - xm) * (y - ym)) / np.sum(w * (x - xm) ** 2))
    a = float(ym - b * xm)
    return a, b, y - a - b * x


def _ratio(t, psi, w, n_eff: float, order: int, f1: float) -> tuple[float, float, float]:
    """Frequency ratio ``n + (d psi / dt) / (2 pi f1)`` from a line through the phase difference ``psi``,
    its standard error (``n_eff`` independent samples) and the slope (rad/s)."""
    _, slope, res = _line(t, psi, w)
    spread = np.average((t - np.average(t, weights=w)) ** 2, weights=w)
    sigma = float(np.sqrt(np.average(res**2, weights=w) / spread / max(n_eff, 2.0)))
    return order + slope / (2 * np.pi * f1), sigma / (2 * np.pi * f1), slope


def _kept(a1: np.ndarray, a2: np.ndarray, floor1: float, floor2: float, trim: int) -> np.ndarray:
    """Samples after the filters' transients (and before the end's) where both envelopes stand over their
    floors."""
    keep = np.zeros(a1.size, bool)
    keep[trim : a1.size - trim] = True
    return np.flatnonzero(keep & (a1 >= floor1) & (a2 >= floor2))


def harmonic_evidence(y, fs: float, parent_band, candidate_band, order: int, noise_rms=(0.0, 0.0)) -> dict:
    """Phase locking and amplitude exponent of a candidate harmonic against its parent (see the module).

    Parameters
    ----------
    y : ndarray (n,) or (ndarray, ndarray)
        The free decay (offset removed); or the parent's and the candidate's own signals (each with the
        other components removed), on the same samples.
    fs : float
        Sampling rate (Hz).
    parent_band, candidate_band : (float, float)
        Each one's own band (Hz).
    order : int
        ``n``: the candidate is tested at ``n`` times the parent's frequency.
    noise_rms : (float, float)
        Noise standard deviation in each band: the envelopes are used down to :data:`MIN_SNR_DB` over it.

    Returns
    -------
    dict
        ``order``, ``frequency_ratio`` and its standard error ``ratio_sigma``, ``phase_drift_rad`` (of
        ``phi_2 - n phi_1`` over the stretch), ``exponent`` (``p``) and ``exponent_sigma``, ``periods``
        (of the candidate, measured), ``locked``, ``locked_within_errors`` and ``harmonic`` (bool),
        ``parent_sweep`` (the parent's relative frequency change over the stretch's pieces) and
        ``locking_proven`` (locked while that change would have moved a mode of its own off ``n`` by more
        than twice :data:`SIGMAS` standard errors plus the spread of the pieces' ratios, where they are not
        all within their errors of ``n``: a harmonic's ratio stays put while its mode sweeps, a mode's
        moves with the sweep), ``resolved`` (the ratio's standard
        error at most :data:`RESOLVED` times ``n``: else nothing is decided from the phases). Too short a
        stretch: the ratio and exponent are NaN and nothing is decided.

    Examples
    --------
    A second harmonic of a decaying, chirping tone (1.2 % over the record), and a true mode whose frequency
    twice the tone's crosses halfway:

    >>> fs, t = 2000.0, np.arange(6000) / 2000.0
    >>> phase = 2 * np.pi * (50 * t + 0.2 * t**2)
    >>> a = np.exp(-0.8 * t)
    >>> harmonic = a * np.cos(phase) + 0.05 * a**2 * np.cos(2 * phase + 1)
    >>> e = harmonic_evidence(harmonic, fs, (40, 60), (90, 120), 2, (1e-5, 1e-5))
    >>> e["locked"], round(e["frequency_ratio"], 4), round(e["exponent"], 2), e["harmonic"]
    (True, 2.0, 2.0, True)
    >>> mode = a * np.cos(phase) + 0.05 * a**2 * np.cos(2 * np.pi * 100.6 * t)
    >>> e = harmonic_evidence(mode, fs, (40, 60), (90, 120), 2, (1e-5, 1e-5))
    >>> e["locked"], round(e["frequency_ratio"], 3), round(e["exponent"], 2), e["harmonic"]
    (False, 2.0, 2.0, False)
    """
    y1, y2 = y if isinstance(y, tuple) else (y, y)
    z1 = bandpass(y1, fs, parent_band, analytic=True)
    z2 = bandpass(y2, fs, candidate_band, analytic=True)
    trim = max(transient_samples(fs, b, tol=_TRANSIENT_TOL) for b in (parent_band, candidate_band))
    floor = 10 ** (MIN_SNR_DB / 20) * np.sqrt(2) * np.asarray(noise_rms, float)
    a1, a2 = np.abs(z1), np.abs(z2)
    keep = _kept(a1, a2, floor[0], floor[1], trim)
    t = np.arange(a1.size)[keep] / fs
    f2 = order * 0.5 * (parent_band[0] + parent_band[1])
    nan = dict(order=order, frequency_ratio=np.nan, ratio_sigma=np.nan, phase_drift_rad=np.nan,
               exponent=np.nan, exponent_sigma=np.nan, periods=float(t.size / fs * f2), locked=False,
               locked_within_errors=False, parent_sweep=np.nan, locking_proven=False, resolved=False,
               harmonic=False)
    if t.size < 8 or t.size / fs * f2 < _MIN_PERIODS:
        return nan
    # the parent's phase unwrapped over every sample of the stretch: where the candidate dips under its
    # floor the kept samples leave gaps, across which the parent's phase would lose whole turns
    phase1 = np.unwrap(np.angle(z1[keep[0] : keep[-1] + 1]))[keep - keep[0]]
    z1, z2, a1, a2 = z1[keep], z2[keep], a1[keep], a2[keep]
    psi = np.unwrap(np.angle(z2 * np.conj(z1 / a1) ** order))
    tiny = 1e-12 * np.array([a1.max(), a2.max()])
    w = 1.0 / (((noise_rms[1] + tiny[1]) / a2) ** 2 + order**2 * ((noise_rms[0] + tiny[0]) / a1) ** 2)
    bandwidth = min(parent_band[1] - parent_band[0], candidate_band[1] - candidate_band[0])
    f1 = float(np.polyfit(t, phase1, 1)[0] / (2 * np.pi))
    ratio, sigma, slope = _ratio(t, psi, w, bandwidth * t.size / fs, order, f1)
    quarters = np.array_split(np.arange(t.size), _SEGMENTS)
    pieces = [(*_ratio(t[k], psi[k], w[k], bandwidth * k.size / fs, order, f1)[:2], bandwidth * k.size / fs)
              for k in quarters]
    # the whole stretch's ratio, resolved, is tested at SIGMAS of its standard error (its pieces, of fewer
    # independent samples each, at their Student-t quantiles): where a fast-decaying mode leaves a stretch of
    # few independent samples, the quantile of one degree of freedom passes ratios tens of errors off n
    resolved = sigma <= RESOLVED * order
    tested = [(ratio, sigma, np.inf), *pieces]
    locked = resolved and all(_near_order(*piece, order) for piece in tested)
    within_errors = locked and all(_near_order(*piece, order, tol=0.0) for piece in tested)
    # the parent's frequency over the pieces: a mode of its own at n f_1 would stay where it is while the
    # parent moves, and its ratio would move by n times the parent's relative change
    f_pieces = [np.polyfit(t[k], phase1[k], 1)[0] / (2 * np.pi) for k in quarters]
    sweep = float((max(f_pieces) - min(f_pieces)) / f1)
    # ... and a harmonic's stays put: within its errors of n, or (locked) its pieces' spread far under that
    ratios = [piece[0] for piece in pieces]
    spread = 0.0 if within_errors else max(ratios) - min(ratios)
    proven = locked and order * sweep > 2 * SIGMAS * max(piece[1] for piece in pieces) + spread
    n_eff = max(t.size * bandwidth / fs, 2.0)
    # log a_2 against log a_1, each envelope's power less the noise's (the analytic noise adds 2 sigma^2 on
    # average), weighted as the phases are (by each sample's SNR): the samples near the floor, which the
    # noise lifts and which would flatten the slope, count little without being cut away
    sigma2 = 2.0 * np.asarray(noise_rms, float) ** 2
    log1, log2 = (0.5 * np.log(np.maximum(a**2 - s2, 1e-2 * a**2)) for a, s2 in zip((a1, a2), sigma2))
    _, p, pres = _line(log1, log2, w)
    spread = np.average((log1 - np.average(log1, weights=w)) ** 2, weights=w)
    p_sigma = float(np.sqrt(np.average(pres**2, weights=w) / max(spread, np.finfo(float).tiny) / n_eff))
    return dict(order=order, frequency_ratio=float(ratio), ratio_sigma=float(sigma),
                phase_drift_rad=float(slope * (t[-1] - t[0])), exponent=float(p), exponent_sigma=p_sigma,
                periods=float(t.size / fs * f2), locked=bool(locked),
                locked_within_errors=bool(within_errors), parent_sweep=sweep, locking_proven=bool(proven),
                resolved=bool(resolved),
                harmonic=bool(locked and _whole_power(p, order)))


def _longest_run(mask: np.ndarray) -> np.ndarray:
    """The indices of the longest run of True in ``mask`` (empty where there is none)."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(np.int8), [0]])))
    if not edges.size:
        return np.zeros(0, int)
    starts, stops = edges[0::2], edges[1::2]
    longest = int(np.argmax(stops - starts))
    return np.arange(starts[longest], stops[longest])


def _product_inputs(signals, fs, bands, counts, noise_rms):
    """:func:`product_evidence`'s inputs checked: three 1-D signals of one length, three ``(low, high)``
    bands, two non-zero whole counts, three noise levels at least zero (a ValueError or TypeError naming
    the problem)."""
    if not isinstance(signals, (tuple, list)) or len(signals) != 3:
        raise TypeError("product_evidence: signals must be three arrays (the two modes' and the "
                        "candidate's)")
    names = ("the first mode's signal", "the second mode's signal", "the candidate's signal")
    signals = [check_signal(y, name, ndim=(1,), as_2d=False) for y, name in zip(signals, names)]
    if len({y.size for y in signals}) != 1:
        raise ValueError(f"product_evidence: the signals must have one length, got "
                         f"{[y.size for y in signals]}")
    check_fs(fs)
    bands = [tuple(float(v) for v in b) for b in bands]
    if len(bands) != 3 or any(len(b) != 2 or not 0 <= b[0] < b[1] for b in bands):
        raise ValueError(f"product_evidence: bands must be three (low, high) pairs in Hz, low < high, "
                         f"got {bands}")
    if len(counts) != 2 or any(int(c) != c or c == 0 for c in counts):
        raise ValueError(f"product_evidence: counts must be two non-zero whole numbers (m, n), got {counts}")
    noise = np.asarray(noise_rms, float)
    if noise.shape != (3,) or not np.all(np.isfinite(noise) & (noise >= 0)):
        raise ValueError(f"product_evidence: noise_rms must be three finite levels >= 0, got {noise_rms}")
    return signals, bands, int(counts[0]), int(counts[1]), noise


def product_evidence(signals, fs: float, bands, counts, noise_rms) -> dict:
    """Phase locking and amplitude of a candidate intermodulation product ``m f_a + n f_b`` of two modes.

    A nonlinear element driven by two modes at once makes tones at their sums and differences (a cubic one
    at ``2 f_a +- f_b`` and ``f_a +- 2 f_b``, a quadratic one at ``f_a +- f_b``): such a product's phase is
    ``m phi_a + n phi_b`` at every instant, and its amplitude goes as ``a_a^|m| a_b^|n|``. A mode of its
    own near that place keeps its own frequency, and the phase ``phi_c - m phi_a - n phi_b`` drifts.

    Parameters
    ----------
    signals : (ndarray, ndarray, ndarray)
        The two modes' and the candidate's own signals (each with the other components removed), on the same
        samples.
    fs : float
        Sampling rate (Hz).
    bands : ((float, float), (float, float), (float, float))
        Each one's band (Hz).
    counts : (int, int)
        ``(m, n)``, non-zero.
    noise_rms : (float, float, float)
        Noise standard deviation in each band: the envelopes are used down to :data:`MIN_SNR_DB` over it.

    Returns
    -------
    dict
        ``counts``, ``frequency_hz`` (of the combination, measured), ``offset`` (the candidate's frequency
        less the combination's, relative to it) and its standard error ``offset_sigma``, ``exponent`` (of
        the candidate's amplitude against ``a_a^|m| a_b^|n|``: 1 for a product), ``sweep`` (the
        combination's relative frequency change over the stretch's pieces), ``resolved`` (the offset's
        standard error at most :data:`RESOLVED`), ``locked`` (resolved, and the whole stretch's and each
        piece's offset within :data:`SIGMAS` standard errors of zero or within half the sweep) and
        ``product`` (locked, and the exponent within :data:`_EXPONENT_TOL` of 1). The samples are the
        longest stretch after the filters' transients where all three envelopes stand :data:`MIN_SNR_DB`
        over their noise. Too short a stretch: NaN, and nothing decided.

    Examples
    --------
    A cubic element's ``2 f_a + f_b`` tone of two decaying modes, and a mode of its own 0.5 % off that
    place:

    >>> fs, t = 4000.0, np.arange(12000) / 4000.0
    >>> pa, pb = 2 * np.pi * 37.0 * t, 2 * np.pi * 93.0 * t + 0.4
    >>> aa, ab = np.exp(-0.9 * t), 0.8 * np.exp(-0.6 * t)
    >>> ya, yb = aa * np.cos(pa), ab * np.cos(pb)
    >>> tone = 0.02 * aa**2 * ab * np.cos(2 * pa + pb + 1.0)
    >>> bands = ((30, 44), (85, 101), (155, 179))
    >>> e = product_evidence((ya, yb, tone), fs, bands, (2, 1), (1e-5, 1e-5, 1e-5))
    >>> e["locked"], round(e["exponent"], 2), e["product"]
    (True, 1.0, True)
    >>> mode = 0.02 * np.exp(-1.5 * t) * np.cos(2 * np.pi * 167.0 * 1.005 * t)
    >>> product_evidence((ya, yb, mode), fs, bands, (2, 1), (1e-5, 1e-5, 1e-5))["product"]
    False
    """
    signals, bands, m, n, noise_rms = _product_inputs(signals, fs, bands, counts, noise_rms)
    z = [bandpass(y, fs, band, analytic=True) for y, band in zip(signals, bands)]
    a = [np.abs(v) for v in z]
    trim = max(transient_samples(fs, b, tol=_TRANSIENT_TOL) for b in bands)
    floor = 10 ** (MIN_SNR_DB / 20) * np.sqrt(2) * np.asarray(noise_rms, float)
    keep = np.zeros(a[0].size, bool)
    keep[trim : a[0].size - trim] = True
    for amplitude, lowest in zip(a, floor):
        keep &= amplitude >= lowest
    keep = _longest_run(keep)  # (the phases are unwrapped: a gap would lose whole turns)
    t = keep / fs
    f_a, f_b = (float(np.mean(b)) for b in bands[:2])
    f_c = abs(m * f_a + n * f_b)
    nan = dict(counts=(m, n), frequency_hz=np.nan, offset=np.nan, offset_sigma=np.nan, exponent=np.nan,
               sweep=np.nan, resolved=False, locked=False, product=False)
    if t.size < 8 or t.size / fs * f_c < _MIN_PERIODS:
        return nan
    z, a = [v[keep] for v in z], [v[keep] for v in a]
    # the candidate's phase less the combination's (a negative count turns the other way)
    turn = (z[0] / a[0]) ** m * (z[1] / a[1]) ** n
    psi = np.unwrap(np.angle(z[2] * np.conj(turn)))
    tiny = 1e-12 * np.array([v.max() for v in a])
    noise = np.asarray(noise_rms, float) + tiny
    w = 1.0 / ((noise[2] / a[2]) ** 2 + (m * noise[0] / a[0]) ** 2 + (n * noise[1] / a[1]) ** 2)
    bandwidth = min(b[1] - b[0] for b in bands)
    stretches = [np.arange(t.size), *np.array_split(np.arange(t.size), _SEGMENTS)]
    # the combination's frequency over the whole stretch and its pieces: a mode of its own stays put while
    # its modes move
    combined_hz = np.array([abs(m * np.polyfit(t[k], np.unwrap(np.angle(z[0][k])), 1)[0]
                                + n * np.polyfit(t[k], np.unwrap(np.angle(z[1][k])), 1)[0]) / (2 * np.pi)
                            for k in stretches])
    f_measured, pieces = float(combined_hz[0]), combined_hz[1:]
    # the offset as a frequency ratio of order 1 (the harmonic test's measure, :func:`_near_order`)
    samples = [bandwidth * k.size / fs for k in stretches]  # independent ones
    tested = [(*_ratio(t[k], psi[k], w[k], n_eff, 1, f_measured)[:2], n_eff)
              for k, n_eff in zip(stretches, samples)]
    tested[0] = (*tested[0][:2], np.inf)
    ratio, sigma = tested[0][:2]
    sweep = float((pieces.max() - pieces.min()) / f_measured)
    resolved = sigma <= RESOLVED
    # locked: each stretch's offset within its errors of zero, or within half the combination's own
    # movement over the stretch (the modes' filtered phases carry their neighbours' leakage; a mode of its
    # own would be offset by about as much as the combination moves)
    locked = resolved and all(_near_order(*piece, 1, tol=0.5 * sweep) for piece in tested)
    combined = abs(m) * np.log(a[0]) + abs(n) * np.log(a[1])
    _, p, _ = _line(combined, np.log(a[2]), w)
    return dict(counts=(m, n), frequency_hz=f_measured, offset=float(ratio - 1),
                offset_sigma=float(sigma), exponent=float(p), sweep=sweep, resolved=bool(resolved),
                locked=bool(locked),
                product=bool(locked and abs(p - 1) <= _EXPONENT_TOL))


def _near_order(ratio: float, sigma: float, n_eff: float, order: int, tol: float = RATIO_TOL) -> bool:
    """Whether a stretch's frequency ratio is ``order`` within :data:`SIGMAS` standard errors or within
    :data:`RATIO_TOL`. The standard error of a stretch of ``n_eff`` independent samples is itself uncertain
    (a line fitted to 4 of them leaves 2 degrees of freedom): the normal's ``SIGMAS`` becomes the Student-t
    quantile of the same probability with ``n_eff - 2`` degrees of freedom (3.0 for long stretches; the
    quarters of a harmonic 20 dB over the noise hold 1.4-3.8 such samples, and the frequency ratios of a
    true second harmonic's quarters to its mode strayed 3-7 standard errors from 2)."""
    sigmas = float(stdtrit(max(n_eff - 2.0, 1.0), _SIGMAS_P))  # the quantile (scipy.stats.t.ppf's own)
    return abs(ratio - order) <= max(sigmas * sigma, tol * order)


#: The normal's probability within :data:`SIGMAS` standard deviations (one-sided), for
#: :func:`_near_order`'s Student-t quantile.
_SIGMAS_P = float(normal_cdf(SIGMAS))


def _whole_power(p: float, order: int) -> bool:
    """Whether an amplitude exponent is that of a term of power 2..order (within :data:`_EXPONENT_TOL`)."""
    return MIN_EXPONENT <= p <= order + _EXPONENT_MARGIN and any(
        abs(p - k) <= _EXPONENT_TOL for k in range(2, order + 1))


def _analysis_bands(pre, modes: list) -> list:
    """Each mode's own band among the record's modes (:func:`~.partition.peak_bands` of their frequencies
    and half-power widths): no band holds a neighbour's centre."""
    f = np.array([m.damped_frequency_hz for m in modes])
    return peak_bands(f, np.array([2 * m.damping_ratio * m.frequency_hz for m in modes]), pre.fs)


def _parent_band(bands: list, freqs: np.ndarray, i: int, candidate_band) -> tuple:
    """Parent ``i``'s band widened to candidate ``j``'s width where its neighbours leave room (to the
    midpoints between their frequencies and its own): both phases then see the same time resolution. A
    narrow parent band smooths the phase of a mode whose frequency moves fast early in the decay over a
    longer time than the harmonic's band (the ratio of a true cubic harmonic read 3.010 and 2.988 in two
    quarters) and its transient hides a fast-decaying harmonic altogether. Its low edge stays above a
    twentieth of the parent's frequency (in a short record of strongly damped modes a candidate's wide band
    reached 0 Hz: an invalid band that aborted the record's survey)."""
    half = 0.5 * (candidate_band[1] - candidate_band[0])
    f = freqs[i]
    lo = max(f - half, 0.5 * (freqs[i - 1] + f)) if i > 0 else f - half
    hi = min(f + half, 0.5 * (freqs[i + 1] + f)) if i + 1 < freqs.size else f + half
    return (max(min(bands[i][0], lo), 0.05 * f), max(bands[i][1], hi))


#: Relative margin around a nonlinear parent's backbone times n within which an undecided candidate is
#: named its harmonic, and share of the backbone's span its top is extended by (the model's backbone covers
#: amplitudes up to about 0.93 of the largest; a harmonic is seen nearer the hit): the rule used before the
#: harmonics were decided on the data.
_BACKBONE_MARGIN, _BACKBONE_REACH = 0.005, 0.25


#: Least ratio of a candidate's decay rate to its parent's for a harmonic named on the parent's backbone (a
#: harmonic of power p >= 2 decays p times as fast; noise flattens its envelope: exponents 2.3-2.6 seen for
#: cubic springs' third harmonics).
_MIN_DECAY_RATIO = 1.5


def _on_backbone(parent, candidate, order: int, decay_ratio: float | None = None) -> bool:
    """Whether ``candidate`` lies at ``order`` times a frequency the nonlinear ``parent``'s backbone passes
    (used when the data cannot decide: a harmonic only a few dB over the noise, or seen only in the first
    tens of milliseconds, e.g. a 35 dB hammer test of a hardening mode). Never for a candidate that decays
    less than :data:`_MIN_DECAY_RATIO` times as fast as the parent (a harmonic's amplitude goes as a power
    p >= 2 of the parent's: its envelope decays p times as fast; an x^2 x' damper's third harmonics decay
    4.2 and 5.7 times as fast as their parents' linear rates), by either of two readings: the modes'
    decay rates, and ``decay_ratio`` where the caller measured it (the ratio of their linear decays'
    rates, the harmonic test's ``decay_exponent``). Each can misread a harmonic: a mode's small-amplitude
    damping ratio, extrapolated by its averaged equations, is not how fast its envelope decays (a quadratic
    spring's second harmonic decaying 1.9 times as fast as its mode read 1.24), and the linear decay of a
    piece of a chirping harmonic is not the harmonic's (a cubic spring's third harmonic fitted as two
    pieces: one read 0.88 times, its mode 2.9 times); a mode of its own decays slowly by both. Nor for a
    parent identified without a band
    signal (no band SNR: the direct or free-decay fit of a short record, :mod:`._short`), whose few periods
    do not make a backbone to extrapolate (in short records of strongly damped linear modes, parents'
    few-period models with cubic terms would name e.g. a 47.9 Hz mode decaying 0.6 times as fast as a 24.3
    Hz one its harmonic 2, and a 307.7 Hz mode at 2.016 times a 152.6 Hz one), nor for a candidate more than
    ``order**2`` times as strong as the parent (a harmonic is weaker than its mode in displacement; an
    acceleration sensor lifts harmonic n by n**2 at most): a weak mode's noisy band equation may have cubic
    terms, and a record's strongest mode near twice its frequency (e.g. 2795.6 Hz, the weak mode 36 dB
    below it) would be named its harmonic 2.
    """
    from ..analysis import backbone
    from ._nonlinear import has_nonlinear_terms

    decay = [m.damping_ratio * m.frequency_hz for m in (parent, candidate)]
    ratios = [decay[1] / decay[0] if decay[0] > 0 and decay[1] > 0 else np.nan, decay_ratio]
    ratios = [r for r in ratios if r is not None and np.isfinite(r)]
    if not has_nonlinear_terms(parent.model) or (ratios and max(ratios) < _MIN_DECAY_RATIO):
        return False  # (a failed peak without a damping ratio, 0, is not judged on its decay)
    if getattr(candidate, "amplitude", np.nan) > order**2 * parent.amplitude:
        return False  # stronger than a harmonic can be (a failed peak or a joint mode: no amplitude)
    if not np.isfinite(parent.snr_db):
        return False
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            curve = backbone(parent.model, coordinate=parent.coordinate_)
    except (ValueError, AttributeError):
        return False
    keep = np.isfinite(curve.frequency_hz) & np.isfinite(curve.amplitude)
    f, a = curve.frequency_hz[keep], curve.amplitude[keep]
    if not f.size:
        return False
    margin = max(_BACKBONE_MARGIN, 2 * candidate.damping_ratio)
    lo, hi = _span(f, a, parent.amplitude)
    return bool(lo * (1 - margin) <= candidate.frequency_hz / order <= hi * (1 + margin))


def _span(f: np.ndarray, a: np.ndarray, amplitude: float) -> tuple[float, float]:
    """The frequencies a backbone ``f(a)`` passes, its top (the end of largest amplitude) extended by
    :data:`_BACKBONE_REACH` of its span and to the mode's amplitude at the hit (:func:`_at_hit`); its
    small-amplitude end is where it is (a hardening mode's backbone never falls below it, a softening one's
    never rises above it).

    Examples
    --------
    A hardening backbone from 100 to 102 Hz, a softening one from 100 down to 98 Hz:

    >>> a = np.array([0.1, 0.5, 1.0])
    >>> _span(np.array([100.0, 100.5, 102.0]), a, 1.0), _span(np.array([100.0, 99.5, 98.0]), a, 1.0)
    ((100.0, 102.5), (97.5, 100.0))
    """
    reach = _BACKBONE_REACH * (f.max() - f.min())
    at_hit = _at_hit(f, a, amplitude)
    if f[np.argmax(a)] >= f[np.argmin(a)]:  # hardening: the top is its highest frequency
        return float(f.min()), float(max(f.max() + reach, at_hit))
    return float(min(f.min() - reach, at_hit)), float(f.max())


def _at_hit(f: np.ndarray, a: np.ndarray, amplitude: float) -> float:
    """The backbone's frequency at the mode's amplitude at the hit, extrapolated from the curve's ends as
    ``f^2`` linear in ``a^2`` (a spring's first-order backbone); the nearer end when the amplitude is not
    above the curve. The curve starts where the band signal does, after the filter's transient: a mode
    refitted on a narrow band (:mod:`._nonlinear`) covered 0.69 of the hit's amplitude, and its third
    harmonic, at 3.09 times the mode's small-amplitude frequency (``tests/test_modes_nonlinear.py``'s
    harmonic seen above the backbone's top), lay above ``3 f`` of the curve's top and of its reach.

    Examples
    --------
    >>> f, a = np.array([146.05, 148.89]), np.array([0.082, 0.708])
    >>> round(_at_hit(f, a, 1.03), 1), round(_at_hit(f, a, 0.5), 2)
    (152.0, 148.89)
    """
    top, low = int(np.argmax(a)), int(np.argmin(a))
    if not np.isfinite(amplitude) or amplitude <= a[top] or a[top] <= a[low]:
        return float(f[top])
    slope = (f[top] ** 2 - f[low] ** 2) / (a[top] ** 2 - a[low] ** 2)
    return float(np.sqrt(max(f[top] ** 2 + slope * (amplitude**2 - a[top] ** 2), 0.0)))


def _nonlinear_parent(exponent: float, order: int, whole: bool = False) -> bool:
    """Whether a locked candidate's exponent is a harmonic's, for a nonlinear parent (the caller checks
    that: a linear mode makes no harmonic): between whole powers (noise flattens a harmonic's envelope:
    2.3-2.6 seen for cubic springs' 3 f), or ``whole``: the exponent must be a whole power
    (:func:`_whole_power`): for the ratio of the fitted decay rates, which the envelopes' noise and the
    filters' transients do not bend (a cubic spring's third harmonic, locked, whose envelopes gave 3.66 +-
    0.06 and whose decay rates 2.92)."""
    if whole:
        return _whole_power(exponent, order)
    return bool(MIN_EXPONENT <= exponent <= order + _EXPONENT_MARGIN)


def _decays_as_power(parent, candidate, order: int) -> bool:
    """Whether the candidate's fitted decay rate is ``k`` times the linear parent's (``2 <= k <= order``)
    within :data:`SIGMAS` standard errors of their ratio (from both modes' standard deviations; True when
    they have none: nothing to judge). A harmonic's amplitude goes as its mode's to the power ``k``: of a mode
    whose equation is linear (a constant decay rate) it decays exactly ``k`` times as fast; a mode near a
    whole multiple of a linear one need not: e.g. a linear 987.54 Hz mode 0.026 % off twice a linear 493.64
    Hz mode, locked within the few independent samples of its stretch, decays 2.21 times as fast.

    Examples
    --------
    >>> from types import SimpleNamespace as Mode
    >>> std = dict(frequency_std_hz=0.02, damping_ratio_std=2e-5)
    >>> parent = Mode(frequency_hz=500.0, damping_ratio=0.01, **std)
    >>> harmonic = Mode(frequency_hz=1000.0, damping_ratio=0.01, **std)
    >>> mode = Mode(frequency_hz=1000.3, damping_ratio=0.011, **std)
    >>> _decays_as_power(parent, harmonic, 2), _decays_as_power(parent, mode, 2)
    (True, False)
    """
    modes = (parent, candidate)
    values = [getattr(m, name, np.nan) for m in modes for name in
              ("damping_ratio", "damping_ratio_std", "frequency_hz", "frequency_std_hz")]
    zp, zp_std, fp, fp_std, zc, zc_std, fc, fc_std = values
    if not (np.all(np.isfinite(values)) and zp > 0 and zc > 0):
        return True
    ratio = zc * fc / (zp * fp)
    sigma = ratio * np.sqrt((zc_std / zc) ** 2 + (fc_std / fc) ** 2 + (zp_std / zp) ** 2 + (fp_std / fp) ** 2)
    return any(abs(ratio - k) <= SIGMAS * sigma for k in range(2, order + 1))


def _reason(parent, e: dict) -> str:
    if e.get("by_backbone"):
        locking = (f"frequency ratio {e['frequency_ratio']:.5f} +- {e['ratio_sigma']:.1g}"
                   if np.isfinite(e["ratio_sigma"]) else "too few periods outlast the band's filter")
        why = ("its band's phase test does not decide for a parent whose frequency moves" if e.get("resolved")
               else "the record cannot resolve the phase locking")
        return (f"harmonic {e['order']} of the nonlinear mode at {parent.frequency_hz:.4g} Hz (its backbone "
                f"passes {e['frequency_hz'] / e['order']:.4g} Hz; {why}: {locking}), not a mode")
    return (f"harmonic {e['order']} of the mode at {parent.frequency_hz:.4g} Hz, not a mode: phase-locked "
            f"to it (frequency ratio {e['frequency_ratio']:.5f} +- {e['ratio_sigma']:.1g}) and its "
            f"amplitude goes as the mode's to the power {e['exponent']:.2f}")


def _evidence(pre, ring, analysis, i: int, parent, band, noise: float, order: int, candidate,
              failed: bool = False, nonlinear: bool | None = None, own=None) -> dict:
    """:func:`harmonic_evidence` of ``band`` as harmonic ``order`` of mode ``i`` (``analysis``: the modes'
    bands and damped frequencies), decided with the parent's model where the data leave it open (a locked
    candidate between whole powers; the backbone when the locking is unresolved). ``candidate``: a mode,
    or a failed peak (``frequency_hz`` and ``damping_ratio`` only, ``failed=True``).

    :data:`RATIO_TOL` serves a nonlinear parent, whose frequency moves along its backbone faster than the
    band-passed phases follow; a parent whose model is linear keeps its frequency, and a harmonic of it
    (from nonlinear terms too weak for its equation) is at ``n`` times it within the standard errors; a
    linear mode near a whole multiple of a linear one passes the tolerance: e.g. a linear 987.54 Hz mode
    0.026 % off twice a linear 493.64 Hz one reads 2.00080 +- 0.00017 (4.7 standard errors off) and would be
    named its harmonic.

    ``nonlinear``: whether the parent is nonlinear, when known without its model (a candidate the linear
    decay does not explain); None reads its model's terms, and only then may its backbone decide.
    ``own``: ``(parent's signal, candidate's signal, parent's band, parent's noise)``, each signal with the
    other components removed (then ``ring`` and ``analysis`` are not read)."""
    from ._nonlinear import has_nonlinear_terms

    if own is not None:
        ring, parent_band, parent_noise = (own[0], own[1]), own[2], own[3]
    else:
        bands, freqs = analysis
        parent_band = _parent_band(bands, freqs, i, band)
        if failed:  # not among the modes, so keep the parent's band clear of it
            f = freqs[i]
            parent_band = (max(parent_band[0], 0.5 * f), min(parent_band[1], 0.5 * (f + band[0])))
        parent_noise = band_noise_rms(pre.peaks.spectrum, parent_band)
    e = harmonic_evidence(ring, pre.fs, parent_band, band, order, (parent_noise, noise))
    e.update(parent_frequency_hz=parent.frequency_hz, frequency_hz=candidate.frequency_hz)
    linear = not (has_nonlinear_terms(parent.model) if nonlinear is None else nonlinear)
    if candidate.damping_ratio > 0 and parent.damping_ratio > 0:  # fitted decays: their ratio is the exponent
        e.update(decay_exponent=float(candidate.damping_ratio * candidate.frequency_hz
                                      / (parent.damping_ratio * parent.frequency_hz)))
    if e["locked"] and not e["locked_within_errors"] and (linear or _loosely_locked(e)):
        e.update(locked=False, harmonic=False)  # a linear parent's harmonic: exactly n times it (see below)
    if e["harmonic"] and linear and not _decays_as_power(parent, candidate, order):
        e.update(harmonic=False)
    if e["locked"] and not e["harmonic"] and not linear and (
            _nonlinear_parent(e["exponent"], order)
            or _nonlinear_parent(e.get("decay_exponent", np.nan), order, whole=True)
            or (e["locking_proven"] and e["exponent"] >= MIN_EXPONENT)):
        # (proven: the ratio stayed n within its errors while the parent's frequency moved more than they
        # allow; the envelopes then only need to decay faster than the parent's: a sensor's frequency
        # weighting steepens an exponent as the frequency moves)
        e.update(harmonic=True)
    # unresolved: the ratio's standard error too large to prove the locking; its value may still rule the
    # order out (a ratio outside the harmonic window is no harmonic, whatever a backbone passes)
    unresolved = not e["resolved"] and not _contradicted(e)
    # a moving parent's harmonic sweeps n times its backbone, and a candidate may be a piece of that sweep,
    # whose band-passed envelope and phase are the piece's, not the harmonic's: its resolved test, not
    # named, leaves it to the parent's backbone as an unresolved one does where its ratio strays from n no
    # farther than the parent's sweep over the stretch explains (and the ratio's standard errors)
    piece = e["resolved"] and not linear and _strays_with_sweep(e)
    e.update(undecided=bool((unresolved or piece) and not e["harmonic"]))
    if unresolved and nonlinear is None and _on_backbone(parent, candidate, order):
        e.update(harmonic=True, by_backbone=True, undecided=False)
    return e


def _loosely_locked(e: dict) -> bool:
    """Whether a ratio locked by :data:`RATIO_TOL` only (beyond its standard errors) has nothing else that
    makes it a harmonic's: the parent's movement over the stretch does not explain the offset
    (:func:`_strays_with_sweep`) and neither amplitude exponent (the envelopes', the decay rates') is a whole
    power. A mode of its own near ``n`` times a parent that hardly moves reads the two modes' ratio, precise
    and off ``n``, and its envelope decays as its own damping says (e.g. 2.99394 +- 0.00006 times a parent
    that moved 0.017 %, exponents 2.46 and 2.54); a harmonic's band-passed phases may lag by as much (a
    quadratic spring's second harmonic read 1.99742 +- 0.00063 beside a parent that moved 0.024 %) and its
    exponent is a whole power (1.98 and 2.05).

    Examples
    --------
    >>> mode = dict(frequency_ratio=2.99394, ratio_sigma=6e-5, order=3, parent_sweep=1.7e-4, exponent=2.46,
    ...             decay_exponent=2.54)
    >>> harmonic = dict(frequency_ratio=1.99742, ratio_sigma=6.3e-4, order=2, parent_sweep=2.4e-4,
    ...                 exponent=1.98, decay_exponent=2.05)
    >>> _loosely_locked(mode), _loosely_locked(harmonic)
    (True, False)
    """
    exponents = (e["exponent"], e.get("decay_exponent", np.nan))
    return not _strays_with_sweep(e) and not any(_whole_power(p, e["order"]) for p in exponents)


def _strays_with_sweep(e: dict) -> bool:
    """Whether a harmonic test's ratio lies off ``n`` by no more than the parent's relative frequency change
    over the stretch (``parent_sweep``) and :data:`SIGMAS` standard errors: as far as a moving parent's
    band-passed phases can make a harmonic's ratio stray. A mode of its own near ``n`` times a parent that
    hardly moves lies farther off than that (e.g. 2.0036 +- 0.00006 times a parent that moved 0.04 %).

    Examples
    --------
    >>> _strays_with_sweep(dict(frequency_ratio=2.991, ratio_sigma=0.0014, order=3, parent_sweep=0.024))
    True
    >>> _strays_with_sweep(dict(frequency_ratio=2.0036, ratio_sigma=6e-5, order=2, parent_sweep=4e-4))
    False
    """
    sweep = e.get("parent_sweep", np.nan)
    off = abs(e["frequency_ratio"] / e["order"] - 1)
    return bool(np.isfinite(sweep) and off <= sweep + SIGMAS * e["ratio_sigma"] / e["order"])


def _contradicted(e: dict) -> bool:
    """Whether a harmonic test's frequency ratio, over the whole stretch, rules its order out: farther from
    ``n`` than a harmonic's can be and :data:`SIGMAS` standard errors beyond. A harmonic's phase is ``n``
    times its mode's at every instant; its measured ratio strays from ``n`` only as far as the band-passed
    phases fall behind a moving frequency: at most the parent's own relative frequency change over the
    stretch (``parent_sweep``) beyond :data:`RATIO_TOL`, and never beyond the window a harmonic of a
    nonlinear mode is looked for in (:data:`NEAR`, relative; also where the sweep was not measured). The
    locking may be unresolved (its standard error too large to prove it) and still be excluded; a ratio
    without a standard error (too few periods outlast the band's filter) rules nothing out.

    Examples
    --------
    >>> _contradicted(dict(frequency_ratio=2.37, ratio_sigma=0.03, order=3))
    True
    >>> _contradicted(dict(frequency_ratio=3.034, ratio_sigma=0.004, order=3))
    False
    >>> _contradicted(dict(frequency_ratio=2.37, ratio_sigma=float("nan"), order=3))
    False

    A ratio 1.8 % off 2 over a stretch where the parent's frequency moved by 0.3 %: no harmonic.

    >>> _contradicted(dict(frequency_ratio=2.0363, ratio_sigma=0.0027, order=2, parent_sweep=0.003))
    True
    >>> _contradicted(dict(frequency_ratio=2.0363, ratio_sigma=0.0027, order=2, parent_sweep=0.03))
    False
    """
    sigma, order = e["ratio_sigma"], e["order"]
    sweep = e.get("parent_sweep", np.nan)
    window = min(NEAR, RATIO_TOL + sweep) if np.isfinite(sweep) else NEAR
    off = abs(e["frequency_ratio"] / order - 1)
    return bool(np.isfinite(sigma) and off > window + SIGMAS * sigma / order)


#: Relative half-width of the band a peak is analysed in as a harmonic (a peak's own band can be wide enough
#: to pass its parent's skirt, whose envelope then reads as the parent's: exponent 1).
_FAILED_BAND = 0.04


def _unseen_peak(spectrum, target: float) -> float | None:
    """The highest bin within :data:`NEAR` of ``target`` Hz when it is a local maximum standing
    :data:`MIN_SNR_DB` over the floor (the height down to which the harmonic test reads envelopes; the
    phase locking, not this height, tells a harmonic from noise); else None."""
    window = np.flatnonzero(np.abs(spectrum.frequency_hz / target - 1) <= NEAR)
    if window.size < 3:
        return None
    k = window[np.argmax(spectrum.psd[window])]
    if k in (window[0], window[-1]):  # the window's edge: a skirt, not a peak
        return None
    height = 10 * np.log10(spectrum.psd[k] / max(spectrum.floor[k], np.finfo(float).tiny))
    return float(spectrum.frequency_hz[k]) if height >= MIN_SNR_DB else None


def _names(row, mode, order: int) -> bool:
    """Whether a rejected row names a harmonic ``order`` of ``mode`` (its parent's frequency in the mode's
    band)."""
    e, band = row.evidence or {}, mode.band_hz or (mode.frequency_hz, mode.frequency_hz)
    parent = e.get("parent_frequency_hz", np.nan)
    return bool(e.get("harmonic") and e.get("order") == order and band[0] <= parent <= band[1])


def _unseen_harmonics(pre, ring, modes: list, rejected: list, poles=()) -> tuple:
    """Harmonics the detection did not keep: near ``n`` times a mode whose model has nonlinear terms (a
    linear mode makes none), where no mode, peak or rejected row lies, a spectral peak over the floor
    (:func:`_unseen_peak`) is tested as that mode's harmonic in a band :data:`_FAILED_BAND` wide (a cubic
    spring's third harmonic sweeps three times its mode's frequency change: the damped-sinusoid test of the
    peaks, made for modes, drops it, even at 37-38 dB SNR). Only the data decide here (no mode is at stake,
    and noise must not be named): a peak phase-locked to the mode whose amplitude goes as a power of at least
    :data:`MIN_EXPONENT` of the mode's (a chirping harmonic seen over a few periods read 4.8) becomes a
    rejected row with its evidence; anything else is left alone. The stable poles of the record's diagram
    near ``n`` times the mode (``poles``, Hz) are tested too, nearest first, after the spectral peak: a
    chirping harmonic spreads its energy over the bins it sweeps, where a noise bin can stand higher, but
    the diagram's poles follow the sweep. A stable pole is not noise, so where the locking cannot be
    resolved it is named a harmonic when it lies at ``n`` times a frequency of the mode's backbone
    (:func:`_on_backbone`, as for a candidate). ``(rejected, notes)``."""
    from ._nonlinear import has_nonlinear_terms

    spectrum = pre.peaks.spectrum
    if not modes or spectrum is None:
        return rejected, []
    bands = _analysis_bands(pre, modes)
    freqs = np.array([m.damped_frequency_hz for m in modes])
    taken = [*freqs, *pre.peaks.frequency_hz, *(0.5 * sum(r.band_hz) for r in rejected if r.band_hz)]
    notes = []
    for i, parent in enumerate(modes):
        for order in ORDERS if has_nonlinear_terms(parent.model) else ():
            target = order * freqs[i]
            if target >= 0.45 * pre.fs or any(abs(f / target - 1) <= NEAR for f in taken):
                continue
            if any(_names(r, parent, order) for r in rejected):
                continue  # its harmonic of this order is named already (a chirping one lies off n f)
            peak = _unseen_peak(spectrum, target)
            near = sorted((p for p in poles if abs(p / target - 1) <= NEAR), key=lambda p: abs(p - target))
            for f in ([] if peak is None else [peak]) + near:
                band = (f * (1 - _FAILED_BAND), f * (1 + _FAILED_BAND))
                try:
                    e = _evidence(pre, ring, (bands, freqs), i, parent, band, band_noise_rms(spectrum, band),
                                  order, SimpleNamespace(frequency_hz=f, damping_ratio=0.0), failed=True)
                except (ValueError, ArithmeticError, np.linalg.LinAlgError):
                    continue  # the band cannot be analysed
                locked = e["locked"] and e["exponent"] >= MIN_EXPONENT
                if locked or (f != peak and e["harmonic"]):  # a stable pole is no noise: its backbone may say
                    source = "a spectral peak" if f == peak else "a stable pole of the diagram"
                    e.update(harmonic=True, by_backbone=not locked,
                             detection=f"{source} the damped-sinusoid test of the peaks did not keep")
                    why = _reason(parent, e)
                    rejected.append(Rejected(band, why, parent.record, e))
                    notes.append(f"record {parent.record}: the peak at {f:.4g} Hz is the {why}")
                    taken.append(f)
                    break
    return rejected, notes

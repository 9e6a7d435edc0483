"""Checks of the measured states before the regression: magnitude, quality per state, collinear channels,
noise removed by the filter, and the rest level (see :mod:`.rest`).

:func:`screen_states` is the one call the estimator makes before building its library; it refuses states
whose magnitude double precision cannot raise to the library's powers, and keeps what the diagnostics of the
fit need from the raw data (the estimator keeps only the filtered states).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._utils.robust import robust_std
from ..preprocessing.peaks import spectral_peaks
from ..preprocessing.quality import LIMITS, check_quality, clipping_mask
from ..preprocessing.states import RestLevel, clipped_rows
from ..simulation.scoring import compare_stride

__all__ = ["DataChecks", "screen_states", "check_magnitude", "quality_problems", "MAGNITUDE_RANGE"]

#: Largest absolute state value outside which a fit is refused: (smallest, largest). Beyond 1e50 the
#: squares of the states' cubes (the library's column norms, its Gram matrix) overflow double precision
#: (5.6e51), and NumPy's overflow warnings reached the user from 1e51 (1e39 before the term tests used
#: unit columns); below 1e-150 their squares underflow, the differentiation's regularisation then sees no
#: signal (measured: the paper's oscillator is identified from 1e-150 to 1e50 times its amplitude without
#: a NumPy warning, and not at 1e-200).
MAGNITUDE_RANGE = (1e-150, 1e50)
#: Trajectories whose quality is checked (repeated impacts share the sensor).
MAX_CHECKED = 8
#: Fewest samples for the spectral quality checks (the noise floor needs 128).
MIN_QUALITY_SAMPLES = 128
#: A spike is a sample off the filtered state by more than this many robust standard deviations of
#: what the filter removed (Gaussian noise exceeds 8 with probability 1e-15) and by more than
#: ``SPIKE_FLOOR`` of the state's amplitude.
SPIKE_SIGMA, SPIKE_FLOOR = 8.0, 0.01


@dataclass(frozen=True)
class DataChecks:
    """What the raw states show, for the diagnostics of the fit.

    Attributes
    ----------
    rest : RestLevel
        Rest level per state and whether it was removed.
    quality : list of QualityReport
        :func:`~sindy_impulse.preprocessing.check_quality` per state (first trajectory; clipping counted
        over all checked ones), empty when the record is too short.
    clipped : int
        Clipped samples (all states and checked trajectories).
    relative_step : float
        Largest ADC step over the amplitude (0 when not quantised).
    noise_ratio : ndarray (n_states,)
        RMS of (measured - filtered) over the RMS of the filtered states about their rest level.
    state_condition : float
        Condition number of the standardised filtered states (large: channels that are nearly copies).
    collinear : tuple of (int, int, float)
        The most correlated pair of states and their correlation.
    peaks_hz, peak_widths_hz, peak_heights_db : ndarray
        Significant spectral peaks of the measured states (first trajectory, every state), their
        half-power widths and heights over the noise floor, searched from 2 periods over the record to
        0.45 of the sampling rate.
    raw : list of ndarray
        The measured states (the term tests compare simulations with them).
    spikes : ndarray of int (n_states,)
        Isolated samples far off the filtered state (see :func:`_spikes`), clipped samples excepted.
    constant : ndarray of bool (n_states,)
        States that never change.
    noise_known : bool
        False when the filtered states are the measured ones (derivatives given): nothing tells the noise
        then, and the checks that compare with it are left out or made robust to coloured errors.
    excluded : int
        Samples left out of the regression because a state is clipped there (:func:`leave_out_clipped`).
    scale_problem : str or None
        States too small for double precision, accepted in plain PySINDy mode (:func:`check_magnitude`).
    """

    rest: RestLevel
    quality: list = field(repr=False)
    clipped: int
    relative_step: float
    noise_ratio: np.ndarray
    state_condition: float
    collinear: tuple
    peaks_hz: np.ndarray = field(default_factory=lambda: np.empty(0))
    peak_widths_hz: np.ndarray = field(default_factory=lambda: np.empty(0))
    peak_heights_db: np.ndarray = field(default_factory=lambda: np.empty(0))
    raw: list = field(default_factory=list, repr=False)
    spikes: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    constant: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))
    noise_known: bool = True
    excluded: int = 0
    scale_problem: str | None = None


def check_magnitude(trajectories, name: str = "x", refuse_small: bool = True) -> str | None:
    """Refuse states whose magnitude lies outside :data:`MAGNITUDE_RANGE` (a clear ValueError).

    With ``refuse_small=False`` (plain PySINDy mode, which solves such data) states too small are not
    refused: the problem is returned as a sentence for the verdict instead (None when there is none).

    Examples
    --------
    >>> check_magnitude([np.ones((5, 2)) * 1e300])  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: x reaches 1e+300: the library's powers ... rescale x (change its units) and fit again
    """
    largest = max(float(np.max(np.abs(x))) for x in trajectories)
    low, high = MAGNITUDE_RANGE
    if largest > high:
        raise ValueError(
            f"{name} reaches {largest:.3g}: the library's powers of the states and their squares overflow "
            f"double precision beyond {high:.0e}; rescale {name} (change its units) and fit again"
        )
    if 0 < largest < low:
        message = (
            f"{name} is at most {largest:.3g}: below {low:.0e} the squares of the states underflow double "
            f"precision and no dynamics can be resolved; rescale {name} (change its units) and fit again"
        )
        if refuse_small:
            raise ValueError(message)
        return message
    return None


def _quality(trajectories, times) -> tuple:
    """Quality reports and spectral peaks of the first trajectory, clipped samples and the coarsest
    relative ADC step."""
    reports, step, peaks, widths, heights = [], 0.0, [], [], []
    for k, (x, t) in enumerate(zip(trajectories[:MAX_CHECKED], times[:MAX_CHECKED])):
        if x.shape[0] < MIN_QUALITY_SAMPLES:
            continue
        stride = compare_stride(x)  # spectra at <= 200 samples per period: long records stay cheap
        fs = (x.shape[0] - 1) / float(t[-1] - t[0]) / stride
        for j in range(x.shape[1]):
            y = x[:, j]
            if k > 0 or not np.ptp(y) > 0:
                continue
            y = y[::stride]
            ring = y - np.mean(y[int(0.75 * y.size) :])
            try:
                found = spectral_peaks(ring, fs, f_range=(2 * fs / y.size, 0.45 * fs), refine=False)
                report = check_quality(y, fs, peaks=found)
            except (ValueError, ArithmeticError, np.linalg.LinAlgError):  # odd records: skip the state
                continue
            reports.append(report)
            step = max(step, report.relative_step)
            peaks.extend(found.frequency_hz.tolist())
            widths.extend(found.half_power_width_hz.tolist())
            heights.extend(found.height_db.tolist())
    found = (np.asarray(peaks), np.asarray(widths), np.asarray(heights))
    return (reports, clipped_samples(trajectories), step, *found)


def clipped_samples(trajectories) -> int:
    """Clipped samples (runs of equal samples at the extremes,
    :func:`~sindy_impulse.preprocessing.clipping_mask`) over every non-constant state of the checked
    trajectories (the first :data:`MAX_CHECKED`, each at least :data:`MIN_QUALITY_SAMPLES` long).

    Examples
    --------
    >>> y = np.sin(np.linspace(0, 20, 400))
    >>> clipped_samples([np.clip(y, -0.8, 0.8)[:, None]]) > 0, clipped_samples([y[:, None]])
    (True, 0)
    """
    return sum(
        int(clipping_mask(x[:, j]).sum())
        for x in trajectories[:MAX_CHECKED]
        if x.shape[0] >= MIN_QUALITY_SAMPLES
        for j in range(x.shape[1])
        if np.ptp(x[:, j]) > 0
    )


def _collinearity(filtered) -> tuple[float, tuple]:
    """Condition number of the standardised states and the most correlated pair."""
    X = np.vstack(filtered)
    X = X[np.all(np.isfinite(X), axis=1)]
    spread = X.std(axis=0)
    if X.shape[1] < 2 or X.shape[0] < 3 or not np.all(spread > 0):
        return 1.0, (0, 0, 0.0)
    Z = (X - X.mean(axis=0)) / spread
    singular = np.linalg.svd(Z, compute_uv=False)
    condition = float(singular[0] / singular[-1]) if singular[-1] > 0 else np.inf
    corr = np.corrcoef(Z, rowvar=False)
    np.fill_diagonal(corr, 0.0)
    i, j = np.unravel_index(np.argmax(np.abs(corr)), corr.shape)
    return condition, (int(min(i, j)), int(max(i, j)), float(corr[i, j]))


def _spikes(raw, filtered) -> np.ndarray:
    """Per state, the samples far off the filtered state (glitches, dropouts, single-sample outliers)."""
    removed = np.vstack([r - f for r, f in zip(raw, filtered)])
    clipped = np.concatenate(clipped_rows(raw, widen=2))
    amplitude = np.max(np.abs(np.vstack(filtered) - np.median(np.vstack(filtered), axis=0)), axis=0)
    centre = np.median(removed, axis=0)
    spread = robust_std(removed, axis=0, centre=centre)
    limit = np.maximum(SPIKE_SIGMA * spread, SPIKE_FLOOR * amplitude)
    far = (np.abs(removed - centre) > limit) & ~clipped[:, None]
    return far.sum(axis=0)


def _noise_ratio(raw, filtered, level) -> np.ndarray:
    """Per state: RMS of what the filter removed over the RMS of the filtered states about the level."""
    removed = np.vstack([r - f for r, f in zip(raw, filtered)])
    signal = np.vstack(filtered) - level
    num = np.sqrt(np.nanmean(removed**2, axis=0))
    den = np.sqrt(np.nanmean(signal**2, axis=0))
    return np.where(den > 0, num / np.where(den > 0, den, 1.0), np.inf)


def screen_states(data, filtered, rest: RestLevel, plain: bool = False, excluded: int = 0) -> DataChecks:
    """Check the measured states of a fit: what :func:`~sindy_impulse.diagnostics.diagnose_fit` reads.

    Refuses states outside :data:`MAGNITUDE_RANGE` (ValueError; in plain PySINDy mode, ``plain=True``,
    states too small are accepted and the problem kept for the verdict). Changes nothing: the rest level
    (``rest``) and the clipped samples left out (``excluded``) come from
    :mod:`sindy_impulse.preprocessing.states`, called by the estimator.

    Parameters
    ----------
    data : Trajectories
        The validated measured states, times and inputs.
    filtered : list of ndarray
        The filtered states (what the library is built on).
    rest : RestLevel
        The rest level of each state and whether it is removed.
    plain : bool
        Plain PySINDy mode (no sweep, no refinement).
    excluded : int
        Samples left out of the regression because a state is clipped there.

    Returns
    -------
    DataChecks

    Examples
    --------
    >>> from sindy_impulse import damped_oscillator
    >>> from sindy_impulse._utils.trajectories import as_trajectories
    >>> from sindy_impulse.preprocessing.states import rest_level
    >>> ring = damped_oscillator()
    >>> data = as_trajectories(ring.x, ring.t)
    >>> checks = screen_states(data, [ring.x], rest_level(data.x, data.t))
    >>> checks.clipped, checks.noise_known
    (0, False)
    """
    scale_problem = check_magnitude(data.x, refuse_small=not plain)
    with np.errstate(all="ignore"):  # tiny states (plain mode): the checks' ratios may overflow
        reports, clipped, step, peaks, widths, heights = _quality(data.x, data.t)
    condition, pair = _collinearity(filtered)
    return DataChecks(
        rest,
        reports,
        clipped,
        step,
        _noise_ratio(data.x, filtered, rest.level),
        condition,
        pair,
        peaks,
        widths,
        heights,
        list(data.x),
        _spikes(data.x, filtered),
        np.array([all(np.ptp(x[:, j]) == 0 for x in data.x) for j in range(data.n_states)]),
        not all(np.array_equal(r, f) for r, f in zip(data.x, filtered)),
        excluded=excluded,
        scale_problem=scale_problem,
    )


def quality_problems(checks: DataChecks) -> dict:
    """The data problems worth a reason in the verdict: clipping, quantisation, spikes, constant states,
    an offset left in place."""
    out = {} if checks.scale_problem is None else {"scale": checks.scale_problem}
    if checks.clipped:
        used = (
            f"{checks.excluded} samples around them were left out of the regression and the refinement "
            "was skipped, but the candidates were still scored on the clipped record"
            if checks.excluded
            else "the fit used them as if they were true"
        )
        out["clipping"] = (
            f"{checks.clipped} sample(s) are clipped (the sensor saturated): {used}; hit softer, or cut the "
            "clipped stretches out"
        )
    if checks.relative_step > LIMITS["quantisation"]:
        out["quantisation"] = (
            f"the record is coarsely quantised (step {checks.relative_step:.2g} of the amplitude): use a "
            "finer input range"
        )
    if np.any(checks.spikes):
        states = ", ".join(f"x{j} ({n})" for j, n in enumerate(checks.spikes) if n)
        out["spikes"] = (
            f"isolated samples far off the rest of the record in state(s) {states} (glitches, dropouts): "
            "remove or interpolate them"
        )
    if np.any(checks.constant):
        states = ", ".join(f"x{j}" for j in np.flatnonzero(checks.constant))
        out["constant"] = f"state(s) {states} never change: they carry no dynamics; drop them"
    kept = checks.rest.sure & ~checks.rest.removed & checks.rest.rings_down
    if np.any(kept):
        states = ", ".join(f"x{j} ({checks.rest.relative[j]:.2g} x amplitude)" for j in np.flatnonzero(kept))
        out["offset"] = (
            f"offset in state(s) {states} left in place (plain PySINDy mode removes nothing): remove it "
            "(sindy_impulse.preprocessing.OffsetRemover) or fit with sweep or refine"
        )
    return out

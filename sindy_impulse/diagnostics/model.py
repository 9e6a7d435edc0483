"""Checks of a fitted model against its data: simulation error, frequencies against the data's spectral
peaks, conditioning of the selected terms (the terms themselves: :mod:`.terms`).

Each function returns numbers; :mod:`.verdict` words them.
"""

from __future__ import annotations

import functools

import numpy as np

from ..feature_library.terms import library_terms
from ..poles.modal import MIN_LINEAR_SHARE, model_modes
from ..preprocessing.peaks import spectral_peaks
from ..simulation import TermTable
from ..simulation.scoring import AUTO_PERIODS, Segmented, compare_stride, oscillation_count

__all__ = [
    "Fitted",
    "segments",
    "simulate_residuals",
    "simulation_grid",
    "simulation_residuals",
    "fit_error",
    "regression",
    "frequency_agreement",
    "support_condition",
]

#: Peaks this far (dB) below the data's highest are not checked (weak harmonics, noise).
STRONG_DB = 30.0
#: Segment length (periods) of the restarted simulations of long records.
SEGMENT_PERIODS = 8.0
#: Segment length (periods) for records that do not ring down (sustained or chaotic oscillation: a
#: simulation's phase, or its trajectory on a chaotic attractor, is lost within a few periods).
SUSTAINED_PERIODS = 1.0


class Fitted:
    """What the checks read from a fitted estimator, as lists over trajectories (measured coordinates).

    ``rings_down``: whether the data decay (then long simulations are informative); sets the segments.
    """

    def __init__(self, estimator, rings_down: bool = True):
        def as_list(v):
            return v if isinstance(v, list) else [v]

        self.model = estimator.model_
        self.filtered = [np.asarray(f, dtype=float) for f in as_list(estimator.x_filtered_)]
        self.times = [np.asarray(t, dtype=float) for t in as_list(estimator.t_)]
        u = getattr(estimator, "u_", None)
        self.inputs = [None] * len(self.filtered) if u is None else [np.asarray(v, float) for v in as_list(u)]
        self.coef = np.asarray(estimator.coef_, dtype=float)
        self.estimator = estimator
        self.segment_periods = SEGMENT_PERIODS if rings_down else SUSTAINED_PERIODS
        self.starts = [_starts(ref, t, self.segment_periods) for ref, t in zip(self.filtered, self.times)]


def _starts(reference: np.ndarray, t: np.ndarray, periods: float) -> np.ndarray:
    """First sample of each simulated segment: one simulation for short ring-downs, restarts every
    ``periods`` periods for long ones and for sustained oscillations."""
    limit = AUTO_PERIODS if periods == SEGMENT_PERIODS else 2 * periods
    if oscillation_count(reference) <= limit:
        return np.zeros(1, dtype=np.int64)
    return Segmented(segment_periods=periods).prepare(reference, t)[0]


def segments(fitted: Fitted) -> list[np.ndarray]:
    """Per trajectory, the first sample of each simulated segment (see :func:`simulate_residuals`)."""
    return fitted.starts


def simulate_residuals(
    model, fitted: Fitted, coef=None, start_offset=None, stride: int = 1
) -> list[np.ndarray]:
    """Per trajectory, ``model``'s simulation minus the filtered states (NaN where it diverged).

    Ring-downs of more than ``AUTO_PERIODS`` periods are simulated in segments of ``SEGMENT_PERIODS``
    periods, each from the filtered state at its start (phase drift over hundreds of periods is not an
    error of the model's structure); data that do not ring down (a limit cycle, a chaotic attractor) in
    segments of ``SUSTAINED_PERIODS``. ``coef`` replaces the model's active coefficients; ``start_offset``
    (n_states,) is added to every segment's initial state.

    ``stride`` > 1 returns the residual at every ``stride``-th sample only, simulated on those samples
    (and the segments' first samples) as the error measures simulate a finely sampled record
    (:class:`~sindy_impulse.simulation.scoring.WeightedL1`): the integrator's sub-steps follow the model's
    time scale, not the sampling, so the samples skipped between them add steps but no accuracy. A
    trajectory with inputs is simulated at every sample (the inputs may change between the compared ones).
    """
    extra = {} if coef is None else {"coef": coef}
    out = []
    for (ref, t, starts, compared), u in zip(simulation_grid(fitted, stride), fitted.inputs):
        if u is None and starts.size > 1 and hasattr(model, "simulate_segments"):  # one run of the kernel
            x0s = ref[starts] if start_offset is None else ref[starts] + start_offset
            residual = model.simulate_segments(x0s, t, starts, **extra) - ref
        else:
            ends = np.append(starts[1:], ref.shape[0] - 1)
            sim = np.full_like(ref, np.nan)
            for a, b in zip(starts, ends):
                inputs = None if u is None else u[a : b + 1]
                x0 = ref[a] if start_offset is None else ref[a] + start_offset
                sim[a : b + 1] = model.simulate(x0, t[a : b + 1], u=inputs, **extra)
            residual = sim - ref
        out.append(residual if compared is None else residual[compared])
    return out


def simulation_grid(fitted: Fitted, stride: int = 1) -> list[tuple]:
    """Per trajectory, the samples :func:`simulate_residuals` simulates and those it returns:
    ``(ref, t, starts, compared)``, the filtered states and times on the simulated samples, the segments'
    first samples among them, and which of them are compared (None: all)."""
    out = []
    for ref, t, u, starts in zip(fitted.filtered, fitted.times, fitted.inputs, segments(fitted)):
        compared = None
        if stride > 1 and u is None:  # simulated on the compared samples and the segments' starts
            compared = np.arange(0, ref.shape[0], stride)
            keep = np.union1d(compared, starts)
            compared = np.searchsorted(keep, compared)
            ref, t, starts = ref[keep], t[keep], np.searchsorted(keep, starts)
        elif stride > 1:  # inputs: simulated at every sample
            compared = np.arange(0, ref.shape[0], stride)
        out.append((ref, t, starts, compared))
    return out


def simulation_residuals(fitted: Fitted) -> list[np.ndarray]:
    """The fitted model's :func:`simulate_residuals`."""
    return simulate_residuals(fitted.model, fitted)


def fit_error(residuals, fitted: Fitted, level: np.ndarray) -> np.ndarray:
    """Per state: RMS of the simulation's deviation over the RMS of the filtered state about its level
    (inf where the simulation diverged)."""
    r = np.vstack(residuals)
    x = np.vstack(fitted.filtered) - level
    den = np.sqrt(np.mean(x**2, axis=0))
    err = np.sqrt(np.mean(r**2, axis=0))
    err = np.where(np.all(np.isfinite(r), axis=0), err, np.inf)
    return np.where(den > 0, err / np.where(den > 0, den, 1.0), np.where(err > 0, np.inf, 0.0))


def _derivative(x: np.ndarray, t: np.ndarray, order: int, stride: int = 1) -> np.ndarray:
    """Central differences of second or fourth order (uniform ``t``; second order otherwise), NaN ends, at
    every ``stride``-th sample (each from its neighbours only: the samples between are not differenced)."""
    steps = np.diff(t)
    n = x.shape[0]
    if order == 2 or n < 5 or np.ptp(steps) > 1e-6 * np.mean(steps):
        if stride == 1:
            return np.gradient(x, t, axis=0)
        return _gradient_at(x, t, np.arange(0, n, stride))
    rows = np.arange(0, n, stride)
    out = np.full((rows.size, x.shape[1]), np.nan)
    inner = (rows >= 2) & (rows < n - 2)
    i = rows[inner]
    out[inner] = (x[i - 2] - 8 * x[i - 1] + 8 * x[i + 1] - x[i + 2]) / (12 * np.mean(steps))
    return out


def _gradient_at(x: np.ndarray, t: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """``np.gradient(x, t, axis=0)[rows]`` (second order inside, first order at the ends) from the rows'
    neighbours only."""
    n = x.shape[0]
    out = np.empty((rows.size, x.shape[1]))
    inner = (rows > 0) & (rows < n - 1)
    i = rows[inner]
    h1 = (t[i] - t[i - 1])[:, None]
    h2 = (t[i + 1] - t[i])[:, None]
    out[inner] = (-h2 / (h1 * (h1 + h2)) * x[i - 1] + (h2 - h1) / (h1 * h2) * x[i]
                  + h1 / (h2 * (h1 + h2)) * x[i + 1])  # fmt: skip
    out[rows == 0] = (x[1] - x[0]) / (t[1] - t[0])
    out[rows == n - 1] = (x[n - 1] - x[n - 2]) / (t[n - 1] - t[n - 2])
    return out


def regression(fitted: Fitted, shift: np.ndarray, order: int = 2, stride: int = 1):
    """Library matrix on the (shifted) filtered states and their derivatives by central differences, at
    every ``stride``-th sample."""
    joined = [
        (f - shift if u is None else np.hstack([f - shift, u]))[::stride]
        for f, u in zip(fitted.filtered, fitted.inputs)
    ]
    # as the fit builds it (stages.prepare): from the library's terms where the simulator knows them (a
    # polynomial library's matrix bit for bit, without PySINDy's per-call overhead), else its transform
    terms = library_terms(fitted.estimator.feature_library_, joined[0].shape[1])
    evaluate = terms.evaluate if isinstance(terms, TermTable) else terms
    theta = np.vstack([np.asarray(evaluate(j)) for j in joined])
    y = np.vstack([_derivative(f, t, order, stride) for f, t in zip(fitted.filtered, fitted.times)])
    return theta, y


def _explained(base: np.ndarray, order: int = 3) -> np.ndarray:
    """Frequencies a model's response may show: sums and differences of up to ``order`` of its own
    frequencies (harmonics and intermodulation products of a nonlinear model)."""
    base = np.unique(np.round(base, 9))[:6]
    n = _small_integer_vectors(base.size, order)
    n = n[np.any(n != 0, axis=1)]  # without the zero vector
    combos = n @ base
    return np.unique(combos[combos > 0])


@functools.lru_cache(maxsize=32)
def _small_integer_vectors(size: int, order: int) -> np.ndarray:
    """Every integer vector of ``size`` entries whose absolute values sum to at most ``order``, in
    lexicographic order: a few hundred of the ``(2 order + 1)^size`` a full grid would enumerate and
    filter."""
    if size == 0:
        return np.zeros((1, 0), dtype=np.int64)
    blocks = []
    for v in range(-order, order + 1):
        rest = _small_integer_vectors(size - 1, order - abs(v))
        blocks.append(np.hstack([np.full((rest.shape[0], 1), v, dtype=np.int64), rest]))
    return np.vstack(blocks)


def _response_peaks(fitted: Fitted, residuals) -> np.ndarray:
    """Spectral peaks of the model's simulated response (first trajectory, every state)."""
    sim = residuals[0] + fitted.filtered[0]
    t = fitted.times[0]
    if sim.shape[0] < 128 or not np.all(np.isfinite(sim)):
        return np.empty(0)
    stride = compare_stride(sim)  # at most 200 samples per period: long records stay cheap
    sim = sim[::stride]
    fs = (t.size - 1) / float(t[-1] - t[0]) / stride
    out = []
    for j in range(sim.shape[1]):
        y = sim[:, j] - np.mean(sim[int(0.75 * sim.shape[0]) :, j])
        if np.ptp(y) > 0:
            peaks = spectral_peaks(y, fs, f_range=(2 * fs / y.size, 0.45 * fs), refine=False)  # cheap
            out.extend(peaks.frequency_hz.tolist())
    return np.asarray(out)


def frequency_agreement(fitted: Fitted, checks, residuals):
    """The model's damped modal frequencies and how far the data's spectral peaks are from the model's.

    The frequencies a model explains are its damped modal frequencies ``f_n sqrt(1 - zeta^2)``, the
    spectral peaks of its simulated response (a weakly nonlinear model rings at amplitude-dependent
    frequencies), and their sums and differences of up to third order (harmonics, intermodulation). Each
    significant peak of the measured states (:class:`~sindy_impulse.diagnostics.data.DataChecks`) within
    ``STRONG_DB`` of the highest must lie on one within the larger of 5 % and its half-power width, and
    the highest on a modal frequency or a peak of the response. Skipped (NaN) when the model's linear
    part does not describe it (:data:`~sindy_impulse.poles.modal.MIN_LINEAR_SHARE`) or no peak stands
    out of the noise.

    Returns
    -------
    model_hz : ndarray
    mismatch : float
        Worst relative distance of a peak to the nearest frequency the model explains (NaN: skipped).
    disagree : bool
        A peak lies beyond its tolerance.
    share : float
        The model's linear share (:func:`~sindy_impulse.poles.modal.linear_share`).
    """
    modes, share = model_modes(fitted.estimator)
    model_hz = modes.frequencies_hz * np.sqrt(np.clip(1 - modes.damping_ratios**2, 0, None))
    peaks = checks.peaks_hz
    if peaks.size == 0 or not share >= MIN_LINEAR_SHARE:
        return model_hz, float("nan"), False, share
    response = _response_peaks(fitted, residuals)
    own = np.concatenate([model_hz, response])
    if own.size == 0:
        return model_hz, float("inf"), True, share
    explained = _explained(own)
    tol = np.maximum(0.05, checks.peak_widths_hz / peaks)
    top = int(np.argmax(checks.peak_heights_db))
    strong = checks.peak_heights_db >= checks.peak_heights_db[top] - STRONG_DB
    miss = np.array([np.min(np.abs(explained / f - 1)) for f in peaks])
    fundamental = float(np.min(np.abs(own / peaks[top] - 1)))
    disagree = bool(np.any((miss > tol) & strong) or fundamental > tol[top])
    return model_hz, float(max(np.max(np.where(strong, miss, 0.0)), fundamental)), disagree, share


def support_condition(fitted: Fitted, shift: np.ndarray) -> float:
    """Condition number of the library columns of the model's terms (each scaled to unit norm)."""
    active = np.flatnonzero(np.any(fitted.coef != 0, axis=0))
    if active.size < 2:
        return 1.0
    theta, _ = regression(fitted, shift, stride=compare_stride(fitted.filtered[0]))  # cheap on long records
    cols = theta[:, active]
    cols = cols[np.all(np.isfinite(cols), axis=1)]
    norms = np.linalg.norm(cols, axis=0)
    if cols.shape[0] < active.size or not np.all(norms > 0):
        return np.inf
    singular = np.linalg.svd(cols / norms, compute_uv=False)
    return float(singular[0] / singular[-1]) if singular[-1] > 0 else np.inf

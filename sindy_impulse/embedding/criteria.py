"""The criteria behind DelayEmbedding's automatic delay and dimension, for one signal.

Delay: the autocorrelation function (first zero crossing) and the auto mutual information (first
minimum). Dimension: the fraction of false nearest neighbours (Kennel, Brown & Abarbanel 1992) and Cao's
``E1``/``E2`` statistics (Cao 1997). Each takes a 1-D signal; :class:`~sindy_impulse.DelayEmbedding`
applies them channel by channel.
"""

from __future__ import annotations

import warnings
from numbers import Integral

import numpy as np
from scipy.spatial import cKDTree

from ..exceptions import DataWarning

__all__ = ["autocorrelation", "auto_mutual_information", "false_nearest_neighbours", "cao_statistics"]

# Fewest embedded points a nearest-neighbour statistic is computed on; dimensions that leave fewer are not
# tested.
MIN_NEIGHBOUR_POINTS = 10


# ----------------------------------------------------------------------------------------------------------
# Estimators of the delay
# ----------------------------------------------------------------------------------------------------------
def autocorrelation(s: np.ndarray, max_lag: int) -> np.ndarray:
    """Normalized autocorrelation ``r(k)``, ``k = 0..max_lag``, of a 1-D signal (mean removed, biased).

    ``r(k) = sum_n (s_n - mean)(s_(n+k) - mean) / sum_n (s_n - mean)**2``, computed with an FFT in
    O(N log N).

    Examples
    --------
    >>> r = autocorrelation(np.cos(np.arange(400) * np.pi / 20), 25)
    >>> float(r[0]), int(np.argmax(r <= 0))
    (1.0, 10)
    """
    x = s - s.mean()
    n = x.size
    n_fft = 1 << (2 * n - 1).bit_length()
    spectrum = np.fft.rfft(x, n_fft)
    r = np.fft.irfft(spectrum * np.conj(spectrum), n_fft)[: max_lag + 1]
    return r / r[0]


def first_zero_crossing(acf: np.ndarray) -> float:
    """Lag of the first zero of ``acf``, linearly interpolated between the bracketing lags; NaN if none."""
    below = np.flatnonzero(acf[1:] <= 0)
    if below.size == 0:
        return float("nan")
    k = int(below[0]) + 1
    return (k - 1) + acf[k - 1] / (acf[k - 1] - acf[k])


def _equiprobable_bins(s: np.ndarray, n_bins: int) -> np.ndarray:
    """Bin index (0..n_bins-1) of every sample, bins holding about equally many samples (quantile edges).

    Equal values always share a bin, so quantized (ADC) signals are not split by time order.
    """
    edges = np.quantile(s, np.linspace(0.0, 1.0, n_bins + 1)[1:-1])
    return np.searchsorted(edges, s, side="right")


def auto_mutual_information(s: np.ndarray, lags, n_bins: int) -> np.ndarray:
    """Auto mutual information ``I(s_n; s_(n+k))`` in nats for each lag ``k`` in ``lags``.

    Histogram estimator on equiprobable (quantile) bins, i.e. on the rank-transformed signal: a decaying
    ring-down has most samples near zero, where equal-width bins would lump them together.

    Examples
    --------
    >>> from sindy_impulse.datasets import damped_oscillator
    >>> s = damped_oscillator().x[:, 0]  # period about 80 samples
    >>> mi = auto_mutual_information(s, range(0, 41), n_bins=8)
    >>> int(np.argmin(mi))  # about a quarter period
    21

    A noise-free, exactly periodic sine sampled at a rational fraction of its period gives a jagged curve
    (the bin transitions repeat at fixed phases): the first minimum then comes too early.
    """
    codes = _equiprobable_bins(s, n_bins)
    n = s.size
    out = np.empty(len(lags))
    for i, k in enumerate(lags):
        joint = np.bincount(codes[: n - k] * n_bins + codes[k:], minlength=n_bins * n_bins)
        p = joint.reshape(n_bins, n_bins) / (n - k)
        p_x = p.sum(axis=1)
        p_y = p.sum(axis=0)
        nz = p > 0
        out[i] = np.sum(p[nz] * np.log(p[nz] / np.outer(p_x, p_y)[nz]))
    return out


def first_minimum(curve: np.ndarray, half_width: int) -> int | None:
    """First lag ``k >= 1`` whose value is the smallest within ``k +- half_width`` and lower than ``k-1``."""
    n = curve.size
    for k in range(1, n - half_width):
        lo = max(0, k - half_width)
        window = curve[lo : k + half_width + 1]
        if curve[k] < curve[k - 1] and curve[k] <= window.min():
            return k
    return None


# ----------------------------------------------------------------------------------------------------------
# Estimators of the dimension
# ----------------------------------------------------------------------------------------------------------
def delay_matrix(s: np.ndarray, tau: int, m: int) -> np.ndarray:
    """Rows ``[s_(n-(m-1)tau), ..., s_(n-tau), s_n]`` for ``n = (m-1)tau .. N-1`` (a new array)."""
    n_rows = s.size - (m - 1) * tau
    windows = np.lib.stride_tricks.sliding_window_view(s, (m - 1) * tau + 1)
    return np.array(windows[:n_rows, ::tau], dtype=float, order="C")


def _nearest_neighbours(points: np.ndarray, theiler_window: int, p: float):
    """Distance to and index of each point's nearest neighbour at least ``theiler_window + 1`` samples away.

    One vectorized KD-tree query: among ``2 w + 2`` nearest points at most ``2 w + 1`` (the point itself
    included) lie within the Theiler window ``w``, so at least one candidate is admissible.
    """
    n = points.shape[0]
    k = min(2 * theiler_window + 2, n)
    dist, idx = cKDTree(points).query(points, k=k, p=p)
    admissible = np.abs(idx - np.arange(n)[:, None]) > theiler_window
    first = np.argmax(admissible, axis=1)
    rows = np.arange(n)
    return dist[rows, first], idx[rows, first]


def max_testable_dimension(n_samples: int, tau: int, max_dimension: int, theiler_window: int) -> int:
    """Largest ``d <= max_dimension`` whose (d+1)-dimensional embedding leaves enough points to test."""
    min_points = max(MIN_NEIGHBOUR_POINTS, 2 * theiler_window + 3)
    return min(max_dimension, (n_samples - min_points) // tau)


def false_nearest_neighbours(
    s: np.ndarray,
    tau: int,
    dimensions,
    ratio_threshold: float = 10.0,
    amplitude_threshold: float = 2.0,
    theiler_window: int = 0,
) -> np.ndarray:
    """Fraction of false nearest neighbours (Kennel et al. 1992) for each embedding dimension ``d``.

    For every point of the ``d``-dimensional embedding its nearest neighbour (Euclidean, outside the
    Theiler window) is found; the pair is false if adding the next delay coordinate ``s_(n-d tau)`` moves
    them apart by more than ``ratio_threshold`` times their distance ``R_d``, or if their distance in
    ``d + 1`` dimensions exceeds ``amplitude_threshold`` times the standard deviation of the signal.
    Only the points that exist in ``d + 1`` dimensions are used.
    """
    spread = np.std(s)
    out = np.empty(len(dimensions))
    for i, d in enumerate(dimensions):
        extended = delay_matrix(s, tau, d + 1)
        added, points = extended[:, 0], extended[:, 1:]
        r_d, nn = _nearest_neighbours(points, theiler_window, p=2)
        gap = np.abs(added - added[nn])
        # written without division: a duplicate point (R_d = 0) is false iff the new coordinate differs
        distance_criterion = gap > ratio_threshold * r_d
        amplitude_criterion = np.sqrt(r_d**2 + gap**2) > amplitude_threshold * spread
        out[i] = np.mean(distance_criterion | amplitude_criterion)
    return out


def cao_statistics(s: np.ndarray, tau: int, dimensions, theiler_window: int = 0):
    """Cao's (1997) ``E1(d) = E(d+1)/E(d)`` and ``E2(d) = E*(d+1)/E*(d)`` for each ``d`` in ``dimensions``.

    ``E(d)`` is the mean over points of ``a(i, d) = ||y_i(d+1) - y_n(d+1)|| / ||y_i(d) - y_n(d)||``
    (maximum norm, ``n`` the nearest neighbour of ``i`` in ``d`` dimensions; pairs at distance zero are
    skipped), ``E*(d)`` the mean of ``|s_(i-d tau) - s_(n-d tau)|``. ``E1`` saturates near 1 from the
    embedding dimension on; ``E2`` near 1 for all ``d`` indicates a stochastic signal.
    """
    dims = list(dimensions) + [dimensions[-1] + 1]
    e = np.empty(len(dims))
    e_star = np.empty(len(dims))
    for i, d in enumerate(dims):
        extended = delay_matrix(s, tau, d + 1)
        added, points = extended[:, 0], extended[:, 1:]
        r_d, nn = _nearest_neighbours(points, theiler_window, p=np.inf)
        gap = np.abs(added - added[nn])
        moved = r_d > 0
        e[i] = np.mean(np.maximum(r_d[moved], gap[moved]) / r_d[moved]) if moved.any() else np.nan
        e_star[i] = np.mean(gap)
    with np.errstate(divide="ignore", invalid="ignore"):
        return e[1:] / e[:-1], e_star[1:] / e_star[:-1]


# ----------------------------------------------------------------------------------------------------------
# The choices of DelayEmbedding, one channel at a time
# ----------------------------------------------------------------------------------------------------------
# Half width (in lags) of the window in which a mutual-information value must be the smallest to count as
# the first minimum: ignores estimator wiggles of one or two lags.
_MI_MINIMUM_HALF_WIDTH = 2
_MI_BLOCK = 64


def estimate_tau(s: np.ndarray, method: str, max_lag: int | None, mi_bins, name: str = "s"):
    """The delay of one signal and its diagnostic curves ``{"acf_": ..., "acf_zero_crossing_": ...}``.

    ``method`` is ``"acf"`` (first zero crossing, rounded to the nearest lag) or ``"mutual_information"``
    (first minimum on ``mi_bins`` equiprobable bins, ``"auto"``: ``max(4, floor(sqrt(N / 5)))``).
    """
    n = s.size
    max_lag = min(n // 2 if max_lag is None else max_lag, n - 1)
    if max_lag < 1:
        raise ValueError(f"{name} has {n} samples; at least 3 are needed to estimate tau")
    if method == "acf":
        acf = autocorrelation(s, max_lag)
        crossing = first_zero_crossing(acf)
        if not np.isfinite(crossing):
            raise ValueError(
                f"the autocorrelation of {name} has no zero crossing within lags 0..{max_lag} (an overdamped "
                "or trend-dominated signal?); pass tau as an int, raise max_lag or use "
                "delay_method='mutual_information'"
            )
        diagnostics = {"acf_": acf, "acf_zero_crossing_": float(crossing)}
        return max(1, int(np.floor(crossing + 0.5))), diagnostics

    n_bins = max(4, int(np.sqrt(n / 5))) if mi_bins == "auto" else int(mi_bins)
    curve = np.empty(0)
    minimum = None
    while curve.size <= max_lag:
        # extend block by block; stop once the first minimum is found and the curve reaches twice it
        stop = min(max_lag, curve.size + _MI_BLOCK - 1)
        curve = np.concatenate([curve, auto_mutual_information(s, range(curve.size, stop + 1), n_bins)])
        if minimum is None:
            minimum = first_minimum(curve, _MI_MINIMUM_HALF_WIDTH)
        if minimum is not None and curve.size > 2 * minimum:
            break
    if minimum is None:
        raise ValueError(
            f"the auto mutual information of {name} has no minimum within lags 0..{max_lag}; pass tau as "
            "an int, raise max_lag or use delay_method='acf'"
        )
    return int(minimum), {"mutual_information_": curve[: 2 * minimum + 1]}


def estimate_dimension(s: np.ndarray, tau: int, est, name: str = "s"):
    """The dimension of one signal by ``est.dimension_method``, whether one passed, and the curves.

    ``est`` carries the settings (a :class:`~sindy_impulse.DelayEmbedding`). Returns ``(dimension, passed,
    criterion, diagnostics)``: ``passed`` is False when no tested dimension met the criterion (the best
    tested one is returned), ``criterion`` describes it for a warning.
    """
    top = max_testable_dimension(s.size, tau, est.max_dimension, est.theiler_window)
    if top < 1:
        needed = tau + max(MIN_NEIGHBOUR_POINTS, 2 * est.theiler_window + 3)
        raise ValueError(
            f"{name} has {s.size} samples, too short to estimate the dimension with tau={tau}: at least "
            f"{needed} are needed (tau + {needed - tau} neighbour points); pass dimension as an int"
        )
    dims = np.arange(1, top + 1)
    diagnostics = {"candidate_dimensions_": dims}
    if est.dimension_method == "fnn":
        curve = false_nearest_neighbours(
            s, tau, dims, est.fnn_ratio_threshold, est.fnn_amplitude_threshold, est.theiler_window
        )
        diagnostics["fnn_fraction_"] = curve
        passed = curve < est.fnn_fraction_threshold
        best_if_none = int(dims[np.argmin(curve)])
        criterion = f"false-neighbour fraction < {est.fnn_fraction_threshold}"
    else:
        e1, e2 = cao_statistics(s, tau, dims, est.theiler_window)
        diagnostics["cao_e1_"], diagnostics["cao_e2_"] = e1, e2
        passed = e1 >= est.cao_threshold
        best_if_none = int(dims[np.nanargmax(e1)]) if np.isfinite(e1).any() else int(dims[-1])
        criterion = f"Cao's E1 >= {est.cao_threshold}"
    if passed.any():
        return int(dims[np.argmax(passed)]), True, criterion, diagnostics
    return best_if_none, False, criterion, diagnostics


#: The diagnostic curves of one channel (DelayEmbedding's attributes of the same names).
DIAGNOSTICS = (
    "acf_",
    "acf_zero_crossing_",
    "mutual_information_",
    "candidate_dimensions_",
    "fnn_fraction_",
    "cao_e1_",
    "cao_e2_",
)


def _filtered(signal: np.ndarray) -> np.ndarray:
    """The TVRegDiff-filtered signal (unit sample spacing: the filter is unit-free)."""
    from ..differentiation import TVRegDiff

    if signal.size < 16:  # too short to filter meaningfully; estimate on the raw samples
        return signal
    diff = TVRegDiff(tol=1e-2)  # a loose tolerance is plenty for estimating tau and m (3x faster)
    diff(signal[:, None], 1.0)
    return np.asarray(diff.smoothed_x_, dtype=float)[:, 0]


def estimate_channels(arr: np.ndarray, est):
    """Delay and dimension of every channel of ``arr`` (n_samples, n_channels) and their common values.

    ``est`` carries the settings (a :class:`~sindy_impulse.DelayEmbedding`; an int ``tau`` or
    ``dimension`` is taken as given). The common delay is the median of the channels' delays (rounded), the
    common dimension the largest of the channels' dimensions estimated at that delay. Returns ``(tau,
    dimension, channel_taus, channel_dimensions, curves)`` with one dict of :data:`DIAGNOSTICS` per channel.
    """
    n_channels = arr.shape[1]
    names = ["s"] if n_channels == 1 else [f"s[:, {j}]" for j in range(n_channels)]
    fixed_tau = isinstance(est.tau, Integral) and not isinstance(est.tau, bool)
    fixed_dim = isinstance(est.dimension, Integral) and not isinstance(est.dimension, bool)
    signals = [arr[:, j] for j in range(n_channels)]
    if est.denoise and not (fixed_tau and fixed_dim):
        signals = [_filtered(sig) for sig in signals]
    curves = [dict.fromkeys(DIAGNOSTICS) for _ in range(n_channels)]
    taus = np.full(n_channels, est.tau if fixed_tau else 0, dtype=int)
    if not fixed_tau:
        for j, sig in enumerate(signals):
            taus[j], found = estimate_tau(sig, est.delay_method, est.max_lag, est.mi_bins, names[j])
            curves[j].update(found)
    tau = int(np.floor(np.median(taus) + 0.5))
    dims = np.full(n_channels, est.dimension if fixed_dim else 0, dtype=int)
    if not fixed_dim:
        for j, sig in enumerate(signals):
            dims[j], passed, criterion, found = estimate_dimension(sig, tau, est, names[j])
            curves[j].update(found)
            if not passed:
                top = found["candidate_dimensions_"][-1]
                which = "" if n_channels == 1 else f" of {names[j]}"
                warnings.warn(
                    f"no dimension in 1..{top}{which} meets the criterion ({criterion}); using dimension "
                    f"{dims[j]}, the best tested. The signal may be noise-dominated or too short; consider "
                    "passing dimension",
                    DataWarning,
                    stacklevel=4,
                )
    return tau, int(dims.max()), taus, dims, curves

"""Time-delay embedding of one measured signal (Takens), with automatic delay and dimension.

Section 2.2 of Stender, Oberst & Hoffmann (2019): a scalar ring-down ``s(t_n)`` is rearranged into the
``m``-variate trajectory

    x(t_n) = [s_(n-(m-1)tau), ..., s_(n-tau), s_n],

with the delay ``tau`` from the first zero of the autocorrelation function (or the first minimum of the
auto mutual information) and the dimension ``m`` from the false nearest neighbours algorithm (Kennel,
Brown & Abarbanel 1992) or Cao's method (Cao 1997). The embedded states are named ``q1, ..., qm`` as in the
paper's Fig. 9b and Table 1: ``q1`` is the most delayed copy, ``qm`` the undelayed signal.
"""

from __future__ import annotations

import warnings
from numbers import Integral, Real

import numpy as np
from scipy.spatial import cKDTree
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted

from ._validation import check_signal, check_time, time_vector

__all__ = ["DelayEmbedding"]

_DELAY_METHODS = ("acf", "mutual_information")
_DIMENSION_METHODS = ("fnn", "cao")
# Fewest embedded points a nearest-neighbour statistic is computed on; dimensions that leave fewer are not
# tested.
_MIN_NEIGHBOUR_POINTS = 10
# Half width (in lags) of the window in which a mutual-information value must be the smallest to count as
# the first minimum: ignores estimator wiggles of one or two lags.
_MI_MINIMUM_HALF_WIDTH = 2
_MI_BLOCK = 64


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


def _first_zero_crossing(acf: np.ndarray) -> float:
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


def _first_minimum(curve: np.ndarray, half_width: int) -> int | None:
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
def _delay_matrix(s: np.ndarray, tau: int, m: int) -> np.ndarray:
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


def _max_testable_dimension(n_samples: int, tau: int, max_dimension: int, theiler_window: int) -> int:
    """Largest ``d <= max_dimension`` whose (d+1)-dimensional embedding leaves enough points to test."""
    min_points = max(_MIN_NEIGHBOUR_POINTS, 2 * theiler_window + 3)
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
        extended = _delay_matrix(s, tau, d + 1)
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
        extended = _delay_matrix(s, tau, d + 1)
        added, points = extended[:, 0], extended[:, 1:]
        r_d, nn = _nearest_neighbours(points, theiler_window, p=np.inf)
        gap = np.abs(added - added[nn])
        moved = r_d > 0
        e[i] = np.mean(np.maximum(r_d[moved], gap[moved]) / r_d[moved]) if moved.any() else np.nan
        e_star[i] = np.mean(gap)
    with np.errstate(divide="ignore", invalid="ignore"):
        return e[1:] / e[:-1], e_star[1:] / e_star[:-1]


# ----------------------------------------------------------------------------------------------------------
# The transformer
# ----------------------------------------------------------------------------------------------------------
def _is_int(value) -> bool:
    return isinstance(value, Integral) and not isinstance(value, bool)


def _is_real(value) -> bool:
    return isinstance(value, Real) and not isinstance(value, bool) and np.isfinite(value)


class DelayEmbedding(TransformerMixin, BaseEstimator):
    """Time-delay embedding of one signal, with delay and dimension estimated as in Stender et al. (2019).

    ``transform`` turns a signal ``s`` of ``N`` samples into the ``(N - (m-1) tau, m)`` trajectory whose row
    for sample ``n`` is ``[s_(n-(m-1)tau), ..., s_(n-tau), s_n]`` (columns ``q1 .. qm``; the last column is
    the undelayed signal). Row ``j`` belongs to time ``t[(m-1) tau + j]``: see :meth:`transform_time`.

    Parameters
    ----------
    tau : "auto" or int >= 1, default="auto"
        Delay in samples. ``"auto"`` estimates it with ``delay_method``; an int skips the estimation.
    dimension : "auto" or int >= 1, default="auto"
        Embedding dimension ``m``. ``"auto"`` estimates it with ``dimension_method``; an int skips it.
    delay_method : {"acf", "mutual_information"}, default="acf"
        ``"acf"``: first zero crossing of the autocorrelation (the paper), linearly interpolated between
        lags and rounded to the nearest lag. ``"mutual_information"``: first minimum (not the global one) of
        the auto mutual information, estimated on equiprobable bins; a lag counts as the minimum if it is
        the smallest within +-2 lags.
    dimension_method : {"fnn", "cao"}, default="fnn"
        ``"fnn"``: the smallest dimension whose false-nearest-neighbour fraction is below
        ``fnn_fraction_threshold``. ``"cao"``: the smallest dimension ``d`` with Cao's ``E1(d) >=
        cao_threshold``.
    max_lag : int or None, default=None
        Largest lag searched for the delay; ``None`` means ``N // 2``.
    max_dimension : int, default=10
        Largest dimension tested; reduced automatically when the signal is too short to test it (at least
        10 embedded points are kept).
    fnn_ratio_threshold : float, default=10.0
        Kennel's ``R_tol``: a neighbour is false if the added coordinate separates the pair by more than this
        times their distance.
    fnn_amplitude_threshold : float, default=2.0
        Kennel's ``A_tol``: a neighbour is false if the pair's distance in ``d + 1`` dimensions exceeds this
        times the standard deviation of the signal.
    fnn_fraction_threshold : float, default=0.1
        The dimension is the first at which the false-neighbour fraction falls below this value.
    cao_threshold : float, default=0.9
        Level at which Cao's ``E1`` counts as saturated.
    theiler_window : int, default=0
        Neighbours closer in time than or as close as this many samples are excluded (0 excludes only the
        point itself). Kept at 0 by default: on a ring-down (a spiral into the origin) a Theiler window
        makes the FNN fraction rise with dimension.
    mi_bins : "auto" or int >= 2, default="auto"
        Number of equiprobable bins of the mutual-information estimator; ``"auto"`` is
        ``max(4, floor(sqrt(N / 5)))`` (Cellucci et al. 2005).
    denoise : bool, default=True
        Estimate the delay and the dimension on the signal filtered by :class:`~sindy_impulse.TVRegDiff`
        (its time-integrated derivative, the paper's filtering of section 2.3) instead of the raw signal.
        Measurement noise makes false neighbours look real: on the paper's x1 at 30 dB the raw signal gives
        ``m = 3`` in 20 of 20 seeds, the filtered one ``m = 2`` in 20 of 20. ``transform`` always embeds the
        signal it is given.

    Attributes
    ----------
    tau_ : int
        Delay used, in samples.
    dimension_ : int
        Embedding dimension used.
    offset_ : int
        ``(dimension_ - 1) * tau_``: the number of leading samples without a complete delay vector.
    acf_ : ndarray of shape (max_lag + 1,) or None
        Autocorrelation for lags ``0..max_lag`` (``delay_method="acf"`` with ``tau="auto"``).
    acf_zero_crossing_ : float or None
        Interpolated lag of its first zero crossing, before rounding to ``tau_``.
    mutual_information_ : ndarray or None
        Auto mutual information (nats) for lags ``0, 1, ...``, computed up to at least twice the chosen
        lag (``delay_method="mutual_information"`` with ``tau="auto"``).
    candidate_dimensions_ : ndarray of int or None
        Dimensions ``d`` tested, ``1, 2, ...``; the curves below are indexed like it.
    fnn_fraction_ : ndarray or None
        False-nearest-neighbour fraction per tested dimension (``dimension_method="fnn"``).
    cao_e1_, cao_e2_ : ndarray or None
        Cao's ``E1(d)`` and ``E2(d)`` per tested dimension (``dimension_method="cao"``).
    n_features_in_ : int
        Always 1.

    Notes
    -----
    The embedding shortens the series by ``offset_`` samples. In a scikit-learn ``Pipeline`` the next step
    receives the ``(N - offset_, m)`` array; align a time vector with :meth:`transform_time`. Input with more
    than one column is refused: embed one signal at a time.

    Examples
    --------
    >>> from sindy_impulse.datasets import damped_oscillator
    >>> ring_down = damped_oscillator()
    >>> emb = DelayEmbedding().fit(ring_down.x[:, 0])
    >>> emb.tau_, emb.dimension_
    (18, 2)
    >>> q = emb.transform(ring_down.x[:, 0])
    >>> q.shape, emb.get_feature_names_out().tolist()
    ((383, 2), ['q1', 'q2'])
    >>> emb.transform_time(ring_down.t)[0]  # time of the first row: 18 * 0.01 s
    np.float64(0.18)
    >>> emb.delay_labels(dt=0.01)
    ['s(t-0.18)', 's(t)']
    """

    def __init__(
        self,
        tau="auto",
        dimension="auto",
        *,
        delay_method: str = "acf",
        dimension_method: str = "fnn",
        max_lag: int | None = None,
        max_dimension: int = 10,
        fnn_ratio_threshold: float = 10.0,
        fnn_amplitude_threshold: float = 2.0,
        fnn_fraction_threshold: float = 0.1,
        cao_threshold: float = 0.9,
        theiler_window: int = 0,
        mi_bins="auto",
        denoise: bool = True,
    ):
        self.tau = tau
        self.dimension = dimension
        self.delay_method = delay_method
        self.dimension_method = dimension_method
        self.max_lag = max_lag
        self.max_dimension = max_dimension
        self.fnn_ratio_threshold = fnn_ratio_threshold
        self.fnn_amplitude_threshold = fnn_amplitude_threshold
        self.fnn_fraction_threshold = fnn_fraction_threshold
        self.cao_threshold = cao_threshold
        self.theiler_window = theiler_window
        self.mi_bins = mi_bins
        self.denoise = denoise

    # ------------------------------------------------------------------ validation
    def _validate_params(self) -> None:
        def auto_or_int(name: str, value, minimum: int) -> None:
            if not (value == "auto" if isinstance(value, str) else _is_int(value) and value >= minimum):
                raise ValueError(f"{name} must be 'auto' or an int >= {minimum}, got {value!r}")

        auto_or_int("tau", self.tau, 1)
        auto_or_int("dimension", self.dimension, 1)
        auto_or_int("mi_bins", self.mi_bins, 2)
        if not isinstance(self.denoise, (bool, np.bool_)):
            raise TypeError(f"denoise must be True or False, got {self.denoise!r}")
        if self.delay_method not in _DELAY_METHODS:
            raise ValueError(f"delay_method must be one of {_DELAY_METHODS}, got {self.delay_method!r}")
        if self.dimension_method not in _DIMENSION_METHODS:
            raise ValueError(
                f"dimension_method must be one of {_DIMENSION_METHODS}, got {self.dimension_method!r}"
            )
        if self.max_lag is not None and not (_is_int(self.max_lag) and self.max_lag >= 1):
            raise ValueError(f"max_lag must be None or an int >= 1, got {self.max_lag!r}")
        if not (_is_int(self.max_dimension) and self.max_dimension >= 1):
            raise ValueError(f"max_dimension must be an int >= 1, got {self.max_dimension!r}")
        if not (_is_int(self.theiler_window) and self.theiler_window >= 0):
            raise ValueError(f"theiler_window must be an int >= 0, got {self.theiler_window!r}")
        for name in (
            "fnn_ratio_threshold",
            "fnn_amplitude_threshold",
            "fnn_fraction_threshold",
            "cao_threshold",
        ):
            value = getattr(self, name)
            if not (_is_real(value) and value > 0):
                raise ValueError(f"{name} must be a positive finite number, got {value!r}")

    @staticmethod
    def _filtered(signal: np.ndarray) -> np.ndarray:
        """The TVRegDiff-filtered signal (unit sample spacing: the filter is unit-free)."""
        from .differentiation import TVRegDiff

        if signal.size < 16:  # too short to filter meaningfully; estimate on the raw samples
            return signal
        diff = TVRegDiff(tol=1e-2)  # a loose tolerance is plenty for estimating tau and m (3x faster)
        diff(signal[:, None], 1.0)
        return np.asarray(diff.smoothed_x_, dtype=float)[:, 0]

    @staticmethod
    def _check_1d(s, min_samples: int = 1) -> np.ndarray:
        """Validate one signal: 1-D or one column, finite, numeric; returns a 1-D float array."""
        arr = check_signal(s, "s", ndim=(1, 2), min_samples=min_samples)
        if arr.shape[1] != 1:
            raise ValueError(
                f"s has {arr.shape[1]} columns (features), but DelayEmbedding is expecting 1 feature as "
                "input: it embeds a single signal, pass a 1-D array or one column at a time"
            )
        return arr[:, 0]

    @staticmethod
    def _check_length(n_samples: int, tau: int, dimension: int, what: str = "s") -> None:
        needed = (dimension - 1) * tau + 1
        if n_samples < needed:
            raise ValueError(
                f"{what} has {n_samples} samples, but tau={tau} and dimension={dimension} need at least "
                f"{needed} ((dimension - 1) * tau + 1)"
            )

    # ------------------------------------------------------------------ estimation
    def _estimate_tau(self, s: np.ndarray) -> int:
        n = s.size
        max_lag = min(n // 2 if self.max_lag is None else self.max_lag, n - 1)
        if max_lag < 1:
            raise ValueError(f"s has {n} samples; at least 3 are needed to estimate tau")
        if self.delay_method == "acf":
            self.acf_ = autocorrelation(s, max_lag)
            crossing = _first_zero_crossing(self.acf_)
            if not np.isfinite(crossing):
                raise ValueError(
                    f"the autocorrelation of s has no zero crossing within lags 0..{max_lag} (an overdamped "
                    "or trend-dominated signal?); pass tau as an int, raise max_lag or use "
                    "delay_method='mutual_information'"
                )
            self.acf_zero_crossing_ = float(crossing)
            return max(1, int(np.floor(crossing + 0.5)))

        n_bins = max(4, int(np.sqrt(n / 5))) if self.mi_bins == "auto" else int(self.mi_bins)
        curve = np.empty(0)
        minimum = None
        while curve.size <= max_lag:
            # extend block by block; stop once the first minimum is found and the curve reaches twice it
            stop = min(max_lag, curve.size + _MI_BLOCK - 1)
            curve = np.concatenate([curve, auto_mutual_information(s, range(curve.size, stop + 1), n_bins)])
            if minimum is None:
                minimum = _first_minimum(curve, _MI_MINIMUM_HALF_WIDTH)
            if minimum is not None and curve.size > 2 * minimum:
                break
        self.mutual_information_ = curve[: 2 * minimum + 1] if minimum is not None else curve
        if minimum is None:
            raise ValueError(
                f"the auto mutual information of s has no minimum within lags 0..{max_lag}; pass tau as an "
                "int, raise max_lag or use delay_method='acf'"
            )
        return int(minimum)

    def _estimate_dimension(self, s: np.ndarray, tau: int) -> int:
        top = _max_testable_dimension(s.size, tau, self.max_dimension, self.theiler_window)
        if top < 1:
            needed = tau + max(_MIN_NEIGHBOUR_POINTS, 2 * self.theiler_window + 3)
            raise ValueError(
                f"s has {s.size} samples, too short to estimate the dimension with tau={tau}: at least "
                f"{needed} are needed (tau + {needed - tau} neighbour points); pass dimension as an int"
            )
        dims = np.arange(1, top + 1)
        self.candidate_dimensions_ = dims
        if self.dimension_method == "fnn":
            curve = false_nearest_neighbours(
                s, tau, dims, self.fnn_ratio_threshold, self.fnn_amplitude_threshold, self.theiler_window
            )
            self.fnn_fraction_ = curve
            passed = curve < self.fnn_fraction_threshold
            best_if_none = int(dims[np.argmin(curve)])
            criterion = f"false-neighbour fraction < {self.fnn_fraction_threshold}"
        else:
            e1, e2 = cao_statistics(s, tau, dims, self.theiler_window)
            self.cao_e1_, self.cao_e2_ = e1, e2
            passed = e1 >= self.cao_threshold
            best_if_none = int(dims[np.nanargmax(e1)]) if np.isfinite(e1).any() else int(dims[-1])
            criterion = f"Cao's E1 >= {self.cao_threshold}"
        if passed.any():
            return int(dims[np.argmax(passed)])
        warnings.warn(
            f"no dimension in 1..{top} meets the criterion ({criterion}); using dimension {best_if_none}, "
            "the best tested. The signal may be noise-dominated or too short; consider passing dimension",
            UserWarning,
            stacklevel=3,
        )
        return best_if_none

    # ------------------------------------------------------------------ sklearn API
    def fit(self, s, y=None):
        """Estimate (or take) the delay ``tau_`` and the dimension ``dimension_`` of signal ``s``.

        Parameters
        ----------
        s : array-like of shape (n_samples,) or (n_samples, 1)
            One measured signal, uniformly sampled (list, ndarray, pandas Series or one-column frame).
        y : None
            Ignored; present for Pipeline compatibility.

        Returns
        -------
        self : DelayEmbedding
        """
        self._validate_params()
        signal = self._check_1d(s)
        if np.ptp(signal) <= 8 * np.finfo(float).eps * np.max(np.abs(signal)):
            raise ValueError(
                f"s is constant (all {signal.size} samples equal {signal[0]!r}); a constant signal "
                "cannot be embedded"
            )
        self.acf_ = self.acf_zero_crossing_ = self.mutual_information_ = None
        self.candidate_dimensions_ = self.fnn_fraction_ = self.cao_e1_ = self.cao_e2_ = None

        estimate_on = signal
        if self.denoise and not (_is_int(self.tau) and _is_int(self.dimension)):
            estimate_on = self._filtered(signal)
        tau = self.tau if _is_int(self.tau) else self._estimate_tau(estimate_on)
        if _is_int(self.dimension):
            dimension = self.dimension
        else:
            dimension = self._estimate_dimension(estimate_on, tau)
        self._check_length(signal.size, tau, dimension)
        self.tau_ = int(tau)
        self.dimension_ = int(dimension)
        self.offset_ = (self.dimension_ - 1) * self.tau_
        self.n_features_in_ = 1
        return self

    def transform(self, s) -> np.ndarray:
        """Delay vectors ``[s_(n-(m-1)tau), ..., s_(n-tau), s_n]`` for ``n = (m-1)tau .. N-1``.

        Parameters
        ----------
        s : array-like of shape (n_samples,) or (n_samples, 1)
            A signal (not necessarily the one passed to :meth:`fit`) with at least ``offset_ + 1`` samples.

        Returns
        -------
        ndarray of shape (n_samples - offset_, dimension_)
        """
        check_is_fitted(self, "tau_")
        signal = self._check_1d(s)
        self._check_length(signal.size, self.tau_, self.dimension_)
        return _delay_matrix(signal, self.tau_, self.dimension_)

    def transform_time(self, t, n_samples: int | None = None) -> np.ndarray:
        """Times of the rows of :meth:`transform`: ``t[offset_:]``.

        Parameters
        ----------
        t : float or array-like of shape (n_samples,)
            The signal's time vector, or its sampling step (then ``n_samples`` is required and the time
            vector is ``0, dt, 2 dt, ...``).
        n_samples : int, optional
            Number of samples of the signal when ``t`` is a step.

        Returns
        -------
        ndarray of shape (n_samples - offset_,)

        Examples
        --------
        >>> emb = DelayEmbedding(tau=3, dimension=3).fit(np.sin(np.arange(50.0)))
        >>> emb.transform_time(0.5, n_samples=10)
        array([3. , 3.5, 4. , 4.5])
        """
        check_is_fitted(self, "tau_")
        if np.ndim(t) == 0:
            if n_samples is None:
                raise ValueError("t is a time step; pass n_samples (the length of the signal) as well")
            if not (_is_int(n_samples) and n_samples >= 1):
                raise ValueError(f"n_samples must be a positive int, got {n_samples!r}")
            times = time_vector(check_time(t, n_samples), n_samples)
        else:
            times = np.asarray(check_time(t, np.size(t)), dtype=float)
            if n_samples is not None and times.size != n_samples:
                raise ValueError(f"t has {times.size} entries but n_samples={n_samples}")
        self._check_length(times.size, self.tau_, self.dimension_, what="t")
        return times[self.offset_ :].copy()

    def get_feature_names_out(self, input_features=None) -> np.ndarray:
        """Names ``q1 .. qm`` of the embedded states (``q1`` most delayed, ``qm = s(t)``), as in the paper.

        ``input_features`` is accepted for scikit-learn compatibility (one name at most) and does not
        change the names; see :meth:`delay_labels` for descriptive labels.
        """
        check_is_fitted(self, "tau_")
        if input_features is not None and len(input_features) != 1:
            raise ValueError(f"DelayEmbedding has 1 input feature, got input_features={input_features!r}")
        return np.asarray([f"q{i + 1}" for i in range(self.dimension_)], dtype=object)

    def delay_labels(self, dt: float | None = None, name: str = "s") -> list[str]:
        """Descriptive labels of the columns, e.g. ``['s(t-36)', 's(t-18)', 's(t)']`` (delays in samples).

        With ``dt`` the delays are in time units, formatted with up to 6 significant digits:
        ``['s(t-0.36)', 's(t-0.18)', 's(t)']``.
        """
        check_is_fitted(self, "tau_")
        if dt is not None:
            dt = check_time(dt, 1, name="dt")
        labels = []
        for j in range(self.dimension_ - 1, -1, -1):
            lag = j * self.tau_
            if lag == 0:
                labels.append(f"{name}(t)")
            elif dt is None:
                labels.append(f"{name}(t-{lag})")
            else:
                labels.append(f"{name}(t-{lag * dt:.6g})")
        return labels

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.one_d_array = True  # a single signal may be 1-D
        return tags

"""Time-delay embedding of measured signals (Takens), with automatic delay and dimension.

Section 2.2 of Stender, Oberst & Hoffmann (2019): a scalar ring-down ``s(t_n)`` is rearranged into the
``m``-variate trajectory

    x(t_n) = [s_(n-(m-1)tau), ..., s_(n-tau), s_n],

with the delay ``tau`` from the first zero of the autocorrelation function (or the first minimum of the
auto mutual information) and the dimension ``m`` from the false nearest neighbours algorithm (Kennel,
Brown & Abarbanel 1992) or Cao's method (Cao 1997). The embedded states are named ``q1, ..., qm`` as in the
paper's Fig. 9b and Table 1: ``q1`` is the most delayed copy, ``qm`` the undelayed signal. Several
channels recorded together are embedded side by side with a common delay and dimension. The criteria
themselves live in :mod:`sindy_impulse.embedding.criteria`.
"""

from __future__ import annotations

from numbers import Integral, Real

import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted

from .._utils.params import Interval, Options, validate_params
from .._utils.validation import check_signal, check_time, time_vector
from .criteria import DIAGNOSTICS as _DIAGNOSTICS
from .criteria import (
    delay_matrix,
    estimate_channels,
)

__all__ = ["DelayEmbedding"]

_POSITIVE = [Interval(Real, 0, None, "neither")]


class DelayEmbedding(TransformerMixin, BaseEstimator):
    """Time-delay embedding of signals, with delay and dimension estimated as in Stender et al. (2019).

    ``transform`` turns a signal ``s`` of ``N`` samples into the ``(N - (m-1) tau, m)`` trajectory whose row
    for sample ``n`` is ``[s_(n-(m-1)tau), ..., s_(n-tau), s_n]`` (columns ``q1 .. qm``; the last column is
    the undelayed signal). Row ``j`` belongs to time ``t[(m-1) tau + j]``: see :meth:`transform_time`.

    Several channels ``(N, c)`` (e.g. sensors of one structure) are embedded with one common delay and
    dimension, channel-major: the output has ``c * m`` columns ``[c0 q1..qm, c1 q1..qm, ...]``, named
    ``<channel>_q1 .. <channel>_qm`` by :meth:`get_feature_names_out`. With ``"auto"`` each channel is
    estimated on its own; the common delay is the median of the channels' delays, the common dimension the
    largest of their dimensions at that delay (``channel_taus_``, ``channel_dimensions_``). A 1-D input is
    one signal, as before.

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
    channel_taus_, channel_dimensions_ : ndarray of int of shape (n_channels,)
        Delay and dimension of each channel on its own (the given value where it was not estimated).
    n_features_in_ : int
        Number of channels.

    The curves ``acf_`` to ``cao_e2_`` are those of the single channel; with several channels each is a
    list with one entry per channel.

    Notes
    -----
    The embedding shortens the series by ``offset_`` samples (the next step gets ``(N - offset_, c * m)``):
    align the time vector with :meth:`transform_time`, measured inputs (forces) with :meth:`transform_input`.

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

    _parameter_constraints = {
        "tau": [Options({"auto"}), Interval(Integral, 1, None, "left")],
        "dimension": [Options({"auto"}), Interval(Integral, 1, None, "left")],
        "delay_method": [Options({"acf", "mutual_information"})],
        "dimension_method": [Options({"fnn", "cao"})],
        "max_lag": [None, Interval(Integral, 1, None, "left")],
        "max_dimension": [Interval(Integral, 1, None, "left")],
        "fnn_ratio_threshold": _POSITIVE,
        "fnn_amplitude_threshold": _POSITIVE,
        "fnn_fraction_threshold": _POSITIVE,
        "cao_threshold": _POSITIVE,
        "theiler_window": [Interval(Integral, 0, None, "left")],
        "mi_bins": [Options({"auto"}), Interval(Integral, 2, None, "left")],
        "denoise": ["boolean"],
    }

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

    def _check_channels(self, s, fitted: bool) -> np.ndarray:
        """Validate ``s``: 1-D (one signal) or (n_samples, n_channels), finite, numeric; returns it 2-D."""
        arr = check_signal(s, "s", ndim=(1, 2))
        if not fitted:
            return arr
        if arr.shape[1] != self.n_features_in_:
            hint = ""
            if np.ndim(s) == 1:
                hint = f"; a 1-D array is one signal: Reshape your data to (n_samples, {self.n_features_in_})"
            raise ValueError(
                f"X has {arr.shape[1]} features, but DelayEmbedding is expecting {self.n_features_in_} "
                f"features as input (s has {arr.shape[1]} channel(s)){hint}"
            )
        return arr

    @staticmethod
    def _check_length(n_samples: int, tau: int, dimension: int, what: str = "s") -> None:
        needed = (dimension - 1) * tau + 1
        if n_samples < needed:
            raise ValueError(
                f"{what} has {n_samples} samples, but tau={tau} and dimension={dimension} need at least "
                f"{needed} ((dimension - 1) * tau + 1)"
            )

    def fit(self, s, y=None):
        """Estimate (or take) the delay ``tau_`` and the dimension ``dimension_`` of ``s``.

        Parameters
        ----------
        s : array-like of shape (n_samples,) or (n_samples, n_channels)
            One measured signal (1-D, list, pandas Series) or several channels sampled together (2-D,
            DataFrame), uniformly sampled. Each channel gets its own estimate; the embedding uses the
            median of the channels' delays and the largest of their dimensions (estimated with that
            delay), see ``channel_taus_`` and ``channel_dimensions_``.
        y : None
            Ignored; present for Pipeline compatibility.

        Returns
        -------
        self : DelayEmbedding
        """
        validate_params(self)
        arr = self._check_channels(s, fitted=False)
        for j in range(arr.shape[1]):
            col = arr[:, j]
            if np.ptp(col) <= 8 * np.finfo(float).eps * np.max(np.abs(col)):
                which = "s" if arr.shape[1] == 1 else f"channel {j} of s"
                raise ValueError(
                    f"{which} is constant (all {col.size} samples equal {col[0]!r}); a constant signal "
                    "cannot be embedded"
                )
        tau, dimension, self.channel_taus_, self.channel_dimensions_, curves = estimate_channels(arr, self)
        for key in _DIAGNOSTICS:  # one channel: the curves themselves; several: a list per channel
            values = [c[key] for c in curves]
            setattr(self, key, values[0] if arr.shape[1] == 1 else values)
        self._check_length(arr.shape[0], tau, dimension)
        self.tau_ = int(tau)
        self.dimension_ = int(dimension)
        self.offset_ = (self.dimension_ - 1) * self.tau_
        self.n_features_in_ = arr.shape[1]
        return self

    def transform(self, s) -> np.ndarray:
        """Delay vectors of every channel, channel-major: ``[c0 q1..qm, c1 q1..qm, ...]``.

        Parameters
        ----------
        s : array-like of shape (n_samples,) or (n_samples, n_channels)
            Signals (not necessarily the ones passed to :meth:`fit`, the same number of channels) with at
            least ``offset_ + 1`` samples.

        Returns
        -------
        ndarray of shape ``(n_samples - offset_, n_channels * dimension_)``
            Row ``r`` holds ``[s_(n-(m-1)tau), ..., s_(n-tau), s_n]`` of channel 0, then of channel 1, ...
            for ``n = offset_ + r``.
        """
        check_is_fitted(self, "tau_")
        arr = self._check_channels(s, fitted=True)
        self._check_length(arr.shape[0], self.tau_, self.dimension_)
        blocks = [delay_matrix(arr[:, j], self.tau_, self.dimension_) for j in range(arr.shape[1])]
        return blocks[0] if len(blocks) == 1 else np.hstack(blocks)

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
        ndarray of shape ``(n_samples - offset_,)``

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
            if isinstance(n_samples, bool) or not (isinstance(n_samples, Integral) and n_samples >= 1):
                raise ValueError(f"n_samples must be a positive int, got {n_samples!r}")
            times = time_vector(check_time(t, n_samples), n_samples)
        else:
            times = np.asarray(check_time(t, np.size(t)), dtype=float)
            if n_samples is not None and times.size != n_samples:
                raise ValueError(f"t has {times.size} entries but n_samples={n_samples}")
        self._check_length(times.size, self.tau_, self.dimension_, what="t")
        return times[self.offset_ :].copy()

    def transform_input(self, u, delayed: bool = True) -> np.ndarray:
        """Inputs measured with the signal (e.g. the hammer force) aligned with the rows of :meth:`transform`.

        Row ``r`` of the embedding is the delay vector ending at sample ``n = offset_ + r``, so the input is
        cut by the same ``offset_`` leading samples. ``delayed=True`` gives the input at every delay of the
        row, ``[u_(n-(m-1)tau), ..., u_n]`` per channel (a delayed coordinate is driven by the input at its
        delay); ``delayed=False`` only ``u_n``. Embed forced records with a short ``tau`` (a few samples):
        the input between the delays is not seen.

        Examples
        --------
        >>> emb = DelayEmbedding(tau=2, dimension=2).fit(np.sin(np.arange(50.0)))
        >>> u = np.arange(6.0)
        >>> emb.transform_input(u).tolist()
        [[0.0, 2.0], [1.0, 3.0], [2.0, 4.0], [3.0, 5.0]]
        >>> emb.transform_input(u, delayed=False).ravel().tolist()
        [2.0, 3.0, 4.0, 5.0]
        """
        check_is_fitted(self, "tau_")
        arr = check_signal(u, "u")
        self._check_length(arr.shape[0], self.tau_, self.dimension_, what="u")
        if not delayed:
            return arr[self.offset_ :].copy()
        return np.hstack([delay_matrix(arr[:, j], self.tau_, self.dimension_) for j in range(arr.shape[1])])

    def _channel_names(self, names, what: str) -> list[str]:
        if names is None:
            return [f"x{j}" for j in range(self.n_features_in_)]
        names = [str(n) for n in names] if not isinstance(names, str) else [names]
        if len(names) != self.n_features_in_:
            raise ValueError(
                f"{what} has {len(names)} name(s) but DelayEmbedding was fitted on {self.n_features_in_} "
                f"channel(s), got {what}={names!r}"
            )
        return names

    def get_feature_names_out(self, input_features=None) -> np.ndarray:
        """Names of the embedded states, in the column order of :meth:`transform`.

        One channel: ``q1 .. qm`` as in the paper (``q1`` most delayed, ``qm = s(t)``); ``input_features``
        (one name at most) does not change them. Several channels: ``<channel>_q1 .. <channel>_qm`` for
        each channel in turn, the channels named by ``input_features`` (default ``x0, x1, ...``). See
        :meth:`delay_labels` for descriptive labels.

        Examples
        --------
        >>> t = np.arange(400) * 0.01
        >>> s = np.column_stack([np.sin(7 * t), np.cos(7 * t)]) * np.exp(-t)[:, None]
        >>> emb = DelayEmbedding(tau=20, dimension=2).fit(s)
        >>> emb.get_feature_names_out(["x", "v"]).tolist()
        ['x_q1', 'x_q2', 'v_q1', 'v_q2']
        """
        check_is_fitted(self, "tau_")
        states = [f"q{i + 1}" for i in range(self.dimension_)]
        if self.n_features_in_ == 1:
            if input_features is not None and len(input_features) != 1:
                raise ValueError(f"DelayEmbedding has 1 input feature, got input_features={input_features!r}")
            return np.asarray(states, dtype=object)
        channels = self._channel_names(input_features, "input_features")
        return np.asarray([f"{c}_{q}" for c in channels for q in states], dtype=object)

    def delay_labels(self, dt: float | None = None, name="s") -> list[str]:
        """Descriptive labels of the columns, e.g. ``['s(t-36)', 's(t-18)', 's(t)']`` (delays in samples).

        With ``dt`` the delays are in time units, formatted with up to 6 significant digits:
        ``['s(t-0.36)', 's(t-0.18)', 's(t)']``. Several channels: ``name`` is one name per channel (a
        single string ``s`` names them ``s0, s1, ...``); the labels follow the column order of
        :meth:`transform`.
        """
        check_is_fitted(self, "tau_")
        if dt is not None:
            dt = check_time(dt, 1, name="dt")
        if self.n_features_in_ == 1:
            channels = [name] if isinstance(name, str) else self._channel_names(name, "name")
        elif isinstance(name, str):
            channels = [f"{name}{j}" for j in range(self.n_features_in_)]
        else:
            channels = self._channel_names(name, "name")
        lags = [j * self.tau_ for j in range(self.dimension_ - 1, -1, -1)]
        shown = {lag: str(lag) if dt is None else f"{lag * dt:.6g}" for lag in lags}
        return [f"{c}(t)" if lag == 0 else f"{c}(t-{shown[lag]})" for c in channels for lag in lags]

"""SINDy coefficients as features of time series (paper section 3.4).

Each series of a collection is reconstructed by a clone of a template estimator (by default
:class:`~sindy_impulse.ImpulseSINDy` with a cubic polynomial library) and its coefficient matrix, flattened
row by row, becomes one feature row. Sparse coefficients discriminate ring-downs of different dynamics
(e.g. linear against Duffing oscillators) where generic time-series features do not.

The fits are independent, so they run in parallel with joblib. Nothing here chooses a joblib backend:
``with joblib.parallel_config(backend="dask"): features.fit_transform(X)`` runs the same code on a dask
cluster (a ``dask.distributed.Client`` must exist).
"""

from __future__ import annotations

import math
import warnings
from numbers import Integral, Real

import numpy as np
from joblib import Parallel, delayed, effective_n_jobs
from sklearn.base import BaseEstimator, TransformerMixin, clone
from sklearn.utils.validation import check_is_fitted

from .._utils.params import HasMethods, Interval, Options, Satisfies, validate_params
from .._utils.progress import progress_bar
from .._utils.threads import one_thread
from .._utils.validation import check_array
from ..embedding import DelayEmbedding
from ..exceptions import FitWarning

__all__ = ["SINDyFeatures", "as_series"]


def _default_estimator():
    import pysindy as ps

    from ..identification.estimator import ImpulseSINDy

    return ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=3))


def _fit_batch(estimator, batch, dt):
    """Fit a clone of ``estimator`` to each series of ``batch``.

    Returns one ``(coefficients or None, error message or None)`` per series; never raises for a series.
    A reconstruction fails when the fit raises, or its coefficients are not finite, or its model
    diverges (Gamma not finite), or it found no dynamics at all (every coefficient zero). Module level
    (not a closure) so that every joblib backend, dask included, can pickle it.
    """
    out = []
    # One BLAS thread in every worker and in the main process alike: joblib's workers run single-threaded
    # BLAS, and the same fits must give the same features whatever n_jobs is (small matrices gain nothing
    # from BLAS threads anyway).
    with one_thread():
        for series in batch:
            out.append(_fit_one(estimator, series, dt))
    return out


def _fit_one(estimator, series, dt):
    """``(coefficients, None)`` for a successful reconstruction, ``(None, message)`` for a failed one."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            model = clone(estimator).fit(series, t=dt)
            coef = np.asarray(model.coefficients(), dtype=float)
            if not np.all(np.isfinite(coef)):
                raise FloatingPointError("the reconstructed coefficients are not finite")
            if not np.isfinite(getattr(model, "gamma_", 0.0)):
                raise FloatingPointError("the reconstructed model diverges when simulated")
            if not np.any(coef):
                raise ValueError("no dynamics found: every coefficient is zero")
            if getattr(getattr(model, "diagnostics_", None), "verdict", None) == "no dynamics":  # noise
                raise ValueError("no dynamics found: " + "; ".join(model.diagnostics_.reasons.values()))
            return coef.ravel(), None
        except Exception as err:  # noqa: BLE001 - a failed series must never abort the batch
            notes = "; ".join(dict.fromkeys(str(w.message) for w in caught))
            return None, f"{type(err).__name__}: {err}" + (f" (warnings: {notes})" if notes else "")


def _round_significant(values: np.ndarray, digits: int) -> np.ndarray:
    """``values`` rounded to ``digits`` significant digits (zeros and NaN unchanged).

    >>> _round_significant(np.array([267.85412, -3.2000071, 0.0, 0.99999]), 4).tolist()
    [267.9, -3.2, 0.0, 1.0]
    """
    out = values.copy()
    ok = np.isfinite(values) & (values != 0)
    exponent = np.floor(np.log10(np.abs(values[ok]))) - (digits - 1)
    # divide by (or multiply with) exact powers of ten so that e.g. 267.9 comes out as the float 267.9
    up = 10.0 ** np.maximum(-exponent, 0)
    down = 10.0 ** np.maximum(exponent, 0)
    out[ok] = np.round(values[ok] * up / down) * down / up
    return out


def as_series(X) -> list[np.ndarray]:
    """Validate ``X`` and return a list of float arrays, each (n_times,) or (n_times, n_states).

    The checks of a value (dtype, NaN/inf, sparse, empty) are the shared ones of
    :mod:`sindy_impulse._utils.validation`; this only adds the layout of a collection of series.
    """
    if X is None:
        raise TypeError("X is None; expected a list of series or an array (n_series, n_times)")
    if isinstance(X, (list, tuple)):
        if len(X) == 0:
            raise ValueError("X is empty; expected at least one series")
        if not all(hasattr(s, "shape") or hasattr(s, "__len__") for s in X):
            raise TypeError("X must be a list of array-like series")
        items = [check_array(s, f"X[{i}]") for i, s in enumerate(X)]
    elif isinstance(X, (str, bytes)) or not (
        hasattr(X, "__array__") or hasattr(X, "to_numpy") or hasattr(X, "shape")
    ):
        raise TypeError(f"X must be a list of series or an array, got {type(X).__name__}")
    else:  # an array, DataFrame or array-like: one series per row
        if isinstance(X, np.ndarray) and X.dtype == object and any(np.ndim(v) > 0 for v in X.flat):
            raise ValueError("X is a ragged (object) array; pass a list of 1-D or 2-D arrays instead")
        arr = check_array(X, "X")  # a DataFrame: its rows
        if arr.ndim == 1:
            raise ValueError(
                f"X is 1-D (shape {arr.shape}); for a single series pass [series] or X.reshape(1, -1)"
            )
        if arr.ndim not in (2, 3):
            raise ValueError(
                "X must be 2-D (n_series, n_times) or 3-D (n_series, n_times, n_states), "
                f"got {arr.ndim}-D"
            )
        items = list(arr)

    out = []
    for i, arr in enumerate(items):
        if arr.ndim == 2 and arr.shape[1] == 1:
            arr = arr[:, 0]
        if arr.ndim not in (1, 2):
            raise ValueError(f"series {i} must be 1-D or 2-D (n_times, n_states), got shape {arr.shape}")
        out.append(arr)
    ndims = {a.ndim for a in out}
    if len(ndims) > 1:
        raise ValueError("X mixes univariate (1-D) and multivariate (2-D) series")
    widths = {a.shape[1] for a in out if a.ndim == 2}
    if len(widths) > 1:
        raise ValueError(f"all series must have the same number of states, got {sorted(widths)}")
    return out


#: Fewest samples (after embedding) a series must have: the library's terms plus this margin (the
#: differentiation discards samples at both ends).
_SAMPLE_MARGIN = 16


class SINDyFeatures(TransformerMixin, BaseEstimator):
    """Map a collection of time series to their SINDy coefficients, one feature row per series.

    Parameters
    ----------
    estimator : SINDy estimator, default=ImpulseSINDy(feature_library=PolynomialLibrary(degree=3))
        Template; a clone is fitted to every series (``fit(series, t=dt)``) and its ``coefficients()``
        (n_states, n_terms) flattened row by row are the features.
    dt : float, optional
        Sampling step of every series. Default: the estimator's ``dt`` if it has one, else 1 (time in
        samples: the coefficients are then per sample, still fine as features).
    embed : {"auto", False} or DelayEmbedding, default="auto"
        How univariate series are turned into states. ``"auto"``: delay-embed them with a delay and a
        dimension common to all series, estimated in :meth:`fit` (the median of the per-series delays
        and the most frequent per-series dimension, see :class:`~sindy_impulse.DelayEmbedding`) and then
        fixed, so that the features of all series, also those passed later to :meth:`transform`, live
        in the same coordinates. A :class:`~sindy_impulse.DelayEmbedding`: its integer ``tau`` and
        ``dimension`` are used as given (``"auto"`` ones are estimated as above). ``False``: a
        univariate series is a one-state system. Multivariate series are never embedded.
    n_jobs : int, optional
        Parallel jobs (joblib semantics: None is 1 unless inside a ``joblib.parallel_config`` context,
        -1 all cores). The backend is joblib's current one, so a dask cluster is used unchanged.
    progress : bool, default=False
        Show a tqdm progress bar over the batches (needs ``tqdm``: ``pip install sindy-impulse[progress]``).
    batch_size : int or "auto", default="auto"
        Series per parallel task; ``"auto"`` makes about four tasks per job.
    fill_failed : float, default=nan
        Value of the feature row of a series whose reconstruction failed. NaN keeps failures visible
        (``n_failed_``, ``failures_``) but stops e.g. PCA; use ``fill_failed=0.0`` or put a
        ``sklearn.impute.SimpleImputer`` after this step in a pipeline.
    significant_digits : int or None, default=4
        Round every coefficient to this many significant digits (None: no rounding). The refinement
        stops with a relative jitter of about 1e-5 in the coefficients; on clean data a coefficient that
        is the same for all series (e.g. the ``1.0`` of ``x0' = x1``) would otherwise vary by that
        jitter, and a ``StandardScaler`` downstream would blow the jitter up to unit variance.

    Attributes
    ----------
    n_states_ : int
        States per series seen by the estimator (the embedding dimension for univariate input).
    embedding_ : DelayEmbedding or None
        The fitted common embedding (None if the input was not embedded).
    feature_names_out_ : ndarray of str
        ``"<state>' : <term>"`` for each feature, e.g. ``"x1' : x0^3"``.
    n_failed_ : int
        Series whose reconstruction failed in the last :meth:`transform` (or :meth:`fit_transform`).
    failures_ : dict
        ``{series index: error message}`` for those series.

    Notes
    -----
    Input: a list of arrays (each (n_times,) univariate or (n_times, n_states)), a 2-D array
    (n_series, n_times) of univariate series, or a 3-D array (n_series, n_times, n_states). Series in a
    list may have different lengths. :meth:`fit` only settles the embedding and the feature names; the
    reconstructions are computed by :meth:`transform` (once by :meth:`fit_transform`).

    Examples
    --------
    >>> import numpy as np
    >>> from sindy_impulse import SINDyFeatures, damped_oscillator
    >>> series = [damped_oscillator(k=k, k_nl=k_nl).x for k, k_nl in [(64, 0), (100, 0), (64, 50)]]
    >>> features = SINDyFeatures(dt=0.01)
    >>> X = features.fit_transform(series)
    >>> X.shape, features.n_failed_
    ((3, 20), 0)
    >>> cubic = list(features.get_feature_names_out()).index("x1' : x0^3")
    >>> np.round(X[:, cubic], 1).tolist()
    [0.0, 0.0, -50.0]
    """

    _parameter_constraints = {
        "estimator": [None, HasMethods(("fit", "coefficients"), "a SINDy estimator (fit, coefficients)")],
        "dt": [None, Interval(Real, 0, None, "neither")],
        "embed": [Options({"auto"}), Satisfies(lambda v: v is False, "False"), DelayEmbedding],
        "n_jobs": [None, Integral],
        "progress": ["boolean"],
        "batch_size": [Options({"auto"}), Interval(Integral, 1, None, "left")],
        "fill_failed": [Real],
        "significant_digits": [None, Interval(Integral, 1, 15)],
    }

    def __init__(
        self,
        estimator=None,
        dt: float | None = None,
        embed="auto",
        n_jobs: int | None = None,
        progress: bool = False,
        batch_size="auto",
        fill_failed: float = np.nan,
        significant_digits: int | None = 4,
    ):
        self.estimator = estimator
        self.dt = dt
        self.embed = embed
        self.n_jobs = n_jobs
        self.progress = progress
        self.batch_size = batch_size
        self.fill_failed = fill_failed
        self.significant_digits = significant_digits

    # ------------------------------------------------------------------------------------------------
    # validation
    # ------------------------------------------------------------------------------------------------
    def _template(self):
        return clone(self.estimator) if self.estimator is not None else _default_estimator()

    def _dt(self, template) -> float:
        if self.dt is not None:
            return float(self.dt)
        dt = getattr(template, "dt", None)
        return float(dt) if dt is not None else 1.0

    # ------------------------------------------------------------------------------------------------
    # fit / transform
    # ------------------------------------------------------------------------------------------------
    def _fit_embedding(self, series):
        """The common delay embedding of univariate series (None if they are not embedded)."""
        if series[0].ndim == 2 or self.embed is False:
            return None
        base = self.embed if isinstance(self.embed, DelayEmbedding) else DelayEmbedding()
        fixed_tau = isinstance(base.tau, Integral) and not isinstance(base.tau, bool)
        fixed_dim = isinstance(base.dimension, Integral) and not isinstance(base.dimension, bool)
        if fixed_tau and fixed_dim:
            return clone(base).fit(series[0])
        taus, dims, errors = [], [], []
        for i, s in enumerate(series):
            try:
                emb = clone(base).fit(s)
            except ValueError as err:
                errors.append(f"series {i}: {err}")
                continue
            taus.append(emb.tau_)
            dims.append(emb.dimension_)
        if not taus:
            raise ValueError("no series could be embedded: " + "; ".join(errors[:3]))
        tau = base.tau if fixed_tau else int(round(float(np.median(taus))))
        if fixed_dim:
            dim = base.dimension
        else:
            values, counts = np.unique(dims, return_counts=True)
            dim = int(values[counts == counts.max()].max())
        return clone(base).set_params(tau=int(tau), dimension=int(dim)).fit(series[0])

    def fit(self, X, y=None):
        """Settle the embedding (univariate input) and the feature names.

        Parameters
        ----------
        X : list of arrays, array (n_series, n_times) or (n_series, n_times, n_states)
            The series (see the class Notes).
        y : None
            Ignored.

        Returns
        -------
        self
        """
        validate_params(self)
        series = as_series(X)
        self._fit_layout(series)
        return self

    def _fit_layout(self, series):
        template = self._template()
        self.embedding_ = self._fit_embedding(series)
        if self.embedding_ is not None:
            self.n_states_ = int(self.embedding_.dimension_)
            state_names = [str(n) for n in self.embedding_.get_feature_names_out()]
        else:
            self.n_states_ = 1 if series[0].ndim == 1 else int(series[0].shape[1])
            state_names = [f"x{i}" for i in range(self.n_states_)]
        self.state_names_ = state_names
        self.terms_ = self._term_names(template, state_names)
        self.feature_names_out_ = np.array(
            [f"{s}' : {term}" for s in state_names for term in self.terms_], dtype=object
        )
        self.min_samples_ = len(self.terms_) + _SAMPLE_MARGIN
        return template

    @staticmethod
    def _term_names(template, state_names) -> list[str]:
        """Names of the template library's terms over states called ``state_names``."""
        library = getattr(template, "feature_library", None)
        if library is None:
            import pysindy as ps

            library = ps.PolynomialLibrary(degree=3)
        library = clone(library)
        from pysindy.utils import AxesArray

        n_states = len(state_names)
        probe = np.linspace(0.5, 1.5, 4 * n_states).reshape(4, n_states)
        library.fit([AxesArray(probe, {"ax_time": 0, "ax_coord": 1})])
        return list(library.get_feature_names(input_features=state_names))

    def _states(self, series) -> list[np.ndarray]:
        """Each series as the (n_times, n_states) array the estimator is fitted to."""
        states = []
        for i, s in enumerate(series):
            if self.embedding_ is not None:
                if s.ndim != 1:
                    raise ValueError(
                        f"series {i} is multivariate but the transformer was fitted on univariate series"
                    )
                offset = self.embedding_.offset_
                if s.size < offset + self.min_samples_:
                    raise ValueError(
                        f"series {i} has {s.size} samples; at least {offset + self.min_samples_} are needed "
                        f"(embedding offset {offset} + {self.min_samples_})"
                    )
                states.append(self.embedding_.transform(s))
                continue
            arr = s[:, None] if s.ndim == 1 else s
            if arr.shape[1] != self.n_states_:
                raise ValueError(
                    f"series {i} has {arr.shape[1]} states but the transformer was fitted on {self.n_states_}"
                )
            if arr.shape[0] < self.min_samples_:
                raise ValueError(
                    f"series {i} has {arr.shape[0]} samples; at least {self.min_samples_} are needed"
                )
            states.append(arr)
        return states

    def transform(self, X) -> np.ndarray:
        """Reconstruct every series and return its coefficients.

        Parameters
        ----------
        X : list of arrays, array (n_series, n_times) or (n_series, n_times, n_states)

        Returns
        -------
        ndarray (n_series, n_states * n_terms)
            Row ``j``: the coefficients of series ``j``, equation by equation; ``fill_failed`` (NaN by
            default) for a series whose reconstruction failed (see ``n_failed_``, ``failures_``).
        """
        check_is_fitted(self, "feature_names_out_")
        validate_params(self)
        series = as_series(X)
        return self._transform(series, self._template())

    def fit_transform(self, X, y=None, **fit_params) -> np.ndarray:
        """:meth:`fit` then :meth:`transform` on the same series (each reconstructed once)."""
        validate_params(self)
        series = as_series(X)
        template = self._fit_layout(series)
        return self._transform(series, template)

    def _transform(self, series, template) -> np.ndarray:
        states = self._states(series)
        dt = self._dt(template)
        n = len(states)
        n_jobs = self.n_jobs
        n_workers = max(1, effective_n_jobs(n_jobs))
        size = self.batch_size if self.batch_size != "auto" else max(1, math.ceil(n / (4 * n_workers)))
        batches = [list(range(start, min(n, start + size))) for start in range(0, n, size)]
        tasks = (delayed(_fit_batch)(template, [states[i] for i in idx], dt) for idx in batches)
        parallel = Parallel(n_jobs=n_jobs, return_as="generator")
        results = parallel(tasks)
        if self.progress:
            results = progress_bar(results, total=len(batches), desc="SINDy fits", unit="batch")

        features = np.full((n, len(self.feature_names_out_)), np.nan)
        failures = {}
        for idx, batch_result in zip(batches, results, strict=True):
            for i, (row, message) in zip(idx, batch_result):
                if row is None:
                    failures[i] = message
                elif row.size != features.shape[1]:
                    failures[i] = f"ValueError: {row.size} coefficients, expected {features.shape[1]}"
                else:
                    features[i] = row
        if self.significant_digits is not None:
            features = _round_significant(features, self.significant_digits)
        self.failures_ = failures
        self.n_failed_ = len(failures)
        if failures:
            first = next(iter(failures.items()))
            warnings.warn(
                f"{len(failures)} of {n} reconstructions failed (see failures_); first: series {first[0]}: "
                f"{first[1]}",
                FitWarning,
                stacklevel=3,
            )
            if not np.isnan(self.fill_failed):
                features[list(failures)] = float(self.fill_failed)
        return features

    def get_feature_names_out(self, input_features=None) -> np.ndarray:
        """Feature names ``"<state>' : <term>"``, e.g. ``"x1' : x0^3"``.

        Parameters
        ----------
        input_features : list of str, optional
            Names of the states of multivariate series, e.g. ``["x", "v"]`` gives ``"v' : x^3"``
            (default ``x0, x1, ...``). Embedded series keep the embedding's names (``q1, q2, ...``);
            then ``input_features`` may name the one measured signal and changes nothing.

        Examples
        --------
        >>> from sindy_impulse import SINDyFeatures, damped_oscillator
        >>> features = SINDyFeatures(dt=0.01).fit([damped_oscillator().x])
        >>> [str(n) for n in features.get_feature_names_out(["x", "v"])[-2:]]
        ["v' : x v^2", "v' : v^3"]
        """
        check_is_fitted(self, "feature_names_out_")
        if input_features is None:
            return self.feature_names_out_.copy()
        names = [str(n) for n in input_features]
        if self.embedding_ is not None:
            self.embedding_.get_feature_names_out(names)  # one name (the measured signal), or ValueError
            return self.feature_names_out_.copy()
        if len(names) != self.n_states_:
            raise ValueError(f"input_features has {len(names)} names for {self.n_states_} states: {names}")
        terms = self._term_names(self._template(), names)
        return np.array([f"{s}' : {term}" for s in names for term in terms], dtype=object)

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.allow_nan = False
        tags.requires_fit = True
        return tags

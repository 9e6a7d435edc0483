"""The series of :class:`~sindy_impulse.features.SINDyFeatures` and their fits: validation of a
collection of series, the default estimator, the per-series fit that never raises (a failed series becomes
a message), batches for joblib workers, and the helpers of the transformer's output (significant-digit
rounding, the progress bar)."""

from __future__ import annotations

import warnings

import numpy as np
from sklearn.base import clone
from threadpoolctl import threadpool_limits

from ._validation import check_array


def _default_estimator():
    import pysindy as ps

    from .estimator import ImpulseSINDy

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
    with threadpool_limits(limits=1):
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


def _progress(iterable, total: int):
    try:
        from tqdm.auto import tqdm
    except ImportError:  # pragma: no cover - depends on the environment
        warnings.warn(
            "progress=True needs tqdm (pip install sindy-impulse[progress]); continuing without a bar",
            RuntimeWarning,
            stacklevel=4,
        )
        return iterable
    return tqdm(iterable, total=total, desc="SINDy fits", unit="batch")


def as_series(X) -> list[np.ndarray]:
    """Validate ``X`` and return a list of float arrays, each (n_times,) or (n_times, n_states).

    The checks of a value (dtype, NaN/inf, sparse, empty) are the shared ones of
    :mod:`sindy_impulse._validation`; this only adds the layout of a collection of series.
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

"""Input validation shared by every public entry point.

One place for the checks a data logger's output needs (NaN/inf, shape, dtype, time vector), so that
every class and function raises the same clear ``ValueError``/``TypeError`` naming the argument.
"""

from __future__ import annotations

from numbers import Real

import numpy as np

__all__ = ["check_array", "check_signal", "check_time", "time_vector"]


def _as_float_array(x, name: str) -> np.ndarray:
    """Convert ``x`` to a float array, refusing complex, non-numeric and empty input."""
    if x is None:
        raise TypeError(f"{name} is None; expected an array of numbers")
    if hasattr(x, "tocsr") or type(x).__module__.startswith("scipy.sparse"):
        raise TypeError(f"{name} is a sparse matrix; sparse input is not supported, pass a dense array")
    if hasattr(x, "to_numpy"):  # pandas DataFrame / Series
        x = x.to_numpy()
    try:
        arr = np.asarray(x)
    except ValueError as err:  # nested lists of unequal length
        raise ValueError(f"{name} is ragged ({err})") from None
    if arr.dtype == object:
        try:
            arr = arr.astype(float)
        except (TypeError, ValueError) as err:
            raise TypeError(f"{name} contains non-numeric entries ({err})") from None
    if np.iscomplexobj(arr):
        raise ValueError(f"{name} is complex: Complex data not supported, expected real-valued data")
    if not (np.issubdtype(arr.dtype, np.number) or arr.dtype == bool):
        raise TypeError(f"{name} has non-numeric dtype {arr.dtype}")
    if arr.ndim == 2 and arr.shape[0] > 0 and arr.shape[1] == 0:
        raise ValueError(f"{name} has 0 feature(s) (shape={arr.shape}) while a minimum of 1 is required.")
    if arr.size == 0:
        raise ValueError(f"{name} is empty (shape={arr.shape}): 0 sample(s)")
    return arr.astype(float, copy=False)


def _check_finite(arr: np.ndarray, name: str, allow_nan: bool, allow_inf: bool, advice: str = "") -> None:
    """Refuse NaN (unless ``allow_nan``) and inf (unless ``allow_inf``), locating the first one."""
    if allow_nan and allow_inf:
        return
    if allow_nan:
        bad = np.isinf(arr)
    elif allow_inf:
        bad = np.isnan(arr)
    else:
        bad = ~np.isfinite(arr)
    if bad.any():
        idx = np.argwhere(bad)[0]
        kind = "NaN" if np.isnan(arr[tuple(idx)]) else "inf"
        raise ValueError(
            f"{name} contains {int(bad.sum())} non-finite value(s) ({kind} first at index "
            f"{tuple(int(i) for i in idx)}){advice}"
        )


def check_array(
    x,
    name: str = "x",
    *,
    ndim: tuple[int, ...] | None = None,
    allow_nan: bool = False,
    allow_inf: bool = False,
) -> np.ndarray:
    """Validate a numeric array that is not a time series (coefficients, a system matrix, parameter values).

    The same checks as :func:`check_signal` (not None, dense, real, numeric, non-empty, finite) without
    its time-series conventions: any number of dimensions unless ``ndim`` is given, no reshaping and no
    sample count. Callers check their own layout (e.g. a square matrix) afterwards.

    Parameters
    ----------
    x : array-like
        The values.
    name : str
        Argument name used in error messages.
    ndim : tuple of int, optional
        Accepted numbers of dimensions (default: any).
    allow_nan, allow_inf : bool
        Accept NaN or infinite values.

    Returns
    -------
    numpy.ndarray
        ``x`` as a float array (not copied when it already is one).

    Examples
    --------
    >>> check_array([[[1, 0]], [[2, 0]]], "coefficients", ndim=(3,)).shape
    (2, 1, 2)
    >>> check_array([1j, 1.0], "values")
    Traceback (most recent call last):
    ...
    ValueError: values is complex: Complex data not supported, expected real-valued data
    """
    arr = _as_float_array(x, name)
    if ndim is not None and arr.ndim not in ndim:
        expected = " or ".join(f"{d}-D" for d in ndim)
        raise ValueError(f"{name} must be {expected}, got an array of shape {arr.shape}")
    _check_finite(arr, name, allow_nan, allow_inf)
    return arr


def check_signal(
    x,
    name: str = "x",
    *,
    ndim: tuple[int, ...] = (1, 2),
    min_samples: int = 1,
    as_2d: bool = True,
    allow_nan: bool = False,
    allow_inf: bool = False,
) -> np.ndarray:
    """Validate one measured signal or trajectory.

    Parameters
    ----------
    x : array-like
        Samples along axis 0 (time), states along axis 1.
    name : str
        Argument name used in error messages.
    ndim : tuple of int
        Accepted numbers of dimensions.
    min_samples : int
        Fewest samples (rows) the caller can use.
    as_2d : bool
        Return a 1-D input as a (n, 1) column.
    allow_nan, allow_inf : bool
        Accept NaN (e.g. the trimmed ends of a derivative, dropped later) or infinite values.

    Returns
    -------
    numpy.ndarray
        A float copy-free view of the data.

    Examples
    --------
    >>> check_signal([1.0, 2.0, 3.0]).shape
    (3, 1)
    """
    arr = _as_float_array(x, name)
    if arr.ndim not in ndim:
        expected = " or ".join(f"{d}-D" for d in ndim)
        hint = ""
        if arr.ndim == 1 and 2 in ndim:
            hint = f"; Reshape your data with {name}.reshape(-1, 1) for a single signal"
        raise ValueError(f"{name} must be {expected}, got an array of shape {arr.shape}{hint}")
    _check_finite(arr, name, allow_nan, allow_inf, "; remove or interpolate them first")
    if arr.shape[0] < min_samples:
        raise ValueError(f"{name} has {arr.shape[0]} samples; at least {min_samples} are needed")
    if as_2d and arr.ndim == 1:
        arr = arr[:, None]
    return arr


def check_time(t, n_samples: int, name: str = "t") -> float | np.ndarray:
    """Validate a time step or a time vector for ``n_samples`` samples.

    Returns the step as a float when ``t`` is a scalar, otherwise the strictly increasing 1-D time
    vector as a float array.

    Examples
    --------
    >>> check_time(0.01, 5)
    0.01
    >>> check_time([0.0, 0.1, 0.2], 3)
    array([0. , 0.1, 0.2])
    """
    if isinstance(t, (bool, np.bool_)):
        raise TypeError(f"{name} must be a time step or a time vector, got {t!r}")
    if isinstance(t, Real):
        dt = float(t)
        if not np.isfinite(dt) or dt <= 0:
            raise ValueError(f"{name} (time step) must be a positive finite number, got {t!r}")
        return dt
    arr = _as_float_array(t, name)
    if arr.ndim == 0:
        return check_time(float(arr), n_samples, name)
    if arr.ndim != 1:
        raise ValueError(f"{name} must be a scalar time step or a 1-D time vector, got shape {arr.shape}")
    if arr.shape[0] != n_samples:
        raise ValueError(f"{name} has {arr.shape[0]} entries but the data have {n_samples} samples")
    if not np.all(np.isfinite(arr)):
        i = int(np.argmax(~np.isfinite(arr)))
        raise ValueError(f"{name} contains NaN or inf ({name}[{i}]={arr[i]!r})")
    steps = np.diff(arr)
    if np.any(steps <= 0):
        i = int(np.argmax(steps <= 0))
        raise ValueError(
            f"{name} must be strictly increasing; {name}[{i + 1}]={arr[i + 1]!r} <= "
            f"{name}[{i}]={arr[i]!r}"
        )
    return arr


def time_vector(t: float | np.ndarray, n_samples: int) -> np.ndarray:
    """The time vector for validated ``t`` (a step gives 0, dt, 2 dt, ...)."""
    if np.ndim(t) == 0:
        return np.arange(n_samples) * float(t)
    return np.asarray(t, dtype=float)

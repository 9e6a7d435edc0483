"""One place that turns ``(y, t, fs)`` into a validated 1-D record, its sampling rate and start time."""

from __future__ import annotations

from numbers import Real

import numpy as np

from .._utils.validation import check_signal, check_time

__all__ = ["MIN_SAMPLES", "as_record", "check_fs", "check_signal_1d"]

#: Fewest samples a record must have: a spectrum, a noise estimate and a ring-down need some length.
MIN_SAMPLES = 64
#: Largest spread of the steps of a time vector, relative to the median step, still taken as uniform
#: (a CSV rounded to 8 significant digits spreads the steps by about 1e-3).
_UNIFORM_RTOL = 0.01


def check_fs(fs, name: str = "fs") -> float:
    """A sampling rate: a positive finite number (Hz).

    Examples
    --------
    >>> check_fs(5000)
    5000.0
    >>> check_fs(0)
    Traceback (most recent call last):
    ...
    ValueError: fs (sampling rate) must be a positive finite number of Hz, got 0
    """
    if isinstance(fs, (bool, np.bool_)) or not isinstance(fs, Real):
        raise TypeError(f"{name} (sampling rate) must be a number of Hz, got {fs!r}")
    if not np.isfinite(fs) or fs <= 0:
        raise ValueError(f"{name} (sampling rate) must be a positive finite number of Hz, got {fs!r}")
    return float(fs)


def check_signal_1d(y, name: str = "y", min_samples: int = MIN_SAMPLES) -> np.ndarray:
    """One channel as a 1-D float array: (n,) or (n, 1), finite, at least ``min_samples`` long."""
    arr = check_signal(y, name, ndim=(1, 2), min_samples=min_samples, as_2d=False)
    if arr.ndim == 2:
        if arr.shape[1] != 1:
            raise ValueError(f"{name} must be one channel, shape (n,) or (n, 1); got shape {arr.shape}")
        arr = arr[:, 0]
    return arr


def as_record(y, t=None, fs=None, *, name: str = "y", min_samples: int = MIN_SAMPLES):
    """Validate a record given with a time vector ``t`` (or step) and/or a sampling rate ``fs``.

    Returns
    -------
    (ndarray, float, float)
        The samples (1-D float), the sampling rate in Hz and the time of the first sample.

    Examples
    --------
    >>> y, fs, t0 = as_record(np.zeros(100), t=1.0 + np.arange(100) / 2000)
    >>> round(fs, 6), t0
    (2000.0, 1.0)
    """
    arr = check_signal_1d(y, name, min_samples)
    if t is None and fs is None:
        raise ValueError(f"give the sampling of {name}: a time vector t or a sampling rate fs")
    rate = None if fs is None else check_fs(fs)
    t0 = 0.0
    if t is not None:
        times = check_time(t, arr.size)
        if np.ndim(times) == 0:
            step = float(times)
        else:
            steps = np.diff(times)
            step = float(times[-1] - times[0]) / (times.size - 1)
            if np.max(np.abs(steps - step)) > _UNIFORM_RTOL * step:
                raise ValueError(
                    f"t is not uniformly sampled (steps from {steps.min():.6g} to {steps.max():.6g}); "
                    "resample the record to a constant step first"
                )
            t0 = float(times[0])
        if rate is not None and abs(rate * step - 1.0) > 1e-3:
            raise ValueError(f"t (step {step:.6g}) and fs={fs!r} disagree; give one of them")
        rate = 1.0 / step
    return arr, rate, t0

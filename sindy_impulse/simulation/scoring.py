"""Error measures: how well a model's simulation reproduces the reference states (paper section 2.4).

A measure receives what it needs to re-simulate -- the model (compiled or fallback), one reference
trajectory, its time vector, a batch of active-coefficient matrices and the control inputs -- and returns
one error per coefficient matrix. The built-in measures are weighted L1 errors computed by the fused
kernel (:meth:`CompiledModel.weighted_l1`): the fast path. Any Python function with the same signature is a
measure too (the general path); registering it by name makes it available to
``ImpulseSINDy(error_measure=name)``:

>>> import numpy as np
>>> from sindy_impulse.simulation import register_error_measure
>>> @register_error_measure("rms")
... def rms(model, reference, t, coefs, u=None):
...     sims = [model.simulate(reference[0], t, u=u, coef=c) for c in coefs]
...     return np.array([np.sqrt(np.mean((s - reference) ** 2)) for s in sims])

Built-in measures
-----------------
``"gamma"``
    The paper's Gamma: one simulation from the first sample, ``sum |x_sim - x_ref| / max|x_ref|`` over
    samples and states (each state normalised by its largest absolute value).
``"segmented"``
    Multiple shooting: the simulation restarts from the reference state every ``segment_periods`` periods
    of the record's dominant oscillation, and each segment's absolute errors are normalised by the
    segment's own amplitude (floored at ``min_scale`` times the record's), so phase drift cannot
    accumulate over hundreds of periods and every amplitude level weighs alike.
``"auto"``
    ``"gamma"`` for records of at most :data:`AUTO_PERIODS` periods, ``"segmented"`` for longer ones
    (:class:`Auto` chooses other measures the same way, e.g. ``Auto(long=Segmented(min_scale=0.3))``).
"""

from __future__ import annotations

import copy
from collections.abc import Callable

import numpy as np

from .._utils.validation import check_signal
from .sensitivity import weighted_l1_gradient

__all__ = [
    "gamma",
    "gamma_from_arrays",
    "ErrorMeasure",
    "WeightedL1",
    "Gamma",
    "Segmented",
    "Auto",
    "FunctionMeasure",
    "ERROR_MEASURES",
    "AUTO_PERIODS",
    "SAMPLES_PER_PERIOD",
    "compare_stride",
    "register_error_measure",
    "get_error_measure",
    "oscillation_count",
    "simulation_gamma",
]

#: Records with more periods than this are scored by ``"segmented"`` when ``error_measure="auto"``.
AUTO_PERIODS = 30
#: Most samples per period of a record's dominant oscillation at which the built-in measures compare a
#: simulation with the reference. A more finely sampled record is compared at every ``stride``-th sample,
#: each compared sample standing for ``stride`` samples; the simulation still takes the steps the model's
#: time scale needs, so the cost of a score depends on the model and the duration, not on the sampling.
SAMPLES_PER_PERIOD = 200


def oscillation_count(x: np.ndarray) -> float:
    """Periods of the most oscillating column of ``x`` (half its zero crossings, with hysteresis).

    The centred signal must cross +-0.1 standard deviations to count, so noise around zero does not.

    Examples
    --------
    >>> t = np.linspace(0, 10, 2001)
    >>> oscillation_count(np.cos(2 * np.pi * t))
    10.0
    """
    x = np.asarray(x, dtype=float).reshape(len(x), -1)
    mean = x.mean(axis=0)
    most = 0
    for j in range(x.shape[1]):  # one contiguous column at a time: a long record is read a few times only
        col = x[:, j] - mean[j]
        band = 0.1 * np.sqrt(np.dot(col, col) / col.size) if col.size else 0.0  # 0.1 standard deviation
        beyond = col[np.abs(col) > band] > 0  # the side of each sample outside the band
        most = max(most, int(np.count_nonzero(beyond[1:] != beyond[:-1])))
    return most / 2


def compare_stride(reference: np.ndarray) -> int:
    """Every how many samples the built-in measures compare (at most :data:`SAMPLES_PER_PERIOD` per period).

    A record without a full oscillation is compared at :data:`SAMPLES_PER_PERIOD` samples in all.

    Examples
    --------
    >>> t = np.linspace(0, 10, 200_001)
    >>> compare_stride(np.cos(2 * np.pi * t)), compare_stride(np.cos(2 * np.pi * t[::100]))
    (100, 1)
    """
    n = len(reference)
    periods = max(oscillation_count(reference), 1.0)
    return max(1, int(n // (SAMPLES_PER_PERIOD * periods)))


class ErrorMeasure:
    """Base class: a measure bound to reference trajectories, called on models.

    Subclasses implement :meth:`evaluate` (one trajectory, a batch of coefficient matrices) and, where the
    measure can be computed between two given arrays, :meth:`compare` (used for the noise level of the
    selection tolerance). :meth:`prepare` precomputes what depends on the reference only.
    """

    #: Name under which the measure is registered.
    name = "custom"
    #: Absolute tolerance per compared value (sample x state) below which models are indistinguishable.
    floor = 0.0

    def bind(self, references, times, inputs=None) -> ErrorMeasure:
        """Attach the reference trajectories (lists) and precompute; returns ``self``."""
        inputs = [None] * len(references) if inputs is None else list(inputs)
        self.trajectories_ = [
            (np.ascontiguousarray(r, dtype=float), np.ascontiguousarray(t, dtype=float), u)
            for r, t, u in zip(references, times, inputs)
        ]
        self.plans_ = [self.prepare(r, t) for r, t, _ in self.trajectories_]
        return self

    def prepare(self, reference: np.ndarray, t: np.ndarray):
        """What the measure precomputes per trajectory (default: nothing)."""
        return None

    def evaluate(self, model, reference, t, coefs, u, plan) -> np.ndarray:
        """Errors of the coefficient matrices ``coefs`` (n_models, n_states, n_active) on one trajectory."""
        raise NotImplementedError

    def compare(self, x_true: np.ndarray, x_other: np.ndarray, t: np.ndarray) -> float:
        """The measure between two given arrays (NaN when the measure cannot compare arrays)."""
        return float("nan")

    def __call__(self, model, coefs=None) -> np.ndarray:
        """Errors of ``coefs`` (default: the model's own), summed over the bound trajectories."""
        c = model.coef[None] if coefs is None else np.asarray(coefs, dtype=float)
        total = np.zeros(c.shape[0])
        for (ref, t, u), plan in zip(self.trajectories_, self.plans_):
            errors = np.asarray(self.evaluate(model, ref, t, c, u, plan), dtype=float).reshape(c.shape[0])
            total += np.where(np.isfinite(errors), errors, np.inf)
        return total

    def noise_level(self, raw, filtered, times) -> float:
        """The measure between the measured and the filtered states (what the filter removed); 0 if n/a."""
        value = sum(self.compare(r, f, t) for r, f, t in zip(raw, filtered, times))
        return float(value) if np.isfinite(value) else 0.0

    def __repr__(self) -> str:
        return f"{type(self).__name__}(name={self.name!r})"


class WeightedL1(ErrorMeasure):
    """Weighted L1 error of segment-restarted simulations: the fused-kernel family.

    Subclasses define the plan: segment starts and weights ``(n_segments, n_states)`` for the samples
    they are given. A finely sampled record is compared at every ``stride``-th sample (see
    :func:`compare_stride`; not with control inputs, which may change between those samples), with the
    weights multiplied by the stride, so a score still sums over the whole record.
    """

    floor = 1e-5  # a mean relative deviation of 1e-5: filter and integrator accuracy on clean data

    def bind(self, references, times, inputs=None) -> ErrorMeasure:
        inputs = [None] * len(references) if inputs is None else list(inputs)
        self.trajectories_, self.plans_, self.strides_ = [], [], []
        for r, t, u in zip(references, times, inputs):
            r, t, stride = self._compared(r, t, u is None)
            starts, weights = self.prepare(r, t)
            self.trajectories_.append((r, t, u))
            self.plans_.append((starts, weights * stride))
            self.strides_.append(stride)
        return self

    @staticmethod
    def _compared(reference, t, may_stride: bool = True):
        """The compared samples of a trajectory and their stride."""
        reference = np.asarray(reference, dtype=float).reshape(len(t), -1)
        stride = compare_stride(reference) if may_stride else 1
        return (
            np.ascontiguousarray(reference[::stride]),
            np.ascontiguousarray(np.asarray(t, dtype=float)[::stride]),
            stride,
        )

    def evaluate(self, model, reference, t, coefs, u, plan) -> np.ndarray:
        starts, weights = plan
        return model.weighted_l1(reference, t, starts, weights, coefs, u)[0]

    def bounded(self, model, cutoff: float, resume=None):
        """The model's error, or a lower bound of it once that passes ``cutoff``.

        A candidate whose error exceeds the best one found so far cannot be selected, whatever the rest of
        its simulation: the simulation stops there (:meth:`CompiledModel.weighted_l1_until`). Summed over
        the trajectories in the order :meth:`__call__` sums them, so an error that stays below ``cutoff``
        (or is resumed to the end) is the one :meth:`__call__` returns. A model without the bounded kernel
        runs whole.

        Parameters
        ----------
        model : CompiledModel or AtRestLevel
        cutoff : float
            ``inf``: run (or resume) to the end.
        resume : tuple, optional
            The ``progress`` of a stopped call on the same model: continue from there.

        Returns
        -------
        (error, finished, progress)
            ``finished`` False: ``error`` is a lower bound above ``cutoff``, ``progress`` where it stopped.
        """
        until = getattr(model, "weighted_l1_until", None)
        if until is None:
            return float(self(model)[0]), True, None
        first, inner, total = (0, None, np.zeros(1)) if resume is None else resume
        for j in range(first, len(self.trajectories_)):
            (ref, t, u), (starts, weights) = self.trajectories_[j], self.plans_[j]
            error, finished, inner = until(ref, t, starts, weights, cutoff - total[0], u, inner)
            if not finished:
                if total[0] + error > cutoff:
                    return float(total[0] + error), False, (j, inner, total.copy())
                error = until(ref, t, starts, weights, np.inf, u, inner)[0]  # passed only in rounding
            total += error if np.isfinite(error) else np.inf
            inner = None
        return float(total[0]), True, None

    def gradient(self, model, coef=None, entries=None):
        """The error of one active-coefficient matrix and its exact gradient by its ``entries`` (forward
        sensitivities, :func:`.sensitivity.weighted_l1_gradient`), summed over the bound trajectories; None
        where the model has no exact gradients (the caller differentiates numerically)."""
        total, gradient = 0.0, 0.0
        for (ref, t, u), (starts, weights) in zip(self.trajectories_, self.plans_):
            out = None if u is not None else weighted_l1_gradient(model, ref, t, starts, weights, coef,
                                                                  entries)
            if out is None:
                return None
            total, gradient = total + out[0], gradient + out[1]
        return total, gradient

    def compare(self, x_true, x_other, t) -> float:
        x_true, t, stride = self._compared(x_true, t)
        x_other = np.asarray(x_other, dtype=float).reshape(-1, x_true.shape[1])[::stride]
        starts, weights = self.prepare(x_true, t)
        segment = np.clip(np.searchsorted(starts, np.arange(len(t)), side="left") - 1, 0, None)
        value = float(np.sum(stride * weights[segment] * np.abs(x_true - x_other)))
        return value if np.isfinite(value) else np.inf


def _scale(x: np.ndarray) -> np.ndarray:
    """Each state's normaliser in Gamma: its largest magnitude (1 for a state that is identically 0)."""
    scale = np.max(np.abs(x), axis=0)
    return np.where(scale > 0, scale, 1.0)


def gamma_from_arrays(x_true: np.ndarray, x_recon: np.ndarray, scale: np.ndarray | None = None) -> float:
    """Gamma on validated float arrays of equal shape (the unchecked fast path).

    A reconstruction with any non-finite value gives ``inf``.
    """
    scale = _scale(x_true) if scale is None else scale
    value = float(np.sum(np.abs(x_true - x_recon) / scale))
    return value if np.isfinite(value) else np.inf


def gamma(x_true, x_recon) -> float:
    """The paper's reconstruction error Gamma (section 3.1).

    ``Gamma = sum_i sum_j |x_true_i(t_j) - x_recon_i(t_j)| / max_j |x_true_i(t_j)|``, summed over states
    ``i`` and samples ``j``: each state normalized by its largest absolute value, so that deflection and
    velocity weigh the same. A state that is identically zero is not normalized. A reconstruction that
    is non-finite anywhere (a diverged simulation) gives ``inf``. Lists of trajectories are summed.

    Parameters
    ----------
    x_true, x_recon : array-like of shape (n_samples,) or (n_samples, n_states), or lists of them
        The measured (or filtered) states and the simulated model states.

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> x = np.array([[1.0, 0.0], [0.5, -2.0]])
    >>> gamma(x, x)
    0.0
    >>> gamma(x, x + [0.1, 0.2])
    0.4
    """
    if isinstance(x_true, (list, tuple)) and x_true and hasattr(x_true[0], "shape"):
        if not isinstance(x_recon, (list, tuple)) or len(x_recon) != len(x_true):
            raise ValueError("x_recon must be a list with one reconstruction per trajectory in x_true")
        return float(sum(gamma(a, b) for a, b in zip(x_true, x_recon)))
    xt = check_signal(x_true, "x_true")
    # a diverged reconstruction (NaN/inf) is valid input: its Gamma is inf
    xr = check_signal(x_recon, "x_recon", allow_nan=True, allow_inf=True)
    if xr.shape != xt.shape:
        raise ValueError(f"x_recon has shape {xr.shape} but x_true has shape {xt.shape}")
    return gamma_from_arrays(xt, xr)


class Gamma(WeightedL1):
    """The paper's Gamma (one simulation from the first sample, states normalised by their maximum)."""

    name = "gamma"

    def prepare(self, reference, t):
        return np.zeros(1, dtype=np.int64), (1.0 / _scale(reference))[None, :]


class Segmented(WeightedL1):
    """Multiple shooting: restart every ``segment_periods`` periods, segment errors normalised.

    Parameters
    ----------
    segment_periods : float, default=8
        Length of a segment in periods of the record's dominant oscillation (at least 8 samples).
    min_scale : float, default=0.01
        Floor of a segment's normalising amplitude, relative to the record's largest: segments that have
        decayed into the noise do not dominate.
    """

    name = "segmented"

    def __init__(self, segment_periods: float = 8.0, min_scale: float = 0.01):
        self.segment_periods = segment_periods
        self.min_scale = min_scale

    def __repr__(self) -> str:
        return f"Segmented(segment_periods={self.segment_periods!r}, min_scale={self.min_scale!r})"

    def prepare(self, reference, t):
        n = reference.shape[0]
        periods = oscillation_count(reference)
        length = n if periods < 1 else int(round(self.segment_periods * n / periods))
        starts = np.arange(0, max(n - 1, 1), max(8, length), dtype=np.int64)
        ends = np.append(starts[1:], n - 1)
        floor = self.min_scale * _scale(reference)
        scales = np.array([np.max(np.abs(reference[a : b + 1]), axis=0) for a, b in zip(starts, ends)])
        return starts, 1.0 / np.maximum(scales, floor)


class FunctionMeasure(ErrorMeasure):
    """A measure from a function ``f(model, reference, t, coefs, u) -> errors`` (the general path).

    ``compare(x_true, x_other, t) -> float``, if given, lets the selection rule estimate the noise level.
    """

    def __init__(self, function: Callable, name: str = "custom", compare: Callable | None = None):
        self.function = function
        self.name = name
        self._compare = compare

    def evaluate(self, model, reference, t, coefs, u, plan) -> np.ndarray:
        return self.function(model, reference, t, coefs, u)

    def compare(self, x_true, x_other, t) -> float:
        return float("nan") if self._compare is None else float(self._compare(x_true, x_other, t))


class Auto(ErrorMeasure):
    """``"auto"`` with chosen measures: ``short`` for records of at most ``periods`` periods, else ``long``.

    Resolved when an estimator binds it to its data (the estimator's ``error_measure_`` then names the
    measure used).

    Parameters
    ----------
    short, long : str or ErrorMeasure, default="gamma", "segmented"
        The measures for short and for long records.
    periods : float, default=AUTO_PERIODS
        The longest record, in periods of its dominant oscillation, that counts as short.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 100, 4001)
    >>> x = np.column_stack([np.cos(2 * np.pi * t), -np.sin(2 * np.pi * t)])
    >>> Auto(long=Segmented(min_scale=0.3)).resolve([x]).min_scale
    0.3
    >>> Auto(periods=200).resolve([x]).name
    'gamma'
    """

    name = "auto"

    def __init__(self, short="gamma", long="segmented", periods: float = AUTO_PERIODS):
        self.short = short
        self.long = long
        self.periods = periods

    def __repr__(self) -> str:
        return f"Auto(short={self.short!r}, long={self.long!r}, periods={self.periods!r})"

    def resolve(self, references=None) -> ErrorMeasure:
        """The measure for these reference trajectories (a fresh copy of ``short`` or ``long``)."""
        long = references is not None and any(oscillation_count(r) > self.periods for r in references)
        spec = self.long if long else self.short
        return get_error_measure(copy.deepcopy(spec) if isinstance(spec, ErrorMeasure) else spec, references)


#: Registered measures: name -> factory of a fresh :class:`ErrorMeasure`.
ERROR_MEASURES: dict[str, Callable[[], ErrorMeasure]] = {"gamma": Gamma, "segmented": Segmented}


def register_error_measure(name: str, function: Callable | None = None, *, compare: Callable | None = None):
    """Register ``function(model, reference, t, coefs, u) -> errors`` as the error measure ``name``.

    Usable as a decorator (``@register_error_measure("l2")``); returns the function unchanged.
    """
    if not isinstance(name, str) or not name or name == "auto":
        raise ValueError(f"an error measure needs a non-empty name other than 'auto', got {name!r}")

    def register(f: Callable) -> Callable:
        if not callable(f):
            raise TypeError(f"error measure {name!r} must be callable, got {type(f).__name__}")
        ERROR_MEASURES[name] = lambda: FunctionMeasure(f, name, compare)
        return f

    return register if function is None else register(function)


def get_error_measure(spec, references=None) -> ErrorMeasure:
    """A fresh measure for ``spec``: a registered name, ``"auto"``, an :class:`ErrorMeasure` or a function.

    ``"auto"`` needs the ``references``: ``"segmented"`` when any holds more than :data:`AUTO_PERIODS`
    periods, else ``"gamma"``.
    """
    if isinstance(spec, Auto):
        return spec.resolve(references)
    if isinstance(spec, ErrorMeasure):
        return spec
    if isinstance(spec, str):
        if spec == "auto":
            return Auto().resolve(references)
        if spec not in ERROR_MEASURES:
            raise ValueError(
                f"unknown error measure {spec!r}; registered: {sorted(ERROR_MEASURES)} or 'auto'"
            )
        return ERROR_MEASURES[spec]()
    if callable(spec):
        return FunctionMeasure(spec, getattr(spec, "__name__", "custom"))
    raise TypeError(f"error_measure must be a name, an ErrorMeasure or a callable, got {type(spec).__name__}")


def simulation_gamma(model, references, times, coef=None, inputs=None) -> float:
    """The paper's Gamma of ``model`` simulated from the first sample of each reference trajectory.

    Examples
    --------
    >>> from sindy_impulse.datasets import damped_oscillator
    >>> from sindy_impulse.simulation import CompiledModel, TermTable
    >>> t, x, _ = damped_oscillator()
    >>> model = CompiledModel([[0, 1.0], [-64.0, -3.2]], TermTable.polynomial([[1, 0], [0, 1]]), x)
    >>> bool(simulation_gamma(model, [x], [t]) < 1e-3)
    True
    """
    measure = Gamma().bind(list(references), list(times), inputs)
    return float(measure(model, None if coef is None else np.asarray(coef, dtype=float)[None])[0])

"""Modal parameters of a reconstructed model (beyond the paper).

Near its rest point ``x*`` (the equilibrium its data settle to: the origin, or where a constant term or a
removed offset puts it) a model ``x' = f(x)`` behaves like ``x' = J (x - x*)`` with ``J`` the Jacobian of
``f`` at ``x*``. Every complex-conjugate eigenvalue pair ``lambda = -zeta omega_n +- i omega_n sqrt(1 -
zeta^2)`` of ``J`` is an oscillatory mode with undamped natural frequency ``omega_n = |lambda|`` and damping
ratio ``zeta = -Re(lambda) / |lambda|``. Eigenvalues do not change under a linear change of coordinates, and
the delay embedding of a linear system's response is one (``q = [x1(t - tau), x1(t)] = T x(t)``), so the
modal parameters of a model fitted to delay-embedded states are those of the physical system.

The linearisation describes the model only where its linear part dominates. :func:`linear_share` measures
that over the data the model was fitted to: the fraction of the variance of the right-hand side ``f(X)``
that the linearisation ``J (X - x*)`` explains (worst equation). Below :data:`MIN_LINEAR_SHARE` (0.9: the
nonlinear remainder has over 30 % of the right-hand side's RMS) the modal parameters describe the small-
amplitude limit only, and :func:`modal_parameters` warns (:class:`~sindy_impulse.exceptions.ModalWarning`):
friction (a sign function's slope at rest is not its effect over the record) and dominant stiffness or
damping nonlinearities. Measured (models fitted to exact derivatives): the paper's Duffing oscillator
(x0 = 1) has a share of 0.97 with k_nl = 20, 0.89 with k_nl = 50 (its frequency at the start of the
record is 26 % above the modal one), 0.56 with k_nl = 200; Coulomb friction models (``sgn(v)`` of
3-8 % of the peak spring force) -10 to -75.
"""

from __future__ import annotations

import warnings
from typing import NamedTuple

import numpy as np

from .._utils.validation import check_array
from ..exceptions import ModalWarning

__all__ = [
    "modal_parameters",
    "ModalParameters",
    "jacobian_at_origin",
    "jacobian_at",
    "rest_point",
    "linear_share",
    "MIN_LINEAR_SHARE",
]

#: An eigenvalue is oscillatory when |Im| exceeds this fraction of its modulus.
_OSCILLATORY = 1e-9
#: Least share of the right-hand side's variance over the data that the linearisation must explain for
#: modal parameters to describe the model (see :func:`linear_share`).
MIN_LINEAR_SHARE = 0.9
#: A point is an equilibrium when |f| there is below this fraction of f's RMS over the data.
_REST_TOL = 1e-8


class ModalParameters(NamedTuple):
    """Oscillatory modes of a model's linear part, sorted by frequency.

    Attributes
    ----------
    frequencies_hz : ndarray
        Undamped natural frequencies ``|lambda| / (2 pi)`` in cycles per time unit of the model (Hz when
        the model was fitted with ``t`` in seconds).
    damping_ratios : ndarray
        ``-Re(lambda) / |lambda|`` (negative for a growing mode).
    """

    frequencies_hz: np.ndarray
    damping_ratios: np.ndarray


def _rhs_function(model):
    """A function ``f(X)`` (n_points, n_states) -> (n_points, n_states) and ``n_states``, or None."""
    compiled = getattr(model, "model_", None)
    if compiled is not None and hasattr(compiled, "rhs"):
        return compiled.rhs, compiled.n_states
    if hasattr(model, "rhs") and hasattr(model, "n_states"):  # a CompiledModel
        return model.rhs, model.n_states
    if hasattr(model, "predict") and hasattr(model, "coefficients"):  # pysindy.SINDy
        coef = np.asarray(model.coefficients())
        return (lambda X: np.asarray(model.predict(X), dtype=float)), coef.shape[0]
    return None


def _data_states(model):
    """The (finite) states a model was fitted to, stacked, or None."""
    x = getattr(model, "x_filtered_", None)
    if x is None:
        return None
    arrays = x if isinstance(x, list) else [x]
    try:
        X = np.vstack([np.asarray(a, dtype=float) for a in arrays])
    except (TypeError, ValueError):
        return None
    X = X[np.all(np.isfinite(X), axis=1)]
    return X if X.shape[0] >= 2 else None


def _resolve(model):
    """``(f, n_states, data states or None)`` of a model; TypeError for anything else."""
    if hasattr(model, "compiled") and callable(model.compiled):  # a Consensus result
        model = model.compiled()
    found = _rhs_function(model)
    if found is None:
        raise TypeError(
            "model must be a fitted ImpulseSINDy or pysindy.SINDy, a CompiledModel, a Consensus or a "
            f"square matrix, got {type(model).__name__}"
        )
    X = _data_states(model)
    return found[0], found[1], (X if X is not None and X.shape[1] == found[1] else None)


def _evaluate(f, points: np.ndarray) -> np.ndarray:
    try:
        return np.asarray(f(points), dtype=float)
    except Exception as err:
        raise ValueError(f"could not evaluate the model's right-hand side (is it fitted?): {err}") from err


def _steps(n: int, X, step: float) -> np.ndarray:
    """Difference steps per state: ``step`` times the data's scale (absolute ``step`` without data)."""
    if X is None:
        return np.full(n, step)
    scale = np.max(np.abs(X - np.median(X, axis=0)), axis=0)
    return step * np.where(scale > 0, scale, 1.0)


def _jacobian(f, point: np.ndarray, h: np.ndarray) -> np.ndarray:
    n = point.size
    plus = point + np.diag(h)
    minus = point - np.diag(h)
    values = _evaluate(f, np.vstack([plus, minus]))
    return (values[:n] - values[n:]).T / (2 * h)


def jacobian_at(model, point, step: float = 1e-6) -> np.ndarray:
    """Jacobian of a model's right-hand side at ``point`` (central differences).

    The difference step is ``step`` times each state's range in the fitted data (``step`` itself for a
    model without data), so the result does not depend on units.

    Parameters
    ----------
    model : fitted ImpulseSINDy, pysindy.SINDy, CompiledModel or a Consensus
    point : array-like (n_states,)
    step : float

    Returns
    -------
    ndarray (n_states, n_states)

    Examples
    --------
    >>> from sindy_impulse.simulation import CompiledModel, TermTable
    >>> terms = TermTable.polynomial([[1, 0], [0, 1], [3, 0]])
    >>> model = CompiledModel([[0.0, 1.0, 0.0], [-64.0, -3.2, -10.0]], terms)
    >>> jacobian_at(model, [1.0, 0.0]).round(6).tolist()
    [[0.0, 1.0], [-94.0, -3.2]]
    """
    f, n, X = _resolve(model)
    point = check_array(point, "point").ravel()
    if point.size != n:
        raise ValueError(f"point has {point.size} entries but the model has {n} states")
    J = _jacobian(f, point, _steps(n, X, step))
    if not np.all(np.isfinite(J)):
        raise ValueError("the model's Jacobian is not finite there")
    return J


def jacobian_at_origin(model, step: float = 1e-6) -> np.ndarray:
    """Jacobian of the model's right-hand side at the origin (central differences).

    Exact up to rounding for polynomial right-hand sides with terms up to degree 3 (the difference
    quotient's error is ``step**2`` times the cubic coefficients).

    Parameters
    ----------
    model : fitted ImpulseSINDy, pysindy.SINDy, CompiledModel, a Consensus, or a square array
        A square array is taken as the system matrix itself.
    step : float
        Difference step.

    Returns
    -------
    ndarray (n_states, n_states)
    """
    if hasattr(model, "compiled") and callable(model.compiled):  # a Consensus result
        model = model.compiled()
    if isinstance(model, (np.ndarray, list, tuple)):
        A = check_array(model, "model")
        if A.ndim != 2 or A.shape[0] != A.shape[1]:
            raise ValueError(f"model (a system matrix) must be square, got shape {A.shape}")
        return A
    found = _rhs_function(model)
    if found is None:
        raise TypeError(
            "model must be a fitted ImpulseSINDy or pysindy.SINDy, a CompiledModel, a Consensus or a "
            f"square matrix, got {type(model).__name__}"
        )
    f, n = found
    try:
        points = np.vstack([np.eye(n) * step, -np.eye(n) * step])
        values = np.asarray(f(points), dtype=float)
    except Exception as err:
        raise ValueError(f"could not evaluate the model's right-hand side (is it fitted?): {err}") from err
    J = (values[:n] - values[n:]).T / (2 * step)
    if not np.all(np.isfinite(J)):
        raise ValueError("the model's Jacobian at the origin is not finite")
    return J


def rest_point(model) -> np.ndarray:
    """The equilibrium a model's data settle to: the origin when ``f(0) = 0``, else the equilibrium found
    by Newton's method from the last fitted state (a constant term, or a removed offset, moves it).

    Falls back to the origin when Newton's method does not converge to a point within the data's range.

    Examples
    --------
    >>> from sindy_impulse.simulation import CompiledModel, TermTable
    >>> terms = TermTable.polynomial([[0, 0], [1, 0], [0, 1]])
    >>> model = CompiledModel([[0.0, 0.0, 1.0], [320.0, -64.0, -3.2]], terms)  # -64 (x0 - 5) - 3.2 x1
    >>> (rest_point(model).round(9) + 0.0).tolist()
    [5.0, 0.0]
    """
    if hasattr(model, "compiled") and callable(model.compiled):
        model = model.compiled()
    f, n, X = _resolve(model)
    origin = np.zeros(n)
    typical = float(np.sqrt(np.mean(_evaluate(f, X) ** 2))) if X is not None else 1.0
    tol = _REST_TOL * (typical if typical > 0 else 1.0)
    if np.all(np.abs(_evaluate(f, origin[None])[0]) <= tol):
        return origin
    h = _steps(n, X, 1e-6)
    x = X[-1].copy() if X is not None else origin.copy()
    for _ in range(50):
        fx = _evaluate(f, x[None])[0]
        if not np.all(np.isfinite(fx)):
            return origin
        if np.all(np.abs(fx) <= tol):
            break
        J = _jacobian(f, x, h)
        if not np.all(np.isfinite(J)):
            return origin
        x = x - np.linalg.lstsq(J, fx, rcond=None)[0]
    else:
        return origin
    if X is not None:
        low, high = X.min(axis=0), X.max(axis=0)
        margin = high - low
        if np.any(x < low - margin) or np.any(x > high + margin):
            return origin
    return x


def linear_share(model) -> float:
    """Share of the right-hand side's variance over the fitted data that the linearisation explains.

    ``1 - sum((f(X) - L(X))^2) / sum((f(X) - mean f(X))^2)`` for the equation where it is least, with
    ``L(X) = f(x*) + J (X - x*)`` the linearisation at the rest point (:func:`rest_point`) and ``X`` the
    states the model was fitted to. 1 for a linear model; negative when the linearisation is worse than
    a constant (friction: the slope of a sign function at rest). NaN for a model without data (a matrix,
    a ``CompiledModel``, a ``pysindy.SINDy``) or without dynamics.

    Examples
    --------
    >>> from sindy_impulse import ImpulseSINDy, damped_oscillator
    >>> t, x, x_dot = damped_oscillator(k_nl=200.0)
    >>> model = ImpulseSINDy().fit(x, t=t, x_dot=x_dot)
    >>> round(linear_share(model), 2)
    0.56
    """
    if isinstance(model, (np.ndarray, list, tuple)):
        return 1.0
    f, n, X = _resolve(model)
    if X is None:
        return float("nan")
    x_star = rest_point(model)
    F = _evaluate(f, X)
    L = _evaluate(f, x_star[None])[0] + (X - x_star) @ _jacobian(f, x_star, _steps(n, X, 1e-6)).T
    spread = np.sum((F - F.mean(axis=0)) ** 2, axis=0)
    live = spread > 1e-24 * max(float(np.max(spread)), np.finfo(float).tiny)
    if not np.any(live) or not np.all(np.isfinite(L)):
        return float("nan")
    return float(np.min(1.0 - np.sum((F - L) ** 2, axis=0)[live] / spread[live]))


def _modes(J: np.ndarray) -> ModalParameters:
    eig = np.linalg.eigvals(J)
    modulus = np.abs(eig)
    upper = eig.imag > _OSCILLATORY * np.maximum(modulus, np.finfo(float).tiny)
    lam = eig[upper]
    omega = np.abs(lam)
    order = np.argsort(omega)
    return ModalParameters(omega[order] / (2 * np.pi), (-lam.real / omega)[order])


def model_modes(model) -> tuple[ModalParameters, float]:
    """The modes at the rest point and the linear share, without warning (for the diagnostics)."""
    if isinstance(model, (np.ndarray, list, tuple)):
        return _modes(jacobian_at_origin(model)), 1.0
    if hasattr(model, "compiled") and callable(model.compiled):
        model = model.compiled()
    f, n, X = _resolve(model)
    point = rest_point(model)
    J = _jacobian(f, point, _steps(n, X, 1e-6)) if X is not None else jacobian_at_origin(model)
    if not np.all(np.isfinite(J)):
        raise ValueError("the model's Jacobian at its rest point is not finite")
    return _modes(J), linear_share(model)


def modal_parameters(model) -> ModalParameters:
    """Natural frequencies and damping ratios of the model's oscillatory modes.

    From the eigenvalues of the Jacobian of the right-hand side at its rest point (:func:`rest_point`: the
    origin unless a constant term or a removed offset moves the equilibrium): one mode per
    complex-conjugate pair, ``frequency = |lambda| / (2 pi)``, ``damping ratio = -Re(lambda) / |lambda|``.
    Real eigenvalues (overdamped or spurious directions) are not modes and are left out. Works for
    physical states and for delay-embedded states alike.

    Parameters
    ----------
    model : fitted ImpulseSINDy or pysindy.SINDy, CompiledModel, Consensus, or a square system matrix

    Returns
    -------
    ModalParameters
        ``(frequencies_hz, damping_ratios)``, sorted by frequency; empty arrays if no mode oscillates.

    Warns
    -----
    ModalWarning
        When the linearisation explains less than :data:`MIN_LINEAR_SHARE` of the model's right-hand side
        over its data (:func:`linear_share`): friction or a dominant nonlinearity. The values returned
        then describe the small-amplitude limit only.

    Examples
    --------
    >>> from sindy_impulse.analysis import modal_parameters
    >>> modes = modal_parameters([[0.0, 1.0], [-64.0, -3.2]])  # the paper's oscillator
    >>> round(float(modes.frequencies_hz[0]), 4), round(float(modes.damping_ratios[0]), 4)
    (1.2732, 0.2)

    From x1 alone, through the delay embedding:

    >>> from sindy_impulse import DelayEmbedding, ImpulseSINDy, damped_oscillator
    >>> ring = damped_oscillator(snr_db=40, random_state=0)
    >>> embedding = DelayEmbedding().fit(ring.x[:, 0])
    >>> model = ImpulseSINDy().fit(embedding.transform(ring.x[:, 0]), t=0.01)
    >>> f, zeta = modal_parameters(model)
    >>> bool(abs(f[0] / 1.2732 - 1) < 0.005 and abs(zeta[0] / 0.2 - 1) < 0.05)
    True
    """
    modes, share = model_modes(model)
    if share < MIN_LINEAR_SHARE:
        part = f"only {100 * share:.0f} %" if share > 0 else "none"
        warnings.warn(
            f"the model's linear part explains {part} of the variance of its right-hand side "
            f"(linear share {share:.3g}) over the fitted data (friction or a dominant nonlinearity): the "
            "modal parameters describe the small-amplitude limit, not the recorded dynamics; use "
            "sindy_impulse.analysis.backbone for frequency and damping against amplitude",
            ModalWarning,
            stacklevel=2,
        )
    return modes

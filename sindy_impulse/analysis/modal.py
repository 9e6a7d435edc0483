"""Modal parameters of a reconstructed model (beyond the paper).

Near the equilibrium at the origin a model ``x' = f(x)`` behaves like ``x' = J x`` with ``J`` the Jacobian of
``f`` at 0. Every complex-conjugate eigenvalue pair ``lambda = -zeta omega_n +- i omega_n sqrt(1 - zeta^2)``
of ``J`` is an oscillatory mode with undamped natural frequency ``omega_n = |lambda|`` and damping ratio
``zeta = -Re(lambda) / |lambda|``. Eigenvalues do not change under a linear change of coordinates, and the
delay embedding of a linear system's response is one (``q = [x1(t - tau), x1(t)] = T x(t)``), so the modal
parameters of a model fitted to delay-embedded states are those of the physical system.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._validation import check_array

__all__ = ["modal_parameters", "ModalParameters", "jacobian_at_origin"]

#: An eigenvalue is oscillatory when |Im| exceeds this fraction of its modulus.
_OSCILLATORY = 1e-9


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


def modal_parameters(model) -> ModalParameters:
    """Natural frequencies and damping ratios of the model's oscillatory modes.

    From the eigenvalues of the Jacobian of the right-hand side at the origin: one mode per
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
    eig = np.linalg.eigvals(jacobian_at_origin(model))
    modulus = np.abs(eig)
    upper = eig.imag > _OSCILLATORY * np.maximum(modulus, np.finfo(float).tiny)
    lam = eig[upper]
    omega = np.abs(lam)
    order = np.argsort(omega)
    return ModalParameters(omega[order] / (2 * np.pi), (-lam.real / omega)[order])

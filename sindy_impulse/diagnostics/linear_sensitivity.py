"""Sensitivities of a linear model's simulation to library terms it lacks, without simulating each.

The term tests (:mod:`.terms`) need, for each library term ``theta_k`` tried in equation ``i``, how the
model's simulation moves when that term is added with a small coefficient ``c``: ``S = dx/dc`` at ``c = 0``.
Finite differences take one simulation of the model with the term (a nonlinear model when the term is,
integrated stage by stage) per pair ``(i, k)``. When the model itself is linear, ``x' = A x + b``, ``S``
solves the linear equation ``S' = A S + e_i theta_k(x(t))`` along the model's own trajectory ``x(t)``
(``S = 0`` where a simulated segment starts from the data), so over a sample interval ``dt``

``S_s = exp(A dt) S_{s-1} + F_s``, ``F_s = int_0^dt exp(A (dt - tau)) e_i theta_k(x(t_{s-1} + tau)) dtau``,

with ``x(t_{s-1} + tau)`` the model's exact flow from its simulated state at ``t_{s-1}``. The integral is
taken by Gauss-Legendre quadrature (:data:`NODES` nodes on each of enough panels that the integrand, whose
fastest oscillation is the model's fastest time scale times the term's degree plus one, turns by at most
:data:`PANEL_PHASE` radians on a panel): a relative error below 1e-6, where the finite differences' own
is about 1e-4 (and the simulation the tests compare follows the exact solution to RK4's accuracy at the
model's sub-steps, finer still). The forcing of every pair is a product of the terms' values at the nodes
with fixed matrices: all pairs at once cost a few evaluations of the library per sample, where finite
differences simulate each pair. Finite differences of a nonlinear term also difference two integration
grids: the model with the term takes a smooth nonlinear model's coarser RK4 sub-steps, the linear model its
own finer ones, and at the tests' small steps the two simulations' integration errors can differ by a
sizeable part (a tenth, more on coarsely sampled records) of the term's effect; the recursion has no such
error.

:func:`linear_sensitivities` applies to a compiled linear model without inputs, on uniform grids, and to
polynomial terms; elsewhere it returns None (or leaves the pair out) and the tests difference simulations.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from ..simulation import TermTable
from ..simulation.program import uniform_step
from ..simulation.terms import PLAIN
from .model import Fitted, simulation_grid

__all__ = ["linear_sensitivities", "NODES", "PANEL_PHASE", "MAX_PANELS"]

#: Gauss-Legendre nodes per panel of a sample interval.
NODES = 3
#: Most radians the quadrature's integrand turns on one panel (3 nodes: a relative error below 1e-6).
PANEL_PHASE = 1.0
#: Most panels per sample interval (beyond, a stiff or coarsely sampled model: finite differences).
MAX_PANELS = 64
#: Most values (node states and term values) held at once: long records are taken in chunks of intervals.
CHUNK_VALUES = 2_000_000


def _linear_part(model, shift: np.ndarray, n: int):
    """``(A, b)`` of a linear model's right-hand side in the deviations from ``shift``."""
    base = np.asarray(model.rhs(shift[None]), dtype=float)[0]
    A = np.asarray(model.rhs(shift[None] + np.eye(n)), dtype=float) - base
    return A.T, base


def _inner(model):
    """The compiled model inside an :class:`~sindy_impulse.simulation.AtRestLevel` (or the model)."""
    return getattr(model, "inner", model)


def applies(model, fitted: Fitted, terms, grid: list) -> bool:
    """Whether ``model`` is a compiled linear model without inputs simulated on uniform grids (then
    :func:`linear_sensitivities` gives its derivatives)."""
    inner = _inner(model)
    if not isinstance(terms, TermTable) or not getattr(inner, "is_linear", False):
        return False
    if any(u is not None for u in fitted.inputs):
        return False
    return all(uniform_step(t) is not None for _, t, _, _ in grid)


def _quadrature(A: np.ndarray, b: np.ndarray, dt: float, degree: int):
    """Nodes ``tau`` in ``[0, dt]``, the exact flow to them ``(E, e)`` (``x(tau) = E x(0) + e``), the
    weights ``w_g exp(A (dt - tau_g))`` and ``exp(A dt)``; None when more than :data:`MAX_PANELS` panels
    would be needed."""
    n = A.shape[0]
    radius = float(np.max(np.abs(np.linalg.eigvals(A)))) if n else 0.0
    panels = max(1, int(np.ceil((degree + 1) * radius * dt / PANEL_PHASE)))
    if not np.isfinite(radius) or panels > MAX_PANELS:
        return None
    x, w = np.polynomial.legendre.leggauss(NODES)
    width = dt / panels
    tau = ((np.arange(panels)[:, None] + (x[None] + 1) / 2) * width).ravel()
    weights = np.tile(w * width / 2, panels)
    augmented = np.zeros((n + 1, n + 1))
    augmented[:n, :n], augmented[:n, n] = A, b
    flows = np.array([scipy.linalg.expm(augmented * t) for t in tau])
    carry = np.array([scipy.linalg.expm(A * (dt - t)) for t in tau]) * weights[:, None, None]
    return flows[:, :n, :n], flows[:, :n, n], carry, scipy.linalg.expm(A * dt)


def _trajectory_sensitivities(model, ref, t, starts, A, b, shift, evaluate, eq, ks, degree):
    """Sensitivities (samples, n, pairs) of one trajectory's simulation on its grid (None: see
    :func:`_quadrature`)."""
    n = A.shape[0]
    rule = _quadrature(A, b, uniform_step(t), degree)
    if rule is None:
        return None
    E, e, carry, Phi = rule
    x = model.simulate_segments(ref[starts], t, starts) - shift  # the model's own trajectory
    forcing = np.zeros((x.shape[0], n, eq.size))  # forcing[s]: the response over interval s-1 -> s
    chunk = max(1, CHUNK_VALUES // (E.shape[0] * (n + ks.max() + 1)))  # intervals held at once
    for lo in range(0, x.shape[0] - 1, chunk):
        hi = min(lo + chunk, x.shape[0] - 1)
        nodes = np.einsum("gab,rb->rga", E, x[lo:hi]) + e[None]  # (intervals, nodes, n)
        theta = evaluate(nodes.reshape(-1, n)).reshape(hi - lo, E.shape[0], -1)
        for i in np.unique(eq):
            mine = np.flatnonzero(eq == i)
            forcing[lo + 1 : hi + 1, :, mine] = np.einsum(
                "rgc,ga->rac", theta[:, :, ks[mine]], carry[:, :, i], optimize=True
            )
    forcing[starts] = 0.0  # a segment starts from the data: S = 0 there
    bounds = np.append(starts, x.shape[0])
    return np.concatenate([_recursion(Phi, forcing[a:b]) for a, b in zip(bounds[:-1], bounds[1:])])


def _recursion(Phi: np.ndarray, forcing: np.ndarray) -> np.ndarray:
    """``S_s = Phi S_{s-1} + forcing_s`` over one simulated segment, from ``S_0 = forcing_0`` (zero: the
    segment starts from the data), sample by sample."""
    S = np.empty_like(forcing)
    S[0] = forcing[0]
    for s in range(1, forcing.shape[0]):
        np.matmul(Phi, S[s - 1], out=S[s])
        S[s] += forcing[s]
    return S


def linear_sensitivities(model, fitted: Fitted, terms, shift, pairs, stride: int = 1):
    """Derivatives of ``model``'s simulated residual (:func:`~.model.simulate_residuals` on the same
    samples) by the coefficient of library term ``k`` in equation ``i``, for each pair ``(i, k)`` of
    ``pairs``, at the model's coefficients (see the module).

    Parameters
    ----------
    model : CompiledModel or AtRestLevel
        A linear model in the deviations from ``shift``.
    fitted : Fitted
    terms : TermTable
        The library's terms (``k`` indexes them).
    shift : ndarray (n_states,)
        The rest level the model's equations are written about.
    pairs : list of (int, int)
    stride : int, default=1
        As :func:`~.model.simulate_residuals`.

    Returns
    -------
    (ndarray (n_compared_samples, n_states, n_done), list) or None
        The sensitivities, stacked over the trajectories as the residuals are, of the pairs listed
        second (those of polynomial terms); None where the model is not one this applies to.

    Examples
    --------
    The paper's oscillator (a linear model) and the cubic term ``x0^3`` tried in its second equation:

    >>> from sindy_impulse import ImpulseSINDy, damped_oscillator
    >>> from sindy_impulse.feature_library.terms import library_terms
    >>> t, x, _ = damped_oscillator(snr_db=40, random_state=0)
    >>> fitted = Fitted(ImpulseSINDy().fit(x, t=t))
    >>> terms = library_terms(fitted.estimator.feature_library_, 2)
    >>> S, done = linear_sensitivities(fitted.model, fitted, terms, np.zeros(2), [(1, 6)])
    >>> S.shape, done
    ((401, 2, 1), [(1, 6)])
    """
    grid = simulation_grid(fitted, stride)
    if not pairs or not applies(model, fitted, terms, grid):
        return None
    done = [(i, k) for i, k in pairs if terms.func[k] == PLAIN]
    if not done:
        return None
    n = fitted.coef.shape[0]
    shift = np.asarray(shift, dtype=float)
    A, b = _linear_part(model, shift, n)
    columns = sorted({k for _, k in done})
    where = {k: c for c, k in enumerate(columns)}
    eq, ks = np.array([i for i, _ in done]), np.array([where[k] for _, k in done])
    degree = int(np.max(terms.powers[columns].sum(axis=1)))
    evaluate = terms.subset(columns).evaluate
    out = []
    for ref, t, starts, compared in grid:
        S = _trajectory_sensitivities(model, ref, t, starts, A, b, shift, evaluate, eq, ks, degree)
        if S is None:
            return None
        out.append(S if compared is None else S[compared])
    return np.concatenate(out, axis=0), done

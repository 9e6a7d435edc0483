"""Choosing one model from the sweep on the complexity-error plane (paper sections 2.5 and 3.2).

``"min_gamma"`` is the paper's rule: the candidate of least Gamma, then refined.

``"auto"`` is complexity-aware. On noisy data the minimum of Gamma often sits on a model with spurious
terms that fit the noise left in the filtered states, while the true, sparser model is only slightly
worse -- and, once refined, often as good. The rule walks the candidates from the sparsest up to the
minimum-Gamma one, refines each, and keeps the first that passes two tests:

1. its refined Gamma is within tolerance of the sweep's least (unrefined) Gamma, and
2. the knee test: the next denser candidate, refined, is not better by more than the tolerance --
   refinement can lower Gamma by orders of magnitude (a sparse model that lacks a true term cannot
   follow), so a sparser model must hold its own against its refined neighbour, not only against
   unrefined numbers.

The tolerance of a Gamma value ``g`` is ``REL_TOL * g`` (differences a finite record does not resolve)
plus ``NOISE_TOL`` times the noise Gamma (the Gamma between the measured and the filtered states: what
the filter removed) plus ``FLOOR`` per compared value (a mean deviation of 1e-5 of the amplitude, the
accuracy of the filter and the integrator on clean data). The dense minimum-Gamma candidate is refined
only when the walk reaches it, which keeps the cost to a few small refinements.
"""

from __future__ import annotations

import numpy as np

__all__ = ["SELECTION_RULES", "select_candidate"]

SELECTION_RULES = ("auto", "min_gamma")

#: Relative tolerance of the "auto" rule (fraction of the Gamma compared with).
REL_TOL = 0.1
#: Weight of the noise Gamma in the tolerance of the "auto" rule.
NOISE_TOL = 0.1
#: Absolute tolerance per compared value (sample x state): the mean deviation below which clean-data
#: models are indistinguishable.
FLOOR = 1e-5
#: Candidates whose unrefined Gamma exceeds this factor times the target are not refined.
HOPELESS = 10.0


def select_candidate(rule: str, gammas, n_terms, refine, noise_gamma: float = 0.0, n_values: int = 0):
    """Select a candidate of the sweep and return it refined.

    Parameters
    ----------
    rule : {"auto", "min_gamma"}
    gammas : ndarray (n_candidates,)
        Gamma of each (unrefined) candidate; ``inf`` for diverged or excluded ones.
    n_terms : ndarray (n_candidates,)
        Number of non-zero coefficients of each candidate.
    refine : callable
        ``refine(index) -> (coefficients, gamma, history)``: the refined candidate (called at most once
        per index).
    noise_gamma : float
        Gamma between measured and filtered states.
    n_values : int
        Number of values Gamma sums over (samples x states), for the absolute floor of the tolerance.

    Returns
    -------
    index, (coefficients, gamma, history)

    Examples
    --------
    >>> g = np.array([1.0, 1.02, 5.0]); k = np.array([5, 3, 1])
    >>> select_candidate("auto", g, k, lambda i: (None, g[i], {}))[0]
    1
    >>> select_candidate("min_gamma", g, k, lambda i: (None, g[i], {}))[0]
    0
    """
    gammas = np.asarray(gammas, dtype=float)
    n_terms = np.asarray(n_terms)
    if rule not in SELECTION_RULES:
        raise ValueError(f"selection must be one of {SELECTION_RULES}, got {rule!r}")
    finite = np.isfinite(gammas)
    # least Gamma, ties broken by fewer terms
    order = np.lexsort((n_terms, np.where(finite, gammas, np.inf)))
    best = int(order[0])
    if rule == "min_gamma":
        return best, refine(best)

    def tolerance(g: float) -> float:
        return REL_TOL * g + NOISE_TOL * noise_gamma + FLOOR * n_values

    target = gammas[best] + tolerance(gammas[best])
    walk = sorted(
        (
            int(i)
            for i in np.flatnonzero(finite)
            if 0 < n_terms[i] < n_terms[best] and gammas[i] <= HOPELESS * target
        ),
        key=lambda i: (n_terms[i], gammas[i]),
    )
    walk.append(best)
    results = {}

    def refined(i):
        if i not in results:
            results[i] = refine(i)
        return results[i]

    for position, i in enumerate(walk[:-1]):
        g = refined(i)[1]
        if g > target:
            continue
        g_denser = refined(walk[position + 1])[1]
        if g <= g_denser + tolerance(g_denser):
            return i, refined(i)
    return best, refined(best)

"""Choosing one model from the sweep on the complexity-error plane (paper sections 2.5 and 3.2).

``"min_gamma"`` is the paper's rule: the candidate of least Gamma, then refined.

``"auto"`` is complexity-aware. On noisy data the minimum of Gamma often sits on a model with spurious
terms that fit the noise left in the filtered states, while the true, sparser model is only slightly
worse -- and, once refined, often better. So the rule refines the minimum-Gamma candidate, then the
sparser ones, sparsest first, and keeps the first whose refined Gamma is within a tolerance of the
best Gamma reached (falling back to the minimum-Gamma candidate). The tolerance has two parts: a
relative one (``REL_TOL`` of the best Gamma: differences smaller than that are not resolved by a finite
record) and one from the data's noise (``NOISE_TOL`` times the Gamma between the measured and the
filtered states, i.e. what the filter removed).
"""

from __future__ import annotations

import numpy as np

__all__ = ["SELECTION_RULES", "select_candidate"]

SELECTION_RULES = ("auto", "min_gamma")

#: Relative tolerance of the "auto" rule (fraction of the best refined Gamma).
REL_TOL = 0.1
#: Weight of the noise Gamma in the tolerance of the "auto" rule.
NOISE_TOL = 0.25
#: Candidates whose unrefined Gamma exceeds this factor times the target are not refined.
HOPELESS = 10.0


def select_candidate(rule: str, gammas, n_terms, refine, noise_gamma: float = 0.0):
    """Select a candidate of the sweep and return it refined.

    Parameters
    ----------
    rule : {"auto", "min_gamma"}
    gammas : ndarray (n_candidates,)
        Gamma of each (unrefined) candidate; ``inf`` for diverged ones.
    n_terms : ndarray (n_candidates,)
        Number of non-zero coefficients of each candidate.
    refine : callable
        ``refine(index) -> (coefficients, gamma, history)``: the refined candidate.
    noise_gamma : float
        Gamma between measured and filtered states.

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
    # Refine the minimum-Gamma candidate first: refinement can lower Gamma by orders of magnitude, and
    # the tolerance must be measured from what the best model achieves, not from its unrefined value.
    # Then walk from the sparsest candidate upwards and keep the first whose refined Gamma is within the
    # tolerance; the minimum-Gamma candidate is the fallback. Candidates whose unrefined Gamma exceeds
    # HOPELESS times the unrefined target are skipped (bounded refinement cannot close such a gap).
    best_result = refine(best)
    g_unrefined = float(gammas[best])
    g_best = min(g_unrefined, float(best_result[1]))
    target = g_best + REL_TOL * g_best + NOISE_TOL * noise_gamma
    skip_above = HOPELESS * (g_unrefined + REL_TOL * g_unrefined + NOISE_TOL * noise_gamma)
    sparser = sorted(
        (int(i) for i in np.flatnonzero(finite) if 0 < n_terms[i] < n_terms[best]),
        key=lambda i: (n_terms[i], gammas[i]),
    )
    for i in sparser:
        if gammas[i] > skip_above:
            continue
        result = refine(i)
        if result[1] <= target:
            return i, result
    return best, best_result

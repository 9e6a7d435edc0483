"""Choosing one model from the scored sweep on the complexity-error plane (paper sections 2.5 and 3.2).

A rule is a name registered in :data:`SELECTION_RULES` or any callable
``rule(scores, n_terms, refine, tolerance) -> index``: ``scores`` are the unrefined errors of the
candidates (``inf`` for diverged or excluded ones), ``n_terms`` their sizes, ``refine(i)`` returns the
refined candidate ``(coefficients, score, history)`` (computed once per index), ``tolerance(g)`` the
difference in score the data cannot resolve at level ``g``.

``"min_gamma"`` (alias ``"min_score"``) is the paper's rule: the candidate of least score, then refined.

``"auto"`` is complexity-aware. On noisy data the minimum of the score often sits on a model with spurious
terms that fit the noise left in the filtered states, while the true, sparser model is only slightly worse
-- and, once refined, often as good. The rule walks the candidates from the sparsest up to the minimum-score
one, refines each, and keeps the first that passes two tests:

1. its refined score is within tolerance of the sweep's least (unrefined) score, and
2. the knee test: the next denser candidate, refined, is not better by more than the tolerance --
   refinement can lower the score by orders of magnitude (a sparse model that lacks a true term cannot
   follow), so a sparser model must hold its own against its refined neighbour, not only against
   unrefined numbers.

The tolerance of a score ``g`` is ``REL_TOL * g`` (differences a finite record does not resolve) plus
``NOISE_TOL`` times the noise level (the measure between the measured and the filtered states: what the
filter removed) plus the measure's floor per compared value (for the weighted-L1 measures a mean deviation of
1e-5 of the amplitude, the accuracy of the filter and the integrator on clean data).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

__all__ = [
    "SELECTION_RULES",
    "select_candidate",
    "register_selection_rule",
    "exact_scores_needed",
    "reads_bounds",
    "tolerance",
    "REL_TOL",
    "NOISE_TOL",
    "FLOOR",
]

#: Relative tolerance of the "auto" rule (fraction of the score compared with).
REL_TOL = 0.1
#: Weight of the noise level in the tolerance of the "auto" rule.
NOISE_TOL = 0.1
#: Default absolute tolerance per compared value (sample x state).
FLOOR = 1e-5
#: Candidates whose unrefined score exceeds this factor times the target are not refined by "auto".
HOPELESS = 10.0


def tolerance(
    score: float,
    noise: float = 0.0,
    n_values: int = 0,
    floor: float = FLOOR,
    rel_tol: float = REL_TOL,
    noise_tol: float = NOISE_TOL,
) -> float:
    """The difference in an error measure that the data cannot resolve at level ``score``.

    ``rel_tol * score + noise_tol * noise + floor * n_values``: a fraction of the score (what a finite record
    does not resolve), a fraction of the noise level (the measure between measured and filtered states) and
    the measure's floor per compared value. The selection rules and the test for nonlinearity both use it.

    Examples
    --------
    >>> round(tolerance(2.0, noise=1.0, n_values=1000), 6)
    0.31
    """
    return rel_tol * score + noise_tol * noise + floor * n_values


def _least(scores, n_terms) -> int:
    """Least score, ties broken by fewer terms."""
    return int(np.lexsort((n_terms, np.where(np.isfinite(scores), scores, np.inf)))[0])


def min_score(scores, n_terms, refine, tolerance) -> int:
    """The paper's rule: the candidate of least (unrefined) score."""
    return _least(scores, n_terms)


def auto(scores, n_terms, refine, tolerance) -> int:
    """The sparsest candidate that matches the best within tolerance and passes the knee test."""
    best = _least(scores, n_terms)
    target = scores[best] + tolerance(scores[best])
    walk = sorted(
        (
            int(i)
            for i in np.flatnonzero(np.isfinite(scores))
            if 0 < n_terms[i] < n_terms[best] and scores[i] <= HOPELESS * target
        ),
        key=lambda i: (n_terms[i], scores[i]),
    )
    walk.append(best)
    for position, i in enumerate(walk[:-1]):
        g = refine(i)[1]
        if g > target:
            continue
        g_denser = refine(walk[position + 1])[1]
        if g <= g_denser + tolerance(g_denser):
            return i
    return best


#: Registered rules: name -> rule.
SELECTION_RULES: dict[str, Callable] = {"auto": auto, "min_gamma": min_score, "min_score": min_score}


def _min_score_reads(scores, n_terms, tolerance) -> np.ndarray:
    return np.zeros(len(scores), dtype=bool)


def _auto_reads(scores, n_terms, tolerance) -> np.ndarray:
    best = _least(scores, n_terms)
    target = scores[best] + tolerance(scores[best])
    return np.isfinite(scores) & (n_terms > 0) & (n_terms < n_terms[best]) & (scores <= HOPELESS * target)


#: For the rules that need no more than the least score exactly: which other candidates' scores they read
#: (``reads(scores, n_terms, tolerance) -> mask``). See :func:`exact_scores_needed`.
_READS = {auto: _auto_reads, min_score: _min_score_reads}


def reads_bounds(rule) -> bool:
    """Whether ``rule`` (a name or a callable) is one that :func:`exact_scores_needed` knows: it may then
    be given lower bounds in place of the scores of candidates worse than the best."""
    rule = SELECTION_RULES.get(rule) if isinstance(rule, str) else rule
    return rule in _READS


def exact_scores_needed(rule, scores, n_terms, noise_gamma=0.0, n_values=0, floor=FLOOR) -> np.ndarray:
    """The candidates whose exact score ``rule`` reads, when some ``scores`` are lower bounds.

    A sweep may stop simulating a candidate once its error passes the least score found so far: it
    cannot be the least. Its score is then a lower bound above that least score. The rules of
    :data:`SELECTION_RULES` read the least score and, ``"auto"``, the scores of the sparser candidates
    within :data:`HOPELESS` times the tolerance target; a lower bound beyond that serves them as well as
    the score (the same selection). Returns a mask of the candidates whose exact score the rule reads
    (where a bound stands, the caller finishes the simulation).

    Examples
    --------
    >>> g = np.array([1.0, 1.05, 5.0, 80.0]); k = np.array([5, 3, 2, 1])
    >>> exact_scores_needed("auto", g, k).tolist()
    [False, True, True, False]
    """
    rule = SELECTION_RULES.get(rule) if isinstance(rule, str) else rule
    if rule not in _READS:
        raise ValueError(f"no lower bounds for the selection rule {rule!r}: it needs every score")
    scores = np.asarray(scores, dtype=float)

    def tolerance_at(g: float) -> float:
        return tolerance(g, noise_gamma, n_values, floor)

    return _READS[rule](scores, np.asarray(n_terms), tolerance_at)


def register_selection_rule(name: str, rule: Callable) -> Callable:
    """Register ``rule(scores, n_terms, refine, tolerance) -> index`` under ``name``."""
    if not isinstance(name, str) or not name:
        raise ValueError(f"a selection rule needs a non-empty name, got {name!r}")
    if not callable(rule):
        raise TypeError(f"selection rule {name!r} must be callable, got {type(rule).__name__}")
    SELECTION_RULES[name] = rule
    return rule


def select_candidate(
    rule,
    scores,
    n_terms,
    refine,
    noise_gamma: float = 0.0,
    n_values: int = 0,
    floor: float = FLOOR,
    final=None,
):
    """Select a candidate of the sweep and return it refined.

    Parameters
    ----------
    rule : str or callable
        A name of :data:`SELECTION_RULES` or ``rule(scores, n_terms, refine, tolerance) -> index``.
    scores : ndarray (n_candidates,)
        Unrefined score of each candidate; ``inf`` for diverged or excluded ones.
    n_terms : ndarray (n_candidates,)
        Number of non-zero coefficients of each candidate.
    refine : callable
        ``refine(index) -> (coefficients, score, history)``: the refined candidate (called at most once
        per index).
    noise_gamma : float
        The measure between measured and filtered states.
    n_values : int
        Number of values the score sums over (samples x states), for the absolute floor.
    floor : float
        The measure's absolute tolerance per value.
    final : callable, optional
        ``final(index) -> (coefficients, score, history)``: the selected candidate as returned (e.g. refined
        to a finer precision than the rule's comparisons need); default ``refine``.

    Returns
    -------
    index, (coefficients, score, history)

    Examples
    --------
    >>> g = np.array([1.0, 1.02, 5.0]); k = np.array([5, 3, 1])
    >>> select_candidate("auto", g, k, lambda i: (None, g[i], {}))[0]
    1
    >>> select_candidate("min_gamma", g, k, lambda i: (None, g[i], {}))[0]
    0
    """
    if isinstance(rule, str):
        if rule not in SELECTION_RULES:
            raise ValueError(
                f"selection must be one of {sorted(SELECTION_RULES)} or a callable, got {rule!r}"
            )
        rule = SELECTION_RULES[rule]
    elif not callable(rule):
        raise TypeError(f"selection must be a rule name or a callable, got {type(rule).__name__}")
    scores = np.asarray(scores, dtype=float)
    n_terms = np.asarray(n_terms)
    results: dict[int, tuple] = {}

    def refined(i: int):
        if i not in results:
            results[i] = refine(int(i))
        return results[i]

    def tolerance_at(g: float) -> float:
        return tolerance(g, noise_gamma, n_values, floor)

    index = int(rule(scores, n_terms, refined, tolerance_at))
    if not 0 <= index < len(scores):
        raise ValueError(f"the selection rule returned index {index} for {len(scores)} candidates")
    return index, (refined(index) if final is None else final(index))

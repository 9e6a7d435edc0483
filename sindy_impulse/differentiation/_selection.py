"""Automatic choice of TVRegDiff's regularization weight: the scan over alpha and its criteria.

One normalized column is an :class:`AlphaProblem` (smoothing at a given weight, and the scores of a
solution); :func:`select_alpha` scans a log grid of weights with warm starts and returns the best solution
by modified GCV or by the paper's consistency error.

The GCV scan runs upwards, from the weakest regularization, and stops once GCV has clearly turned up past
its minimum. Strong weights are where the lagged-diffusivity iteration converges slowest: on a
1,500-sample ring-down at 40 dB it ran its 30 iterations without converging at every weight from 3e-2 to
3e-6 times the largest useful one, against 6-20 iterations near the minimum (about 1e-9 of it) and 1-4
below. Scanned upwards, those weights are not computed: over the 240 columns of 40 ring-downs of 2-DOF
systems and 40 of the paper's oscillator the scans took 37 % of the time of the downward ones. A downward
scan could stop early only where GCV turned up below its minimum, which it rarely does (it flattens
there). The scan's best point and its quarter-decade neighbours are then solved from cold starts and the
best of the three is returned, so that the criterion compared is that of the solution returned.
"""

from __future__ import annotations

import numpy as np

from ._banded import lambda_max, normal_band, penalty_weight, polynomial_residual, trace_inverse, tv_smooth

__all__ = ["AlphaProblem", "select_alpha", "empty_curve"]

# Modified GCV (Cummins, Filloon & Nychka 2001; Kim & Gu 2004): gamma > 1 counters GCV's tendency to
# undersmooth and removes its spurious minimum where the effective number of parameters approaches N.
_GCV_GAMMA = 1.4
_GRID_STEP = 0.5  # decades between alphas of the coarse scan, refined to a quarter decade at the minimum
_GRID_DECADES = 12.0  # alphas scanned from alpha_max down to alpha_max * 10**-12


def select_alpha(problem: AlphaProblem, to_alpha: float, scale: float, use_gcv: bool):
    """Scan the log grid of alphas (warm starts; GCV upwards and stopped past its minimum, the consistency
    error downwards from alpha_max over the whole grid) and return the best solution."""
    lam_max = problem.lambda_max()
    if not np.isfinite(lam_max) or lam_max <= 0:  # g is a polynomial the penalty cannot see
        c, its = problem.smooth(0.0)
        return c, 0.0, empty_curve(), its
    records = {}  # exponent r (alpha = lam_max * 10**-r) -> (gcv, consistency, residual, dof, c)
    c = None
    grid = np.arange(0.0, _GRID_DECADES + 1e-9, _GRID_STEP)
    for r in grid[::-1] if use_gcv else grid:
        c, _ = problem.smooth(lam_max * 10**-r, c)
        records[r] = problem.score(lam_max * 10**-r, c) + (c,)  # GCV inf where dof > N / gamma
        if use_gcv and _past_minimum(records):
            break  # GCV has clearly turned up: larger alphas only smooth the signal away
    key = 0 if use_gcv else 1

    # The quarter-decade neighbours of the scan's best point and that point itself, each solved from a cold
    # start: the criterion compared is that of the solution returned (which alpha=alpha_ and transform
    # reproduce), whatever the warm starts of the scan left in its last digits.
    r_scan = min(records, key=lambda r: (records[r][key], r))
    final = {}
    for r in (r_scan - _GRID_STEP / 2, r_scan, r_scan + _GRID_STEP / 2):
        if r >= 0:
            c, its = problem.smooth(lam_max * 10**-r)
            final[r] = problem.score(lam_max * 10**-r, c) + (c, its)
    records.update({r: value[:5] for r, value in final.items()})
    r_best = min(final, key=lambda r: (final[r][key], r))
    lam_best = lam_max * 10**-r_best
    c_sel, its_sel = final[r_best][4], final[r_best][5]
    order = sorted(records, reverse=True)  # increasing alpha
    table = np.array([records[r][:4] for r in order], dtype=float).reshape(-1, 4)
    curve = {
        "alpha": np.array([lam_max * 10**-r for r in order]) * to_alpha,  # as alpha_ is computed
        "error": table[:, key] * (1.0 if use_gcv else scale),
        "gcv": table[:, 0],
        "consistency": table[:, 1] * scale,
        "residual": table[:, 2] * scale,
        "dof": table[:, 3],
    }
    return c_sel, lam_best, curve, its_sel


def _past_minimum(records: dict, steps: int = 3, factor: float = 2.0) -> bool:
    """True once the upward GCV scan is ``steps`` grid points past its minimum and ``factor`` times above
    it."""
    order = sorted(records, reverse=True)  # increasing alpha: the order of the scan
    gcv = [records[r][0] for r in order]
    best = int(np.argmin(gcv))
    return len(gcv) - 1 - best >= steps and gcv[-1] > factor * gcv[best]


class AlphaProblem:
    """One normalized column: smoothing at a given lam and the selection criteria."""

    def __init__(self, g, basis, coef, h, est):
        self.g = g
        self.basis = basis
        self.coef = coef
        self.h = h
        self.rhs = basis.rhs(g)
        self.c_start = basis.start(g)
        self.options = {"max_iter": est.max_iter, "tol": est.tol, "eps_rel": est.eps}
        self.trim = est.trim
        self.m = coef.shape[1] - 1

    def smooth(self, lam: float, c0=None):
        start = self.c_start if c0 is None else c0
        return tv_smooth(self.rhs, self.coef, self.h, lam, start, self.basis.gram, **self.options)

    def lambda_max(self) -> float:
        resid = polynomial_residual(self.g, self.basis.tau, self.m - 1)
        return lambda_max(self.basis.rhs(resid), self.coef, self.h)

    def score(self, lam: float, c):
        """(modified GCV, paper's consistency error, RMS residual, effective dof), normalized units."""
        n = self.g.shape[0]
        weight = penalty_weight(self.coef, self.h, lam, c, self.options["eps_rel"])
        gram = self.basis.gram
        dof = trace_inverse(normal_band(self.coef, weight, c.shape[0], gram), gram)
        rss, consistency = self.basis.fit_scores(c, self.g, self.trim)
        denom = n - _GCV_GAMMA * dof
        gcv = n * rss / denom**2 if denom > 0 and 0 < dof <= n else np.inf
        return gcv, consistency, float(np.sqrt(rss / n)), dof


def empty_curve() -> dict:
    """The curve of a column whose alpha was not chosen (given, or a constant column)."""
    empty = np.empty(0)
    return {k: empty for k in ("alpha", "error", "gcv", "consistency", "residual", "dof")}

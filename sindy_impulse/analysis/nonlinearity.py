from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from pysindy.utils import AxesArray

from .._trajectories import as_trajectories
from ..differentiation import differentiate
from ..feature_library.terms import library_terms, term_table
from ..optimizers import fresh_copy, least_squares
from ..refinement import refine
from ..selection import tolerance
from ..simulation import compile_model, get_error_measure
from ..simulation.terms import PLAIN

__all__ = ["nonlinearity_test", "NonlinearityResult", "NonlinearTerm"]

#: Default relative tolerance: the error must grow by more than this fraction of the nonlinear model's.
REL_TOL = 0.5
#: Default weight of the noise level in the tolerance.
NOISE_TOL = 0.05
#: Nonlinear library terms (ranked by derivative residual) refined in the search.
N_SEARCH = 3


@dataclass(frozen=True)
class NonlinearTerm:
    """A nonlinear term of the model the decision rests on.

    Attributes
    ----------
    equation : str
        Left-hand side, e.g. ``"x1'"``.
    term : str
        Library term, e.g. ``"x0^3"``.
    coefficient : float
        Its (refined) coefficient.
    share : float
        Its share of the equation's right-hand side magnitude over the data (0 to 1).
    """

    equation: str
    term: str
    coefficient: float
    share: float


@dataclass
class NonlinearityResult:
    """Outcome of :func:`nonlinearity_test`; truthy when the system was found nonlinear.

    Attributes
    ----------
    nonlinear : bool
        The decision: ``statistic > threshold``.
    terms : list of NonlinearTerm
        The nonlinear terms of the best nonlinear alternative, strongest first (empty if the library has
        none).
    statistic : float
        ``gamma_linear - gamma_nonlinear``: how much Gamma grows without the nonlinear terms.
    threshold : float
        ``rel_tol * gamma_nonlinear + noise_tol * noise_gamma``: the growth that noise explains.
    gamma_linear, gamma_nonlinear : float
        Gamma of the refined linear model and of the refined nonlinear alternative on the test data.
    noise_gamma : float
        Gamma between the measured and the filtered states of the test data.
    linear_coefficients, nonlinear_coefficients : ndarray (n_states, n_features)
        The two refined models.
    feature_names : list of str
        Library term names (columns of the coefficient matrices).
    source : str
        Where the nonlinear alternative came from: ``"model"`` (the model's own nonlinear terms),
        ``"search"`` (a term added by the search) or ``"none"`` (no nonlinear term in the library).
    """

    nonlinear: bool
    terms: list[NonlinearTerm]
    statistic: float
    threshold: float
    gamma_linear: float
    gamma_nonlinear: float
    noise_gamma: float
    linear_coefficients: np.ndarray
    nonlinear_coefficients: np.ndarray
    feature_names: list[str] = field(default_factory=list)
    source: str = "model"

    def __bool__(self) -> bool:
        return bool(self.nonlinear)

    @property
    def relative_growth(self) -> float:
        """``statistic / gamma_nonlinear``: the growth of Gamma relative to the nonlinear model's."""
        return float(self.statistic / self.gamma_nonlinear) if self.gamma_nonlinear > 0 else np.inf

    def __repr__(self) -> str:
        terms = ", ".join(f"{t.equation} {t.coefficient:+.4g} {t.term} ({t.share:.1%})" for t in self.terms)
        return (
            f"NonlinearityResult(nonlinear={self.nonlinear}, statistic={self.statistic:.4g}, "
            f"threshold={self.threshold:.4g}, gamma_linear={self.gamma_linear:.4g}, "
            f"gamma_nonlinear={self.gamma_nonlinear:.4g}, terms=[{terms}])"
        )


def _model_parts(model):
    """Coefficients, fitted library, differentiation method and state names of a fitted SINDy model."""
    if not hasattr(model, "coefficients") or not callable(model.coefficients):
        raise TypeError(f"model must be a fitted ImpulseSINDy (or pysindy.SINDy), got {type(model).__name__}")
    try:
        coef = np.asarray(model.coefficients(), dtype=float)
    except Exception as err:  # not fitted
        raise ValueError(f"model is not fitted: {err}") from err
    library = getattr(model, "feature_library_", None) or getattr(model, "feature_library", None)
    diff = getattr(model, "differentiation_method_", None) or getattr(model, "differentiation_method", None)
    names = list(getattr(model, "feature_names_", None) or getattr(model, "feature_names", None) or [])
    return coef, library, diff, names or [f"x{i}" for i in range(coef.shape[0])]


class _Comparison:
    """Fits of given supports on the test data with the estimator's own steps (lstsq, compile, refine)."""

    def __init__(self, library, diff, data, measure_name, bound_factor, max_iter):
        self.filtered, derivs = differentiate(fresh_copy(diff), data.x, data.t)
        self.measure = get_error_measure(measure_name, self.filtered).bind(self.filtered, data.t)
        self.noise = self.measure.noise_level(data.x, self.filtered, data.t)
        self.theta = np.vstack(
            [
                np.asarray(library.transform(AxesArray(f, {"ax_time": 0, "ax_coord": 1})))
                for f in self.filtered
            ]
        )
        self.y = np.vstack(derivs)
        self.terms = library_terms(library, data.n_states)
        self.n_values = int(sum(f.size for f in self.filtered))
        self.bound_factor, self.max_iter = bound_factor, max_iter

    def fit(self, support):
        """Least squares on ``support``, then refined; ``(coefficients, score)``, never worse than lstsq."""
        coef = least_squares(self.theta, self.y, support)
        model = compile_model(coef, self.terms, np.vstack(self.filtered))
        g0 = float(self.measure(model)[0])
        if not np.isfinite(g0) or not np.any(coef):
            return coef, g0
        res = refine(model, self.measure, self.bound_factor, self.max_iter)
        return (res.coefficients, res.score) if res.score <= g0 else (coef, g0)

    def search(self, lin_support, candidates, n_search):
        """The ``n_search`` supports ``linear + one nonlinear term`` that best explain the residual."""
        rows = np.all(np.isfinite(self.y), axis=1) & np.all(np.isfinite(self.theta), axis=1)
        theta, y = self.theta[rows], self.y[rows]
        residual = y - theta @ least_squares(theta, y, lin_support).T
        scores = []
        for i in range(lin_support.shape[0]):
            basis = theta[:, np.flatnonzero(lin_support[i])]
            for k in candidates:
                col = theta[:, k]
                if basis.shape[1]:
                    col = col - basis @ np.linalg.lstsq(basis, col, rcond=None)[0]
                norm = float(col @ col)
                if norm > 0:
                    scores.append(((col @ residual[:, i]) ** 2 / norm, i, k))
        scores.sort(reverse=True)
        out = []
        for _, i, k in scores[:n_search]:
            support = lin_support.copy()
            support[i, k] = True
            out.append(support)
        return out


def _shares(coef, theta):
    """Share of each term in its equation's right-hand side magnitude, mean over the samples."""
    contrib = np.abs(theta)[None, :, :] * np.abs(coef)[:, None, :]  # (n_states, n_samples, n_features)
    mean = contrib.mean(axis=1)
    total = mean.sum(axis=1, keepdims=True)
    return np.divide(mean, total, out=np.zeros_like(mean), where=total > 0)


def nonlinearity_test(
    model,
    x,
    t=None,
    *,
    rel_tol: float = REL_TOL,
    noise_tol: float = NOISE_TOL,
    search: bool = True,
    bound_factor: float = 1.5,
    max_iter: int = 100,
) -> NonlinearityResult:
    """Decide whether the system behind ``x`` is nonlinear, with the statistic behind the decision.

    The best linear model (the model's linear terms) and the best nonlinear alternative (the model's
    nonlinear terms and, with ``search``, the strongest single nonlinear library term) are fitted to the
    filtered data and refined on Gamma; the system is nonlinear when removing the nonlinear terms makes
    Gamma grow by more than the noise explains (see the module docstring).

    Parameters
    ----------
    model : fitted ImpulseSINDy
        Its library, differentiation method and linear support define the two model classes.
    x : array-like (n_samples, n_states) or list of them
        The data the model was fitted on or new data of the same system.
    t : float, array or list of arrays, optional
        Time step or vectors (default: the model's ``dt``, else 1).
    rel_tol : float, default=0.5
        Gamma growth, relative to the nonlinear model's Gamma, that is not significant.
    noise_tol : float, default=0.05
        Weight of the noise Gamma (measured vs filtered states) in the tolerance.
    search : bool, default=True
        Also try the linear model plus the single nonlinear library term that explains most of its
        derivative residual (refining the best ``N_SEARCH`` of them), so that a nonlinearity dropped
        by the sparsification is still found.
    bound_factor, max_iter : float, int
        Refinement bounds and iterations (as in :class:`~sindy_impulse.ImpulseSINDy`).

    Returns
    -------
    NonlinearityResult

    Examples
    --------
    >>> from sindy_impulse import ImpulseSINDy, damped_oscillator
    >>> from sindy_impulse.analysis import nonlinearity_test
    >>> ring = damped_oscillator(k_nl=10.0, x0=(2.0, 0.0), snr_db=40, random_state=0)
    >>> model = ImpulseSINDy().fit(ring.x, t=ring.t)
    >>> result = nonlinearity_test(model, ring.x, ring.t)
    >>> result.nonlinear, result.terms[0].term
    (True, 'x0^3')
    >>> linear = damped_oscillator(snr_db=40, random_state=0)
    >>> bool(nonlinearity_test(ImpulseSINDy().fit(linear.x, t=linear.t), linear.x, linear.t))
    False
    """
    for name, val in (("rel_tol", rel_tol), ("noise_tol", noise_tol)):
        if isinstance(val, bool) or not isinstance(val, (int, float, np.number)) or not val >= 0:
            raise ValueError(f"{name} must be a non-negative number, got {val!r}")
    coef, library, diff, state_names = _model_parts(model)
    if diff is None:
        raise TypeError("model has no differentiation method")
    n_states = coef.shape[0]
    terms = term_table(library, n_states)
    data = as_trajectories(x, t, default_dt=getattr(model, "dt", None) or 1.0, min_samples=3)
    if data.n_states != n_states:
        raise ValueError(f"x has {data.n_states} states but the model has {n_states}")
    test = _Comparison(library, diff, data, getattr(model, "error_measure_", "gamma"), bound_factor, max_iter)
    degree = terms.powers.sum(axis=1)
    linear_cols = (terms.func == PLAIN) & (degree <= 1)
    lin_support = (coef != 0) & linear_cols[None, :]
    if not lin_support.any():  # a model without linear part: all linear terms of the library
        lin_support = np.broadcast_to(linear_cols & (degree == 1), coef.shape).copy()
    nl_support_model = (coef != 0) & ~linear_cols[None, :]
    lin_coef, g_lin = test.fit(lin_support)

    alternatives = [("model", lin_support | nl_support_model)] if nl_support_model.any() else []
    if search and (~linear_cols).any():
        for support in test.search(lin_support, np.flatnonzero(~linear_cols), N_SEARCH):
            if not any(np.array_equal(support, other) for _, other in alternatives):
                alternatives.append(("search", support))
    source, nl_coef, g_nl = "none", lin_coef, g_lin
    for name, support in alternatives:
        c, g = test.fit(support)
        if g < g_nl or source == "none":
            source, nl_coef, g_nl = name, c, g
    if source != "none" and not (np.isfinite(g_nl) and g_nl <= g_lin):
        # every nonlinear alternative diverged or did worse: nothing to gain from nonlinear terms
        source, nl_coef, g_nl = "none", lin_coef, g_lin

    names = library.get_feature_names(input_features=state_names)
    rows = np.all(np.isfinite(test.theta), axis=1)
    shares = _shares(nl_coef, test.theta[rows])
    found = [
        NonlinearTerm(f"{state_names[i]}'", names[k], float(nl_coef[i, k]), float(shares[i, k]))
        for i in range(n_states)
        for k in np.flatnonzero(~linear_cols)
        if nl_coef[i, k] != 0
    ]
    found.sort(key=lambda term: -term.share)
    statistic = float(g_lin - g_nl) if np.isfinite(g_lin) else np.inf
    threshold = tolerance(g_nl, test.noise, 0, 0.0, rel_tol, noise_tol) if np.isfinite(g_nl) else np.inf
    return NonlinearityResult(
        nonlinear=bool(found) and statistic > threshold,
        terms=found,
        statistic=statistic,
        threshold=float(threshold),
        gamma_linear=float(g_lin),
        gamma_nonlinear=float(g_nl),
        noise_gamma=test.noise,
        linear_coefficients=lin_coef,
        nonlinear_coefficients=nl_coef,
        feature_names=list(names),
        source=source,
    )

"""A test for nonlinearity that decides (paper section 3.3.3).

The paper reads the answer off the reconstructed equations: a non-zero cubic coefficient means a nonlinear
system. On noisy data that reading is fragile both ways: a spurious nonlinear term can compensate a small
error of the linear coefficients (the paper's own section 3.1.2 shows an artefact ``-0.51 x1^3``), and a
weak true nonlinearity can be dropped by the sparsification. :func:`nonlinearity_test` therefore turns the
reading into a model comparison on the simulated response, the quantity the method is built on:

1. filter the data with (a clone of) the model's differentiation method, as the fit did;
2. fit the best *linear* model (the model's linear and constant terms, least squares on the derivatives,
   then the bounded refinement of Gamma) and the best *nonlinear* alternative (the model's own support,
   and, with ``search=True``, the linear support plus the single nonlinear library term that explains
   most of the derivative residual; both least squares then refined);
3. the statistic is how much Gamma grows when the nonlinear terms are removed,
   ``delta = Gamma_linear - Gamma_nonlinear``; the system is called nonlinear when ``delta`` exceeds
   ``rel_tol * Gamma_nonlinear + noise_tol * Gamma_noise``, where ``Gamma_noise`` is the Gamma between the
   measured and the filtered states (what the filter removed). An extra term always lowers Gamma a little
   by fitting what is left of the noise; the tolerance is what that explains.

The strength of each nonlinear term is its share of the right-hand side's magnitude over the data:
``mean_t |xi_ik theta_k(x(t))| / mean_t sum_j |xi_ij theta_j(x(t))|`` in its equation ``i``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from pysindy.utils import AxesArray
from sklearn.base import clone

from .._validation import check_time, check_trajectories, time_vector
from ..feature_library.terms import PLAIN, term_table
from ..metrics import gamma_from_arrays
from ..refinement import refine_coefficients, simulation_gamma
from ..simulation import CompiledModel

__all__ = ["nonlinearity_test", "NonlinearityResult", "NonlinearTerm"]

#: Default relative tolerance: Gamma must grow by more than this fraction of the nonlinear model's Gamma.
REL_TOL = 0.5
#: Default weight of the noise Gamma in the tolerance.
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
    library = getattr(model, "feature_library_", None)
    if library is None:
        library = getattr(model, "feature_library", None)
    diff = getattr(model, "differentiation_method_", None)
    if diff is None:
        diff = getattr(model, "differentiation_method", None)
    names = list(getattr(model, "feature_names_", None) or getattr(model, "feature_names", None) or [])
    if not names:
        names = [f"x{i}" for i in range(coef.shape[0])]
    return coef, library, diff, names


def _filter(diff, trajectories, times):
    """Filtered states and derivatives per trajectory, as ImpulseSINDy.fit computes them."""
    filtered, derivs = [], []
    for xi, ti in zip(trajectories, times):
        method = clone(diff)
        d = np.asarray(method(AxesArray(xi, {"ax_time": 0, "ax_coord": 1}), ti), dtype=float)
        smoothed = getattr(method, "smoothed_x_", None)
        filtered.append(xi.copy() if smoothed is None else np.asarray(smoothed, float).reshape(xi.shape))
        derivs.append(d.reshape(xi.shape))
    return filtered, derivs


def _lstsq(theta, y, support):
    """Least squares per equation on a boolean support (n_states, n_features)."""
    coef = np.zeros(support.shape)
    for i in range(support.shape[0]):
        cols = np.flatnonzero(support[i])
        if cols.size:
            coef[i, cols] = np.linalg.lstsq(theta[:, cols], y[:, i], rcond=None)[0]
    return coef


def _refined(coef, terms, filtered, times, bound_factor, max_iter):
    """Coefficients refined on Gamma and their Gamma (never worse than the start)."""
    reference = np.vstack(filtered)
    model = CompiledModel(coef, terms, reference=reference)
    g0 = simulation_gamma(model, filtered, times)
    if not np.isfinite(g0) or not np.any(coef):
        return coef, g0
    res = refine_coefficients(model, filtered, times, bound_factor, max_iter)
    g = simulation_gamma(CompiledModel(res.coefficients, terms, reference=reference), filtered, times)
    return (res.coefficients, g) if g <= g0 else (coef, g0)


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
    trajectories, _ = check_trajectories(x, "x", min_samples=3)
    for i, xi in enumerate(trajectories):
        if xi.shape[1] != n_states:
            raise ValueError(f"x[{i}] has {xi.shape[1]} states but the model has {n_states}")
    if t is None:
        t = getattr(model, "dt", None) or 1.0
    if isinstance(t, (list, tuple)) and len(t) == len(trajectories) and np.ndim(t[0]) == 1:
        times = [time_vector(check_time(ti, len(xi), "t"), len(xi)) for ti, xi in zip(t, trajectories)]
    else:
        times = [time_vector(check_time(t, len(xi), "t"), len(xi)) for xi in trajectories]

    filtered, derivs = _filter(diff, trajectories, times)
    noise = float(sum(gamma_from_arrays(r, f) for r, f in zip(trajectories, filtered)))
    theta = np.vstack(
        [np.asarray(library.transform(AxesArray(f, {"ax_time": 0, "ax_coord": 1}))) for f in filtered]
    )
    y = np.vstack(derivs)
    rows = np.all(np.isfinite(y), axis=1) & np.all(np.isfinite(theta), axis=1)
    theta_fit, y_fit = theta[rows], y[rows]
    names = library.get_feature_names(input_features=state_names)

    degree = terms.powers.sum(axis=1)
    linear_cols = (terms.func == PLAIN) & (degree <= 1)
    active = coef != 0
    lin_support = active & linear_cols[None, :]
    if not lin_support.any():  # a model without linear part: all linear terms of the library
        lin_support = np.broadcast_to(linear_cols & (degree == 1), coef.shape).copy()
    nl_support_model = active & ~linear_cols[None, :]

    lin_coef, g_lin = _refined(
        _lstsq(theta_fit, y_fit, lin_support), terms, filtered, times, bound_factor, max_iter
    )

    alternatives = []
    if nl_support_model.any():
        alternatives.append(("model", lin_support | nl_support_model))
    if search and (~linear_cols).any():
        residual = y_fit - theta_fit @ _lstsq(theta_fit, y_fit, lin_support).T
        scores = []
        for i in range(n_states):
            for k in np.flatnonzero(~linear_cols):
                col = theta_fit[:, k]
                # residual reduction by adding column k to equation i, after projecting out the linear part
                cols = np.flatnonzero(lin_support[i])
                if cols.size:
                    basis = theta_fit[:, cols]
                    col = col - basis @ np.linalg.lstsq(basis, col, rcond=None)[0]
                norm = float(col @ col)
                if norm > 0:
                    scores.append(((col @ residual[:, i]) ** 2 / norm, i, k))
        scores.sort(reverse=True)
        for _, i, k in scores[:N_SEARCH]:
            support = lin_support.copy()
            support[i, k] = True
            if not any(np.array_equal(support, s) for _, s in alternatives):
                alternatives.append(("search", support))

    best = ("none", lin_coef, g_lin)
    for source, support in alternatives:
        c, g = _refined(_lstsq(theta_fit, y_fit, support), terms, filtered, times, bound_factor, max_iter)
        if g < best[2] or best[0] == "none":
            best = (source, c, g)
    source, nl_coef, g_nl = best
    if source != "none" and not (np.isfinite(g_nl) and g_nl <= g_lin):
        # every nonlinear alternative diverged or did worse: nothing to gain from nonlinear terms
        source, nl_coef, g_nl = "none", lin_coef, g_lin

    shares = _shares(nl_coef, theta[rows])
    found = [
        NonlinearTerm(f"{state_names[i]}'", names[k], float(nl_coef[i, k]), float(shares[i, k]))
        for i in range(n_states)
        for k in np.flatnonzero(~linear_cols)
        if nl_coef[i, k] != 0
    ]
    found.sort(key=lambda term: -term.share)
    statistic = float(g_lin - g_nl) if np.isfinite(g_lin) else np.inf
    threshold = float(rel_tol * g_nl + noise_tol * noise) if np.isfinite(g_nl) else np.inf
    return NonlinearityResult(
        nonlinear=bool(found) and statistic > threshold,
        terms=found,
        statistic=statistic,
        threshold=threshold,
        gamma_linear=float(g_lin),
        gamma_nonlinear=float(g_nl),
        noise_gamma=noise,
        linear_coefficients=lin_coef,
        nonlinear_coefficients=nl_coef,
        feature_names=list(names),
        source=source,
    )

"""The model comparison behind :func:`~sindy_impulse.analysis.nonlinearity_test` (its engine).

Everything here is done with the estimator's own steps, on the test data made unit-free:

1. :func:`normalise`: each state's equilibrium (the Hann-weighted mean of the record's end, as the backbone
   estimator takes it) is removed and the state divided by its largest remaining magnitude, so the same
   record in other units, or with an offset, gives the same numbers (up to rounding);
2. :class:`Comparison`: the fit's own stages (:mod:`sindy_impulse.identification.stages`) on the
   normalised data: the model's differentiation method and a fresh copy of its library build the
   regression once (:func:`~sindy_impulse.identification.stages.prepare`); each support is fitted by
   :func:`~sindy_impulse.identification.stages.run_stages` (least squares on the support, scored, refined
   on the model's error measure);
3. :meth:`Comparison.search`: the nonlinear library terms that best explain the linear model's derivative
   residual (one term added to one equation);
4. :func:`alternatives`: the refined linear model and the best refined nonlinear alternative;
5. :meth:`Comparison.backbones` and :func:`amplitude_ratio`: the backbones of the data
   (:func:`hilbert_backbone`) and of a refined model (:func:`backbone`), and the amplitude dependence they
   show;
6. :func:`to_data_units`, :func:`in_data_units`: coefficients and backbones back in the data's units.
"""

from __future__ import annotations

import warnings

import numpy as np

from .._utils.trajectories import as_trajectories
from ..identification.stages import filter_states, prepare, run_stages
from ..optimizers import fresh_copy, least_squares
from ..simulation import get_error_measure, oscillation_count
from ..simulation.terms import ABS, PLAIN, SIGNED_SQUARE, SMOOTH_SIGN
from .backbone import Backbone, backbone, hilbert_backbone
from .instantaneous import carrier_hz, offset

__all__ = ["normalise", "Comparison", "alternatives", "amplitude_ratio", "in_data_units", "to_data_units"]

#: The data backbone ends where its envelope falls below this many times its noise estimate. A band-passed
#: record's noise is narrow-band, which the Hilbert residual underestimates several times over, so the
#: default of :func:`hilbert_backbone` (10) would let the curve run into the noise.
DATA_MIN_SNR = 50.0


def _equilibrium(x: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Each state's equilibrium: the Hann-weighted mean of the end of the decay (``_decay.offset``)."""
    dt = float(np.median(np.diff(t))) if len(t) > 1 else 1.0
    out = np.empty(x.shape[1])
    for j in range(x.shape[1]):
        col = x[:, j]
        try:
            out[j] = offset(col, 1.0 / (carrier_hz(col, dt) * dt))
        except ValueError:  # no oscillation (a constant column): its last value
            out[j] = float(col[-1])
    return out


def normalise(trajectories, times):
    """Trajectories with each state's equilibrium removed and divided by its largest magnitude.

    Returns ``(normalised, scales, equilibria)``: lists of arrays, the scale per state (over all
    trajectories) and the equilibrium per trajectory and state.

    Examples
    --------
    >>> t = np.arange(2000) * 0.01
    >>> x = 3.0 + 1e-6 * np.exp(-0.05 * t) * np.cos(2 * np.pi * t)
    >>> z, scales, equilibria = normalise([x[:, None]], [t])
    >>> round(float(np.max(np.abs(z[0]))), 6), round(float(equilibria[0][0]), 6)
    (1.0, 3.0)
    """
    equilibria = [_equilibrium(x, t) for x, t in zip(trajectories, times)]
    centred = [x - e for x, e in zip(trajectories, equilibria)]
    scales = np.max([np.max(np.abs(c), axis=0) for c in centred], axis=0)
    scales = np.where(scales > 0, scales, 1.0)
    return [c / scales for c in centred], scales, equilibria


class Comparison:
    """Fits of given supports to the normalised test data through the estimator's own stages.

    The regression is built once (:func:`~sindy_impulse.identification.stages.prepare`); each support is
    then fitted by :func:`~sindy_impulse.identification.stages.run_stages` with the test's constraints:
    the support's least-squares coefficients as the only candidate, refined on the model's error measure.
    """

    def __init__(self, library, diff, xs, ts, measure_name, bound_factor, max_iter):
        data = as_trajectories(list(xs), list(ts))
        self.filtered, derivs = filter_states(fresh_copy(diff), data)
        self.measured, self.times = xs, ts
        self.problem = prepare(fresh_copy(library), data, self.filtered, derivs, refuse_underdetermined=False)
        self.measure = get_error_measure(measure_name, self.filtered).bind(self.filtered, ts)
        self.noise = self.measure.noise_level(xs, self.filtered, ts)
        self.theta, self.y, self.terms = self.problem.theta, self.problem.y, self.problem.terms
        self.n_values = self.problem.n_values
        self.n_cycles = float(sum(oscillation_count(f) for f in self.filtered))
        self.bound_factor, self.max_iter = bound_factor, max_iter

    def compile(self, coef):
        return self.problem.compile(coef)

    def fit(self, support):
        """Least squares on ``support``, then refined; ``(coefficients, score)``, never worse than lstsq."""
        result = run_stages(
            self.problem,
            self.problem.on_supports([support]),
            self.measure,
            selection="min_gamma",
            bound_factor=self.bound_factor,
            max_iter=self.max_iter,
            all_diverged="keep",
        )
        return result.coefficients, result.score

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
                if norm > 1e-12 * float(theta[:, k] @ theta[:, k]):  # not a combination of the basis
                    scores.append(((col @ residual[:, i]) ** 2 / norm, i, k))
        scores.sort(reverse=True)
        out = []
        for _, i, k in scores[:n_search]:
            support = lin_support.copy()
            support[i, k] = True
            out.append(support)
        return out

    def backbones(self, coef, coordinate: int):
        """``(data, model)`` backbones of the measured coordinate (normalised units; None where n/a).

        The data curve is :func:`hilbert_backbone` of the measured coordinate of the trajectory with the
        largest range, cut at :data:`DATA_MIN_SNR`; the model curve is :func:`backbone` of the refined
        model ``coef`` over the whole decay (from the data's first state to the amplitude at its end).
        """
        i = int(np.argmax([np.ptp(f[:, coordinate]) for f in self.filtered]))
        curves = []
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            y, t = self.measured[i][:, coordinate], self.times[i]
            for make in (
                lambda: hilbert_backbone(y, t, min_snr=DATA_MIN_SNR),
                lambda: backbone(_RefinedModel(self, coef, coordinate)),
            ):
                try:
                    curve = make()
                except (ValueError, FloatingPointError):
                    curve = None
                curves.append(curve if curve is not None and len(curve) >= 2 else None)
        return tuple(curves)


def alternatives(test: Comparison, coef, terms, search: bool, n_search: int):
    """The linear fit and the best nonlinear alternative: ``(lin_coef, g_lin), (source, coef, g)``."""
    degree = terms.powers.sum(axis=1)
    linear_cols = terms.linear
    lin_support = (coef != 0) & linear_cols[None, :]
    if not lin_support.any():  # a model without linear part: all linear terms of the library
        lin_support = np.broadcast_to(linear_cols & (degree == 1), coef.shape).copy()
    nl_support_model = (coef != 0) & ~linear_cols[None, :]
    lin_coef, g_lin = test.fit(lin_support)
    candidates = [("model", lin_support | nl_support_model)] if nl_support_model.any() else []
    if search and (~linear_cols).any():
        for support in test.search(lin_support, np.flatnonzero(~linear_cols), n_search):
            if not any(np.array_equal(support, other) for _, other in candidates):
                candidates.append(("search", support))
    best = ("none", lin_coef, g_lin)
    for name, support in candidates:
        c, g = test.fit(support)
        if np.any(c[:, ~linear_cols]) and (g < best[2] or best[0] == "none"):
            best = (name, c, g)
    if best[0] != "none" and not (np.isfinite(best[2]) and best[2] < g_lin):
        best = ("none", lin_coef, g_lin)  # every alternative diverged, did worse or lost its terms
    return (lin_coef, g_lin), best, linear_cols


#: Share of the model's shift the data must show the other way (besides the resolution) to contradict
#: it: the data's Hilbert backbone scatters, its damping-ratio change over the decay of a linear record
#: reaching 0.04 (median) to 0.15 (90 %) on short, strongly damped simulated decays, where the model's
#: backbone of an amplitude-dependent damper shows 0.12-0.36.
CONTRADICTION_SHARE = 0.5


def amplitude_ratio(model_curve, data_curve, frequency_resolution, damping_resolution) -> float:
    """``max(|shift| / resolution)`` over frequency and damping, unless the data show it the other way
    (by at least the resolution and :data:`CONTRADICTION_SHARE` of the model's shift)."""
    if model_curve is None:
        return np.inf
    ratios = [0.0]
    pairs = (("frequency_shift", frequency_resolution), ("damping_ratio_shift", damping_resolution))
    for name, resolution in pairs:
        shift = getattr(model_curve, name)
        seen = np.nan if data_curve is None else getattr(data_curve, name)
        contradicted = (np.isfinite(seen) and seen * shift < 0
                        and abs(seen) >= max(resolution, CONTRADICTION_SHARE * abs(shift)))
        if np.isfinite(shift) and not contradicted:
            ratios.append(abs(shift) / resolution)
    return float(max(ratios))



class _RefinedModel:
    """A refined candidate as :func:`backbone` sees a fitted model (simulate, fitted data, coordinate)."""

    def __init__(self, comparison: Comparison, coef, coordinate: int):
        self._model = comparison.compile(coef)
        self.x_filtered_ = comparison.filtered
        self.t_ = comparison.times
        self.coordinate_ = coordinate

    def simulate(self, x0, t):
        return self._model.simulate(x0, t)


def in_data_units(curve: Backbone | None, scale: float) -> Backbone | None:
    """A backbone of the normalised coordinate with its amplitudes back in the data's units."""
    if curve is None:
        return None
    return Backbone(curve.amplitude * scale, curve.frequency_hz, curve.damping_ratio, curve.source)


def to_data_units(coef, terms, scales):
    """Coefficients for the normalised states in the data's units (about the equilibrium), or None.

    A term of state degrees ``d_j`` (its monomial's powers, plus 2 for ``x|x|`` and 1 for ``|x|`` of its
    function's state; a smooth sign, whose width follows the amplitude, counts 0) is homogeneous: in
    equation ``i`` its coefficient scales by ``s_i / prod_j s_j**d_j``. Libraries with other terms (sin,
    cos; no term table) have no such conversion: None.
    """
    homogeneous = (PLAIN, SIGNED_SQUARE, ABS, SMOOTH_SIGN)
    if not hasattr(terms, "func") or not np.all(np.isin(terms.func, homogeneous)):
        return None
    degrees = np.array(terms.powers[:, : len(scales)], dtype=float)
    rows = np.arange(terms.n_features)
    extra = np.select([terms.func == SIGNED_SQUARE, terms.func == ABS], [2.0, 1.0], 0.0)
    np.add.at(degrees, (rows, terms.func_state), extra)
    factor = scales[:, None] / np.prod(scales[None, :] ** degrees, axis=1)[None, :]
    return np.asarray(coef, dtype=float) * factor

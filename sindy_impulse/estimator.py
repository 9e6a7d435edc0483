"""ImpulseSINDy: PySINDy plus the lambda sweep scored by Gamma and the bounded refinement.

The estimator reads like the paper's Figure 1 plus sections 2.4-2.5: differentiate (and filter) the
states, build the library on the filtered states, compute every sparse candidate along the threshold
path, simulate each from the first sample and score it by Gamma, select, refine. It holds no algorithm
of its own: each step is a module of the package.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import pysindy as ps
from pysindy.utils import AxesArray
from sklearn.base import clone
from sklearn.utils.validation import check_is_fitted

from ._validation import check_signal, check_time, check_trajectories, time_vector
from .feature_library.terms import term_table
from .metrics import gamma_from_arrays
from .optimizers import ThresholdSweep
from .refinement import WorkBudget, refine_coefficients, simulation_gamma
from .selection import SELECTION_RULES, select_candidate
from .simulation import CompiledModel

__all__ = ["ImpulseSINDy", "SweepPath"]


@dataclass
class SweepPath:
    """Every candidate of the threshold sweep (the data of the paper's Figure 6a).

    Attributes
    ----------
    threshold : ndarray (n_candidates,)
        Relative threshold at which each candidate appears (0: all terms).
    gamma : ndarray (n_candidates,)
        Gamma of each candidate's simulation (inf if it diverged).
    n_terms : ndarray (n_candidates,)
        Number of non-zero coefficients.
    coefficients : ndarray (n_candidates, n_states, n_features)
    selected : int
        Index of the selected candidate.
    """

    threshold: np.ndarray
    gamma: np.ndarray
    n_terms: np.ndarray
    coefficients: np.ndarray
    selected: int

    def __len__(self) -> int:
        return len(self.gamma)


def _default_library():
    return ps.PolynomialLibrary(degree=3)


def _default_differentiation():
    from .differentiation import TVRegDiff

    return TVRegDiff()


class ImpulseSINDy(ps.SINDy):
    """SINDy for impulse responses: threshold sweep on Gamma and bounded refinement.

    A drop-in :class:`pysindy.SINDy`: the same constructor arguments and methods (``fit``,
    ``predict``, ``simulate``, ``coefficients``, ``equations``, ``print``), plus the paper's extensions.
    With the default :class:`~sindy_impulse.ThresholdSweep` optimizer every distinct sparse model along
    the threshold path is simulated from the first sample and scored by Gamma; another PySINDy optimizer
    turns the sweep off (its single model is used). ``refine=True`` then minimizes Gamma over the non-zero
    coefficients within ``[0, 1.5 xi]``.

    Parameters
    ----------
    optimizer : pysindy optimizer, default=ThresholdSweep()
        ``ThresholdSweep`` (the sweep) or any PySINDy optimizer (no sweep). Cloned at fit.
    feature_library : pysindy feature library, default=PolynomialLibrary(degree=3)
        ``PolynomialLibrary`` or :class:`~sindy_impulse.MechanicalLibrary` (the compiled simulator
        supports these). Cloned at fit.
    differentiation_method : pysindy differentiation, default=TVRegDiff()
        Its ``smoothed_x_`` (the filtered states) is what the library, the simulations and Gamma use.
    selection : {"auto", "min_gamma"}, default="auto"
        ``"min_gamma"`` keeps the candidate of least Gamma (the paper). ``"auto"`` keeps the sparsest
        candidate whose refined Gamma is within the noise tolerance of the best (see
        :func:`sindy_impulse.selection.select_candidate`).
    refine : bool, default=True
        Refine the selected model's non-zero coefficients (SLSQP on Gamma).
    bound_factor : float, default=1.5
        Refinement bounds ``[0, bound_factor * xi]``.
    refine_max_iter : int, default=100
        SLSQP iterations.
    divergence_factor : float, default=100
        A simulation that exceeds this factor times the data's range counts as diverged (Gamma = inf).
    dt : float, optional
        Sampling step used when ``fit`` gets no ``t`` (e.g. as a Pipeline step). Without either, the
        time unit is one sample.

    Attributes
    ----------
    gamma_ : float
        Gamma of the final model.
    gamma_sindy_ : float
        Gamma of the selected candidate before refinement.
    threshold_ : float
        Relative threshold of the selected candidate.
    path_ : SweepPath
        Every candidate of the sweep.
    refinement_history_ : dict
        ``"gamma"`` and ``"coefficients"`` per SLSQP iteration.
    x_filtered_ : ndarray or list of ndarray
        The states the library was built from (filtered by the differentiation).
    t_ : ndarray or list of ndarray
        Their time vectors.
    model_ : CompiledModel
        The compiled final model used by ``simulate`` and ``predict``.

    Examples
    --------
    >>> from sindy_impulse import ImpulseSINDy, damped_oscillator
    >>> t, x, x_dot = damped_oscillator()
    >>> model = ImpulseSINDy().fit(x, t=t)
    >>> model.print(precision=2)
    (x0)' =  1.00 x1
    (x1)' = -64.00 x0 + -3.20 x1
    """

    def __init__(
        self,
        optimizer=None,
        feature_library=None,
        differentiation_method=None,
        *,
        selection: str = "auto",
        refine: bool = True,
        bound_factor: float = 1.5,
        refine_max_iter: int = 100,
        divergence_factor: float = 100.0,
        dt: float | None = None,
    ):
        # Parameters are stored untouched (scikit-learn contract); defaults are built at fit.
        self.optimizer = optimizer
        self.feature_library = feature_library
        self.differentiation_method = differentiation_method
        self.selection = selection
        self.refine = refine
        self.bound_factor = bound_factor
        self.refine_max_iter = refine_max_iter
        self.divergence_factor = divergence_factor
        self.dt = dt

    # ------------------------------------------------------------------------------------------------
    # fit
    # ------------------------------------------------------------------------------------------------
    def _check_params(self):
        if self.selection not in SELECTION_RULES:
            raise ValueError(f"selection must be one of {sorted(SELECTION_RULES)}, got {self.selection!r}")
        if not isinstance(self.refine, (bool, np.bool_)):
            raise TypeError(f"refine must be True or False, got {self.refine!r}")
        for name in ("bound_factor", "divergence_factor"):
            val = getattr(self, name)
            if isinstance(val, bool) or not isinstance(val, (int, float, np.number)) or not val > 0:
                raise ValueError(f"{name} must be a positive number, got {val!r}")
        if self.dt is not None:
            check_time(self.dt, 1, "dt")

    def _times(self, t, trajectories):
        """One validated time vector per trajectory."""
        if t is None:
            t = 1.0 if self.dt is None else self.dt
        if (
            isinstance(t, (list, tuple))
            and len(trajectories) > 1
            or (isinstance(t, (list, tuple)) and len(t) == 1 and np.ndim(t[0]) == 1)
        ):
            if len(t) != len(trajectories):
                raise ValueError(f"t has {len(t)} time vectors but x has {len(trajectories)} trajectories")
            checked = [check_time(ti, len(xi), f"t[{i}]") for i, (ti, xi) in enumerate(zip(t, trajectories))]
        else:
            checked = [check_time(t, len(xi), "t") for xi in trajectories]
        return [time_vector(ti, len(xi)) for ti, xi in zip(checked, trajectories)]

    def fit(self, x, t=None, x_dot=None, u=None, feature_names=None):
        """Fit the model: differentiate, sweep, select by Gamma, refine.

        Parameters
        ----------
        x : array-like (n_samples, n_states) or list of them
            Measured states; a list means several trajectories (e.g. repeated impacts).
        t : float, array (n_samples,) or list of arrays, optional
            Time step or time vector(s); defaults to ``dt``.
        x_dot : array-like or list, optional
            Known derivatives; then ``x`` itself is used as the filtered states.
        u : None
            Control inputs are not supported (free responses only).
        feature_names : list of str, optional
            Names of the states, e.g. ``["x", "v"]``.

        Returns
        -------
        self
        """
        self._check_params()
        if u is not None:
            raise ValueError("control inputs u are not supported: ImpulseSINDy models free responses")
        trajectories, multiple = check_trajectories(x, "x", min_samples=3)
        times = self._times(t, trajectories)
        n_states = trajectories[0].shape[1]
        if feature_names is not None:
            feature_names = [str(f) for f in feature_names]
            if len(feature_names) != n_states:
                raise ValueError(f"feature_names has {len(feature_names)} names for {n_states} states")

        self.feature_library_ = (
            clone(self.feature_library) if self.feature_library is not None else (_default_library())
        )
        self.optimizer_ = clone(self.optimizer) if self.optimizer is not None else ThresholdSweep()
        self.differentiation_method_ = (
            clone(self.differentiation_method)
            if self.differentiation_method is not None
            else _default_differentiation()
        )

        filtered, derivatives = self._differentiate(trajectories, times, x_dot, multiple)
        theta = self.feature_library_.fit_transform(
            [AxesArray(f, {"ax_time": 0, "ax_coord": 1}) for f in filtered]
        )
        theta = np.vstack([np.asarray(th) for th in theta])
        y = np.vstack(derivatives)
        usable = int(np.sum(np.all(np.isfinite(y), axis=1)))
        n_features = theta.shape[1]
        if usable < n_features + 1:
            raise ValueError(
                f"too few samples: {usable} usable derivative samples for a library of {n_features} terms; "
                f"at least {n_features + 1} are needed"
            )
        self.optimizer_.fit(theta, y)

        self.n_features_in_ = n_states
        self.n_output_features_ = n_features
        self.n_control_features_ = 0
        self.feature_names_ = feature_names or [f"x{i}" for i in range(n_states)]
        self.x_filtered_ = filtered if multiple else filtered[0]
        self.t_ = times if multiple else times[0]

        sweep = isinstance(self.optimizer_, ThresholdSweep)
        candidates = np.asarray(self.optimizer_.history_) if sweep else self.optimizer_.coef_[None].copy()
        thresholds = np.asarray(self.optimizer_.thresholds_) if sweep else np.array([np.nan])
        n_terms = np.array([np.count_nonzero(c) for c in candidates])
        try:
            terms = term_table(self.feature_library_, n_states)
        except TypeError:
            if sweep or self.refine:
                raise
            # plain PySINDy use with a library the simulator does not support: no simulation, no Gamma
            self.model_ = None
            self.path_ = SweepPath(thresholds, np.array([np.nan]), n_terms, candidates, 0)
            self.gamma_ = self.gamma_sindy_ = np.nan
            self.threshold_ = thresholds[0]
            self.refinement_history_ = {"gamma": [], "coefficients": []}
            return self

        reference = np.vstack(filtered)

        def compile_(coef):
            return CompiledModel(coef, terms, reference=reference, divergence_factor=self.divergence_factor)

        # One deterministic work budget bounds all simulations of the fit (sweep and refinements).
        budget = WorkBudget()
        gammas, n_skipped = self._score_candidates(candidates, n_terms, compile_, filtered, times, budget)
        usable = self._usable_candidates(gammas, n_terms)
        noise = self._noise_gamma(trajectories, filtered)
        index, (coef, g, history) = select_candidate(
            self.selection,
            np.where(usable, gammas, np.inf),
            n_terms,
            lambda i: self._refine_candidate(candidates[i], gammas[i], compile_, filtered, times, budget),
            noise,
            n_values=int(sum(f.size for f in filtered)),
        )
        if budget.exhausted:
            what = f"{n_skipped} dense candidates not simulated" if n_skipped else "refinement stopped early"
            warnings.warn(
                f"the simulation work budget of the fit ran out (long record or large library): {what}; "
                "the model may be less accurate (see sindy_impulse.refinement.WORK_BUDGET)",
                RuntimeWarning,
                stacklevel=2,
            )

        self.path_ = SweepPath(thresholds, gammas, n_terms, candidates, index)
        self.threshold_ = float(thresholds[index])
        self.gamma_sindy_ = float(gammas[index])
        self.gamma_ = float(g)
        self.refinement_history_ = history
        self.noise_gamma_ = noise
        self.optimizer_.coef_ = np.asarray(coef, dtype=float)
        self.optimizer_.ind_ = self.optimizer_.coef_ != 0
        self.model_ = compile_(self.optimizer_.coef_)
        return self

    @staticmethod
    def _score_candidates(candidates, n_terms, compile_, filtered, times, budget):
        """Gamma of every candidate simulated from the first sample (paper sections 2.4, 3.1).

        Sparsest first: if the work budget runs out, the densest candidates stay unsimulated (inf).
        """
        gammas = np.full(len(candidates), np.inf)
        n_skipped = 0
        for i in np.argsort(n_terms, kind="stable"):
            if budget.exhausted:
                n_skipped += 1
                continue
            gammas[i] = simulation_gamma(compile_(candidates[i]), filtered, times, budget=budget)
        return gammas, n_skipped

    @staticmethod
    def _usable_candidates(gammas, n_terms):
        """Candidates that may be selected: finite Gamma and at least one term.

        The empty model (x' = 0) stays on the path for plotting and is selected only when every other
        candidate diverged (e.g. white noise): the honest answer "no deterministic dynamics found".
        """
        usable = np.isfinite(gammas) & (n_terms > 0)
        if np.any(usable):
            return usable
        if not np.any(np.isfinite(gammas)):
            raise RuntimeError(
                "every candidate model diverged when simulated from the first sample; check the data "
                "(units of t, trends, clipping) or use a smaller feature library"
            )
        warnings.warn(
            "every non-trivial candidate model diverged when simulated; the fitted model is x' = 0 "
            "(no deterministic dynamics found in the data)",
            RuntimeWarning,
            stacklevel=3,
        )
        return np.isfinite(gammas)

    def _refine_candidate(self, coef, gamma, compile_, filtered, times, budget):
        """The candidate refined by SLSQP on Gamma (paper section 2.5); never worse than unrefined."""
        if not self.refine:
            return coef, gamma, {"gamma": [gamma], "coefficients": []}
        res = refine_coefficients(
            compile_(coef), filtered, times, self.bound_factor, self.refine_max_iter, budget=budget
        )
        g = simulation_gamma(compile_(res.coefficients), filtered, times)
        if not g <= gamma:
            return coef, gamma, res.history
        return res.coefficients, g, res.history

    def _differentiate(self, trajectories, times, x_dot, multiple):
        """Derivatives and filtered states per trajectory."""
        if x_dot is not None:
            derivs, multiple_dot = check_trajectories(x_dot, "x_dot")
            if multiple_dot != multiple or len(derivs) != len(trajectories):
                raise ValueError("x_dot must have the same trajectories as x")
            for i, (d, xi) in enumerate(zip(derivs, trajectories)):
                if d.shape != xi.shape:
                    raise ValueError(f"x_dot[{i}] has shape {d.shape} but x[{i}] has shape {xi.shape}")
            return [xi.copy() for xi in trajectories], derivs
        filtered, derivs = [], []
        for xi, ti in zip(trajectories, times):
            axes = AxesArray(xi, {"ax_time": 0, "ax_coord": 1})
            d = np.asarray(self.differentiation_method_(axes, ti), dtype=float)
            smoothed = getattr(self.differentiation_method_, "smoothed_x_", None)
            filtered.append(
                xi.copy() if smoothed is None else np.asarray(smoothed, dtype=float).reshape(xi.shape)
            )
            derivs.append(d.reshape(xi.shape))
        return filtered, derivs

    @staticmethod
    def _noise_gamma(raw, filtered) -> float:
        """Gamma between the measured and the filtered states: the noise the filter removed."""
        return float(sum(gamma_from_arrays(r, f) for r, f in zip(raw, filtered)))

    # ------------------------------------------------------------------------------------------------
    # the fitted model (PySINDy's methods, reading the fitted components)
    # ------------------------------------------------------------------------------------------------
    @property
    def feature_names(self):
        """Names of the states (PySINDy's attribute)."""
        return getattr(self, "feature_names_", None)

    @feature_names.setter
    def feature_names(self, value):  # PySINDy's methods may assign it
        self.feature_names_ = value

    def coefficients(self) -> np.ndarray:
        """Coefficient matrix (n_states, n_features): rows are equations, columns library terms."""
        check_is_fitted(self, "optimizer_")
        return self.optimizer_.coef_

    def get_feature_names(self) -> list[str]:
        """Names of the library terms."""
        check_is_fitted(self, "optimizer_")
        return self.feature_library_.get_feature_names(input_features=self.feature_names_)

    def equations(self, precision: int = 3) -> list[str]:
        """Right-hand sides as strings, formatted as PySINDy does (``'-64.000 x0 + -3.200 x1'``)."""
        names = self.get_feature_names()
        out = []
        for row in self.coefficients():
            terms = [f"{c: .{precision}f} {n}" for c, n in zip(row, names) if np.round(c, precision) != 0]
            out.append(" + ".join(terms) if terms else f"{0: .{precision}f}")
        return out

    def print(self, lhs=None, precision: int = 3, **kwargs) -> None:
        """Print the equations, one per state."""
        lhs = lhs or [f"({n})'" for n in self.feature_names_]
        for name, eq in zip(lhs, self.equations(precision)):
            print(f"{name} = {eq}", **kwargs)

    @property
    def complexity(self) -> int:
        """Number of non-zero coefficients."""
        return int(np.count_nonzero(self.coefficients()))

    def _check_states(self, x, min_samples: int = 1):
        """Validate states for a fitted model: one column per state."""
        if np.ndim(x) == 1 and self.n_features_in_ > 1:
            raise ValueError(
                f"x is 1-D but the model has {self.n_features_in_} states: Reshape your data to "
                f"(n_samples, {self.n_features_in_})"
            )
        trajectories, multiple = check_trajectories(x, "x", min_samples=min_samples)
        for xi in trajectories:
            if xi.shape[1] != self.n_features_in_:
                raise ValueError(
                    f"X has {xi.shape[1]} features, but {type(self).__name__} is expecting "
                    f"{self.n_features_in_} features as input (x must have one column per state)"
                )
        return trajectories, multiple

    def predict(self, x, u=None):
        """The model's right-hand side at states ``x`` (or a list of state arrays)."""
        check_is_fitted(self, "optimizer_")
        if u is not None:
            raise ValueError("control inputs u are not supported")
        trajectories, multiple = self._check_states(x)
        if self.model_ is not None:
            out = [self.model_.rhs(xi) for xi in trajectories]
        else:
            out = [
                np.asarray(self.feature_library_.transform(AxesArray(xi, {"ax_time": 0, "ax_coord": 1})))
                @ self.coefficients().T
                for xi in trajectories
            ]
        return out if multiple else out[0]

    def simulate(self, x0, t, **kwargs) -> np.ndarray:
        """Integrate the model from ``x0`` over the time vector ``t`` with the compiled simulator.

        Extra keyword arguments of :meth:`pysindy.SINDy.simulate` (integrator options) are accepted and
        ignored. Rows after a divergence are NaN (with a warning).

        Examples
        --------
        >>> import numpy as np
        >>> from sindy_impulse import ImpulseSINDy, damped_oscillator
        >>> t, x, x_dot = damped_oscillator()
        >>> model = ImpulseSINDy().fit(x, t=t, x_dot=x_dot)
        >>> bool(np.allclose(model.simulate(x[0], t), x, atol=1e-6))
        True
        """
        check_is_fitted(self, "optimizer_")
        if self.model_ is None:
            raise TypeError(
                f"{type(self.feature_library_).__name__} is not supported by the compiled simulator"
            )
        x0 = check_signal(x0, "x0", ndim=(1,), as_2d=False)
        if x0.shape[0] != self.n_features_in_:
            raise ValueError(f"x0 has {x0.shape[0]} entries but the model has {self.n_features_in_} states")
        tt = np.asarray(t, dtype=float)
        if tt.ndim == 0:
            raise ValueError("t must be an array of time points at which to simulate")
        tt = check_time(tt, tt.shape[0], "t")
        out = self.model_.simulate(x0, tt)
        if np.isnan(out).any():
            warnings.warn(
                "the simulation diverged; rows after the divergence are NaN", RuntimeWarning, stacklevel=2
            )
        return out

    def score(self, x, t=None, x_dot=None, u=None, **kwargs) -> float:
        """Negative Gamma of the model simulated from the first sample of ``x`` (higher is better).

        Used by scikit-learn's model selection (e.g. ``GridSearchCV``).
        """
        check_is_fitted(self, "optimizer_")
        trajectories, _ = self._check_states(x, min_samples=2)
        times = self._times(t, trajectories)
        total = 0.0
        for xi, ti in zip(trajectories, times):
            total += gamma_from_arrays(xi, self.model_.simulate(xi[0], ti))
        return -float(total)

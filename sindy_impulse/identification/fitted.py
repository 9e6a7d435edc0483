"""What a fitted ImpulseSINDy does, in PySINDy's terms: equations, prediction, simulation, score.

A mixin of :class:`~sindy_impulse.ImpulseSINDy`; it reads the fitted components (``coef_``, ``model_``,
``feature_library_``, ``differentiation_method_``) and adds no algorithm: simulation is
:mod:`sindy_impulse.simulation`'s, scoring its error measures'.
"""

from __future__ import annotations

import copy
import warnings
from dataclasses import dataclass

import numpy as np
from sklearn.metrics import r2_score
from sklearn.utils.validation import check_is_fitted

from .._utils.trajectories import as_times, check_trajectories, restore
from .._utils.validation import check_signal, check_time
from ..differentiation import differentiate
from ..exceptions import DataWarning, DivergenceWarning
from ..simulation import ERROR_MEASURES, ErrorMeasure, get_error_measure
from ..simulation.integrators import solve_ivp_simulate

__all__ = ["FittedModelMixin", "SweepPath", "fresh_measure"]

_PYSINDY_INTEGRATOR_KWS = {"method": "LSODA", "rtol": 1e-12, "atol": 1e-12}


@dataclass
class SweepPath:
    """Every candidate of the threshold sweep (the data of the paper's Figure 6a).

    Attributes
    ----------
    threshold : ndarray (n_candidates,)
        Threshold at which each candidate appears (0: all terms; NaN for a single model).
    score : ndarray (n_candidates,)
        The error measure of each candidate's simulation (``inf`` if it diverged or was not simulated).
    n_terms : ndarray (n_candidates,)
        Number of non-zero coefficients.
    coefficients : ndarray (n_candidates, n_states, n_features)
    selected : int
        Index of the selected candidate.
    measure : str
        Name of the error measure (``"gamma"`` is the paper's Gamma).
    """

    threshold: np.ndarray
    score: np.ndarray
    n_terms: np.ndarray
    coefficients: np.ndarray
    selected: int
    measure: str = "gamma"

    @property
    def gamma(self) -> np.ndarray:
        """The candidates' scores (the paper's Gamma when ``measure == "gamma"``)."""
        return self.score

    def __len__(self) -> int:
        return len(self.score)


def fresh_measure(spec, references=None) -> ErrorMeasure:
    """An unbound error measure for the ``error_measure`` parameter ``spec`` (a given
    :class:`~sindy_impulse.simulation.ErrorMeasure` is copied: binding it must not change the parameter)."""
    return get_error_measure(copy.deepcopy(spec) if isinstance(spec, ErrorMeasure) else spec, references)


class FittedModelMixin:
    """PySINDy's methods of a fitted model, reading the fitted components."""

    @property
    def feature_names(self):
        """Names of the states and inputs (PySINDy's attribute)."""
        return getattr(self, "feature_names_", None)

    @feature_names.setter
    def feature_names(self, value):  # PySINDy's methods may assign it
        self.feature_names_ = value

    def _record_data(self, data, filtered, feature_names, n_features) -> None:
        """The fitted data and PySINDy's shape attributes and names (``x0, x1, ..., u0, ...``)."""
        n_states, n_inputs = data.n_states, data.n_inputs
        names = [f"x{i}" for i in range(n_states)] + [f"u{i}" for i in range(n_inputs)]
        if feature_names is not None:
            given = [str(f) for f in feature_names]
            if len(given) not in (n_states, n_states + n_inputs):
                raise ValueError(f"feature_names has {len(given)} names for {n_states} states")
            names = given + names[len(given) :]
        self.feature_names_ = names
        self.n_states_ = n_states
        self.n_control_features_ = n_inputs
        self.n_features_in_ = n_states + n_inputs
        self.n_output_features_ = n_features
        self.x_filtered_ = restore(filtered, data.multiple)
        self.t_ = restore(data.t, data.multiple)
        self.u_ = None if data.u is None else restore(data.u, data.multiple)

    def coefficients(self) -> np.ndarray:
        """Coefficient matrix (n_states, n_features): rows are equations, columns library terms."""
        check_is_fitted(self, "coef_")
        return self.coef_

    def get_feature_names(self) -> list[str]:
        """Names of the library terms."""
        check_is_fitted(self, "coef_")
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
        lhs = lhs or [f"({n})'" for n in self.feature_names_[: self.n_states_]]
        for name, eq in zip(lhs, self.equations(precision)):
            print(f"{name} = {eq}", **kwargs)

    @property
    def complexity(self) -> int:
        """Number of non-zero coefficients."""
        return int(np.count_nonzero(self.coefficients()))

    # -- inputs of a fitted model ------------------------------------------------------------------------
    def _check_states(self, x, min_samples: int = 1):
        """Validate states for a fitted model: one column per state."""
        items = x if isinstance(x, (list, tuple)) and all(hasattr(xi, "shape") for xi in x) else [x]
        if self.n_states_ > 1 and any(np.ndim(xi) == 1 for xi in items):
            raise ValueError(
                f"x is 1-D but the model has {self.n_states_} states: Reshape your data to "
                f"(n_samples, {self.n_states_})"
            )
        trajectories, multiple = check_trajectories(x, "x", min_samples=min_samples)
        for xi in trajectories:
            if xi.shape[1] != self.n_states_:
                raise ValueError(
                    f"X has {xi.shape[1]} features, but {type(self).__name__} is expecting "
                    f"{self.n_states_} features as input (x must have one column per state)"
                )
        return trajectories, multiple

    def _check_inputs(self, u, trajectories, multiple):
        """Control inputs per trajectory for a fitted model (PySINDy's errors and warning)."""
        if self.n_control_features_ and u is None:
            raise TypeError("Model was fit using control variables, so u is required")
        if not self.n_control_features_:
            if u is not None:
                warnings.warn(
                    "Control variables u were ignored because control variables were not used when the "
                    "model was fit",
                    DataWarning,
                    stacklevel=3,
                )
            return [None] * len(trajectories)
        us = list(u) if multiple else [u]
        if len(us) != len(trajectories):
            raise ValueError(f"u has {len(us)} trajectories but x has {len(trajectories)}")
        out = []
        for i, (ui, xi) in enumerate(zip(us, trajectories)):
            arr = check_signal(ui, f"u[{i}]" if multiple else "u")
            if arr.shape != (xi.shape[0], self.n_control_features_):
                raise ValueError(
                    f"u has shape {arr.shape}; expected ({xi.shape[0]}, {self.n_control_features_})"
                )
            out.append(arr)
        return out

    # -- PySINDy's methods ---------------------------------------------------------------------------------
    def predict(self, x, u=None):
        """The model's right-hand side at states ``x`` (and inputs ``u``), or a list for several."""
        check_is_fitted(self, "coef_")
        trajectories, multiple = self._check_states(x)
        inputs = self._check_inputs(u, trajectories, multiple)
        return restore([self.model_.rhs(xi, ui) for xi, ui in zip(trajectories, inputs)], multiple)

    def simulate(
        self, x0, t, u=None, integrator=None, interpolator=None, integrator_kws=None, interpolator_kws=None
    ) -> np.ndarray:
        """Integrate the model from ``x0`` over the time vector ``t``.

        Without integrator options the compiled simulator runs (RK4 with sub-steps from the model's time
        scale, an adaptive integrator for stiff models); ``u`` is then an array on ``t`` (interpolated
        linearly) or a function of time. With PySINDy's options (``integrator="solve_ivp" | "odeint"``,
        ``integrator_kws``, ``interpolator``), the call behaves as :meth:`pysindy.SINDy.simulate`: SciPy's
        integrator, an array ``u`` interpolated by ``interp1d(kind="cubic")`` and the last time point
        dropped. Rows after a divergence are NaN (with a
        :class:`~sindy_impulse.exceptions.DivergenceWarning`).

        Examples
        --------
        >>> import numpy as np
        >>> from sindy_impulse import ImpulseSINDy, damped_oscillator
        >>> t, x, x_dot = damped_oscillator()
        >>> model = ImpulseSINDy().fit(x, t=t, x_dot=x_dot)
        >>> bool(np.allclose(model.simulate(x[0], t), x, atol=1e-6))
        True
        """
        check_is_fitted(self, "coef_")
        x0 = check_signal(x0, "x0", ndim=(1, 2), as_2d=False).ravel()
        if x0.shape[0] != self.n_states_:
            raise ValueError(f"x0 has {x0.shape[0]} entries but the model has {self.n_states_} states")
        if np.ndim(t) == 0:
            raise ValueError("t must be an array of time points at which to simulate")
        tt = check_time(np.asarray(t, dtype=float), np.shape(t)[0], "t")
        if self.n_control_features_ and u is None:
            raise TypeError("Model was fit using control variables, so u is required")
        if u is not None and not self.n_control_features_:
            self._check_inputs(u, [x0[None]], False)  # warns that u is ignored
            u = None
        if integrator is not None or integrator_kws is not None or interpolator is not None:
            out = self._simulate_like_pysindy(
                x0, tt, u, integrator or "solve_ivp", interpolator, integrator_kws, interpolator_kws or {}
            )
        else:
            out = self.model_.simulate(x0, tt, u=u)
        if np.isnan(out).any():
            warnings.warn(
                "the simulation diverged (left 100x the fitted data's range or became non-finite); rows "
                "after the divergence are NaN: check x0 against the fitted amplitudes",
                DivergenceWarning,
                stacklevel=2,
            )
        return out

    def _simulate_like_pysindy(self, x0, t, u, integrator, interpolator, integrator_kws, interpolator_kws):
        if integrator not in ("solve_ivp", "odeint"):
            raise ValueError("Integrator not supported, exiting")
        u_fun = u
        if u is not None and not callable(u):
            from scipy.interpolate import interp1d

            make = interpolator or (
                lambda tt, uu, **kw: interp1d(tt, uu, axis=0, kind="cubic", fill_value="extrapolate", **kw)
            )
            u_fun = make(t, np.asarray(u, dtype=float), **interpolator_kws)
            t = t[:-1]
            warnings.warn(
                "Last time point dropped in simulation because interpolation of control input was used. To "
                "avoid this, pass in a callable for u.",
                DataWarning,
                stacklevel=3,
            )
        kws = dict(_PYSINDY_INTEGRATOR_KWS if integrator_kws is None else integrator_kws)
        if integrator == "odeint":
            from scipy.integrate import odeint

            kws.pop("method", None)

            def rhs(tt, x):
                return self._rhs_at(x, u_fun, tt)

            return odeint(rhs, x0, t, tfirst=True, **kws)
        n = self.n_states_
        out, _ = solve_ivp_simulate(
            lambda z: self.model_.rhs(z[None, :n], z[None, n:] if z.size > n else None)[0],
            x0,
            t,
            u_fun,
            None,
            **kws,
        )
        return out

    def _rhs_at(self, x, u_fun, tt):
        u = None if u_fun is None else np.atleast_2d(np.ravel(u_fun(tt)))
        return self.model_.rhs(np.atleast_2d(x), u)[0]

    def score(self, x, t=None, x_dot=None, u=None, metric=None, **metric_kws) -> float:
        """How well the model explains ``x`` (and ``u``): higher is better, as scikit-learn expects.

        Two scores, chosen by ``sweep`` (the parameter that decides how the model was selected):

        - ``sweep=False``: PySINDy's score, ``metric`` (default R^2) of the model's right-hand side against
          the derivatives of ``x`` (``x_dot``, or ``differentiation_method_`` applied to ``x``); 1 is
          perfect. ``metric`` and ``metric_kws`` are PySINDy's.
        - ``sweep=True``: minus the fit's error measure (``error_measure_``, the paper's Gamma by default)
          of the model simulated from the first sample of each trajectory of ``x``, driven by ``u``; 0 is
          perfect, ``-inf`` a simulation that diverged. R^2 on derivatives rewards dense models, whose
          spurious terms fit the noise of the derivatives and then make the simulation drift: the very
          problem the sweep on the simulation error solves (paper section 2.4). A ``GridSearchCV`` over an
          ImpulseSINDy therefore ranks candidates the way its fit does.

        Parameters
        ----------
        x : array-like (n_samples, n_states) or list of them
            States; a list is several (possibly ragged) trajectories.
        t : float, array or list of arrays, optional
            Time step or vector(s), as in :meth:`fit`; defaults to ``dt``.
        x_dot : array-like or list, optional
            Known derivatives (``sweep=False`` only).
        u : array-like or list, optional
            Inputs; required if the model was fitted with inputs.
        metric : callable, optional
            ``metric(x_dot, x_dot_predicted, **metric_kws)`` (``sweep=False`` only).

        Returns
        -------
        float

        Examples
        --------
        >>> from sindy_impulse import ImpulseSINDy, damped_oscillator
        >>> t, x, _ = damped_oscillator(snr_db=40, random_state=0)
        >>> bool(ImpulseSINDy(sweep=False, refine=False).fit(x, t=t).score(x, t=t) > 0.99)  # R^2
        True
        >>> bool(-3 < ImpulseSINDy().fit(x, t=t).score(x, t=t) < 0)  # minus Gamma
        True
        """
        check_is_fitted(self, "coef_")
        trajectories, multiple = self._check_states(x, min_samples=2)
        inputs = self._check_inputs(u, trajectories, multiple)
        listed = isinstance(x, (list, tuple)) and not multiple
        times = as_times(t, trajectories, 1.0 if self.dt is None else self.dt, listed=listed)
        if not self.sweep:
            return self._derivative_score(trajectories, times, x_dot, inputs, metric or r2_score, metric_kws)
        inputs = inputs if self.n_control_features_ else None
        measure = self._fitted_measure().bind(trajectories, times, inputs)
        return -float(measure(self.model_)[0])

    def _fitted_measure(self):
        """A fresh error measure of the kind the fit used (the parameter's, or what ``"auto"`` chose)."""
        spec = self.error_measure_ if isinstance(self.error_measure, str) else self.error_measure
        return fresh_measure(spec if not isinstance(spec, str) or spec in ERROR_MEASURES else "gamma")

    def _derivative_score(self, trajectories, times, x_dot, inputs, metric, metric_kws) -> float:
        predicted = np.vstack([self.model_.rhs(xi, ui) for xi, ui in zip(trajectories, inputs)])
        if x_dot is None:
            _, derivs = differentiate(self.differentiation_method_, trajectories, times)
        else:
            derivs, _ = check_trajectories(x_dot, "x_dot")
        target = np.vstack(derivs)
        keep = np.all(np.isfinite(target), axis=1) & np.all(np.isfinite(predicted), axis=1)
        return float(metric(target[keep], predicted[keep], **metric_kws))

"""The result of :func:`~sindy_impulse.analysis.complexity_error`: models on the complexity-error plane."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["ComplexityError"]


@dataclass
class ComplexityError:
    """Models on the complexity-error plane: one entry per (estimator, input) pair.

    Entries are ordered estimator-major: model ``k`` is estimator ``k // n_inputs`` fitted on input
    ``k % n_inputs``. Arrays have one value per model.

    Attributes
    ----------
    gamma : ndarray of float
        Gamma of the model simulated from the first input sample against the input states (the
        paper's definition: the embedded trajectories ``q(t)`` for single-signal input). ``inf`` if the
        simulation diverged or the fit failed.
    gamma_filtered : ndarray of float
        The estimator's own ``gamma_``: against the states filtered by its differentiation (NaN if the
        estimator has none or the fit failed).
    gamma_sindy : ndarray of float
        The estimator's ``gamma_sindy_``: the selected sweep candidate before refinement, against the
        filtered states (NaN if unavailable).
    n_terms : ndarray of int
        Number of non-zero coefficients (the complexity); -1 for a failed fit.
    estimator_index, input_index : ndarray of int
        Position of the model's estimator and input.
    estimator_label, input_label : ndarray
        Their labels (numbers stay numeric, e.g. degrees and mixing ratios).
    tau, dimension : ndarray of int
        Embedding delay and dimension used for the input (-1 without embedding or if it failed).
    fit_time : ndarray of float
        Wall time of each fit in seconds (embedding excluded).
    coefficients : list of ndarray or None
        Coefficient matrix (n_states, n_features) of each model; None for a failed fit.
    term_names : list of list of str or None
        Names of the library terms (the columns of ``coefficients``).
    equations : list of list of str or None
        Right-hand sides, one string per state.
    models : list of estimator or None
        The fitted estimators (None for failed fits, or all None with ``keep_models=False``).
    errors : list of str or None
        ``"ExceptionType: message"`` for each failed fit, None for the others.

    Examples
    --------
    >>> import numpy as np, pysindy as ps
    >>> from sindy_impulse import DelayEmbedding, ImpulseSINDy, damped_oscillator
    >>> from sindy_impulse.analysis import complexity_error
    >>> ring_down = damped_oscillator()
    >>> signals = {beta: beta * ring_down.x[:, 0] + (1 - beta) * ring_down.x[:, 1] for beta in (0.5, 1.0)}
    >>> estimators = {p: ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=p)) for p in (1, 2)}
    >>> result = complexity_error(estimators, signals, t=0.01, embedding=DelayEmbedding())
    >>> len(result), result.n_terms.tolist()
    (4, [4, 4, 4, 4])
    >>> bool(np.all(result.gamma < 0.01))
    True
    >>> rec = result.to_records()
    >>> rec.dtype.names[:4]
    ('estimator_label', 'input_label', 'n_terms', 'gamma')
    >>> result.grid("n_terms")
    array([[4, 4],
           [4, 4]])
    """

    gamma: np.ndarray
    gamma_filtered: np.ndarray
    gamma_sindy: np.ndarray
    n_terms: np.ndarray
    estimator_index: np.ndarray
    input_index: np.ndarray
    estimator_label: np.ndarray
    input_label: np.ndarray
    tau: np.ndarray
    dimension: np.ndarray
    fit_time: np.ndarray
    coefficients: list = field(repr=False)
    term_names: list = field(repr=False)
    equations: list = field(repr=False)
    models: list = field(repr=False)
    errors: list = field(repr=False)
    n_estimators: int = 1
    n_inputs: int = 1

    def __len__(self) -> int:
        return int(self.gamma.size)

    @property
    def succeeded(self) -> np.ndarray:
        """Boolean mask of the fits that did not raise."""
        return np.array([e is None for e in self.errors], dtype=bool)

    @property
    def stable(self) -> np.ndarray:
        """Boolean mask of the models whose simulation stayed finite (finite ``gamma``)."""
        return np.isfinite(self.gamma)

    def _metric(self, metric: str) -> np.ndarray:
        if metric not in ("gamma", "gamma_filtered", "gamma_sindy"):
            raise ValueError(f"metric must be 'gamma', 'gamma_filtered' or 'gamma_sindy', got {metric!r}")
        return getattr(self, metric)

    def pareto_front(self, metric: str = "gamma") -> np.ndarray:
        """Indices of the non-dominated models, sparsest first.

        A model is dominated if another has no more terms and no larger error, and is better in one
        of the two. Failed fits and models with non-finite error are never on the front; of exactly
        equal points the first is kept.

        Parameters
        ----------
        metric : {"gamma", "gamma_filtered", "gamma_sindy"}, default="gamma"
            The error axis.

        Returns
        -------
        ndarray of int
            Model indices ordered by increasing number of terms (and decreasing error).
        """
        err = self._metric(metric)
        ok = np.flatnonzero(self.succeeded & np.isfinite(err) & (self.n_terms >= 0))
        order = ok[np.lexsort((ok, err[ok], self.n_terms[ok]))]
        front, best = [], np.inf
        for i in order:
            if err[i] < best:
                front.append(int(i))
                best = err[i]
        return np.asarray(front, dtype=int)

    def best(self, metric: str = "gamma", max_terms: int | None = None) -> int:
        """Index of the model of least error (fewest terms on ties), optionally at most ``max_terms``.

        Raises
        ------
        ValueError
            If no successful model with finite error (and few enough terms) exists.
        """
        err = self._metric(metric)
        ok = self.succeeded & np.isfinite(err) & (self.n_terms >= 0)
        if max_terms is not None:
            ok &= self.n_terms <= max_terms
        idx = np.flatnonzero(ok)
        if idx.size == 0:
            raise ValueError("no successful model with a finite error" + ("" if max_terms is None else
                             f" and at most {max_terms} terms"))
        return int(idx[np.lexsort((idx, self.n_terms[idx], err[idx]))[0]])

    def grid(self, name: str) -> np.ndarray:
        """A per-model array reshaped to (n_estimators, n_inputs), e.g. for a heat map.

        Parameters
        ----------
        name : str
            One of ``gamma``, ``gamma_filtered``, ``gamma_sindy``, ``n_terms``, ``tau``, ``dimension``,
            ``fit_time``.
        """
        allowed = ("gamma", "gamma_filtered", "gamma_sindy", "n_terms", "tau", "dimension", "fit_time")
        if name not in allowed:
            raise ValueError(f"name must be one of {allowed}, got {name!r}")
        return getattr(self, name).reshape(self.n_estimators, self.n_inputs)

    def to_records(self) -> np.recarray:
        """All scalar columns as a NumPy record array (one record per model).

        Fields: ``estimator_label, input_label, n_terms, gamma, gamma_filtered, gamma_sindy,
        estimator_index, input_index, tau, dimension, fit_time, succeeded, stable, pareto``. Pass it to
        ``pandas.DataFrame`` or ``numpy.savetxt``-like writers as is.
        """
        pareto = np.zeros(len(self), dtype=bool)
        pareto[self.pareto_front()] = True
        columns = {
            "estimator_label": self.estimator_label,
            "input_label": self.input_label,
            "n_terms": self.n_terms,
            "gamma": self.gamma,
            "gamma_filtered": self.gamma_filtered,
            "gamma_sindy": self.gamma_sindy,
            "estimator_index": self.estimator_index,
            "input_index": self.input_index,
            "tau": self.tau,
            "dimension": self.dimension,
            "fit_time": self.fit_time,
            "succeeded": self.succeeded,
            "stable": self.stable,
            "pareto": pareto,
        }
        return np.rec.fromarrays(list(columns.values()), names=list(columns))

    def summary(self, metric: str = "gamma") -> str:
        """A text table per estimator: terms (min/median/max), error (min/median/max), failures.

        Examples
        --------
        The first line is the header: ``estimator  n  failed  unstable  terms min/med/max ...``.
        """
        err = self._metric(metric)
        lines = [
            f"{'estimator':>12} {'n':>4} {'failed':>6} {'unstable':>8} {'terms min/med/max':>18} "
            f"{metric + ' min/median/max':>34}"
        ]
        for e in range(self.n_estimators):
            sel = self.estimator_index == e
            ok = sel & self.succeeded
            fin = ok & np.isfinite(err)
            if fin.any():
                k = self.n_terms[fin]
                g = err[fin]
                terms = f"{k.min()}/{np.median(k):g}/{k.max()}"
                gam = f"{g.min():.4g}/{np.median(g):.4g}/{g.max():.4g}"
            else:
                terms, gam = "-", "-"
            label = self.estimator_label[np.flatnonzero(sel)[0]]
            lines.append(
                f"{label!s:>12} {int(sel.sum()):>4} {int((sel & ~self.succeeded).sum()):>6} "
                f"{int((ok & ~np.isfinite(err)).sum()):>8} {terms:>18} {gam:>34}"
            )
        return "\n".join(lines)

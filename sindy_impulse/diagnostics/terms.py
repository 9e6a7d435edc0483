"""Which terms the data support: the model's neighbourhood, tested by linearised simulation.

Around the fitted coefficients the simulation is linearised: ``r(b + d) ~ r0 + J d``, where ``r0`` is the
model's simulation minus the measured states (each state in units of its noise level) and ``J`` the
sensitivity of the simulation to each coefficient of the model and to each library term it lacks (finite
differences: one simulation per coefficient; for a linear model, the terms it lacks all at once by the
linearised recursion of :mod:`.linear_sensitivity`). Every neighbouring support is then refitted by linear
least squares on ``J`` (Gauss-Newton from the fitted model), and its least squared error compared with the
model's own support refitted the same way:

- **drop** a term (its coefficient forced to 0, the others refitted): a rise below :data:`SUPPORT_CHI2`
  (the 0.1 % point of a chi-square with one degree of freedom) means the data do not need the term;
- **add** a term: a fall beyond the 0.1 % point corrected for the number of terms tried (Bonferroni),
  judged against the residual's own spectrum (:class:`_Colour`), means the data ask for a term the model
  lacks;
- **swap** a term for another of the same equation: a rise below :data:`SUPPORT_CHI2` (or a fall) means
  another term explains the data as well, so the data cannot tell which is right (e.g. ``v|v|``, ``v^3``
  and ``sgn(v)`` damping on a short or noisy ring-down).

The add test's statistic is divided by how much the residual's colour inflates it in the new term's
direction (``c' Sigma c / c' c``, read from the residual's smoothed cross-periodogram): a band-passed or
differentiated signal leaves a residual whose power sits around the mode's own frequency, where the cubic
terms act too, and judged as white it made the test ask for cubic terms in a fifth of the modes of linear
hammer tests (nominal level :data:`FALSE_ALARM`; ``python -m benchmarks.robustness.term_false_alarm``
measures both the false alarms and the power).

These are the likelihood-ratio tests of nonlinear least squares under white Gaussian measurement noise: the
comparison is with the measured states, whose noise is white, not with the filtered ones, whose smoothing
leaves systematic differences a flexible model could follow. The noise level is the model's own RMS error
(floored by what the filter removed and by ``NOISE_FLOOR``). The initial state of every simulated segment is
refitted with the coefficients (a filtered first sample is off by about the noise, and a term that makes up
for it would look needed). The relative standard error of each coefficient, ``sqrt((J'J)^-1)`` over its
value times the correlation inflation of the model's residual (:func:`correlation_inflation`: white noise
gives 1, a systematic misfit more), comes with them. The simulations are counted against a work budget
(:data:`WORK_FRACTION` of a fit's).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg
from scipy.ndimage import uniform_filter1d
from scipy.stats import chi2

from ..exceptions import DataWarning
from ..feature_library.terms import library_terms
from ..simulation import WORK_BUDGET, Reference, WorkBudget, at_rest_level, compile_model
from ..simulation.scoring import compare_stride
from .linear_sensitivity import linear_sensitivities
from .model import Fitted, regression, segments, simulate_residuals

__all__ = ["TermTests", "term_tests", "SUPPORT_CHI2", "FALSE_ALARM", "WORK_FRACTION", "MAX_TEST_SAMPLES"]

#: 0.1 % point of a chi-square with one degree of freedom: a change smaller than this is within the noise.
SUPPORT_CHI2 = float(chi2.isf(1e-3, 1))
#: False-alarm probability of the add test over all the terms tried.
FALSE_ALARM = 1e-3
#: Floor of the noise level relative to each state's RMS (clean data: the filter's accuracy).
NOISE_FLOOR = 1e-4
#: Relative size of the finite-difference steps (of a term's typical share of its equation).
STEP = 1e-4
#: Simulation work of the tests, as a fraction of a fit's work budget (2.5e7 term evaluations).
WORK_FRACTION = 0.125
#: Frequency bins either side over which the residual's cross-periodogram is averaged (:class:`_Colour`).
SMOOTHING = 2
#: Library terms tried per equation by the add and swap tests (the most promising ones).
MAX_CANDIDATES = 12
#: Most samples per state the tests compare (every k-th beyond): each sensitivity is a column of that
#: length, so memory grows with samples times terms. A 1 s record at 25.6 kHz with a few-kHz mode
#: (4,000 periods at 200 compared samples a period, eight states) otherwise needs gigabytes per column set;
#: a band of ``max_periods`` = 200 (at most 40,000 compared samples) stays below.
MAX_TEST_SAMPLES = 50_000


@dataclass(frozen=True)
class TermTests:
    """Outcome of :func:`term_tests`.

    Attributes
    ----------
    statistics : dict
        ``{"x1' : x0": statistic}``: drop statistic of each term of the model.
    unsupported : list of str
        Terms whose drop statistic is below :data:`SUPPORT_CHI2`.
    missing : list of str
        Terms the data ask for (add statistic beyond the corrected threshold).
    alternatives : list of (str, str)
        ``(term, replacement)`` pairs that explain the data as well.
    uncertainty : dict
        ``{term: relative standard error}`` of each coefficient.
    complete : bool
        False when the work budget stopped the tests (the lists cover the terms tested).
    """

    statistics: dict = field(default_factory=dict)
    unsupported: list = field(default_factory=list)
    missing: list = field(default_factory=list)
    alternatives: list = field(default_factory=list)
    uncertainty: dict = field(default_factory=dict)
    complete: bool = True


def correlation_inflation(residual: np.ndarray, max_lag: int = 200) -> np.ndarray:
    """Per column, ``1 + 2 sum(rho_k)``: how much correlation between neighbouring samples inflates the
    variance of a least-squares statistic (the sum stops at the first lag whose correlation is below 0.05).

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> white = rng.standard_normal((4000, 1))
    >>> smooth = np.convolve(white[:, 0], np.ones(10) / 10, "same")[:, None]
    >>> bool(correlation_inflation(white)[0] < 1.2), bool(correlation_inflation(smooth)[0] > 5)
    (True, True)
    """
    r = residual - residual.mean(axis=0)
    n = r.shape[0]
    spectrum = np.fft.rfft(r, 2 * n, axis=0)
    acf = np.fft.irfft(np.abs(spectrum) ** 2, axis=0)[: min(max_lag, n // 4) + 1]
    acf = acf / np.where(acf[0] > 0, acf[0], 1.0)
    out = np.ones(r.shape[1])
    for j in range(r.shape[1]):
        low = np.flatnonzero(acf[1:, j] < 0.05)
        stop = low[0] if low.size else acf.shape[0] - 1
        out[j] = 1.0 + 2.0 * float(np.sum(acf[1 : stop + 1, j]))
    return out


class _Sensitivity:
    """Residual of the model (noise units) and its sensitivity to coefficients of the library."""

    def __init__(self, fitted: Fitted, shift: np.ndarray, noise_ratio: np.ndarray, raw: list):
        est = fitted.estimator
        self.fitted, self.coef, self.shift = fitted, fitted.coef, shift
        # residuals compared at <= 200 samples per period, as the error measures do: long records stay cheap
        self.stride = _test_stride(fitted.filtered[0])
        noise = [(r - f)[:: self.stride] for r, f in zip(raw, fitted.filtered)] if raw else None
        self.noise = noise or [0.0] * len(fitted.filtered)
        self.n_inputs = 0 if fitted.inputs[0] is None else fitted.inputs[0].shape[1]
        self.terms = library_terms(est.feature_library_, self.coef.shape[0] + self.n_inputs)
        self.reference_u = None if self.n_inputs == 0 else np.vstack(fitted.inputs)
        # what every tested model takes from the data (its time scale's probes, its bounds), computed once
        self.reference = Reference(np.vstack(fitted.filtered) - shift, self.reference_u, self.n_inputs)
        self.divergence = float(getattr(est, "divergence_factor", 100.0))
        self.budget = WorkBudget(WORK_FRACTION * WORK_BUDGET)
        self.theta, self.y = regression(fitted, shift, stride=self.stride)
        rows = np.all(np.isfinite(self.theta), axis=1) & np.all(np.isfinite(self.y), axis=1)
        self.theta, self.y = self.theta[rows], self.y[rows]
        typical_y = np.sqrt(np.mean(self.y**2, axis=0))
        typical_theta = np.sqrt(np.mean(self.theta**2, axis=0))
        ratio = typical_y[:, None] / np.where(typical_theta > 0, typical_theta, np.inf)[None, :]
        self.steps = STEP * np.where(ratio > 0, ratio, STEP)
        self.base_model = self.model(np.flatnonzero(np.any(self.coef != 0, axis=0)))
        self._with_term = {}  # term -> the base model with that term added (:meth:`column`)
        self._linearised = {}  # (i, j) -> its column from the linearised recursion (:meth:`prepare`)
        centred = np.vstack(fitted.filtered) - np.median(np.vstack(fitted.filtered), axis=0)
        scale = np.sqrt(np.mean(centred**2, axis=0))
        floor = np.maximum(np.asarray(noise_ratio, float), NOISE_FLOOR) * np.where(scale > 0, scale, 1.0)
        self.sigma, self.inflation = np.ones_like(floor), 1.0
        self.floor = floor
        own = self.residual(self.base_model, self.coef)
        self.r0 = None
        if own is not None:
            own = own.reshape(-1, scale.size)
            self.sigma = np.maximum(floor, np.sqrt(np.mean(own**2, axis=0)))
            inflation = correlation_inflation(own)
            if not raw:  # compared with filtered states: correlated errors count fewer independent samples
                self.sigma = self.sigma * np.sqrt(inflation)
            else:  # white noise plus what the model misses: the standard errors count the latter's samples
                self.inflation = float(np.max(inflation))
            self.r0 = (own / self.sigma).ravel()

    def model(self, columns):
        """A compiled model whose active terms are ``columns`` of the library (measured coordinates)."""
        placeholder = np.zeros_like(self.coef)  # the model's coefficients, a tiny one where a term is new
        placeholder[:, columns] = np.where(self.coef[:, columns] != 0, self.coef[:, columns], 1e-300)
        inner = compile_model(
            placeholder, self.terms, self.reference, self.divergence, self.reference_u, self.n_inputs
        )
        if hasattr(self, "base_model"):  # a new term at 1e-300 leaves the model's time scale as it is
            inner.spectral_radius = self.base_model.spectral_radius
        return at_rest_level(inner, self.shift)

    @staticmethod
    def _at(model, coef: np.ndarray) -> np.ndarray:
        return np.ascontiguousarray(coef[:, model.active])

    def residual(self, model, coef: np.ndarray, start_offset=None):
        """Simulation minus measured states in noise units, flattened (None if it diverged)."""
        res = simulate_residuals(model, self.fitted, self._at(model, coef), start_offset, self.stride)
        self.budget.charge_model(model)
        r = np.vstack([ri - ni for ri, ni in zip(res, self.noise)])
        return (r / self.sigma).ravel() if np.all(np.isfinite(r)) else None

    def start_columns(self):
        """Sensitivities to the initial state of every simulated segment (one simulation per state), as
        :class:`_Segments`, the blocks of the nuisance columns (None if a simulation diverged)."""
        n_states = self.sigma.size
        owner, offset = [], 0
        for ref, starts in zip(self.fitted.filtered, segments(self.fitted)):
            rows = np.searchsorted(starts, np.arange(ref.shape[0])[:: self.stride], side="right") - 1
            owner.append(offset + rows)
            offset += len(starts)
        owner = np.repeat(np.concatenate(owner), n_states)  # flattened (sample, state) order
        out = []
        for j in range(n_states):
            delta = np.zeros(n_states)
            delta[j] = 1e-2 * self.sigma[j]  # well inside the linear range
            r = self.residual(self.base_model, self.coef, delta)
            if r is None:
                return None
            out.append(r - self.r0)
        return _Segments(owner, np.column_stack(out))

    def prepare(self, pairs: list) -> None:
        """The columns of the coefficients ``pairs`` from the linearised recursion of a linear model
        (:func:`.linear_sensitivity.linear_sensitivities`: one pass for all, where each column otherwise
        takes a simulation), kept for :meth:`column`; nothing where the recursion does not apply."""
        if self.budget.exhausted or not pairs:
            return
        found = linear_sensitivities(self.base_model, self.fitted, self.terms, self.shift, pairs, self.stride)
        self.budget.charge_model(self.base_model)
        if found is None or not np.all(np.isfinite(found[0])):
            return
        S, done = found
        for c, (i, j) in enumerate(done):
            self._linearised[(i, j)] = (self.steps[i, j] * S[:, :, c] / self.sigma).ravel()

    def column(self, i: int, j: int):
        """Sensitivity of the residual to coefficient (i, j), per step (None if diverged or over budget):
        the difference of two simulations, or the linearised one :meth:`prepare` computed."""
        if (i, j) in self._linearised:
            return self._linearised[(i, j)]
        if self.budget.exhausted:
            return None
        used = np.any(self.coef != 0, axis=0)
        if used[j]:
            model = self.base_model
        else:  # the term in every equation (at 1e-300 where not tested): one model per term, shared
            if j not in self._with_term:
                self._with_term[j] = self.model(np.flatnonzero(used | (np.arange(used.size) == j)))
            model = self._with_term[j]
        trial = self.coef.copy()
        trial[i, j] += self.steps[i, j]
        r = self.residual(model, trial)
        return None if r is None else r - self.r0

    def candidates(self, support: np.ndarray) -> list:
        """The library terms missing from each equation, the most promising first: at most
        :data:`MAX_CANDIDATES` per equation, ranked by how much each would reduce the equation's
        least-squares residual on the derivatives."""
        out = []
        for i in range(support.shape[0]):
            cols, others = np.flatnonzero(support[i]), np.flatnonzero(~support[i])
            resid, block = self.y[:, i], self.theta[:, others]
            if cols.size:  # both made orthogonal to the equation's terms (as least squares would)
                u, sv, _ = np.linalg.svd(self.theta[:, cols], full_matrices=False)
                u = u[:, sv > sv[0] * np.finfo(float).eps * max(u.shape)] if sv[0] > 0 else u[:, :0]
                resid = resid - u @ (u.T @ resid)
                block = block - u @ (u.T @ block)
            norms = np.sqrt(np.einsum("ij,ij->j", block, block))
            unit = np.divide(block, norms, out=np.zeros_like(block), where=norms > 0)
            gains = (resid @ unit) ** 2  # (unit columns: no product of the library's powers squared again)
            ranked = sorted(zip(gains.tolist(), others.tolist()), reverse=True)
            out += [(i, k) for _, k in ranked[:MAX_CANDIDATES]]
        return out


class _Segments:
    """The nuisance columns (each segment's initial state): column ``(j, k)`` is ``sensitivity[:, j]`` on
    segment ``k``'s rows and zero elsewhere. Never built densely (segments times rows grows with the square
    of the record's length); every least-squares problem keeps all of them, so they are profiled out: each
    column is replaced by its residual after projection on the segment blocks (:meth:`project`)."""

    def __init__(self, owner: np.ndarray, sensitivity: np.ndarray):
        order = np.argsort(owner, kind="stable")
        bounds = np.flatnonzero(np.diff(owner[order])) + 1
        self.blocks = []  # (rows, orthonormal basis of the block's columns)
        for rows in np.split(order, bounds):
            block = sensitivity[rows]
            u, sv, _ = np.linalg.svd(block, full_matrices=False)
            keep = sv > (sv[0] if sv.size else 0.0) * max(block.shape) * np.finfo(float).eps
            self.blocks.append((rows, u[:, keep]))

    def project(self, x: np.ndarray) -> np.ndarray:
        """``x`` minus its least-squares fit by the nuisance columns."""
        out = np.array(x, dtype=float, copy=True)
        for rows, basis in self.blocks:
            if basis.shape[1]:
                out[rows] -= basis @ (basis.T @ out[rows])
        return out


class _Gram:
    """Least squares of ``r0 + J d`` on subsets of the columns of ``J``, from its Gram matrix: each test
    is then algebra on a matrix of the model's size, not on the samples. The nuisance columns
    (:class:`_Segments`) are in every subset, so they are profiled out of ``r0`` and of every column."""

    def __init__(self, r0: np.ndarray, columns: list, nuisance: _Segments | None = None):
        self.nuisance = nuisance
        self.J = np.column_stack([self._projected(c) for c in columns])
        self.r0 = self._projected(r0)
        self.G = self.J.T @ self.J
        self.b = self.J.T @ self.r0
        self.rr = float(self.r0 @ self.r0)
        # the model's own fit for :meth:`candidate` (None when G fails :func:`_solve_gram`'s Cholesky test)
        self._factor = _cholesky(self.G)
        if self._factor is not None:
            self._beta = scipy.linalg.cho_solve(self._factor, self.b, check_finite=False)
            eye = np.eye(self.G.shape[0])
            self._inverse_diagonal = np.diag(scipy.linalg.cho_solve(self._factor, eye, check_finite=False))

    def _projected(self, x: np.ndarray) -> np.ndarray:
        return x if self.nuisance is None else self.nuisance.project(x)

    def orthogonal(self, column: np.ndarray) -> np.ndarray:
        """``column`` without its least-squares fit by the nuisance columns and by every column of ``J``:
        the direction a term adds to the model."""
        column = self._projected(column)
        return column - self.J @ _solve_gram(self.G, self.J.T @ column)

    def residual(self) -> np.ndarray:
        """The residual of the least-squares fit by every column (the model's own support refitted)."""
        return self.r0 - self.J @ _solve_gram(self.G, self.b)

    def extended(self, column: np.ndarray):
        """Gram matrix and right-hand side with one more column (it is the last)."""
        column = self._projected(column)
        cross = self.J.T @ column
        G = np.block([[self.G, cross[:, None]], [cross[None, :], np.array([[column @ column]])]])
        return G, np.append(self.b, column @ self.r0)

    def candidate(self, column: np.ndarray, fixes: list):
        """The add and swap statistics of one more column, in closed form from the model's own fit.

        With ``o`` the column's part orthogonal to the nuisance columns and to ``J`` (:meth:`orthogonal`),
        adding it lowers the least squared residual by ``(o . r0)^2 / (o . o)``; holding column ``j``'s
        coefficient at ``v`` (``fixes``: ``(j, v)`` as :meth:`ssr`'s ``fix``) in the extended fit raises it
        from the extended least by ``(beta_j + v)^2 / (G_ext^-1)_jj``, where the extended fit's ``beta``
        and inverse follow from the model's own by the column's coefficient ``(o . r0) / (o . o)`` and its
        regression on ``J`` (a rank-one update: the same numbers as refitting on the extended Gram matrix,
        without a factorisation per test). Returns ``(gain, o, [rise over the model's least per fix])``,
        or None where the extended Gram matrix is singular to within :func:`_solve_gram`'s test (the
        caller refits).
        """
        if self._factor is None:
            return None
        column = self._projected(column)
        q = scipy.linalg.cho_solve(self._factor, self.J.T @ column, check_finite=False)
        o = column - self.J @ q
        d = float(o @ o)
        if not d > 1e-12 * max(float(column @ column), float(np.max(np.diag(self.G)))):
            return None
        gamma = float(o @ self.r0) / d
        gain = gamma * gamma * d
        rises = []
        for j, v in fixes:
            beta = self._beta[j] - q[j] * gamma
            rises.append((beta + v) ** 2 / (self._inverse_diagonal[j] + q[j] * q[j] / d) - gain)
        return gain, o, rises

    def ssr(self, keep, fix=None, G=None, b=None) -> float:
        """Least squared residual over the columns ``keep``; ``fix=(j, v)`` holds column ``j``'s
        coefficient at ``v`` (it then is not in ``keep``)."""
        G = self.G if G is None else G
        b = self.b if b is None else b
        rr = self.rr
        if fix is not None:
            j, v = fix
            rr = rr + 2 * v * b[j] + v * v * G[j, j]
            b = b + v * G[:, j]
        keep = np.asarray(keep, dtype=int)
        if keep.size == 0:
            return float(rr)
        return float(rr - b[keep] @ _solve_gram(G[np.ix_(keep, keep)], b[keep]))


def _test_stride(reference: np.ndarray) -> int:
    """Every how many samples the tests compare: the error measures' stride (:func:`compare_stride`),
    coarser when more than :data:`MAX_TEST_SAMPLES` would remain (with a :class:`DataWarning`)."""
    stride = compare_stride(reference)
    cap = -(-len(reference) // MAX_TEST_SAMPLES)
    if cap > stride:
        warnings.warn(
            f"the term tests compare every {cap}th sample of the {len(reference)} (more than "
            f"{MAX_TEST_SAMPLES} would hold a dense sensitivity matrix of that length per term): their "
            "statistics use fewer samples than the record has; fit a shorter excerpt for the full test",
            DataWarning,
            stacklevel=2,
        )
    return max(stride, cap)


class _Colour:
    """The spectrum of the model's residual, to judge a statistic against coloured errors.

    A band-passed or differentiated signal leaves a residual whose power sits in a narrow band, often
    around the mode's own frequency, where the terms tested also act: the least-squares statistics, which
    assume white errors, then overstate how much a term explains. With ``Sigma`` the covariance of the
    residual, the score of a direction ``c`` (orthogonal to the model) has variance ``c' Sigma c``, which
    is read here in the frequency domain from the smoothed (Daniell, :data:`SMOOTHING` bins either side)
    cross-periodogram of the residual's states: ``c' Sigma c ~ sum_f C(f)^H S(f) C(f) / n``. A floor
    (the noise level's floor, in the residual's units) keeps clean data from judging by rounding errors.
    """

    def __init__(self, residual: np.ndarray, n_states: int, floor: np.ndarray):
        r = residual.reshape(-1, n_states)
        self.n = r.shape[0]
        spectrum = np.fft.rfft(r, axis=0)
        cross = spectrum[:, :, None] * spectrum.conj()[:, None, :] / self.n
        width = 2 * SMOOTHING + 1
        smooth = uniform_filter1d(cross.real, width, axis=0)
        smooth = smooth + 1j * uniform_filter1d(cross.imag, width, axis=0)
        self.S = smooth + np.diag(np.asarray(floor, float) ** 2)[None]
        self.weights = np.full(spectrum.shape[0], 2.0)
        self.weights[0] = 1.0
        if self.n % 2 == 0:
            self.weights[-1] = 1.0

    def ratio(self, column: np.ndarray) -> float:
        """``c' Sigma c / c' c``: how much the residual's colour inflates the statistic of ``c``."""
        c = np.fft.rfft(column.reshape(self.n, -1), axis=0)
        quad = np.einsum("fi,fij,fj->f", c.conj(), self.S, c).real
        power = np.einsum("fi,fi->f", c.conj(), c).real
        total = float(self.weights @ power)
        return float(self.weights @ quad) / total if total > 0 else 1.0


def _cholesky(G: np.ndarray):
    """The Cholesky factor of a Gram matrix (``cho_factor``), None when ``G`` is singular or nearly so."""
    try:
        factor = scipy.linalg.cho_factor(G, check_finite=False)
    except np.linalg.LinAlgError:
        return None
    return factor if np.min(np.abs(np.diag(factor[0]))) ** 2 > 1e-12 * np.max(np.diag(G)) else None


def _solve_gram(G: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``G x = b`` for a Gram matrix: Cholesky (a few hundred columns when every segment's start is a
    column: 20x faster than an SVD), least squares when ``G`` is singular or nearly so."""
    factor = _cholesky(G)
    if factor is not None:
        return scipy.linalg.cho_solve(factor, b, check_finite=False)
    return np.linalg.lstsq(G, b, rcond=None)[0]


def _name(fitted: Fitted, i: int, j: int) -> str:
    if getattr(fitted, "_term_names", None) is None:  # PySINDy builds the names anew at every call
        fitted._term_names = fitted.estimator.get_feature_names()
    return f"{fitted.estimator.feature_names_[i]}' : {fitted._term_names[j]}"


def _drops(fitted, s, active, gram, base):
    """Drop statistics and relative standard errors of the active coefficients (columns 0..n-1)."""
    stats, uncertainty = {}, {}
    cov = np.diag(np.linalg.pinv(gram.G))
    everything = np.arange(gram.G.shape[0])
    for n, (i, j) in enumerate(active):
        value = -s.coef[i, j] / s.steps[i, j]  # the coefficient in units of its step, removed
        stats[_name(fitted, i, j)] = gram.ssr(everything[everything != n], (n, value)) - base
        uncertainty[_name(fitted, i, j)] = float(np.sqrt(max(cov[n], 0.0) * s.inflation) / abs(value))
    return stats, uncertainty


def _candidate_tests(fitted, s, support, active, gram, base):
    """Add and swap tests of the promising library terms; ``(missing, alternatives, complete)``."""
    candidates = s.candidates(support)
    s.prepare(candidates)
    colour = _Colour(gram.residual(), s.sigma.size, s.floor / s.sigma)
    threshold = float(chi2.isf(FALSE_ALARM / max(len(candidates), 1), 1))
    everything = np.arange(gram.G.shape[0] + 1)
    missing, alternatives, complete = [], [], True
    for i, k in candidates:
        col = s.column(i, k)
        if col is None:
            complete = complete and not s.budget.exhausted
            continue
        fixes = [(active.index((i, j)), -s.coef[i, j] / s.steps[i, j]) for j in np.flatnonzero(support[i])]
        found = gram.candidate(col, fixes)
        if found is None:  # a singular extended Gram matrix: refitted by least squares
            G, b = gram.extended(col)
            gain, o = base - gram.ssr(everything, G=G, b=b), gram.orthogonal(col)
            rises = [gram.ssr(everything[everything != n], (n, v), G, b) - base for n, v in fixes]
        else:
            gain, o, rises = found
        if gain / colour.ratio(o) > threshold:
            missing.append(_name(fitted, i, k))
        for j, rise in zip(np.flatnonzero(support[i]), rises):
            if rise < SUPPORT_CHI2:
                alternatives.append((_name(fitted, i, j), _name(fitted, i, k)))
    return missing, alternatives, complete


def term_tests(fitted: Fitted, shift: np.ndarray, noise_ratio: np.ndarray, raw=None) -> TermTests | None:
    """Drop, add and swap tests around the fitted model (None when its simulation diverges).

    Parameters
    ----------
    fitted : Fitted
    shift : ndarray (n_states,)
        The rest level removed before the regression.
    noise_ratio : ndarray (n_states,)
        RMS of (measured - filtered) over each state's RMS.
    raw : list of ndarray, optional
        The measured states, per trajectory (the simulations are compared with them; without them, with
        the filtered states).
    """
    support = fitted.coef != 0
    if not support.any():
        return TermTests()
    s = _Sensitivity(fitted, shift, noise_ratio, raw)
    if s.r0 is None:
        return None
    active = list(zip(*np.nonzero(support)))
    cols = [s.column(*a) for a in active]
    nuisance = s.start_columns()
    if nuisance is None or any(c is None for c in cols):
        return TermTests(complete=False)
    gram = _Gram(s.r0, cols, nuisance)
    base = gram.ssr(np.arange(gram.G.shape[0]))
    stats, uncertainty = _drops(fitted, s, active, gram, base)
    unsupported = [t for t, v in stats.items() if v < SUPPORT_CHI2]
    missing, alternatives, complete = _candidate_tests(fitted, s, support, active, gram, base)
    return TermTests(stats, unsupported, missing, alternatives, uncertainty, complete)

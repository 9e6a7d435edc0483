"""diagnose_fit: every check of a fitted estimator, the verdict, and the one warning."""

from __future__ import annotations

import numpy as np

from ..simulation.scoring import AUTO_PERIODS
from .data import DataChecks
from .model import Fitted, fit_error, frequency_agreement, simulation_residuals, support_condition
from .report import FitDiagnostics
from .terms import TermTests, term_tests
from .verdict import NO_DYNAMICS_ERROR, judge

__all__ = ["diagnose_fit"]

#: Exceptions a check may raise on odd data; the check is then skipped with a note, the fit stands.
_CHECK_ERRORS = (ValueError, ArithmeticError, np.linalg.LinAlgError)


def _estimator_warned(estimator) -> frozenset:
    """Reasons the estimator itself has already warned about during this fit."""
    # the sweep's scores as the fit left them, without finishing the simulations it stopped early (as
    # reading ``path_`` would): a stopped candidate's finite lower bound gives the same answer, since a
    # simulation stops only below the finished score of a candidate with terms
    path = vars(estimator)["_path"] if "_path" in vars(estimator) else getattr(estimator, "path_", None)
    out = set()
    if path is not None:
        live = np.isfinite(path.score) & (path.n_terms > 0)
        if not live.any() and np.isfinite(path.score).any():
            out.add("no_dynamics")
    return frozenset(out)


def _guarded(check, notes: dict, key: str, what: str, default):
    """``check()``, or ``default`` with a note when it fails on odd data."""
    try:
        return check()
    except _CHECK_ERRORS as err:
        notes[key] = f"the {what} could not run ({err})"
        return default


def _terms(fitted: Fitted, checks: DataChecks, notes: dict) -> TermTests:
    raw = checks.raw if checks.noise_known else None  # None: errors coloured like the data
    tests = term_tests(fitted, checks.rest.shift, checks.noise_ratio, raw)
    if tests is None:
        notes["terms"] = "the term tests were skipped: the model's simulation diverges when perturbed"
        return TermTests(complete=False)
    if not tests.complete:
        notes["terms"] = "the term tests stopped at their work budget: some terms were not tested"
    return tests


def _model_checks(fitted: Fitted, checks: DataChecks, notes: dict) -> dict:
    """The numbers of the model checks (each guarded: a failing check is noted and skipped)."""
    m = {"zero_model": not np.any(fitted.coef), "terms": TermTests(), "model_hz": np.empty(0)}
    m.update(mismatch=float("nan"), disagree=False, share=float("nan"), condition=1.0)
    residuals = simulation_residuals(fitted)
    m["fit_error"] = fit_error(residuals, fitted, checks.rest.level)
    if m["zero_model"] or not np.all(np.isfinite(m["fit_error"])):
        return m
    if np.max(m["fit_error"]) < NO_DYNAMICS_ERROR:  # beyond, the model misses the data: nothing to test
        m["terms"] = _guarded(
            lambda: _terms(fitted, checks, notes), notes, "terms", "term tests", TermTests()
        )
        if "terms" in notes:  # stopped or skipped: the model's own terms without a drop test
            m["untested"] = int(np.count_nonzero(fitted.coef)) - len(m["terms"].statistics)
    frequency = _guarded(
        lambda: frequency_agreement(fitted, checks, residuals), notes, "frequency", "frequency check", None
    )
    if frequency is not None:
        m["model_hz"], m["mismatch"], m["disagree"], m["share"] = frequency
    m["condition"] = _guarded(
        lambda: support_condition(fitted, checks.rest.shift), notes, "conditioning", "conditioning check", 1.0
    )
    return m


def _notes(estimator, checks: DataChecks, fitted: Fitted) -> dict:
    notes = {}
    if checks.rest.removed.any():
        states = ", ".join(
            f"{estimator.feature_names_[j]} = {checks.rest.level[j]:.6g}"
            for j in np.flatnonzero(checks.rest.removed)
        )
        notes["offset"] = (
            f"rest level removed before the regression ({states}): the equations are written in the "
            "deviations from it; simulate and predict take the measured states"
        )
    if (estimator.sweep or estimator.refine) and float(getattr(estimator, "budget_used_", 0.0)) >= 1.0:
        notes["budget"] = (
            "the simulation work budget ran out: the sweep or the refinement was cut short; the checks "
            "judge the model it gave"
        )
    if any(oscilations > AUTO_PERIODS for oscilations in _periods(fitted)):
        notes["segments"] = "long record: the checks restart the simulation every 8 periods"
    return notes


def _periods(fitted: Fitted):
    from ..simulation.scoring import oscillation_count

    return [oscillation_count(f) for f in fitted.filtered]


def diagnose_fit(estimator, warn: bool = True, stacklevel: int = 2) -> FitDiagnostics:
    """Check a fitted :class:`~sindy_impulse.ImpulseSINDy` against its data and give a verdict.

    Called at the end of ``fit`` (the result is ``diagnostics_``); warns once for a doubtful, unreliable or
    no-dynamics verdict, with the class of :mod:`sindy_impulse.exceptions` that fits (never raises for a
    doubtful model, in plain PySINDy mode too).

    Parameters
    ----------
    estimator : ImpulseSINDy
        Fitted (``coef_``, ``model_``, ``x_filtered_``, and the data checks of ``fit``).
    warn : bool
        Issue the warning.
    stacklevel : int
        Stack level of the warning, counted from the caller of this function.

    Returns
    -------
    FitDiagnostics

    Examples
    --------
    >>> from sindy_impulse import ImpulseSINDy, damped_oscillator
    >>> t, x, _ = damped_oscillator(snr_db=40, random_state=0)
    >>> model = ImpulseSINDy().fit(x, t=t)
    >>> model.diagnostics_.verdict, model.diagnostics_.unsupported_terms
    ('ok', [])
    """
    checks: DataChecks = estimator._screening
    fitted = Fitted(estimator, rings_down=bool(np.any(checks.rest.rings_down)))
    notes = _notes(estimator, checks, fitted)
    m = _model_checks(fitted, checks, notes)
    m["noise_ratio"] = checks.noise_ratio
    m["budget"] = (
        float(getattr(estimator, "budget_used_", 0.0) or 0.0)
        if (estimator.sweep or estimator.refine)
        else 0.0
    )
    names = estimator.feature_names_
    verdict, reasons = judge(m, checks, names)
    noise = float(np.max(checks.noise_ratio)) if checks.noise_ratio.size else float("nan")
    out = FitDiagnostics(
        verdict=verdict,
        reasons=reasons,
        notes=notes,
        fit_error=m["fit_error"],
        noise_ratio=checks.noise_ratio,
        snr_db=float(-20 * np.log10(noise)) if noise > 0 else float("inf"),
        unsupported_terms=m["terms"].unsupported,
        missing_terms=m["terms"].missing,
        alternative_terms=m["terms"].alternatives,
        term_uncertainty=m["terms"].uncertainty,
        term_statistics=m["terms"].statistics,
        peaks_hz=checks.peaks_hz,
        model_frequency_hz=m["model_hz"],
        frequency_mismatch=m["mismatch"],
        linear_share=m["share"],
        condition_number=m["condition"],
        state_condition=checks.state_condition,
        offset=checks.rest.shift,
        offset_ratio=checks.rest.relative,
        clipped_samples=checks.clipped,
        quantisation=checks.relative_step,
        budget_used=m["budget"],
        quality=checks.quality,
    )
    if warn:
        out.warn(stacklevel=stacklevel + 1, skip=_estimator_warned(estimator))
    return out

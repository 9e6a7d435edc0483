"""The verdict rules: from the numbers of the checks to ``"ok"``, ``"doubtful"``, ``"unreliable"`` or
``"no dynamics"``, each problem worded with what to do.

Thresholds (fit error and noise are RMS values relative to each state's RMS about its rest level):

====================  =======================================================================  ============
verdict               when                                                                      class
====================  =======================================================================  ============
no dynamics           every coefficient is zero; the simulation misses every state (fit error   NoDynamics-
                      >= ``NO_DYNAMICS_ERROR``); or no state rings down (no spectral peak, no   Warning
                      decay) and the simulation misses the data (fit error >=
                      ``UNRELIABLE_ERROR``) or the filter removed more than it kept (noise
                      ratio > 1 in every state): the record looks like noise
unreliable            the simulation diverges or misses the data (fit error >=                  FitWarning
                      ``UNRELIABLE_ERROR``); a spectral peak of the data without a model mode
                      near it; the model's terms are collinear over the data (condition number
                      >= ``CONDITION_LIMIT``); two channels are nearly copies
                      (``STATE_CONDITION_LIMIT``)
doubtful              the simulation departs from the data by more than the noise explains      FitWarning,
                      (fit error > ``ADEQUACY`` x noise and > ``ERROR_FLOOR``); a term the      or Data-
                      data do not support, lack, or cannot tell from another (:mod:`.terms`);   Warning for
                      a coefficient uncertain by more than ``UNCERTAINTY_LIMIT`` (relative      data only
                      standard error); terms that could not be tested; clipping, coarse
                      quantisation, an offset left in place
ok                    none of the above
====================  =======================================================================  ============
"""

from __future__ import annotations

import numpy as np

from .data import DataChecks, quality_problems

__all__ = [
    "judge",
    "NO_DYNAMICS_ERROR",
    "UNRELIABLE_ERROR",
    "ADEQUACY",
    "ERROR_FLOOR",
    "UNCERTAINTY_LIMIT",
    "CONDITION_LIMIT",
    "STATE_CONDITION_LIMIT",
]

#: Fit error from which a model is unreliable (it explains under 75 % of the data's variance: 1 - 0.5**2);
#: with data that do not ring down, the record is taken for noise.
UNRELIABLE_ERROR = 0.5
#: Fit error from which the term tests are not run (the model explains under half the variance); in every
#: state, the verdict is "no dynamics".
NO_DYNAMICS_ERROR = 0.7
#: A fit error above this multiple of the noise ratio is more than the noise explains.
ADEQUACY = 3.0
#: Fit errors below this are never a problem (the filter's own smoothing error on clean data).
ERROR_FLOOR = 0.02
#: Relative standard error of a coefficient beyond which it is uncertain (10 % is then under three standard
#: errors). The standard errors count the correlation of the model's residual (:mod:`.terms`), so a model
#: that misses the data systematically gets wider ones; they are still a lower bound for this estimator
#: (sweep and refinement are not the maximum-likelihood fit): in the soak (benchmarks/robustness/soak.py) the
#: wrong coefficients of weak terms at 15-30 dB were 2.5-4 standard errors off. Chosen on the soak's seeds
#: 0-999 (unwarned wrong / warned right: 0.03 -> 6 / 41 of 688, 0.035 -> 10 / 32, 0.04 -> 12 / 31,
#: 0.05 -> 16 / 25), checked on seeds 1000-1999 (see benchmarks/robustness/soak.py).
UNCERTAINTY_LIMIT = 0.035
#: Condition number of the model's library columns from which its coefficients are not determined.
CONDITION_LIMIT = 1e8
#: Condition number of the standardised states from which two channels are nearly copies.
STATE_CONDITION_LIMIT = 1e3


def _no_dynamics(m: dict, checks: DataChecks) -> dict:
    if m["zero_model"]:
        return {"no_dynamics": "every coefficient is zero (x' = 0): the data show no deterministic dynamics"}
    best = float(np.min(m["fit_error"]))
    copies = checks.state_condition >= STATE_CONDITION_LIMIT  # then the cause is known: "unreliable"
    if np.isfinite(best) and best >= NO_DYNAMICS_ERROR and not copies:  # noise may look like a ring-down
        return {
            "no_dynamics": (
                f"the model's simulation explains under half the variance of every state (fit error "
                f"{best:.2g} or more of the RMS; x' = 0 gives 1): the record looks like noise, or the "
                "library lacks its dynamics; check the sensor and the trigger, or try another library"
            )
        }
    rings = any(report.ringdown_found for report in checks.quality) or checks.peaks_hz.size > 0
    worst = float(np.max(m["fit_error"]))
    noisy = bool(np.min(m["noise_ratio"]) > 1.0)  # the filter removed more than it kept, in every state
    if not rings and (worst >= UNRELIABLE_ERROR or noisy):
        return {
            "no_dynamics": (
                f"no state rings down (no spectral peak, no decay) and the model's simulation misses the "
                f"data (fit error {worst:.2g}, noise {np.min(m['noise_ratio']):.2g} of the signal): the "
                "record looks like noise; check the sensor and the trigger"
            )
        }
    return {}


def _unreliable(m: dict, checks: DataChecks, names) -> dict:
    out = {}
    worst = float(np.max(m["fit_error"]))
    if not np.isfinite(worst):
        out["divergence"] = (
            "the model's simulation from the data's first state diverges: it does not describe the data; "
            "use a smaller library or a longer, cleaner record"
        )
    elif worst >= UNRELIABLE_ERROR:
        out["fit_error"] = (
            f"the model's simulation misses the data (fit error {worst:.2g} of the RMS): the library may "
            "lack the right terms, or the record is too noisy"
        )
    if m["disagree"]:
        peaks = ", ".join(f"{f:.4g}" for f in checks.peaks_hz)
        model = ", ".join(f"{f:.4g}" for f in m["model_hz"]) or "none"
        out["frequency"] = (
            f"the data's spectral peaks ({peaks} Hz) are not the model's frequencies ({model} Hz): check "
            "for an offset, a trend or a missing state"
        )
    if m["condition"] >= CONDITION_LIMIT:
        out["conditioning"] = (
            f"the model's terms are nearly collinear over the data (condition number {m['condition']:.2g}): "
            "their coefficients are not determined; use a smaller library or remove redundant channels"
        )
    if checks.state_condition >= STATE_CONDITION_LIMIT:
        i, j, r = checks.collinear
        out["collinear"] = (
            f"channels {names[i]} and {names[j]} are nearly copies (correlation {r:.6f}): the model cannot "
            "tell them apart; keep one of them (or delay-embed a single channel)"
        )
    return out


def _doubtful(m: dict, checks: DataChecks) -> dict:
    out = {}
    err, noise = np.asarray(m["fit_error"]), np.asarray(m["noise_ratio"])
    excess = (err > ADEQUACY * noise) & (err > ERROR_FLOOR) & checks.noise_known
    if np.all(np.isfinite(err)) and np.any(excess):
        j = int(np.argmax(np.where(excess, err / np.maximum(noise, 1e-300), 0)))
        out["adequacy"] = (
            f"the model's simulation departs from the data by more than the noise explains (fit error "
            f"{err[j]:.2g}, noise {noise[j]:.2g} of the RMS): a term may be missing or wrong; compare "
            "other libraries"
        )
    tests = m["terms"]
    if tests.unsupported:
        out["support"] = (
            f"the data hardly determine the term(s) {', '.join(tests.unsupported)}: leaving each out changes "
            "the simulation by less than the noise, so it may be spurious or too weak to resolve in this "
            "record (a longer or cleaner record decides)"
        )
    uncertain = [
        t for t, u in tests.uncertainty.items() if u > UNCERTAINTY_LIMIT and t not in tests.unsupported
    ]
    if uncertain:
        worst = max(tests.uncertainty[t] for t in uncertain)
        out["uncertain"] = (
            f"the coefficient(s) of {', '.join(uncertain)} are uncertain by up to +-{300 * worst:.0f} % "
            "(three standard errors): the record does not pin them down; fit a longer or cleaner record"
        )
    if tests.missing:
        out["missing"] = (
            f"the data ask for term(s) the model lacks ({', '.join(tests.missing)}): adding one explains "
            "more than the noise; the selection may have stopped too sparse"
        )
    if tests.alternatives:
        pairs = ", ".join(f"{a} -> {b.split(' : ')[-1]}" for a, b in tests.alternatives[:4])
        more = f" and {len(tests.alternatives) - 4} more" if len(tests.alternatives) > 4 else ""
        out["ambiguous"] = (
            f"other terms explain the data as well ({pairs}{more}): the data cannot tell which is right; "
            "fit a record with larger amplitude or less noise, or restrict the library to the physics"
        )
    if m.get("untested", 0) > 0:
        out["untested"] = (
            f"{m['untested']} term(s) of the model could not be tested (work budget of the tests, or a "
            "simulation that diverges when perturbed): its structure is unverified; use a smaller library, "
            "or decimate or shorten the record"
        )
    if out and m.get("budget", 0.0) >= 1.0:  # alone, a note: the checks above judge the model it gave
        out["budget"] = (
            "the simulation work budget of the fit ran out (long record or large library): some dense "
            "candidates were not simulated or the refinement stopped early; shorten or decimate the record, "
            "or use a smaller library (sindy_impulse.simulation.WORK_BUDGET)"
        )
    out.update(quality_problems(checks))
    return out


def judge(m: dict, checks: DataChecks, names) -> tuple[str, dict]:
    """The verdict and its reasons from the model checks ``m`` and the data checks.

    ``m`` holds ``fit_error``, ``noise_ratio`` (arrays per state), ``zero_model``, ``disagree``,
    ``model_hz``, ``condition`` and ``terms`` (:class:`~.terms.TermTests`); ``names`` are the state
    names.
    """
    reasons = _no_dynamics(m, checks)
    if reasons:
        if checks.scale_problem is not None:  # the cause, and what to do
            reasons["scale"] = checks.scale_problem
        return "no dynamics", reasons
    reasons = _unreliable(m, checks, names)
    if reasons:
        reasons.update(_doubtful(m, checks))
        return "unreliable", reasons
    reasons = _doubtful(m, checks)
    return ("doubtful" if reasons else "ok"), reasons

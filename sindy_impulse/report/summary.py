"""What is said about each mode, said once: its values in the chosen damping unit, its amplitude and shape
per channel, the verdict of the test for nonlinearity and of the diagnostics, and which of the two decides
when they seem to disagree. The command line's terminal lines and JSON, and the HTML report, all read
:func:`mode_account`, so they cannot contradict each other.

The fit error is one number, ``Mode.fit_error`` (the model's simulation error per compared value, each
stretch of the decay measured against its own amplitude; :data:`FIT_ERROR_MEANING`); the diagnostics'
RMS deviation, on which their thresholds are set, is called that wherever it is shown.
"""

from __future__ import annotations

import math
import re

import numpy as np

from .._utils.units import (
    DAMPING_UNITS,
    DEFAULT_DAMPING_UNIT,
    check_damping_unit,
    damping_in_words,
    damping_text,
)
from .text import nonlinearity_words, problem_lines

__all__ = [
    "FIT_ERROR_MEANING",
    "channel_table",
    "decision",
    "default_channel_names",
    "mode_account",
    "phase_text",
    "survey_account",
]

#: What "fit error" means, wherever it is shown.
FIT_ERROR_MEANING = (
    "fit error: the mean deviation of the model's simulation from the band signal, each stretch of the decay "
    "relative to its own amplitude (0: exact; Mode.fit_error)"
)


def phase_text(degrees: float, decimals: int = 1) -> str:
    """A phase in degrees with its sign, zero without one.

    Examples
    --------
    >>> phase_text(-0.04), phase_text(179.46), phase_text(-170.5, 0)
    ('0.0', '+179.5', '-170')
    """
    text = f"{degrees:+.{decimals}f}"
    return f"{0.0:.{decimals}f}" if float(text) == 0 else text


def default_channel_names(n: int) -> list[str]:
    """``["ch0", "ch1", ...]``: the names of channels that have none."""
    return [f"ch{k}" for k in range(n)]


def _finite(value):
    value = float(value)
    return value if math.isfinite(value) else None


def channel_table(mode, names) -> list[dict]:
    """Per channel: its name, the mode's amplitude there, and its shape (magnitude and phase in degrees
    relative to the reference channel, the one whose shape is exactly 1). One row, the reference channel's
    amplitude, when the mode has no shape (one channel, or a mode identified jointly with its neighbours).

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> shape = np.array([-0.5 + 0j, 1.0 + 0j])
    >>> mode = NS(amplitude=2.0, shape=shape, channel_amplitudes=lambda: 2.0 * np.abs(shape))
    >>> rows = channel_table(mode, ["a", "b"])
    >>> [(r["channel"], r["amplitude"], r["phase_deg"], r["reference"]) for r in rows]
    [('a', 1.0, 180.0, False), ('b', 2.0, 0.0, True)]
    """
    if mode.shape is None:
        return [{"channel": None, "amplitude": _finite(mode.amplitude), "magnitude": 1.0, "phase_deg": 0.0,
                 "reference": True}]
    shape = np.asarray(mode.shape, dtype=complex)
    amplitudes = mode.channel_amplitudes()
    if names is None or len(names) != shape.size:
        names = default_channel_names(shape.size)
    return [
        {
            "channel": name,
            "amplitude": _finite(a),
            "magnitude": _finite(abs(s)),
            "phase_deg": _finite(round(float(np.degrees(np.angle(s))), 6) + 0.0),  # no -0.0
            "reference": bool(s == 1.0),
        }
        for name, a, s in zip(names, amplitudes, shape)
    ]


_FACTOR = re.compile(r"^([A-Za-z_][\w]*)(\^(\d+))?$")


def _is_nonlinear(term: str, states) -> bool:
    """Whether a library term (``"y' : dy^3"`` or ``"dy^3"``) is more than a constant or one state."""
    name = term.split(" : ")[-1].strip()
    if name == "1":
        return False
    factors = name.split()
    if len(factors) != 1:
        return True
    match = _FACTOR.match(factors[0])
    return not (match and match.group(1) in states and match.group(3) in (None, "1"))


def _model_nonlinear_terms(mode) -> list[str]:
    model = mode.model
    names = model.get_feature_names()
    states = list(model.feature_names_)
    coef = np.asarray(model.coefficients())
    return [names[j] for j in np.flatnonzero(np.any(coef != 0, axis=0)) if _is_nonlinear(names[j], states)]


def _untested(missing: list) -> str:
    if not missing:
        return ""
    return (
        f"The diagnostics find that the nonlinear term(s) {', '.join(missing)} would lower the error; the "
        "test for nonlinearity, which decides whether the mode is nonlinear, was skipped: run it"
    )


def _stand_ins(diag, states) -> list[str]:
    """The diagnostics' exchanges of a linear term for a nonlinear one that explains the data as well."""
    pairs = getattr(diag, "alternative_terms", [])
    return [
        f"{a.split(' : ')[-1]} -> {b.split(' : ')[-1]}"
        for a, b in pairs
        if _is_nonlinear(b, states) and not _is_nonlinear(a, states)
    ]


def decision(mode, tested: bool) -> str:
    """Which verdict decides, and why, when the test for nonlinearity and the diagnostics seem to disagree
    (``""`` when they do not). ``tested``: whether the test for nonlinearity was run."""
    diag = mode.diagnostics
    if diag is None:
        return ""
    states = list(mode.model.feature_names_)
    missing = [t for t in diag.missing_terms if _is_nonlinear(t, states)]
    if not tested:
        return _untested(missing)
    if diag.verdict in ("unreliable", "no dynamics"):
        return (
            f"The model is {diag.verdict}, so the test for nonlinearity, which rests on it, decides "
            "nothing: treat the mode's values with caution"
        )
    test = mode.nonlinearity
    numbers = (
        f"statistic {test.statistic:.3g} {'>' if test.nonlinear else '<='} threshold {test.threshold:.3g}"
    )
    own = _model_nonlinear_terms(mode)
    unsupported = [t for t in diag.unsupported_terms if _is_nonlinear(t, states)]
    if not test.nonlinear and missing:
        return (
            "Linear wins: the test for nonlinearity refits the mode with nonlinear terms over the whole "
            f"decay and finds no amplitude dependence it can resolve ({numbers}); the diagnostics' add test "
            f"only sees that {', '.join(missing)} would lower the simulation error a little, which a small "
            "misfit of the band signal (a neighbouring mode, the band-pass) also explains"
        )
    swaps = _stand_ins(diag, states)
    if not test.nonlinear and swaps:
        return (
            f"Linear wins: the diagnostics find that nonlinear terms could stand in for linear ones on this "
            f"record ({', '.join(swaps[:3])}), that is the record alone cannot tell them apart; the test for "
            f"nonlinearity, which compares the decay at all its amplitudes, finds no amplitude dependence it "
            f"can resolve ({numbers})"
        )
    if not test.nonlinear and own:
        return (
            f"Linear wins: the model carries {', '.join(own)}, but over the decay their effect on frequency "
            f"and damping is below what the test resolves ({numbers}); the modal values are the linear part's"
        )
    if test.nonlinear and unsupported:
        return (
            f"Nonlinear wins: the decay's amplitude dependence is beyond the noise ({numbers}), but the "
            f"data hardly determine {', '.join(unsupported)}: which term carries it is uncertain"
        )
    if test.nonlinear and not own:
        return (
            "Nonlinear wins: the selected equation is linear, but the test's nonlinear alternative explains "
            f"the decay's amplitude dependence beyond the noise ({numbers}); the backbone drawn is the "
            "alternative's"
        )
    return ""


def _equations(mode) -> dict:
    model = mode.model
    names = list(model.feature_names_)[: getattr(model, "n_states_", len(model.feature_names_))]
    return {f"{n}'": eq for n, eq in zip(names, model.equations(4))}


def _coefficients_std(mode) -> dict:
    """Per equation, the standard deviation of each of its terms' coefficients (terms the model has)."""
    if mode.coefficients_std is None:
        return {}
    terms = mode.model.get_feature_names()
    return {
        f"{n}'": {term: float(std) for term, std in zip(terms, row) if math.isfinite(std)}
        for n, row in zip(mode.model.feature_names_, mode.coefficients_std)
    }


def _diagnostics(mode) -> dict:
    diag = mode.diagnostics
    if diag is None:
        return {"diagnostics": None, "problems": [], "problem_details": {}, "diagnostic_notes": {}}
    return {
        "diagnostics": diag.verdict,
        "problems": [short for _, short, _ in problem_lines(diag.reasons)],
        "problem_details": {str(k): str(v) for k, v in diag.reasons.items()},
        "diagnostic_notes": {str(k): str(v) for k, v in diag.notes.items()},
    }


def mode_account(mode, *, nonlinearity: bool = True, damping_unit: str = DEFAULT_DAMPING_UNIT,
                 channel_names=None) -> dict:
    """Everything said about one mode, JSON-ready (non-finite numbers as None).

    The modal-table row (:meth:`Mode.row`, damping in ``damping_unit`` under names that say it), the
    reference channel and the amplitude and shape per channel (:func:`channel_table`), the equations,
    their coefficients' standard deviations and the chance that noise alone makes their nonlinear terms
    (:attr:`Mode.nonlinear_chance`, None where not computed), the diagnostics' verdict with its problems
    (short lines and whole sentences), and with ``nonlinearity`` the test's verdict, its numbers in words
    and the :func:`decision` sentence.
    """
    check_damping_unit(damping_unit)
    row = mode.row(nonlinearity, damping_unit)
    row = {k: (_finite(v) if isinstance(v, float) else v) for k, v in row.items()}
    channels = channel_table(mode, channel_names)
    reference = next((c["channel"] for c in channels if c["reference"]), None)
    out = {**row, "damping_unit": damping_unit, "reference_channel": reference}
    out["channels"] = channels if mode.shape is not None else []
    out["equations"] = _equations(mode)
    out["coefficients_std"] = _coefficients_std(mode)
    out["nonlinear_chance"] = _finite(getattr(mode, "nonlinear_chance", math.nan))
    out.update(_diagnostics(mode))
    if nonlinearity:
        out["nonlinearity"] = nonlinearity_words(mode.nonlinearity)[1]
    out["decision"] = decision(mode, nonlinearity)
    return out


def survey_account(survey, *, nonlinearity: bool = True, damping_unit: str = DEFAULT_DAMPING_UNIT,
                   channel_names=None) -> dict:
    """:func:`mode_account` of every mode, with the survey's rejected bands and notes (their damping ratios in
    ``damping_unit``), and the meaning of the damping unit and of the fit error.

    Examples
    --------
    >>> import warnings
    >>> from sindy_impulse import identify_modes, impact_record
    >>> rec = impact_record([120.0], [0.01], fs=2000, duration=1.0, snr_db=50, random_state=0)
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     account = survey_account(identify_modes(rec.y, fs=rec.fs), nonlinearity=False)
    >>> round(account["modes"][0]["damping_ratio_percent"], 2), account["modes"][0]["diagnostics"]
    (1.0, 'ok')
    """
    scale, symbol, _ = DAMPING_UNITS[check_damping_unit(damping_unit)]
    return {
        "damping_unit": damping_unit,
        "units": {
            "damping": f"damping ratio {'in per cent' if scale == 100 else 'as a fraction'} "
            f"(e.g. {damping_text(0.01, damping_unit)} for 1 % of critical damping)",
            "fit_error": FIT_ERROR_MEANING,
            "phase_deg": "phase of the mode in each channel relative to the reference channel, degrees",
        },
        "modes": [
            mode_account(m, nonlinearity=nonlinearity, damping_unit=damping_unit, channel_names=channel_names)
            for m in survey.modes
        ],
        "rejected": [
            {
                "band_hz": r.band_hz and list(r.band_hz),
                "reason": damping_in_words(str(r.reason), damping_unit),
                "record": r.record,
            }
            for r in survey.rejected
        ],
        "notes": [damping_in_words(str(n), damping_unit) for n in survey.notes],
    }

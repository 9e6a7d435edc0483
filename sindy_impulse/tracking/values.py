"""What the tracker reads from a survey: per mode its linear values, their ±, its amplitude and shape, and
its equation's coefficients written in the engineer's form.

A mode's model (:attr:`Mode.model`, states ``[y, dy]`` with ``y' = a dy``) is rewritten as one
second-order equation of the measured coordinate,

    y'' + w^2 y + 2 zeta w y' + sum_k c_k y^p_k y'^q_k = 0,

whose coefficients do not depend on how the fit split ``a`` and the stiffness between its two rows
(``c = -a^(1 - q) beta`` for the model's coefficient ``beta`` of ``y^p dy^q`` in ``dy'``). Positive
coefficients resist motion: ``w^2`` is the linear stiffness, ``2 zeta w`` the linear damping, a positive
``y^3`` coefficient a hardening cubic spring, a positive ``y^2 y'`` coefficient a damping that grows with
amplitude. The linear stiffness and damping are taken from the mode's reported ``frequency_hz`` and
``damping_ratio`` (and their ±), so that the coefficients agree with the modal table. A model of another
form (more states, a first row that is not ``y' = a dy``) keeps its raw coefficients, named
``"(state)' term"``.

:class:`SurveyValues` is small (a few numbers per mode) and round-trips through :meth:`SurveyValues.to_dict`
(JSON-ready): surveys computed once can be tracked again without their models.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np

__all__ = ["ModeValues", "SurveyValues", "survey_values", "term_name", "term_powers", "LINEAR_TERMS"]

#: The keys of the linear stiffness and damping among a mode's terms.
LINEAR_TERMS = ("y", "y'")

#: Engineering names of the monomials ``y^p y'^q`` of the equation (``(p, q) -> name``).
_NAMES = {
    (0, 0): "constant force",
    (1, 0): "linear stiffness",
    (0, 1): "linear damping",
    (2, 0): "quadratic stiffness",
    (3, 0): "cubic stiffness",
    (0, 2): "quadratic damping (y'^2)",
    (0, 3): "cubic damping",
    (2, 1): "amplitude-dependent damping (y^2 y')",
    (1, 1): "stiffness-damping coupling (y y')",
    (1, 2): "velocity-dependent stiffness (y y'^2)",
}


def _monomial_key(p: int, q: int) -> str:
    parts = ([f"y^{p}" if p > 1 else "y"] if p else []) + ([f"y'^{q}" if q > 1 else "y'"] if q else [])
    return " ".join(parts) or "1"


def term_powers(key: str) -> tuple[int, int] | None:
    """``(p, q)`` of a monomial key ``"y^p y'^q"``; None for a raw (non-canonical) term.

    Examples
    --------
    >>> term_powers("y^2 y'"), term_powers("y'"), term_powers("(dy)' tanh(y)")
    ((2, 1), (0, 1), None)
    """
    if key == "1":
        return (0, 0)
    p = q = 0
    for token in key.split():
        match = re.fullmatch(r"(y'?)(?:\^(\d+))?", token)
        if match is None:
            return None
        power = int(match.group(2) or 1)
        if match.group(1) == "y":
            p += power
        else:
            q += power
    return (p, q)


def term_name(key: str) -> str:
    """The engineer's name of a term of the equation.

    Examples
    --------
    >>> term_name("y^3"), term_name("y'"), term_name("y^4"), term_name("(dy)' y|y|")
    ('cubic stiffness', 'linear damping', 'y^4 term', "(dy)' y|y| term")
    """
    powers = term_powers(key)
    return _NAMES.get(powers, f"{key} term") if powers is not None else f"{key} term"


@dataclass(eq=False)
class ModeValues:
    """One mode of one survey as the tracker sees it.

    Attributes
    ----------
    frequency_hz, frequency_std_hz, damping_ratio, damping_ratio_std : float
        The survey's linear values and their standard deviations (NaN when the survey gives none).
    amplitude : float
        The mode's amplitude at the hit, in the sensor's units (the coordinate ``y`` of its equation).
    snr_db : float
        Signal-to-noise ratio of its band (NaN when unknown): where the ± are unknown, ``10^(-snr/20)``
        stands in for the noise the fit saw.
    shape : ndarray of complex or None
        Its shape over the channels (several sensors only).
    terms : dict
        ``key -> (value, std)`` of the equation's coefficients (module docstring): ``"y"`` the linear
        stiffness ``w^2`` (1/s^2), ``"y'"`` the linear damping ``2 zeta w`` (1/s), ``"y^3"`` a cubic
        stiffness, ... Terms the model does not have are absent (a coefficient of 0). The linear ones,
        when not given, follow from the frequency and damping ratio.
    canonical : bool
        True when the model was rewritten as one equation of ``y`` (else the nonlinear terms are raw).
    note : str
        Why a standard deviation is missing (the survey's ``uncertainty_note``).
    """

    frequency_hz: float
    frequency_std_hz: float
    damping_ratio: float
    damping_ratio_std: float
    amplitude: float
    snr_db: float = math.nan
    shape: np.ndarray | None = None
    terms: dict = field(default_factory=dict)
    canonical: bool = True
    note: str = ""

    def __post_init__(self):
        if not all(k in self.terms for k in LINEAR_TERMS):  # the linear part from the modal values
            self.terms = {
                **_linear_terms(
                    self.frequency_hz, self.frequency_std_hz, self.damping_ratio, self.damping_ratio_std
                ),
                **self.terms,
            }

    @property
    def nonlinear_terms(self) -> dict:
        """The terms other than the linear stiffness and damping."""
        return {k: v for k, v in self.terms.items() if k not in LINEAR_TERMS}

    def to_dict(self) -> dict:
        """JSON-ready (NaN as None, a complex shape as pairs)."""
        shape = None if self.shape is None else [[float(z.real), float(z.imag)] for z in self.shape]
        return {
            "frequency_hz": _num(self.frequency_hz),
            "frequency_std_hz": _num(self.frequency_std_hz),
            "damping_ratio": _num(self.damping_ratio),
            "damping_ratio_std": _num(self.damping_ratio_std),
            "amplitude": _num(self.amplitude),
            "snr_db": _num(self.snr_db),
            "shape": shape,
            "terms": {k: [_num(v), _num(s)] for k, (v, s) in self.terms.items()},
            "canonical": self.canonical,
            "note": self.note,
        }

    @classmethod
    def from_dict(cls, d: dict) -> ModeValues:
        """The inverse of :meth:`to_dict`."""
        shape = d.get("shape")
        return cls(
            *(
                _float(d[k])
                for k in (
                    "frequency_hz",
                    "frequency_std_hz",
                    "damping_ratio",
                    "damping_ratio_std",
                    "amplitude",
                )
            ),
            snr_db=_float(d.get("snr_db")),
            shape=None if shape is None else np.array([complex(a, b) for a, b in shape]),
            terms={k: (_float(v), _float(s)) for k, (v, s) in d.get("terms", {}).items()},
            canonical=bool(d.get("canonical", True)),
            note=str(d.get("note", "")),
        )


@dataclass(eq=False)
class SurveyValues:
    """The modes of one survey as the tracker sees them (:func:`survey_values`).

    Attributes
    ----------
    modes : list of ModeValues
        Sorted by frequency.
    label : str
        A name for the survey (its file, its date); default ``"survey <index>"`` in :func:`track`.
    failed : str
        Why the survey has no modes when it failed ("" otherwise).
    """

    modes: list
    label: str = ""
    failed: str = ""

    def to_dict(self) -> dict:
        """JSON-ready; :meth:`from_dict` reads it back."""
        return {"label": self.label, "failed": self.failed, "modes": [m.to_dict() for m in self.modes]}

    @classmethod
    def from_dict(cls, d: dict) -> SurveyValues:
        """The inverse of :meth:`to_dict`."""
        return cls(
            [ModeValues.from_dict(m) for m in d["modes"]], str(d.get("label", "")), str(d.get("failed", ""))
        )


def _num(x):
    x = float(x)
    return x if math.isfinite(x) else None


def _float(x) -> float:
    return math.nan if x is None else float(x)


def _linear_terms(f, f_std, zeta, zeta_std) -> dict:
    """``w^2`` and ``2 zeta w`` with their standard deviations from those of f and zeta."""
    w = 2 * math.pi * f
    return {
        "y": (w * w, 2 * w * w * f_std / f if f > 0 else math.nan),
        "y'": (2 * zeta * w, 2 * math.hypot(w * zeta_std, zeta * 2 * math.pi * f_std)),
    }


def _powers(feature: str, states: list) -> tuple | None:
    """The power of each state in a library feature that is a monomial of the states (``"y^2 dy"``), else
    None (a function of them, a term of another library)."""
    powers = [0] * len(states)
    if feature.strip() == "1":
        return tuple(powers)
    for token in feature.split() or ["?"]:
        name, _, power = token.rpartition("^") if "^" in token else (token, "", "1")
        if name not in states or not power.isdigit():
            return None
        powers[states.index(name)] += int(power)
    return tuple(powers)


def _model_terms(model, coordinate: int, std) -> tuple[dict, bool]:
    """The model's nonlinear terms as ``key -> (value, std)`` and whether they are canonical (module
    docstring); a model of another form keeps its raw coefficients of degree other than one."""
    coef = np.asarray(model.coefficients(), float)
    features = list(model.get_feature_names())[: coef.shape[1]]
    names = list(getattr(model, "feature_names_", []))
    states = (names + [f"x{i}" for i in range(len(names), coef.shape[0])])[: coef.shape[0]]
    std = np.full(coef.shape, np.nan) if std is None else np.asarray(std, float)
    powers = [_powers(f, states) for f in features]
    first = np.flatnonzero(coef[0, : len(features)]) if coef.shape[0] else []
    canonical = coef.shape[0] == 2 and coordinate == 0 and len(first) == 1 and powers[first[0]] == (0, 1)
    terms = {}
    for i, j in zip(*np.nonzero(coef[:, : len(features)])):
        if powers[j] is not None and sum(powers[j]) == 1:
            continue  # the linear part: the frequency and damping ratio say it
        if canonical and i == 1 and powers[j] is not None:
            scale = coef[0, first[0]] ** (1 - powers[j][1])
            terms[_monomial_key(*powers[j])] = (float(-scale * coef[i, j]), float(abs(scale) * std[i, j]))
        elif not canonical or i == 1:
            terms[f"({states[i]})' {features[j]}"] = (float(coef[i, j]), float(std[i, j]))
    return terms, canonical


def mode_values(mode) -> ModeValues:
    """One :class:`~sindy_impulse.modes.Mode` (or anything with its attributes) as :class:`ModeValues`."""
    f = float(mode.frequency_hz)
    f_std = float(getattr(mode, "frequency_std_hz", math.nan))
    zeta = float(mode.damping_ratio)
    zeta_std = float(getattr(mode, "damping_ratio_std", math.nan))
    terms = _linear_terms(f, f_std, zeta, zeta_std)
    canonical = True
    model = getattr(mode, "model", None)
    if model is not None and hasattr(model, "coefficients"):
        extra, canonical = _model_terms(
            model, getattr(mode, "coordinate_", 0), getattr(mode, "coefficients_std", None)
        )
        terms.update(extra)
    shape = getattr(mode, "shape", None)
    return ModeValues(
        f,
        f_std,
        zeta,
        zeta_std,
        float(getattr(mode, "amplitude", math.nan)),
        float(getattr(mode, "snr_db", math.nan)),
        None if shape is None else np.asarray(shape, complex),
        terms,
        canonical,
        str(getattr(mode, "uncertainty_note", "")),
    )


def survey_values(survey, label: str = "") -> SurveyValues:
    """A survey (what :func:`~sindy_impulse.identify_modes` returns, a ``FailedRecord`` of
    :func:`~sindy_impulse.survey_many`, a :class:`SurveyValues` or its dict) as :class:`SurveyValues`.

    Examples
    --------
    >>> from sindy_impulse import identify_modes, impact_record
    >>> rec = impact_record([120.0], [0.01], fs=2000, duration=1.0, snr_db=50, random_state=0)
    >>> values = survey_values(identify_modes(rec.y, fs=rec.fs), label="hit 1")
    >>> mode = values.modes[0]
    >>> round(mode.frequency_hz, 1), sorted(mode.terms)
    (120.0, ['y', "y'"])
    >>> round(mode.terms["y"][0] / (2 * 3.14159265 * 120.0) ** 2, 3)  # w^2
    1.0
    """
    if isinstance(survey, SurveyValues):
        return survey if not label or survey.label else SurveyValues(survey.modes, label, survey.failed)
    if isinstance(survey, dict) and "modes" in survey:
        values = SurveyValues.from_dict(survey)
        values.label = values.label or label
        return values
    if not hasattr(survey, "modes"):
        raise TypeError(
            "each survey must be what identify_modes or survey_many returns (or SurveyValues), got "
            f"{type(survey).__name__}"
        )
    failed = str(survey) if hasattr(survey, "error") and hasattr(survey, "message") else ""
    modes = sorted((mode_values(m) for m in survey.modes), key=lambda m: m.frequency_hz)
    if failed and not label:
        label = str(getattr(survey, "name", ""))
    return SurveyValues(modes, label, failed)

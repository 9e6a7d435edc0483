"""The diagnostics of a fit: the numbers, the verdict and its reasons in plain words, and the one warning."""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from ..exceptions import DataWarning, FitWarning, NoDynamicsWarning

__all__ = ["FitDiagnostics", "VERDICTS"]

#: The verdicts, from best to worst.
VERDICTS = ("ok", "doubtful", "unreliable", "no dynamics")
#: Reasons about the data only (a verdict with only these warns with a DataWarning).
DATA_REASONS = frozenset({"clipping", "quantisation", "offset", "collinear", "spikes", "constant", "scale"})


@dataclass(frozen=True)
class FitDiagnostics:
    """How far a fitted model can be trusted, and why.

    Attributes
    ----------
    verdict : str
        ``"ok"``, ``"doubtful"``, ``"unreliable"`` or ``"no dynamics"`` (rules:
        :mod:`sindy_impulse.diagnostics.verdict`).
    reasons : dict
        ``{check: sentence}``: each problem behind the verdict and what to do about it.
    notes : dict
        ``{check: sentence}``: what was done or seen that is not a problem (e.g. an offset removed).
    fit_error : ndarray (n_states,)
        The RMS deviation: RMS of the model's simulation minus the filtered states, over the RMS of the
        filtered states about their rest level (segment-restarted for records over 30 periods; inf:
        diverged); the verdict's thresholds are set on it. It is worded "RMS deviation" (also
        :attr:`rms_deviation`): a modal survey's "fit error" is ``Mode.fit_error``, another measure.
    noise_ratio : ndarray (n_states,)
        RMS of the measured minus the filtered states over the same RMS: the noise the filter removed.
    snr_db : float
        ``-20 log10`` of the largest noise ratio: the signal-to-noise ratio of the worst state.
    unsupported_terms : list of str
        Terms the data do not support (leaving one out and refitting the others does not change the
        simulation by more than the noise can explain), e.g. ``["x1' : x0^2"]``.
    missing_terms : list of str
        Terms the model lacks that the data ask for (adding one reduces the simulation error by more than
        the noise can explain).
    alternative_terms : list of (str, str)
        ``(term, replacement)``: exchanges that explain the data as well (the data cannot tell them apart).
    term_uncertainty : dict
        ``{term: relative standard error}`` of each term's coefficient, from its statistic.
    term_statistics : dict
        ``{term: statistic}``: the likelihood-ratio statistic of each term (>= 10.8: supported).
    peaks_hz : ndarray
        Significant spectral peaks of the measured states.
    model_frequency_hz : ndarray
        Damped frequencies of the model's modes at its rest point.
    frequency_mismatch : float
        Worst relative distance of a data peak to the nearest model frequency (NaN: not checked).
    linear_share : float
        Share of the model's right-hand side over the data that its linear part explains
        (:func:`~sindy_impulse.poles.modal.linear_share`).
    condition_number : float
        Condition number of the library columns of the model's terms (scaled to unit norm).
    state_condition : float
        Condition number of the standardised states (large: channels that are nearly copies).
    offset : ndarray (n_states,)
        Rest level removed from each state before the regression (0: none); the equations are written in
        the deviations ``x - offset``, simulations and predictions use the measured states.
    offset_ratio : ndarray (n_states,)
        Each state's rest level over its largest excursion.
    clipped_samples : int
    quantisation : float
        Largest ADC step over the amplitude (0: not quantised).
    budget_used : float
        Fraction of the simulation work budget the fit used (``budget_used_``).
    quality : list of QualityReport
        :func:`~sindy_impulse.preprocessing.check_quality` of each state (first trajectory).
    """

    verdict: str
    reasons: dict
    notes: dict
    fit_error: np.ndarray
    noise_ratio: np.ndarray
    snr_db: float
    unsupported_terms: list
    missing_terms: list
    alternative_terms: list
    term_uncertainty: dict = field(repr=False)
    term_statistics: dict = field(repr=False)
    peaks_hz: np.ndarray = field(repr=False)
    model_frequency_hz: np.ndarray = field(repr=False)
    frequency_mismatch: float
    linear_share: float
    condition_number: float
    state_condition: float
    offset: np.ndarray
    offset_ratio: np.ndarray = field(repr=False)
    clipped_samples: int
    quantisation: float
    budget_used: float
    quality: list = field(repr=False)

    @property
    def rms_deviation(self) -> np.ndarray:
        """:attr:`fit_error` under the name the diagnostics' sentences give it."""
        return self.fit_error

    @property
    def ok(self) -> bool:
        """True when the verdict is ``"ok"``."""
        return self.verdict == "ok"

    def summary(self) -> str:
        """The verdict and its reasons, one per line."""
        head = (
            f"verdict: {self.verdict} (RMS deviation {_worst(self.fit_error):.3g}, "
            f"noise {_worst(self.noise_ratio):.3g}"
            f" = {self.snr_db:.1f} dB SNR, budget {100 * self.budget_used:.0f} % used)"
        )
        lines = [head]
        lines += [f"  - {text}" for text in self.reasons.values()]
        lines += [f"  note: {text}" for text in self.notes.values()]
        return "\n".join(lines)

    def warning_class(self):
        """The class of the warning this verdict gives (None for "ok")."""
        if self.verdict == "ok":
            return None
        if self.verdict == "no dynamics":
            return NoDynamicsWarning
        return DataWarning if set(self.reasons) <= DATA_REASONS else FitWarning

    def warn(self, stacklevel: int = 2, skip: frozenset = frozenset()) -> None:
        """Warn once for a doubtful, unreliable or no-dynamics verdict, with what to do.

        ``skip``: reasons the caller has already warned about (nothing is warned if only these remain).
        """
        kind = self.warning_class()
        reasons = {k: v for k, v in self.reasons.items() if k not in skip}
        if kind is None or not reasons:
            return
        text = "; ".join(reasons.values())
        head = (
            "no deterministic dynamics found"
            if self.verdict == "no dynamics"
            else f"the fitted model is {self.verdict}"
        )
        warnings.warn(
            f"{head}: {text} (details: diagnostics_)",
            kind,
            stacklevel=stacklevel + 1,
        )


def _worst(values) -> float:
    values = np.asarray(values, dtype=float)
    return float(np.max(values)) if values.size else float("nan")

"""What :func:`~sindy_impulse.tracking.track` hands back: the alarms, the trends, the series, the tables."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import stats

__all__ = ["QUANTITIES", "Alarm", "ModeEvent", "Trend", "TrackResult"]

#: The quantities of each mode that are tested: its linear frequency and damping ratio, and how far its
#: backbone departs from them at the common amplitude (the nonlinear terms' share).
QUANTITIES = ("frequency_hz", "damping_ratio", "backbone_frequency_shift_hz", "backbone_damping_shift")
#: Their names in words.
WORDS = {
    "frequency_hz": "frequency",
    "damping_ratio": "damping ratio",
    "backbone_frequency_shift_hz": "backbone frequency (nonlinear shift at the common amplitude)",
    "backbone_damping_shift": "backbone damping ratio (nonlinear shift at the common amplitude)",
}


def _pct(x: float) -> str:
    return f"{100 * x:+.3g} %" if math.isfinite(x) else "?"


@dataclass(frozen=True)
class Alarm:
    """A mode of a new survey that changed beyond the rate asked.

    Attributes
    ----------
    survey, mode : int
        The survey's index and the mode's (the track's) index.
    quantity : str
        The most significant quantity that changed (one of :data:`QUANTITIES`); ``quantities`` all of them.
    value, t, p : float
        Its value in this survey, the test statistic and the p-value (before the correction over the
        survey's tests; the survey is flagged by Holm's procedure).
    terms : list of TermChange
        Every coefficient of the mode's equation tested, most significant first.
    term : TermChange or None
        The term that carries the change (:func:`~sindy_impulse.tracking.terms.named_term`);
        ``term_significant`` False when no term changed significantly on its own.
    frequency_hz, damping_ratio, amplitude : float
        The mode in this survey (``amplitude``: at the hit, sensor units).
    """

    survey: int
    mode: int
    quantity: str
    quantities: list
    value: float
    t: float
    p: float
    terms: list = field(repr=False)
    term: object = None
    term_significant: bool = False
    frequency_hz: float = math.nan
    damping_ratio: float = math.nan
    amplitude: float = math.nan

    def change(self, result) -> str:
        """The change of :attr:`quantity` in words: ``"frequency -0.25 %"``."""
        ref = result.reference_mean(self.quantity, self.mode)
        if self.quantity == "frequency_hz":
            return f"frequency {_pct(self.value / ref - 1)}"
        if self.quantity == "damping_ratio":
            return f"damping ratio {_pct(self.value / ref - 1)}"
        at = f"at amplitude {result.amplitudes[self.mode]:.3g}"
        if self.quantity == "backbone_frequency_shift_hz":
            return f"frequency {at} {_pct((self.value - ref) / self.frequency_hz)} beyond the linear"
        return f"damping ratio {at} {_pct((self.value - ref) / self.damping_ratio)} beyond the linear"

    def text(self, result) -> str:
        """One line: the survey, the mode, what changed, and which term of its equation carries it."""
        track = result.tracks[self.mode]
        head = f"{result.labels[self.survey]}: {track.label(self.mode)} changed: {self.change(result)} "
        head += f"(t = {self.t:.3g}, p = {self.p:.2g})"
        if self.term is None:
            return head + "; no term of its equation could be tested"
        words = self.term.describe()
        if not self.term_significant:
            words += " - the most likely term, not significant on its own"
        others = [
            c.describe()
            for c in self.terms
            if c is not self.term and c.significant
        ]
        unchanged = [c.name for c in self.terms if not c.significant and c.key in ("y", "y'")]
        tail = "; ".join(
            [words] + others + ([f"the {' and '.join(unchanged)} unchanged"] if unchanged else [])
        )
        return f"{head}; {tail}"


@dataclass(frozen=True)
class Trend:
    """The Mann-Kendall trend of one quantity of one mode over the new surveys.

    Attributes
    ----------
    mode : int
    quantity : str
    z, p : float
        The statistic (positive: rising) and the p-value.
    significant : bool
        Beyond the rate asked, Holm-corrected over every mode and quantity.
    slope : float
        Median change per survey (Theil-Sen), in the quantity's units.
    """

    mode: int
    quantity: str
    z: float
    p: float
    significant: bool
    slope: float

    def text(self, result) -> str:
        """One line."""
        ref = result.reference_mean(self.quantity, self.mode)
        per = self.slope / ref if self.quantity in ("frequency_hz", "damping_ratio") and ref else math.nan
        rate = f"{_pct(per)} per survey" if math.isfinite(per) else f"{self.slope:+.3g} per survey"
        return (
            f"trend: {result.tracks[self.mode].label(self.mode)} {WORDS[self.quantity]} {rate} over the "
            f"{len(result.new)} new surveys (Mann-Kendall z = {self.z:.3g}, p = {self.p:.2g})"
        )


@dataclass(frozen=True)
class ModeEvent:
    """A mode found less often in the new surveys than in the reference (``"vanished"``), or found in
    new surveys and in no reference one (``"appeared"``), and whether that is beyond chance: Fisher's exact
    test of the share of surveys that found it (one-sided), Holm-corrected over the modes.

    Attributes
    ----------
    mode : int
    kind : str
        ``"vanished"`` or ``"appeared"``.
    found_reference, n_reference, found_new, n_new : int
        In how many surveys of each group the mode was found.
    p : float
    significant : bool
    """

    mode: int
    kind: str
    found_reference: int
    n_reference: int
    found_new: int
    n_new: int
    p: float
    significant: bool

    def text(self, result) -> str:
        """One line."""
        missed = [result.labels[s] for s in result.new if result.slot[s, self.mode] < 0]
        where = (f": {', '.join(missed[:5])}{' ...' if len(missed) > 5 else ''}" if self.kind == "vanished"
                 and missed else "")
        verdict = "" if self.significant else (
            "; within chance after Holm's correction over the modes" if self.p < result.alpha
            else "; within chance")
        label = result.tracks[self.mode].label(self.mode)
        return (f"{label} {self.kind}: found in {self.found_reference} of {self.n_reference} reference and "
                f"{self.found_new} of {self.n_new} new surveys (Fisher p = {self.p:.2g}{verdict}){where}")


class TrackResult:
    """The result of :func:`~sindy_impulse.tracking.track`.

    Attributes
    ----------
    changed : ndarray of bool (n_surveys,)
        Whether any mode of a survey changed beyond the false-alarm rate (False for the reference).
    alarms : list of Alarm
        One per changed mode of a new survey, in survey order.
    trends : list of Trend
        Every mode and quantity's trend over the new surveys; ``trend_alarms`` the significant ones.
    mode_events : list of ModeEvent
        Modes the new surveys found less often than the reference, or that appeared; ``event_alarms`` those
        beyond chance (a survey that lacks a mode is not ``changed``: one miss proves nothing).
    tracks : list of ModeTrack
        The modes followed (reference ones first, then any that appeared).
    labels : list of str
        A name per survey.
    reference, new : ndarray of int
        The indices of the reference surveys and of the new ones.
    amplitudes : ndarray
        Per mode, the amplitude at which the backbones are compared.
    alpha : float
        The false-alarm rate asked.
    """

    def __init__(
        self,
        values,
        reference,
        new,
        tracks,
        slot,
        testable,
        amplitudes,
        series,
        tests,
        flags,
        alarms,
        trends,
        alpha,
        mode_events=(),
    ):
        self.values, self.reference, self.new = values, reference, new
        self.tracks, self.slot, self.testable, self.amplitudes = tracks, slot, testable, amplitudes
        self.series, self.fits, self.t, self.p = series, tests[0], tests[1], tests[2]
        self.flags, self.alarms, self.trends, self.alpha = flags, alarms, trends, alpha
        self.mode_events = list(mode_events)
        self.quantities = QUANTITIES

    @property
    def labels(self) -> list:
        return [v.label for v in self.values]

    @property
    def changed(self) -> np.ndarray:
        return self.flags.any(axis=(1, 2))

    @property
    def changed_modes(self) -> np.ndarray:
        """(n_surveys, n_modes): which modes of which survey changed."""
        return self.flags.any(axis=2)

    @property
    def trend_alarms(self) -> list:
        return [tr for tr in self.trends if tr.significant]

    def reference_mean(self, quantity: str, mode: int) -> float:
        """The reference's mean of a quantity of a mode (NaN when it is not tested)."""
        fit = self.fits.get((quantity, mode))
        return float(fit.mean) if fit is not None else math.nan

    def reference_std(self, quantity: str, mode: int) -> float:
        """The reference's test-to-test scatter (standard deviation for a test of typical ±)."""
        fit = self.fits.get((quantity, mode))
        return float(fit.std) if fit is not None else math.nan

    def limits(self, quantity: str, mode: int):
        """``(mean, low, high)``: the reference's mean and the band outside which a new test of typical ±
        raises an alarm (the Bonferroni threshold of a survey's family of tests); None when not tested."""
        fit = self.fits.get((quantity, mode))
        if fit is None:
            return None
        n_tests = max(
            int(
                np.isfinite(np.stack([self.p[q] for q in QUANTITIES], axis=2))[self.new]
                .sum(axis=(1, 2))
                .max()
            )
            if self.new.size
            else 0,
            1,
        )
        k = int(fit.best)
        dof = max(fit.n - (2 if fit.shares[k] > 0 else 1), 1)
        half = stats.t.isf(self.alpha / (2 * n_tests), dof) * math.sqrt(
            fit.scales[k] * (1 + 1 / fit.sum_w[k])
        )
        return float(fit.means[k]), float(fit.means[k] - half), float(fit.means[k] + half)

    @property
    def event_alarms(self) -> list:
        """The modes that vanished or appeared beyond chance."""
        return [e for e in self.mode_events if e.significant]

    def events(self) -> list[str]:
        """Modes that new surveys missed or that appeared in them, one line each (significant first)."""
        return [e.text(self) for e in sorted(self.mode_events, key=lambda e: not e.significant)]

    def notes(self) -> list[str]:
        """What limits the tests, once per mode and kind: a survey that failed, a mode not tested, a ± the fit
        did not give (the reference scatter then carries the uncertainty)."""
        from .export import row_note

        notes = {}
        for j in range(len(self.tracks)):
            for s in range(len(self.values)):
                note = row_note(self, s, j)
                if note and "not found" not in note:
                    notes.setdefault((j, note), []).append(self.labels[s])
        failed = [f"{v.label}: its survey failed ({v.failed}); it counts as a survey without modes"
                  for v in self.values if v.failed]
        return failed + [
            f"{self.tracks[j].label(j)}: {note} ({len(who)} survey(s), e.g. {who[0]})"
            for (j, note), who in notes.items()
        ]

    def lines(self) -> list[str]:
        """The report as lines: one per alarm, per significant trend, per event."""
        return [a.text(self) for a in self.alarms] + [t.text(self) for t in self.trend_alarms] + self.events()

    def __repr__(self) -> str:
        n_new = len(self.new)
        head = (
            f"TrackResult({len(self.values)} surveys: {len(self.reference)} reference, {n_new} new; "
            f"{len(self.tracks)} mode(s); {int(self.changed.sum())} of {n_new} new surveys changed at the "
            f"{100 * self.alpha:g} % false-alarm rate; {len(self.trend_alarms)} trend(s); "
            f"{len(self.event_alarms)} mode(s) vanished or appeared)"
        )
        lines = self.lines()
        return "\n".join([head] + ["  " + ln for ln in lines[:20]] + (["  ..."] if len(lines) > 20 else []))

    def to_frame(self):
        """One row per survey and mode (pandas; see :mod:`.export`)."""
        from .export import track_frame

        return track_frame(self)

    def to_dict(self) -> dict:
        """The result as JSON-ready data (see :mod:`.export`)."""
        from .export import track_dict

        return track_dict(self)

    def plot(self, quantities=("frequency_hz", "damping_ratio"), modes=None, axes=None):
        """Control charts (:func:`sindy_impulse.plotting.plot_tracking`)."""
        from ..plotting import plot_tracking

        return plot_tracking(self, quantities=quantities, modes=modes, axes=axes)

    def to_html(self, path=None, *, overwrite: bool = False, source: str | None = None) -> str:
        """The result as one self-contained HTML page (:func:`sindy_impulse.report.track_html`)."""
        from ..report import track_html, write_html

        page = track_html(self, source=source)
        if path is not None:
            write_html(path, page, overwrite=overwrite)
        return page

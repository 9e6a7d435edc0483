"""The survey's vocabulary: what a candidate is (:class:`Kind`) and why a row is rejected (:class:`Reason`).

Decisions are taken on these codes, never on message text; each code carries its words for people.
"""

from __future__ import annotations

from enum import Enum

__all__ = ["Kind", "Reason"]


class Kind(str, Enum):
    """What a candidate of the free decay is, from the cheap evidence of :mod:`.classify`.

    Examples
    --------
    >>> Kind.LINEAR.words
    'a linear mode: its poles give its equation'
    >>> Kind("nonlinear") is Kind.NONLINEAR
    True
    """

    LINEAR = "linear"
    NONLINEAR = "nonlinear"
    MERGED = "merged"
    HARMONIC = "harmonic"
    PRODUCT = "product"
    CLIPPING = "clipping"
    TONE = "tone"
    UNSUPPORTED = "unsupported"

    @property
    def words(self) -> str:
        return _KIND_WORDS[self]


_KIND_WORDS = {
    Kind.LINEAR: "a linear mode: its poles give its equation",
    Kind.NONLINEAR: "a mode the linear decay does not explain: the paper's sweep and refinement fit it",
    Kind.MERGED: "a piece of a nonlinear mode fitted with it",
    Kind.HARMONIC: "a harmonic of a lower, nonlinear mode, not a mode",
    Kind.PRODUCT: "an intermodulation product of two modes through a nonlinear element, not a mode",
    Kind.CLIPPING: "a product of the clipping of stronger modes (harmonic, intermodulation), not a mode",
    Kind.TONE: "a tone that does not decay (hum, a rotating machine), not a mode",
    Kind.UNSUPPORTED: "does not decay, and neither a stable pole nor a sinusoid describes it: not a mode",
}


class Reason(str, Enum):
    """Why a candidate or band gave no mode (:attr:`~sindy_impulse.modes.result.Rejected.code`).

    Examples
    --------
    >>> Reason.TONE.words
    'a tone that does not decay, not a mode'
    """

    TONE = "tone"
    HARMONIC = "harmonic"
    INTERMODULATION = "intermodulation"
    CLIPPING_PRODUCT = "clipping_product"
    POOR_FIT = "poor_fit"
    UNSTABLE = "unstable"
    TOO_SHORT = "too_short"
    FIT_FAILED = "fit_failed"
    NO_SIGNAL = "no_signal"
    UNSUPPORTED = "unsupported"
    DUPLICATE = "duplicate"

    @property
    def words(self) -> str:
        return _REASON_WORDS[self]


_REASON_WORDS = {
    Reason.TONE: "a tone that does not decay, not a mode",
    Reason.HARMONIC: "a harmonic of a lower mode, not a mode",
    Reason.INTERMODULATION: "an intermodulation product of two modes, not a mode",
    Reason.CLIPPING_PRODUCT: "a product of the sensor's clipping, not a mode",
    Reason.POOR_FIT: "no model reproduces the band",
    Reason.UNSTABLE: "the identified model's mode is not damped",
    Reason.TOO_SHORT: "too few periods of the mode are left to identify it",
    Reason.FIT_FAILED: "the identification failed",
    Reason.NO_SIGNAL: "no ring-down above the noise",
    Reason.UNSUPPORTED: "does not decay, and neither a stable pole nor a sinusoid describes it: not a mode",
    Reason.DUPLICATE: "the same mode, found again from another component's band",
}

"""Many tests of one structure: which mode, and which term of its equation, changed beyond its
uncertainty (:func:`track`).

=====================  ==========================================================================
module                 its job
=====================  ==========================================================================
:mod:`.values`         a survey's modes as the tracker reads them: linear values, ±, amplitude,
                       shape, the equation in the engineer's form (JSON round trip)
:mod:`.averaging`      a mode's backbone at one amplitude from its equation (first-order
                       averaging), and what one coefficient's change does to it
:mod:`.matching`       the same mode across surveys (frequency, MAC; nothing forced)
:mod:`.statistics`     a new value against the reference (prediction interval with the reference's
                       scatter estimated), Holm over a survey's tests, the Mann-Kendall trend
:mod:`.terms`          which coefficient of a changed mode's equation carries the change
:mod:`.track`          ``track``: the steps in order
:mod:`.result`         ``TrackResult``, ``Alarm``, ``Trend``
:mod:`.export`         the result as a table (pandas) and as JSON-ready data
=====================  ==========================================================================
"""

from .result import QUANTITIES, Alarm, TrackResult, Trend
from .track import track
from .values import ModeValues, SurveyValues, survey_values

__all__ = [
    "QUANTITIES",
    "Alarm",
    "ModeValues",
    "SurveyValues",
    "TrackResult",
    "Trend",
    "survey_values",
    "track",
]

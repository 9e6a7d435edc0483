"""Reports of a modal survey: one self-contained HTML page (:func:`survey_html`; ``survey.to_html``); of
many tests of one structure (:func:`track_html`; ``result.to_html``).

=========================  ===================================================================
module                     its job
=========================  ===================================================================
:mod:`.html`               the page: sections, tables, escaped text, the file written
:mod:`.figures`            the figures (from :mod:`sindy_impulse.plotting`) as inline PNG images
:mod:`.text`               values with uncertainties, verdicts and diagnostics in plain words
:mod:`.tracking`           many tests of one structure (``track``): alarms, terms, trends, control charts
=========================  ===================================================================
"""

from .html import survey_html, write_html
from .tracking import track_html, tracking_section

__all__ = ["survey_html", "track_html", "tracking_section", "write_html"]

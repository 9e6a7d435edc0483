"""Reports of a modal survey: one self-contained HTML page (:func:`survey_html`; ``survey.to_html``).

=========================  ===================================================================
module                     its job
=========================  ===================================================================
:mod:`.html`               the page: sections, tables, escaped text, the file written
:mod:`.figures`            the figures (from :mod:`sindy_impulse.plotting`) as inline PNG images
:mod:`.text`               values with uncertainties, verdicts and diagnostics in plain words
=========================  ===================================================================
"""

from .html import survey_html, write_html

__all__ = ["survey_html", "write_html"]

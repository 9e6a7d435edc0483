"""Take the two screenshots the README links: the site's front page and an HTML report of a hammer test.

    python docs/make_screenshots.py          # after building the site into docs/_build/html

The report is the README's hammer test (``impact_record`` of three modes at 45 dB) written by
``survey.to_html``; both pages go through the browser check's Chromium run (``docs/browser_check.py``),
which fails on any console or resource error. Writes ``docs/screenshot-site.png`` and
``docs/screenshot-report.png``.
"""

from __future__ import annotations

import sys
import tempfile
import warnings
from pathlib import Path

from browser_check import check_page, chromium

DOCS = Path(__file__).resolve().parent


def write_report(folder: Path) -> Path:
    from sindy_impulse import identify_modes, impact_record

    record = impact_record([118.0, 243.0, 402.0], [0.002, 0.004, 0.008], fs=5000.0, duration=1.0,
                           offset=2.0, snr_db=45, random_state=7)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        survey = identify_modes(record.y, fs=record.fs, force=record.force)
        survey.to_html(folder / "report.html", source="the README's hammer test (impact_record, 45 dB)")
    return folder / "report.html"


def main() -> int:
    browser = chromium()
    if browser is None:
        print("no Chromium found; on Debian: apt-get install -y chromium", file=sys.stderr)
        return 2
    problems = check_page(browser, DOCS / "_build" / "html" / "index.html", DOCS / "screenshot-site.png")
    with tempfile.TemporaryDirectory() as folder:
        report = write_report(Path(folder))
        problems += check_page(browser, report, DOCS / "screenshot-report.png", size="1100,2200")
    for problem in problems:
        print(problem, file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())

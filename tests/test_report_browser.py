"""The HTML report in a real browser: headless Chromium renders it, saves a screenshot, and its own log and
the page's DOM after loading say whether the page loaded without errors (no script error, every image
decoded). Skipped where Chromium is missing, except in CI (``CI`` set), where that is a failure."""

import os
import re
import shutil
import subprocess
import warnings

import pytest

from sindy_impulse import identify_modes, impact_record
from sindy_impulse.report.html import _MARKER as MARKER  # the report's own load marker

BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
#: Lines of Chromium's log that mean the page itself failed (its console, its resources).
PAGE_ERRORS = re.compile(r"CONSOLE.*(Uncaught|Error)|Failed to load resource|net::ERR_|Not allowed to load")


@pytest.fixture(scope="module")
def chromium():
    found = next((path for path in map(shutil.which, BROWSERS) if path), None)
    if found is None:
        message = f"no Chromium found ({', '.join(BROWSERS)}); on Debian: apt-get install -y chromium"
        if os.environ.get("CI"):
            pytest.fail(f"{message} (CI is set: .ci/run installs it)")
        pytest.skip(message)
    return found


def _run(chromium, tmp_path, page, *args) -> subprocess.CompletedProcess:
    command = [
        chromium, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-extensions",
        f"--user-data-dir={tmp_path / 'profile'}", "--enable-logging=stderr", "--v=0",
        "--virtual-time-budget=5000", *args, page.as_uri(),
    ]
    proc = subprocess.run(command, capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return proc


def _page_errors(log: str) -> list[str]:
    return [line for line in log.splitlines() if PAGE_ERRORS.search(line)]


def test_report_renders_without_errors(chromium, tmp_path):
    rec = impact_record([150.0, 320.0], [0.01, 0.01], fs=2000.0, duration=0.8, snr_db=50, random_state=2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        survey = identify_modes(rec.y, fs=rec.fs)
    page = tmp_path / "report.html"
    html = survey.to_html(page, source="synthetic hammer test", nonlinearity=False)
    n_images = html.count("<img ")
    shot = tmp_path / "report.png"
    size = "--window-size=1000,2400"
    proc = _run(chromium, tmp_path, page, "--hide-scrollbars", size, f"--screenshot={shot}")
    assert shot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and shot.stat().st_size > 20_000
    assert _page_errors(proc.stderr) == []
    dom = _run(chromium, tmp_path, page, "--dump-dom")
    body = re.search(r"<body[^>]*>", dom.stdout).group(0)
    assert 'data-loaded="yes"' in body, body  # the page's load handler ran
    assert f'data-images="{n_images}/{n_images}"' in body and n_images >= 4, body
    assert "data-error" not in body and _page_errors(dom.stderr) == []


def test_the_checks_see_a_broken_page(chromium, tmp_path):
    """The same checks on a page with the report's marker, a script error and a missing image."""
    page = tmp_path / "broken.html"
    page.write_text(
        f"<!DOCTYPE html><html><head><meta charset='utf-8'></head><body><script>{MARKER}</script>"
        "<img src='missing.png' alt=''><script>nothing();</script></body></html>"
    )
    proc = _run(chromium, tmp_path, page, "--dump-dom")
    body = re.search(r"<body[^>]*>", proc.stdout).group(0)
    assert "data-error" in body and 'data-images="0/1"' in body, body
    assert any("nothing is not defined" in line for line in _page_errors(proc.stderr)), proc.stderr[-2000:]

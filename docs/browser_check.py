"""Load pages of the built site in headless Chromium and fail on any console or resource error.

    python docs/browser_check.py docs/_build/html                  # the front page and a gallery page
    python docs/browser_check.py docs/_build/html --self-test      # first show that a broken page fails
    python docs/browser_check.py docs/_build/html --screenshot docs/screenshot-site.png
    python docs/browser_check.py FOLDER --pages report.html --screenshot docs/screenshot-report.png \
        --window-size 1100,2200                                    # a report written by survey.to_html

For each page: Chromium (Debian's ``chromium``) renders it from disk with a fresh profile and no network
features, its log is searched for the page's console errors and failed resources, the rendered DOM must
hold the page's main content, and every image the page names must exist next to it. ``--self-test`` runs
the same checks on a page with a script error and a missing image and stops with an error unless both are
caught. Exit status 0 when every page is clean, 1 otherwise (each problem printed), 2 when Chromium is
missing.
"""

from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys
import tempfile
from html.parser import HTMLParser
from pathlib import Path

BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
FLAGS = (
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
    "--disable-extensions", "--enable-logging=stderr", "--v=0", "--virtual-time-budget=5000",
)
#: Lines of Chromium's log that mean the page itself failed (its console, its resources).
PAGE_ERRORS = re.compile(r"CONSOLE.*(Uncaught|Error)|Failed to load resource|net::ERR_|Not allowed to load")
#: The pages CI checks: the front page and one gallery page (with figures).
PAGES = ("index.html", "auto_examples/plot_hammer_test.html")


class _Sources(HTMLParser):
    """The local files a page loads: images, scripts, style sheets."""

    def __init__(self):
        super().__init__()
        self.found: list[str] = []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        link = {"img": a.get("src"), "script": a.get("src")}.get(tag)
        if tag == "link" and a.get("rel") == "stylesheet":
            link = a.get("href")
        if link and not re.match(r"^[a-z]+:", link):
            self.found.append(link.split("#")[0].split("?")[0])


def chromium() -> str | None:
    return next((path for path in map(shutil.which, BROWSERS) if path), None)


def _run(browser: str, page: Path, profile: Path, *extra: str) -> subprocess.CompletedProcess:
    command = [browser, *FLAGS, f"--user-data-dir={profile}", *extra, page.resolve().as_uri()]
    return subprocess.run(command, capture_output=True, text=True, timeout=120)


def check_page(browser: str, page: Path, screenshot: Path | None = None, size: str = "1280,900") -> list[str]:
    """The problems of one page (an empty list when it is clean)."""
    if not page.is_file():
        return [f"{page}: no such page (was the site built?)"]
    problems = []
    parser = _Sources()
    parser.feed(page.read_text(encoding="utf-8"))
    missing = [src for src in parser.found if not (page.parent / src).exists()]
    problems += [f"{page}: names {src}, which is missing" for src in missing]
    with tempfile.TemporaryDirectory() as profile:
        dom = _run(browser, page, Path(profile), "--dump-dom")
    if dom.returncode != 0:
        return problems + [f"{page}: Chromium exited with {dom.returncode}: {dom.stderr[-500:]}"]
    problems += [f"{page}: {line.strip()}" for line in dom.stderr.splitlines() if PAGE_ERRORS.search(line)]
    if not re.search(r"<(main|article|h1)\b", dom.stdout) or "</html>" not in dom.stdout:
        problems.append(f"{page}: the rendered page has no main content")
    if screenshot is not None:
        with tempfile.TemporaryDirectory() as profile:
            shot = _run(browser, page, Path(profile), "--hide-scrollbars", f"--window-size={size}",
                        f"--screenshot={screenshot.resolve()}")
        if shot.returncode != 0 or not screenshot.is_file():
            problems.append(f"{page}: no screenshot ({shot.stderr[-300:]})")
    return problems


def self_test(browser: str) -> list[str]:
    """The checks must catch a script error and a missing image; the problems they missed."""
    with tempfile.TemporaryDirectory() as folder:
        page = Path(folder) / "broken.html"
        page.write_text("<!DOCTYPE html><html><body><main><img src='missing.png' alt=''>"
                        "<script>nothing();</script></main></body></html>")
        found = "\n".join(check_page(browser, page))
    missed = []
    if "nothing is not defined" not in found:
        missed.append("self-test: a script error was not caught")
    if "missing.png" not in found:
        missed.append("self-test: a missing image was not caught")
    return missed


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("site", type=Path, help="the built site (docs/_build/html)")
    parser.add_argument("--pages", nargs="+", default=list(PAGES), help="pages to check, relative to SITE")
    parser.add_argument("--self-test", action="store_true", help="first check that a broken page fails")
    parser.add_argument("--screenshot", type=Path, help="save a PNG of the first page here")
    parser.add_argument("--window-size", default="1280,900", help="the screenshot's WIDTH,HEIGHT in pixels")
    args = parser.parse_args(argv)
    browser = chromium()
    if browser is None:
        names = ", ".join(BROWSERS)
        print(f"no Chromium found ({names}); on Debian: apt-get install -y chromium", file=sys.stderr)
        return 2
    problems = self_test(browser) if args.self_test else []
    for i, name in enumerate(args.pages):
        shot = args.screenshot if i == 0 else None
        problems += check_page(browser, args.site / name, shot, args.window_size)
    for problem in problems:
        print(problem, file=sys.stderr)
    if not problems:
        print(f"{len(args.pages)} page(s) loaded without console or resource errors: {', '.join(args.pages)}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())

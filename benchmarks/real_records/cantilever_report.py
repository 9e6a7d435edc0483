"""A real record in an analyser format, read directly by the command line, with its HTML report and a
browser screenshot of it (``docs/report-cantilever.html``, ``docs/report-cantilever.png``).

The record: a steel cantilever beam (759 x 50.66 x 5.14 mm) tapped once, one PCB 352C33 accelerometer near
the tip (g), NI-9234, LabVIEW ``.lvm`` text, 81,920 samples at 51,200 / 31 = 1651.6 Hz (49.6 s, the decay
reaches the noise after 10-20 s). University of South Carolina (Downey lab), repository
``PujaChowdhury/Dataset-4-Univariate-signal-with-non-stationarity``, file
``modal_analysis/data/timeseries_data.lvm`` of commit 42c970f7e931e879f9179475b758267d9c12b538; licence
CC BY-SA 4.0 (its ``LICENSE.txt``). Not shipped (1.6 MB, share-alike); fetch it first::

    curl -L -o timeseries_data.lvm https://github.com/PujaChowdhury/Dataset-4-Univariate-signal-with-non-stationarity/raw/42c970f7e931e879f9179475b758267d9c12b538/modal_analysis/data/timeseries_data.lvm
    python -m benchmarks cantilever_report timeseries_data.lvm            # report + screenshot in docs/

It runs ``sindy-impulse modes timeseries_data.lvm --report docs/report-cantilever.html`` (the command a
user types, with ``--json`` to a temporary file for the table below, and ``--overwrite`` to replace the
report of an earlier run), prints the modal table beside the
frequencies the source publishes (6.62, 41.4, 117.5 Hz; an older README says 6.64 / 41.34 / 117.5), and
saves a screenshot of the report with headless Chromium (``--no-screenshot`` skips it).
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

DOCS = Path(__file__).resolve().parents[2] / "docs"
#: The frequencies the record's source publishes (its README), Hz.
SOURCE_HZ = (6.62, 41.4, 117.5)


def run_cli(record: Path, report: Path, table: Path) -> float:
    """The command line on the record; its wall time (s)."""
    command = [sys.executable, "-m", "sindy_impulse.cli", "modes", record.name, "--report", str(report),
               "--json", str(table), "--overwrite"]  # a rerun replaces the report in docs/
    print("$ sindy-impulse modes", record.name, "--report", report.relative_to(DOCS.parent))
    start = time.perf_counter()
    subprocess.run(command, check=True, cwd=record.resolve().parent)  # the source named as typed
    return time.perf_counter() - start


def print_table(table: Path) -> list:
    modes = json.loads(table.read_text())["modes"]
    print("\n  f_n [Hz]   damping ratio   nonlinear   nearest published [Hz]   difference")
    for m in modes:
        near = min(SOURCE_HZ, key=lambda f: abs(f - m["frequency_hz"]))
        diff = m["frequency_hz"] / near - 1
        shown = f"{near:<24g} {100 * diff:+.2f} %" if abs(diff) < 0.05 else "-"
        nonlinear = str(m.get("nonlinear"))
        print(f"  {m['frequency_hz']:<10.5g} {m['damping_ratio']:<15.4g} {nonlinear:<11} {shown}")
    return [{"frequency_hz": m["frequency_hz"], "damping_ratio": m["damping_ratio"],
             "nonlinear": m.get("nonlinear")} for m in modes]


def screenshot(report: Path, png: Path, height: int) -> None:
    """The top of the report as the browser shows it, 1000 px wide (palette PNG, to stay small)."""
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if browser is None:
        raise SystemExit("no chromium on PATH (Debian: apt-get install -y chromium); or pass --no-screenshot")
    with tempfile.TemporaryDirectory() as profile:
        subprocess.run(
            [browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", "--no-first-run",
             f"--user-data-dir={profile}", f"--window-size=1000,{height}", f"--screenshot={png}",
             report.resolve().as_uri()],
            check=True, capture_output=True, timeout=120,
        )
    from PIL import Image

    image = Image.open(png).convert("RGB").quantize(colors=256, method=Image.Quantize.MAXCOVERAGE)
    image.save(png, optimize=True)
    print(f"screenshot: {png.relative_to(DOCS.parent)} ({png.stat().st_size / 1e3:.0f} kB)")


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("record", type=Path, help="timeseries_data.lvm, fetched as the docstring says")
    parser.add_argument("--name", default="report-cantilever", help="base name of the files in docs/")
    parser.add_argument("--height", type=int, default=2600, help="screenshot height in pixels")
    parser.add_argument("--no-screenshot", action="store_true")
    args = parser.parse_args(argv)
    report = DOCS / f"{args.name}.html"
    with tempfile.TemporaryDirectory() as folder:
        table = Path(folder) / "modes.json"
        seconds = run_cli(args.record, report, table)
        size = report.stat().st_size / 1e6
        print(f"\nreport: {report.relative_to(DOCS.parent)} ({size:.2f} MB), {seconds:.0f} s")
        modes = print_table(table)
    if not args.no_screenshot:
        screenshot(report, DOCS / f"{args.name}.png", args.height)
    return {"report": str(report.relative_to(DOCS.parent)), "seconds": seconds, "modes": modes,
            "published_hz": SOURCE_HZ}


if __name__ == "__main__":
    main()

"""Run PySINDy 2.1.0's own tests against plain PySINDy and against ImpulseSINDy as a drop-in.

The to-do list of the drop-in work: PySINDy's test files ``test_pysindy.py``, ``test_sindyc.py``,
``test_feature_library.py``, ``test_scikit_time.py`` and ``test_differentiation.py`` run twice,

1. as they are (``pysindy.SINDy``), and
2. with ``pysindy.SINDy`` (and ``pysindy._core.SINDy``) replaced, before the test modules import it, by
   :class:`sindy_impulse.ImpulseSINDy` configured as plain PySINDy: ``optimizer=STLSQ()``,
   ``feature_library=PolynomialLibrary(degree=2)``, ``differentiation_method=FiniteDifference(axis=-2)``
   when a test gives none (PySINDy's defaults), ``sweep=False`` and ``refine=False`` (plain mode: the
   given optimizer, library and differentiation are fitted in place, nothing is simulated),

and the script prints the counts side by side and the failures of the ImpulseSINDy run grouped by cause
(the first line of the error). ``benchmarks/pysindy_suite/tvregdiff_tests.py`` (PySINDy's differentiation
tests asked of TVRegDiff) runs along in both.

No PySINDy code is part of this project: the test files are copied from a PySINDy checkout into a
temporary directory, where two imports are patched (``pytest.lazy_fixture`` becomes
``pytest_lazy_fixtures.lf``, for pytest 8; the ``jax`` import of the conftest becomes optional). Setup, in
a virtual environment of its own::

    git clone --branch v2.1.0 https://github.com/dynamicslab/pysindy /tmp/pysindy
    python -m venv /work/venv-suite
    /work/venv-suite/bin/pip install -e ".[suite]" pytest
    /work/venv-suite/bin/python -m benchmarks pysindy_suite --pysindy-repo /tmp/pysindy

``--pysindy-repo`` may also be a bare git directory (the tests are then read from ``--ref``, default
``v2.1.0``, with ``git archive``).
"""

from __future__ import annotations

import argparse
import collections
import io
import re
import shutil
import subprocess
import sys
import tarfile
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

TEST_FILES = [
    "test_pysindy.py",
    "test_sindyc.py",
    "test_feature_library.py",
    "test_scikit_time.py",
    "test_differentiation.py",
]
TVREGDIFF_TESTS = Path(__file__).with_name("tvregdiff_tests.py")
TVREGDIFF_COPY = "test_differentiation_tvregdiff.py"

#: Written next to the copied test directory for the ImpulseSINDy run (conftest files of parent
#: directories load first, so the swap happens before PySINDy's conftest and the test modules import SINDy).
SWAP_CONFTEST = '''"""Written by python -m benchmarks pysindy_suite: SINDy becomes a plain ImpulseSINDy."""
import inspect

import pysindy
import pysindy._core
from pysindy.differentiation import FiniteDifference
from pysindy.feature_library import PolynomialLibrary
from pysindy.optimizers import STLSQ

from sindy_impulse import ImpulseSINDy

PLAIN = {"sweep": False, "refine": False}
_SIGNATURE = inspect.signature(ImpulseSINDy.__init__)


class ImpulseSINDy(ImpulseSINDy):  # noqa: F811 - the name tests and reprs show
    def __init__(self, optimizer=None, feature_library=None, differentiation_method=None, **kwargs):
        # PySINDy builds its defaults in __init__ (STLSQ, PolynomialLibrary(degree=2), FiniteDifference)
        super().__init__(
            STLSQ() if optimizer is None else optimizer,
            PolynomialLibrary(degree=2) if feature_library is None else feature_library,
            FiniteDifference(axis=-2) if differentiation_method is None else differentiation_method,
            **{**PLAIN, **kwargs},
        )


# The full signature with the plain defaults, so that get_params/clone keep the configuration.
ImpulseSINDy.__init__.__signature__ = _SIGNATURE.replace(
    parameters=[
        p.replace(default=PLAIN[p.name]) if p.name in PLAIN else p for p in _SIGNATURE.parameters.values()
    ]
)
pysindy.SINDy = ImpulseSINDy
pysindy._core.SINDy = ImpulseSINDy
'''


def _copy_tests(repo: Path, ref: str, dest: Path) -> None:
    """PySINDy's test/ directory into ``dest`` (from a work tree, or ``git archive`` of a bare repo)."""
    if (repo / "test").is_dir():
        shutil.copytree(repo / "test", dest / "test")
        return
    archive = subprocess.run(
        ["git", "--git-dir", str(repo), "archive", ref, "test"], capture_output=True, check=True
    ).stdout
    with tarfile.open(fileobj=io.BytesIO(archive)) as tar:
        tar.extractall(dest, filter="data")


def _patch(test_dir: Path) -> list[str]:
    """Make the copies run with pytest 8 and without jax; returns what was changed."""
    changes = []
    conftest = test_dir / "conftest.py"
    text = conftest.read_text()
    if "\nimport jax\n" in text:
        text = text.replace("\nimport jax\n", "\ntry:\n    import jax\nexcept ImportError:\n    jax = None\n")
        text = text.replace("\njax.config.update(", "\nif jax is not None:\n    jax.config.update(")
        conftest.write_text(text)
        changes.append("conftest.py: jax import optional")
    for path in sorted(test_dir.glob("test_*.py")):
        text = path.read_text()
        if "pytest.lazy_fixture(" in text:
            text = text.replace("pytest.lazy_fixture(", "lf(")
            lf = "import pytest\nfrom pytest_lazy_fixtures import lf"
            text = re.sub(r"^import pytest$", lf, text, count=1, flags=re.M)
            path.write_text(text)
            changes.append(f"{path.name}: pytest.lazy_fixture -> pytest_lazy_fixtures.lf")
    return changes


def _run(python: str, root: Path, files: list[str], label: str, timeout: float) -> Path:
    report = root / f"report-{label}.xml"
    cmd = [python, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-o", "addopts=", f"--junitxml={report}"]
    cmd += [f"test/{f}" for f in files]
    print(f"[{label}] {' '.join(cmd[2:])}", flush=True)
    try:
        done = subprocess.run(cmd, cwd=root, capture_output=True, text=True, timeout=timeout)
        tail = done.stdout.strip().splitlines()[-1:] if done.stdout.strip() else ["(no output)"]
        print(f"[{label}] exit {done.returncode}: {tail[0]}", flush=True)
        if done.returncode not in (0, 1):
            print(done.stdout[-3000:], done.stderr[-3000:], sep="\n")
    except subprocess.TimeoutExpired:
        print(f"[{label}] timed out after {timeout:.0f} s", flush=True)
    return report


def _outcomes(report: Path) -> dict[str, tuple[str, str]]:
    """test id -> (outcome, first line of the error) from a junit report."""
    out = {}
    if not report.exists():
        return out
    for case in ET.parse(report).getroot().iter("testcase"):
        module = Path(case.get("file") or case.get("classname", "").replace(".", "/")).stem
        name = f"{module}::{case.get('name')}"
        outcome, cause = "passed", ""
        for child in case:
            if child.tag in ("failure", "error"):
                outcome = "failed" if child.tag == "failure" else "error"
                message = (child.get("message") or child.text or "").strip()
                cause = message.splitlines()[0] if message else child.tag
            elif child.tag == "skipped":
                outcome = "xfailed" if child.get("type") == "pytest.xfail" else "skipped"
        out[name] = (outcome, cause)
    return out


def _counts(outcomes: dict, module: str) -> collections.Counter:
    return collections.Counter(o for name, (o, _) in outcomes.items() if name.split("::")[0] == module)


def _print_summary(plain: dict, impulse: dict, modules: list[str]) -> dict:
    kinds = ["passed", "failed", "error", "skipped", "xfailed"]
    head = " ".join(f"{k[:6]:>6}" for k in kinds)
    print(f"\n{'test file':34} | pysindy.SINDy: {head} | ImpulseSINDy: {head}")
    totals = [collections.Counter(), collections.Counter()]
    for module in modules:
        a, b = _counts(plain, module), _counts(impulse, module)
        totals[0].update(a)
        totals[1].update(b)
        row_a = " ".join(f"{a[k]:6d}" for k in kinds)
        row_b = " ".join(f"{b[k]:6d}" for k in kinds)
        print(f"{module:34} | {'':15}{row_a} | {'':14}{row_b}")
    row_a = " ".join(f"{totals[0][k]:6d}" for k in kinds)
    row_b = " ".join(f"{totals[1][k]:6d}" for k in kinds)
    print(f"{'total':34} | {'':15}{row_a} | {'':14}{row_b}")
    return {"pysindy.SINDy": dict(totals[0]), "ImpulseSINDy": dict(totals[1])}


def _print_causes(plain: dict, impulse: dict) -> None:
    """Failures of the ImpulseSINDy run that pass with pysindy.SINDy, grouped by the error's first line."""
    groups = collections.defaultdict(list)
    for name, (outcome, cause) in impulse.items():
        if outcome in ("failed", "error") and plain.get(name, ("",))[0] == "passed":
            groups[re.sub(r"0x[0-9a-f]+", "0x..", cause)[:160]].append(name)
    also = sum(
        1 for n, (o, _) in impulse.items() if o in ("failed", "error") and plain.get(n, ("",))[0] != "passed"
    )
    print(f"\nImpulseSINDy failures of tests that pass with pysindy.SINDy, by cause ({len(groups)} causes):")
    for cause, names in sorted(groups.items(), key=lambda kv: -len(kv[1])):
        print(f"\n{len(names):4d}  {cause}")
        for name in sorted(names)[:6]:
            print(f"        {name}")
        if len(names) > 6:
            print(f"        ... and {len(names) - 6} more")
    refused = sum(len(names) for cause, names in groups.items() if "UnsupportedProblemError" in cause)
    print(f"\n({also} further failures also fail with pysindy.SINDy)")
    print(
        f"{refused} of the failures are UnsupportedProblemError (a NotImplementedError): PDE, weak-form, "
        "implicit (SINDy-PI) or spatiotemporal problems, refused by design; "
        f"{sum(map(len, groups.values())) - refused} other failures"
    )


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pysindy-repo", required=True, type=Path, help="PySINDy checkout at tag v2.1.0")
    parser.add_argument("--ref", default="v2.1.0", help="tag read from a bare git directory")
    parser.add_argument("--python", default=sys.executable, help="interpreter with pytest, cvxpy, ...")
    parser.add_argument("--files", nargs="+", default=TEST_FILES, help="PySINDy test files to run")
    parser.add_argument("--timeout", type=float, default=3600.0, help="seconds per run")
    parser.add_argument("--keep", action="store_true", help="keep the temporary directory")
    args = parser.parse_args(argv)

    tmp = Path(tempfile.mkdtemp(prefix="pysindy-suite-"))
    try:
        plain_root, impulse_root = tmp / "plain", tmp / "impulse"
        for root in (plain_root, impulse_root):
            root.mkdir()
            _copy_tests(args.pysindy_repo, args.ref, root)
            changes = _patch(root / "test")
            shutil.copy(TVREGDIFF_TESTS, root / "test" / TVREGDIFF_COPY)
        print("patched copies:", "; ".join(changes) or "nothing")
        (impulse_root / "conftest.py").write_text(SWAP_CONFTEST)
        files = list(args.files) + [TVREGDIFF_COPY]
        plain = _outcomes(_run(args.python, plain_root, files, "pysindy.SINDy", args.timeout))
        impulse = _outcomes(_run(args.python, impulse_root, files, "ImpulseSINDy", args.timeout))
        totals = _print_summary(plain, impulse, [Path(f).stem for f in files])
        _print_causes(plain, impulse)
        if args.keep:
            print(f"\nkept {tmp}")
    finally:
        if not args.keep:
            shutil.rmtree(tmp, ignore_errors=True)
    failed = sorted(name for name, (outcome, _) in impulse.items() if outcome in ("failed", "error"))
    return {"totals": totals, "impulse_failures": failed}


if __name__ == "__main__":
    main()

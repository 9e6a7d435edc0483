"""Cold start: the first fit of the paper's case in a fresh process right after installing the package.

An installation is emulated by copying the package (without any ``__pycache__``) into a fresh directory,
with a fresh user cache directory (``XDG_CACHE_HOME``) and no ``NUMBA_CACHE_DIR``: nothing compiled
exists. Each process times ``import sindy_impulse``, then the import of the estimator (PySINDy,
scikit-learn, numba), then the first and the second ``ImpulseSINDy().fit`` of the paper's oscillator.
A third new process times the bare import of the same dependencies (every module outside the package that
the first process had imported), and ``beyond_dependencies`` is issue 36's measure: the first process's
imports and first fit minus that bare import (the package's own cost on a new machine, compilation and
the background build's competition for the cores included).

Variants: ``pip install`` (a wheel built by ``pip wheel`` from a copy of the project as a fresh clone holds
it, and installed by ``pip``: the package as ``pip install .`` ships it, its kernels compiled into it at the
build), ``warm-up`` (the package copied without a compiled kernel: the first import builds them in the
background), ``no warm-up`` (``SINDY_IMPULSE_PRECOMPILE=0``: each kernel compiled at its first call, the
baseline), ``read-only package`` (numba cannot write next to the package and caches in the user's
directory), and a second process after the first (the cache is there).
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

CHILD = r"""
import json, time
t0 = time.perf_counter()
import sindy_impulse
t1 = time.perf_counter()
from sindy_impulse import ImpulseSINDy, damped_oscillator
t2 = time.perf_counter()
t, x, _ = damped_oscillator()
t3 = time.perf_counter()
ImpulseSINDy().fit(x, t=t)
t4 = time.perf_counter()
ImpulseSINDy().fit(x, t=t)
t5 = time.perf_counter()
import sys
modules = [m for m in sys.modules if m.split(".")[0] != "sindy_impulse" and m != "__main__"]
print(json.dumps({"import": t1 - t0, "import_estimator": t2 - t1, "first_fit": t4 - t3,
                  "second_fit": t5 - t4, "modules": modules}))
"""

DEPENDENCIES = r"""
import importlib, json, sys, time
modules = json.loads(sys.stdin.read())
t0 = time.perf_counter()
for name in modules:
    try:
        importlib.import_module(name)
    except Exception:  # a module only importable as a side effect of another: its parent imports it
        pass
print(json.dumps({"dependencies": time.perf_counter() - t0}))
"""


#: What a fresh clone holds of the project that a build reads (the rest, and what earlier builds or runs
#: left in the source tree, is not copied).
_PROJECT_FILES = ("pyproject.toml", "README.md")
_NOT_SHIPPED = shutil.ignore_patterns("__pycache__", "*.pyc", "kernels_shipped.json")


def _pip_install(package: Path, target: Path) -> None:
    """Build a wheel of the package's project (``pip wheel``, the build isolated as ``pip install .``
    isolates it) and install it into ``target`` (its dependencies are the running environment's).

    The wheel is built from a copy of the project as a fresh clone has it (its sources, ``pyproject.toml``
    and the README), not from the source tree itself: setuptools builds in the tree's ``build/``
    directory, which earlier builds have filled and which two builds from one tree at a time share."""
    project = target.parent / "project"
    shutil.copytree(package, project / package.name, ignore=_NOT_SHIPPED)
    for name in _PROJECT_FILES:
        shutil.copy2(package.parent / name, project / name)
    wheels = target.parent / "wheel"

    def pip(*args) -> None:
        out = subprocess.run([sys.executable, "-m", "pip", *args], capture_output=True, text=True)
        if out.returncode != 0:
            raise RuntimeError(out.stderr[-2000:])

    pip("wheel", "--no-deps", "-q", "-w", str(wheels), str(project))
    pip("install", "--no-deps", "-q", "--target", str(target), *map(str, wheels.glob("*.whl")))


def _install(package: Path, target: Path, read_only: bool) -> None:
    """Copy the package as an installer would; ``read_only``: no ``__pycache__`` can be created in it."""
    shutil.copytree(package, target / package.name, ignore=shutil.ignore_patterns("__pycache__"))
    if read_only:  # a file where numba would create its cache directory: the in-tree cache is unusable
        for directory in (target / package.name).rglob("*"):
            if directory.is_dir():
                (directory / "__pycache__").write_text("")
        (target / package.name / "__pycache__").write_text("")


def _run(env: dict, cwd: str, code: str = CHILD, stdin: str | None = None) -> dict:
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, cwd=cwd,
                         input=stdin)
    if out.returncode != 0:
        raise RuntimeError(out.stderr[-2000:])
    return json.loads(out.stdout.strip().splitlines()[-1])


def cold_start(package: Path, variant: str = "warm-up") -> dict:
    """Times of a first process after installation, of a second one (``second_process``), and of the bare
    import of the dependencies in a third (``dependencies``, and ``beyond_dependencies``: the first
    process's imports and first fit minus it)."""
    with tempfile.TemporaryDirectory() as tmp:
        site = Path(tmp) / "site"
        site.mkdir()
        if variant == "pip install":
            _pip_install(package, site)
        else:
            _install(package, site, read_only=variant == "read-only package")
        env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CACHE_DIR", "PYTHONPATH")}
        env.update(PYTHONPATH=str(site), XDG_CACHE_HOME=str(Path(tmp) / "cache"), PYTHONDONTWRITEBYTECODE="1")
        if variant == "no warm-up":
            env["SINDY_IMPULSE_PRECOMPILE"] = "0"
        first = _run(env, tmp)
        _wait_for_builds(Path(tmp) / "cache" / "sindy_impulse")
        first["second_process"] = _run(env, tmp)
        first["second_process"].pop("modules")
        modules = first.pop("modules")
        first["dependencies"] = _run(env, tmp, DEPENDENCIES, json.dumps(modules))["dependencies"]
        first["beyond_dependencies"] = (
            first["import"] + first["import_estimator"] + first["first_fit"] - first["dependencies"]
        )
        return first


def _wait_for_builds(directory: Path, timeout: float = 120.0) -> None:
    """Let a background build finish before the next measurement (it would compete for the CPU)."""
    deadline = time.monotonic() + timeout
    while directory.exists() and any(directory.glob("*.lock")) and time.monotonic() < deadline:
        time.sleep(0.05)

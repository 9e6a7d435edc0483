"""Where the compiled kernels' cache lives, and how a kernel waits for a build of it under way.

A leaf: it imports nothing from the package, so the numba decorator (:mod:`.jit`) can wait for a build
without importing the build itself (:mod:`.warmup`, which imports every kernel to compile it).

- :func:`cache_dir`: ``$NUMBA_CACHE_DIR/sindy_impulse`` or the user's cache directory; a build's marker
  files and locks live there, named after :func:`build_key` (the kernel sources, numba, Python);
- :func:`paths`: the marker of a group's finished build and the lock of its build under way;
- :func:`wait`: before a kernel's first call, wait for its group's build under way (at most
  :data:`WAIT_SECONDS`), after which numba compiles what is still missing.
"""

from __future__ import annotations

import hashlib
import os
import sys
import time
from pathlib import Path

__all__ = [
    "cache_dir",
    "build_key",
    "base",
    "paths",
    "wait",
    "GROUPS",
    "KERNEL_FILES",
    "WAIT_SECONDS",
    "STALE_SECONDS",
    "CHILD_ENV",
]

#: Sources of the compiled kernels (relative to the package): a change in any of them means a new build.
KERNEL_FILES = (
    "_utils/jit.py",
    "simulation/integrators.py",
    "simulation/two_state_cubic.py",
    "simulation/sensitivity.py",
    "differentiation/_banded.py",
    "differentiation/_spline.py",
    "differentiation/_smoother.py",
)
#: The kernels in two groups, each built by its own background process (two cores compile at once).
GROUPS = ("differentiation", "simulation")
#: Longest wait of a kernel's first call for a build under way (then it compiles itself).
WAIT_SECONDS = 120.0
#: A lock older than this belongs to a build that died.
STALE_SECONDS = 600.0
#: Set in the environment of a background build: its kernels compile without waiting for themselves.
CHILD_ENV = "SINDY_IMPULSE_WARMUP_CHILD"
_PACKAGE = Path(__file__).resolve().parent.parent


def cache_dir() -> Path:
    """Where the markers and the locks live: ``$NUMBA_CACHE_DIR/sindy_impulse`` or the user's cache."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return Path(os.environ["NUMBA_CACHE_DIR"]) / "sindy_impulse"
    if sys.platform == "win32":
        root = Path(os.environ.get("LOCALAPPDATA", Path.home() / "AppData" / "Local"))
    elif sys.platform == "darwin":
        root = Path.home() / "Library" / "Caches"
    else:
        root = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return root / "sindy_impulse"


def build_key() -> str:
    """Identifies a build: kernel sources (path, size, time), numba's installation, Python, machine."""
    import importlib.util

    parts = [sys.version, sys.platform, os.environ.get("NUMBA_CACHE_DIR", "")]
    spec = importlib.util.find_spec("numba")
    sources = [_PACKAGE / f for f in KERNEL_FILES] + ([Path(spec.origin)] if spec and spec.origin else [])
    for path in sources:
        stat = path.stat()
        parts.append(f"{path}:{stat.st_size}:{stat.st_mtime_ns}")
    return hashlib.sha1("|".join(parts).encode()).hexdigest()[:16]


def base() -> Path:
    """The stem of this build's marker and lock files."""
    return cache_dir() / f"kernels-{build_key()}"


def paths(group: str) -> tuple[Path, Path]:
    """The marker of a group's finished build and the lock of its build under way."""
    stem = base()
    return stem.with_name(f"{stem.name}.{group}.done"), stem.with_name(f"{stem.name}.{group}.lock")


def wait(name: str) -> None:
    """Before kernel ``name`` is first called: wait for its build under way (at most ``WAIT_SECONDS``)."""
    if os.environ.get(CHILD_ENV):
        return
    try:
        group = "simulation" if ".simulation." in name else "differentiation"
        done, lock = paths(group)
        stem = base()
        mine = stem.with_name(f"{stem.name}.{name}.done")
        deadline = time.monotonic() + WAIT_SECONDS
        while lock.exists() and not (done.exists() or mine.exists()) and time.monotonic() < deadline:
            time.sleep(0.01)
    except OSError:
        return

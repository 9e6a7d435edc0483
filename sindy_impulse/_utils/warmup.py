"""Compiled kernels ready for a machine's first fit.

The package's numba kernels (the simulation's RK4 kernel, TVRegDiff's smoother trace and spline passes)
are compiled once per machine and cached on disk by numba (:mod:`sindy_impulse._utils.jit`). Compiling
them takes
seconds, so the first ``import sindy_impulse`` on a machine (or after an upgrade) starts one background
process that compiles them while the importing process goes on (importing PySINDy and scikit-learn takes
about as long), and the first call of a kernel waits for that build instead of compiling the same code
twice. Later processes find the cache and start at once.

- Nothing starts when the package came with its kernels compiled (a wheel built by ``pip install`` on
  this machine: :mod:`.kernel_build`), when the kernels were built for this package, numba and Python (a
  marker file in the user's cache directory, ``NUMBA_CACHE_DIR`` if set), when no cache directory can be
  written, or when the environment variable ``SINDY_IMPULSE_PRECOMPILE`` is ``0``.
- Two builds, one per group of kernels (:data:`~.kernel_cache.GROUPS`: TVRegDiff's, the simulation's), so
that two cores
  compile at once; one build per group at a time (a lock file); a kernel's first call waits for its build
  under way at most :data:`~.kernel_cache.WAIT_SECONDS`, then compiles what it needs itself
  (:func:`~.kernel_cache.wait`, in the leaf :mod:`.kernel_cache` so that :mod:`.jit` does not import this
  module, which imports the kernels).

``python -c "from sindy_impulse._utils.warmup import main; main()"`` builds the cache in the foreground (e.g.
when building a container image).
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

from .kernel_cache import CHILD_ENV, GROUPS, STALE_SECONDS, base, paths

__all__ = ["start", "build", "main", "ship", "shipped_key", "shipped", "SHIPPED"]

_ENV_OFF = "SINDY_IMPULSE_PRECOMPILE"
#: The file beside this module that says for which numba, Python and machine the kernels shipped with the
#: package were compiled (:func:`ship`, in a wheel's build: :mod:`.kernel_build`).
SHIPPED = "kernels_shipped.json"
_PACKAGE = Path(__file__).resolve().parent.parent


def _disabled() -> bool:
    return os.environ.get(_ENV_OFF, "1") == "0" or bool(os.environ.get(CHILD_ENV))


def shipped_key() -> dict:
    """What compiled kernels are valid for: numba's version, Python's, the platform and the machine (read
    without importing numba: the name of its installed distribution's metadata directory)."""
    import importlib.util
    import platform

    spec = importlib.util.find_spec("numba")
    found = []
    if spec is not None and spec.submodule_search_locations:
        found = sorted(Path(spec.submodule_search_locations[0]).parent.glob("numba-*.dist-info"))
    numba = found[0].name[len("numba-"):-len(".dist-info")] if len(found) == 1 else None
    return {"numba": numba, "python": list(sys.version_info[:2]), "implementation": sys.implementation.name,
            "platform": sys.platform, "machine": platform.machine()}


def shipped() -> bool:
    """Whether the package came with its kernels compiled for this numba, Python and machine
    (:mod:`.kernel_build`)."""
    import json

    try:
        return json.loads(_shipped_file().read_text()) == shipped_key()
    except (OSError, ValueError):
        return False


def ship() -> None:
    """Compile every kernel into the package's own numba cache and write :func:`shipped_key` beside it (a
    wheel's build: :mod:`.kernel_build`)."""
    import json

    for group in GROUPS:
        build(group)
    _shipped_file().write_text(json.dumps(shipped_key()))


def _shipped_file() -> Path:
    return Path(__file__).parent / SHIPPED


def start() -> bool:
    """Start the background builds of the groups not built here yet (none where the package came with
    its kernels compiled: :func:`shipped`); True if one was started."""
    if _disabled() or shipped():
        return False
    started = False
    for group in GROUPS:
        try:
            done, lock = paths(group)
            if done.exists():
                continue
            lock.parent.mkdir(parents=True, exist_ok=True)
            if lock.exists() and time.time() - lock.stat().st_mtime > STALE_SECONDS:
                lock.unlink(missing_ok=True)  # a build that died
            fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY)  # fails if a build is under way
            os.close(fd)
            started = _spawn(lock, group) or started
        except OSError:  # no writable cache directory, a build under way, or no way to start a process
            continue
    return started


def _spawn(lock: Path, group: str) -> bool:
    import subprocess

    env = dict(os.environ, **{CHILD_ENV: "1"})
    code = f"from sindy_impulse._utils.warmup import main; main(['--background', {group!r}])"
    try:
        subprocess.Popen(
            [sys.executable, "-c", code],
            env=env,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            close_fds=True,
            start_new_session=True,
            cwd=str(_PACKAGE.parent),
        )
        return True
    except OSError:
        lock.unlink(missing_ok=True)
        return False


def build(group: str, mark=lambda entry: None) -> None:
    """Compile the kernels of ``group`` in the order a fit needs them; ``mark(entry)`` after each."""
    import numpy as np

    if group == "differentiation":
        from ..differentiation import _banded, _smoother, _spline

        coef, h = _banded.difference_stencil(None, 12, 4)
        _banded.tv_smooth(np.linspace(0.0, 1.0, 12) ** 2, coef, h, 1.0, np.ones(12), max_iter=2)
        mark(_smoother.lagged_diffusivity)
        band = np.zeros((5, 12))
        band[0], band[1] = 4.0, 1.0
        _banded.trace_inverse(band)
        mark(_banded._trace_inverse_kernel)
        basis = _spline.SplineBasis(np.arange(40.0), 8)
        basis.rhs(np.ones(40))
        mark(_spline._bincounts)
        basis.fit_scores(np.ones(basis.n_coef), np.ones(40), 2)
        mark(_spline._scores)
        basis.evaluate(np.ones(basis.n_coef))
        mark(_spline._evaluate)
        return
    from ..simulation import CompiledModel, TermTable, integrators, two_state_cubic

    grid = np.linspace(0.0, 1.0, 5)
    # two-state cubic models (the paper's first fit needs only this kernel): linear and nonlinear
    linear = CompiledModel([[0.0, 1.0], [-1.0, -0.1]], TermTable.polynomial([[1, 0], [0, 1]]), [[1.0, 1.0]])
    linear.simulate([1.0, 0.0], grid)
    duffing = TermTable.polynomial([[1, 0], [0, 1], [3, 0]])
    cubic = CompiledModel([[0.0, 1.0, 0.0], [-1.0, -0.1, -0.01]], duffing, [[1.0, 1.0]])
    cubic.simulate([1.0, 0.0], grid)
    mark(two_state_cubic.integrate_cubic2)
    # linear models of more states (by their propagators alone)
    terms = TermTable.polynomial([[1, 0, 0], [0, 1, 0], [0, 0, 1]])
    chain = CompiledModel([[0.0, 1.0, 0.0], [-1.0, -0.1, 0.1], [0.0, 0.1, -1.0]], terms, [[1.0, 1.0, 1.0]])
    chain.simulate([1.0, 0.0, 0.0], grid)
    chain.weighted_l1(np.ones((5, 3)), grid, [0], np.ones((1, 3)))
    mark(integrators.integrate_linear)
    # three states: the general kernel, then the refinement's batch kernel
    terms = TermTable.polynomial([[1, 0, 0], [0, 0, 1], [2, 1, 0]])
    coef = [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [-1.0, -0.1, 0.01]]
    nonlinear = CompiledModel(coef, terms, [[1.0, 1.0, 1.0]])
    nonlinear.simulate([1.0, 0.0, 0.0], grid)
    mark(integrators.integrate)
    nonlinear.weighted_l1(np.ones((5, 3)), grid, [0], np.ones((1, 3)), np.ones((3, 3, 3)))
    mark(integrators.integrate_batch)
    # Not built: the exact gradients' kernels (simulation.sensitivity), which no fit calls unless
    # refinement.EXACT_GRADIENTS is switched on; they compile at their first call then. Built here they
    # took a core for 7 s (half the group's compile time; niced, 2 loaded cores) while the first fit ran.


def main(argv=None) -> int:
    """Build the cache now: every group, or (``--background GROUP``) as a process :func:`start` launched."""
    argv = sys.argv[1:] if argv is None else list(argv)
    groups = [g for g in argv if g in GROUPS] or list(GROUPS)
    stem = base()
    stem.parent.mkdir(parents=True, exist_ok=True)

    def mark(entry) -> None:
        stem.with_name(f"{stem.name}.{entry.__module__}.{entry.__qualname__}.done").touch()

    for group in groups:
        done, lock = paths(group)
        try:
            build(group, mark)
            done.touch()
        finally:
            if "--background" in argv:
                lock.unlink(missing_ok=True)
    return 0

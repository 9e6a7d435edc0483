"""The numba kernels compiled when the package is built, and shipped with it (setuptools' ``build_py``).

``pip install .`` builds a wheel on the machine it installs on. After setuptools has copied the sources,
:class:`build_py` runs one process on the copy that compiles every kernel
(:func:`sindy_impulse._utils.warmup.ship`): numba writes its cache next to the sources (``__pycache__``,
keyed by the sources' contents, numba's version and the processor), and the wheel carries it. The first
process after the installation then loads the kernels instead of compiling them, and does not start the
background build (:func:`sindy_impulse._utils.warmup.start`) when the wheel's key
(:data:`sindy_impulse._utils.warmup.SHIPPED`) matches its own numba, Python and machine.

Nothing here is needed at run time; a build that cannot compile (no numba in the build environment, a
failure, more than :data:`_TIMEOUT` seconds) gives a wheel without the cache, and the kernels compile on
the machine as before. A wheel installed on another machine (another processor) carries a cache that numba
does not load there: its kernels compile at their first call, once. The variable
``SINDY_IMPULSE_PRECOMPILE=0`` turns the step off.

This module is loaded by setuptools from its file (``[tool.setuptools.cmdclass]`` in ``pyproject.toml``),
before the package can be imported: it imports nothing from the package.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

try:
    from setuptools.command.build_py import build_py as _build_py
except ImportError:  # an installation without setuptools: only a build needs this module
    _build_py = object

__all__ = ["build_py"]

#: Longest time the compilation may take (then the wheel ships without it): it takes 10-20 s on 2 cores.
_TIMEOUT = 300


class build_py(_build_py):  # noqa: N801 - setuptools' command name
    """setuptools' ``build_py``, then the kernels compiled into the built copy (see the module)."""

    def run(self) -> None:
        super().run()
        if self.dry_run or os.environ.get("SINDY_IMPULSE_PRECOMPILE", "1") == "0":
            return
        root = Path(self.build_lib).resolve()
        if not (root / "sindy_impulse" / "_utils" / "warmup.py").exists():
            return
        # the built copy first, then the build environment's own paths (pip's isolated build puts numba there)
        env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
        inherited = env.get("PYTHONPATH", "").split(os.pathsep)
        path = [str(root), *(p for p in sys.path if p), *(p for p in inherited if p)]
        env.update(PYTHONPATH=os.pathsep.join(dict.fromkeys(path)), SINDY_IMPULSE_PRECOMPILE="0",
                   PYTHONDONTWRITEBYTECODE="1")
        code = "from sindy_impulse._utils.warmup import ship; ship()"
        try:
            subprocess.run([sys.executable, "-c", code], env=env, cwd=str(root), check=True,
                           timeout=_TIMEOUT, capture_output=True)
        except (OSError, subprocess.SubprocessError) as err:
            detail = getattr(err, "stderr", b"") or b""
            self.warn(f"sindy_impulse: the numba kernels were not compiled into the build ({err}; "
                      f"{detail.decode(errors='replace')[-500:]}); they compile on first use instead")

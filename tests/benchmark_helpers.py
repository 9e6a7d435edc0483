"""The helper modules of the ``benchmarks`` package, for the tests that check them.

Tests import no benchmark (a module with a ``main``): only the helpers several benchmarks share (the
modal-table families, the scorer, the bad-input matrix) and the runner. The package is loaded from its
files, without putting the repository on ``sys.path`` (which would shadow the installed ``sindy_impulse``
by the source tree).
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
from pathlib import Path
from types import ModuleType

PACKAGE = Path(__file__).resolve().parent.parent / "benchmarks"


def _package() -> ModuleType:
    loaded = sys.modules.get("benchmarks")
    if loaded is not None:
        if Path(loaded.__file__).resolve().parent != PACKAGE:
            raise ImportError(f"another module named benchmarks is loaded ({loaded.__file__})")
        return loaded
    spec = importlib.util.spec_from_file_location(
        "benchmarks", PACKAGE / "__init__.py", submodule_search_locations=[str(PACKAGE)]
    )
    package = importlib.util.module_from_spec(spec)
    sys.modules["benchmarks"] = package
    spec.loader.exec_module(package)
    return package


def helper(name: str) -> ModuleType:
    """``benchmarks.<name>`` (e.g. ``"accuracy.families"``, or ``"__main__"`` for the runner); a benchmark
    (a module with a ``main``) is refused."""
    _package()
    module = importlib.import_module(f"benchmarks.{name}")
    if name != "__main__" and hasattr(module, "main"):
        raise ImportError(f"benchmarks.{name} is a benchmark: tests run benchmarks through the runner only")
    return module

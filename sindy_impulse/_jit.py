"""The one numba decorator of the package's kernels: compiled once, cached on disk when possible.

Numba caches a compiled kernel next to its source (``__pycache__``) or, where the installed package is
not writable (a system or read-only site-packages), in the user's cache directory (``NUMBA_CACHE_DIR`` if
set). Where neither can be written the kernels are compiled in every process (correct, slower to start).
"""

from __future__ import annotations

import numba

__all__ = ["jit"]

_OPTIONS = {"error_model": "numpy", "nogil": True}


def jit(function=None, **options):
    """``numba.njit`` with the package's options, cached on disk if a writable cache location exists."""
    if function is None:
        return lambda f: jit(f, **options)
    try:
        return numba.njit(cache=True, **_OPTIONS, **options)(function)
    except RuntimeError:  # numba found no writable cache location for this source file
        return numba.njit(**_OPTIONS, **options)(function)

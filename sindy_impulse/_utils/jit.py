"""The one numba decorator of the package's kernels: compiled once per machine, cached on disk.

Numba caches a compiled kernel next to its source (``__pycache__``) or, where the installed package is
not writable (a system or read-only site-packages), in the user's cache directory (``NUMBA_CACHE_DIR`` if
set). Where neither can be written the kernels are compiled in every process (correct, slower to start).

:func:`kernel` marks the entry points called from Python: their first call waits for a background build
of the cache that is under way (:func:`~.kernel_cache.wait`; :mod:`sindy_impulse._utils.warmup` builds
it) instead of compiling the same code twice.
"""

from __future__ import annotations

import functools

import numba

from .kernel_cache import wait

__all__ = ["jit", "kernel"]

_OPTIONS = {"error_model": "numpy", "nogil": True}


def jit(function=None, cache=True, **options):
    """``numba.njit`` with the package's options, cached on disk if a writable cache location exists.

    ``cache=False`` for a function compiled only into kernels that are cached themselves (a function that
    closes over another cannot be cached by numba, and needs no cache of its own there).
    """
    if function is None:
        return lambda f: jit(f, cache=cache, **options)
    if not cache:
        return numba.njit(**_OPTIONS, **options)(function)
    try:
        return numba.njit(cache=True, **_OPTIONS, **options)(function)
    except RuntimeError:  # numba found no writable cache location for this source file
        return numba.njit(**_OPTIONS, **options)(function)


def kernel(function):
    """:func:`jit` for an entry point called from Python (``.dispatcher`` is the numba dispatcher)."""
    dispatcher = jit(function)
    name = f"{function.__module__}.{function.__qualname__}"
    ready = []

    @functools.wraps(function)
    def call(*args):
        if not ready:
            wait(name)
            ready.append(True)
        return dispatcher(*args)

    call.dispatcher = dispatcher
    return call

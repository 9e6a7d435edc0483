"""One BLAS thread around small linear algebra, without re-scanning the process's libraries every time.

``threadpoolctl.threadpool_limits`` looks up every loaded library at each call (1-4 ms in a process that
has imported numba and scikit-learn); a modal survey enters such a limit a dozen times per record. One
:class:`threadpoolctl.ThreadpoolController`, built at the first call, finds them once; the BLAS libraries
that matter (numpy's and SciPy's) are loaded with those packages, before any call here.
"""

from __future__ import annotations

from threadpoolctl import ThreadpoolController

__all__ = ["one_thread"]

_CONTROLLER: list = []


def one_thread(user_api: str | None = None):
    """A context manager holding the thread pools of ``user_api`` (``"blas"``, ``"openmp"``; None: all)
    at one thread.

    Examples
    --------
    >>> import numpy as np
    >>> with one_thread("blas"):
    ...     float(np.ones((3, 3)) @ np.ones(3) @ np.ones(3))
    9.0
    """
    if not _CONTROLLER:
        _CONTROLLER.append(ThreadpoolController())
    return _CONTROLLER[0].limit(limits=1, user_api=user_api)

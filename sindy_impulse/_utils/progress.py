"""The one progress bar of the package (tqdm, an optional dependency) and when to show it.

Examples
--------
>>> bar = progress_bar(range(3), total=3, desc="records", enabled=False)
>>> list(bar)
[0, 1, 2]
"""

from __future__ import annotations

import sys
import warnings
from collections.abc import Iterable

__all__ = ["progress_bar", "wants_progress"]


def wants_progress(progress: bool | None, n_items: int) -> bool:
    """Whether to show a bar: ``progress`` when given; for None, when standard error is a terminal and
    there is more than one item (a log file or a test run gets no bar).

    Examples
    --------
    >>> wants_progress(True, 1), wants_progress(False, 10)
    (True, False)
    """
    if progress is not None:
        return bool(progress)
    isatty = getattr(sys.stderr, "isatty", None)
    return n_items > 1 and bool(isatty and isatty())


def progress_bar(iterable: Iterable, total: int, desc: str, unit: str = "item", enabled: bool = True):
    """``iterable`` wrapped in a tqdm bar on standard error (``tqdm.auto``: a widget in a notebook), or
    unchanged when ``enabled`` is False; without tqdm a RuntimeWarning says how to get it and the
    iterable comes back unchanged."""
    if not enabled:
        return iterable
    try:
        from tqdm.auto import tqdm
    except ImportError:  # pragma: no cover - depends on the environment
        warnings.warn(
            "a progress bar needs tqdm (pip install sindy-impulse[progress]); continuing without a bar",
            RuntimeWarning,
            stacklevel=3,
        )
        return iterable
    return tqdm(iterable, total=total, desc=desc, unit=unit)

"""What every figure module shares: line styles, the ``ax`` argument, argument checks, fitted-object checks.

matplotlib is imported inside the functions, so importing :mod:`sindy_impulse.plotting` stays cheap.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from numbers import Integral
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

INPUT_STYLE = {"color": "0.6", "lw": 2.5}
MODEL_STYLE = {"color": "C3", "lw": 1.2, "ls": "--"}
MARK_STYLE = {"color": "C3", "ls": ":", "lw": 1.2}


# ----------------------------------------------------------------------------------------------------------
# the ax argument
# ----------------------------------------------------------------------------------------------------------
def _is_axes(obj) -> bool:
    from matplotlib.axes import Axes

    return isinstance(obj, Axes)


def one_axes(ax, name: str = "ax", **subplot_kw) -> Axes:
    """``ax`` checked to be one matplotlib Axes, or a new figure's Axes."""
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(6, 3.5), **subplot_kw)
        return ax
    if not _is_axes(ax):
        raise TypeError(f"{name} must be a matplotlib Axes, got {type(ax).__name__}")
    return ax


def _new_axes(n: int, ncols: int, sharex: bool) -> np.ndarray:
    """``n`` Axes of a new figure laid out in ``ncols`` columns; the unused cells of the grid hidden."""
    import matplotlib.pyplot as plt

    ncols = max(1, min(ncols, n))
    nrows = -(-n // ncols)
    _, grid = plt.subplots(
        nrows, ncols, sharex=sharex, squeeze=False, figsize=(3.6 * ncols if ncols > 1 else 7, 2.4 * nrows)
    )
    flat = grid.ravel()
    for extra in flat[n:]:
        extra.set_visible(False)
    return flat[:n]


def many_axes(ax, n: int, name: str = "ax", ncols: int = 1, sharex: bool = False) -> np.ndarray:
    """``n`` Axes: ``ax`` (one Axes when ``n == 1``, or a sequence/array of exactly ``n``), else new ones."""
    if ax is None:
        return _new_axes(n, ncols, sharex)
    if _is_axes(ax):
        axes = np.array([ax], dtype=object)
    elif isinstance(ax, (Sequence, np.ndarray)) and not isinstance(ax, str):
        axes = np.asarray(ax, dtype=object).ravel()
    else:
        raise TypeError(f"{name} must be a matplotlib Axes or a sequence of {n}, got {type(ax).__name__}")
    bad = [type(a).__name__ for a in axes if not _is_axes(a)]
    if bad:
        raise TypeError(f"{name} must contain matplotlib Axes only, got {bad[0]}")
    if len(axes) != n:
        raise ValueError(f"{name} has {len(axes)} axes but {n} are needed")
    return axes


# ----------------------------------------------------------------------------------------------------------
# arguments
# ----------------------------------------------------------------------------------------------------------
def check_int(value, name: str, low: int, high: int) -> int:
    """``value`` as an int in ``[low, high)``; TypeError for a non-integer, ValueError out of range."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, Integral):
        raise TypeError(f"{name} must be an int, got {value!r}")
    if not low <= int(value) < high:
        raise ValueError(f"{name}={value} is out of range: expected {low} <= {name} < {high}")
    return int(value)


def check_choice(value, name: str, choices: Sequence[str]) -> str:
    """``value`` if it is one of the strings ``choices``, else ValueError."""
    if not isinstance(value, str) or value not in choices:
        raise ValueError(f"{name} must be one of {list(choices)}, got {value!r}")
    return value


def positive(y: np.ndarray) -> np.ndarray:
    """``y`` with zeros raised to a tiny positive value so that a log axis can show them."""
    y = np.asarray(y, dtype=float)
    pos = y[np.isfinite(y) & (y > 0)]
    floor = pos.min() * 1e-2 if pos.size else 1e-16
    return np.where(np.isfinite(y) & (y <= 0), floor, y)


def names_or_default(names, n: int, prefix: str) -> list[str]:
    """``names`` as strings when there are ``n`` of them, else ``prefix0, prefix1, ...``."""
    if names is not None and len(names) == n:
        return [str(s) for s in names]
    return [f"{prefix}{i}" for i in range(n)]


# ----------------------------------------------------------------------------------------------------------
# fitted objects
# ----------------------------------------------------------------------------------------------------------
def is_sindy(obj) -> bool:
    """Whether ``obj`` looks like an ImpulseSINDy (a ``coefficients()`` method), fitted or not."""
    return hasattr(obj, "coefficients") and callable(obj.coefficients)


def is_tvregdiff(obj) -> bool:
    """Whether ``obj`` is a :class:`~sindy_impulse.TVRegDiff`, fitted or not (no import spent on arrays)."""
    if isinstance(obj, (np.ndarray, list, tuple)):
        return False
    from ..differentiation import TVRegDiff

    return isinstance(obj, TVRegDiff)


def first(value):
    """The first trajectory of a model attribute that is a list for several trajectories."""
    return value[0] if isinstance(value, list) else value


def fitted_sindy(model, name: str = "model", attrs: Sequence[str] = ("x_filtered_", "t_")):
    """Refuse anything that is not a fitted ImpulseSINDy-like estimator."""
    if model is None or not hasattr(model, "coefficients"):
        raise TypeError(f"{name} must be a fitted ImpulseSINDy, got {type(model).__name__}")
    missing = [a for a in attrs if not hasattr(model, a)]
    if missing:
        raise ValueError(f"{name} is not fitted (no {missing[0]}): call fit first")
    return model


def resolve_state_names(model, n: int, names=None) -> list[str]:
    """``names``, else the model's ``feature_names_``, else ``x0, x1, ...``; ValueError unless ``n`` long."""
    names = names if names is not None else getattr(model, "feature_names_", None)
    names = [str(s) for s in names] if names is not None else [f"x{i}" for i in range(n)]
    if len(names) != n:
        raise ValueError(f"state_names has {len(names)} names for {n} states")
    return names


# ----------------------------------------------------------------------------------------------------------
# drawing
# ----------------------------------------------------------------------------------------------------------
def scatter_groups(
    ax, x, y, labels: np.ndarray, groups: Iterable, keep: np.ndarray, legend: Callable, **style
) -> None:
    """One scatter per value of ``groups`` (colors C0, C1, ...): the rows in ``keep`` with that label."""
    values = labels.tolist()
    for j, group in enumerate(groups):
        sel = keep & np.array([v == group for v in values])
        ax.scatter(x[sel], y[sel], color=f"C{j % 10}", label=legend(group), **style)


def log_ticks(ax: Axes, axis: str = "x") -> None:
    """Tick labels of a log axis that never crowd: over a decade or more, the powers of ten only (minor
    ticks unlabelled); over less, 1, 2 and 5 times them, written plainly (``0.02``). Call it once the
    axis's limits are set."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    target = ax.xaxis if axis == "x" else ax.yaxis
    low, high = sorted(ax.get_xlim() if axis == "x" else ax.get_ylim())
    if not (low > 0 and np.isfinite(high)):
        return
    if np.log10(high / low) >= 1.0:
        target.set_major_locator(LogLocator(base=10.0, subs=(1.0,), numticks=8))
    else:
        target.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0), numticks=8))
        target.set_major_formatter(FuncFormatter(lambda v, _: f"{v:.3g}"))
    target.set_minor_locator(LogLocator(base=10.0, subs=tuple(range(2, 10)), numticks=12))
    target.set_minor_formatter(NullFormatter())

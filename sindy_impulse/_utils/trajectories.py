"""One place that turns single, multiple and ragged trajectories (with their times and inputs) into lists
of validated arrays, and back.

PySINDy's conventions: a list (or tuple) whose items are arrays is several trajectories, of possibly
different lengths; anything else is one trajectory. ``t`` is a step, one time vector (shared by trajectories
of equal length) or one vector per trajectory. Control inputs ``u`` follow ``x``: one array (n_samples,) or
(n_samples, n_inputs) per trajectory.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..exceptions import InvalidParameterError, UnsupportedProblemError
from .validation import check_signal, check_time, time_vector

__all__ = [
    "Trajectories",
    "check_trajectories",
    "as_trajectories",
    "as_times",
    "check_derivatives",
    "refuse_unsupported",
    "restore",
]

#: PySINDy's libraries of PDE, weak-form and implicit (SINDy-PI) problems.
UNSUPPORTED_LIBRARIES = ("PDELibrary", "WeakPDELibrary", "SINDyPILibrary")


def check_trajectories(x, name: str = "x", *, min_samples: int = 1) -> tuple[list[np.ndarray], bool]:
    """Validate one trajectory or a list of them.

    Returns
    -------
    (list of numpy.ndarray, bool)
        The validated (n_i, n_states) arrays and whether the input was a list of trajectories.

    Examples
    --------
    >>> trajs, multiple = check_trajectories([np.zeros((5, 2)), np.ones((4, 2))])
    >>> len(trajs), multiple
    (2, True)
    """
    if isinstance(x, (list, tuple)):
        if len(x) == 0:
            raise ValueError(f"{name} is an empty list")
        if all(hasattr(xi, "shape") for xi in x):
            arrs = [check_signal(xi, f"{name}[{i}]", min_samples=min_samples) for i, xi in enumerate(x)]
            widths = {a.shape[1] for a in arrs}
            if len(widths) != 1:
                raise ValueError(
                    f"all trajectories in {name} must have the same number of states, got {sorted(widths)}"
                )
            return arrs, True
    return [check_signal(x, name, min_samples=min_samples)], False


def as_times(
    t, trajectories: list[np.ndarray], default: float = 1.0, *, listed: bool = False
) -> list[np.ndarray]:
    """One validated, strictly increasing time vector per trajectory.

    A list (or tuple) ``t`` holds one time vector (or step) per trajectory, as in PySINDy, so next to an
    array ``x`` a plain list of numbers is refused (pass a numpy array). With ``listed`` (``x`` was one
    trajectory given as nested lists) a list of numbers is its time vector: plain Python data throughout.
    Invalid times raise a ``ValueError``; a ``t`` of the wrong type (a string, None in a list) an
    :class:`~sindy_impulse.exceptions.InvalidParameterError`, which is both a ``TypeError`` and, as PySINDy
    raises, a ``ValueError``.

    Examples
    --------
    >>> [v.tolist() for v in as_times(0.5, [np.zeros((3, 1))])]
    [[0.0, 0.5, 1.0]]
    >>> as_times([0.0, 0.5, 1.0], [np.zeros((3, 1))])  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: t is a list of 3 items but x is one trajectory: a list holds one time vector per trajectory...
    """
    if t is None:
        t = default
    if listed and isinstance(t, (list, tuple)) and all(np.ndim(ti) == 0 for ti in t):
        t = np.asarray(t, dtype=object)  # one trajectory in list form, its times too
    if isinstance(t, (list, tuple)):
        if len(t) != len(trajectories):
            if len(trajectories) == 1:
                raise ValueError(
                    f"t is a list of {len(t)} items but x is one trajectory: a list holds one time vector "
                    "per trajectory (PySINDy's convention); pass one trajectory's times as a numpy array"
                )
            raise ValueError(f"t has {len(t)} time vectors but x has {len(trajectories)} trajectories")
        checked = [_check_time(ti, len(xi), f"t[{i}]") for i, (ti, xi) in enumerate(zip(t, trajectories))]
    else:
        checked = [_check_time(t, len(xi), "t") for xi in trajectories]
    return [time_vector(ti, len(xi)) for ti, xi in zip(checked, trajectories)]


def _check_time(t, n_samples: int, name: str):
    """:func:`check_time` whose type errors are also ValueErrors (what PySINDy raises for a bad ``t``)."""
    try:
        return check_time(t, n_samples, name)
    except InvalidParameterError:
        raise
    except TypeError as err:
        raise InvalidParameterError(str(err)) from None


def _as_inputs(u, trajectories: list[np.ndarray], multiple: bool) -> list[np.ndarray] | None:
    if u is None:
        return None
    if multiple:
        if not isinstance(u, (list, tuple)):
            raise TypeError("x is a list of trajectories, so u must be a list with one input array each")
        if len(u) != len(trajectories):
            raise ValueError(f"u has {len(u)} trajectories but x has {len(trajectories)}")
        arrays = [check_signal(ui, f"u[{i}]") for i, ui in enumerate(u)]
    else:
        arrays = [check_signal(u, "u")]
    for i, (ui, xi) in enumerate(zip(arrays, trajectories)):
        if ui.shape[0] != xi.shape[0]:
            raise ValueError(f"u[{i}] has {ui.shape[0]} samples but x[{i}] has {xi.shape[0]}")
    if len({ui.shape[1] for ui in arrays}) != 1:
        raise ValueError("every trajectory of u must have the same number of inputs")
    return arrays


@dataclass
class Trajectories:
    """Validated trajectories: states ``x``, times ``t`` and inputs ``u`` (None without inputs)."""

    x: list[np.ndarray]
    t: list[np.ndarray]
    u: list[np.ndarray] | None
    multiple: bool

    @property
    def n_states(self) -> int:
        return self.x[0].shape[1]

    @property
    def n_inputs(self) -> int:
        return 0 if self.u is None else self.u[0].shape[1]

    def joined(self) -> list[np.ndarray]:
        """States and inputs side by side per trajectory: what a library is built on."""
        return self.x if self.u is None else [np.hstack([xi, ui]) for xi, ui in zip(self.x, self.u)]

    def inputs(self) -> list:
        """One input array (or None) per trajectory."""
        return [None] * len(self.x) if self.u is None else list(self.u)


def as_trajectories(x, t=None, u=None, *, default_dt: float = 1.0, min_samples: int = 1) -> Trajectories:
    """Validate ``x`` (one or several trajectories), ``t`` and ``u`` together.

    Examples
    --------
    >>> data = as_trajectories([np.zeros((4, 2)), np.zeros((6, 2))], t=0.1, u=[np.ones(4), np.ones(6)])
    >>> data.multiple, data.n_states, data.n_inputs, [len(ti) for ti in data.t]
    (True, 2, 1, [4, 6])
    """
    trajectories, multiple = check_trajectories(x, "x", min_samples=min_samples)
    times = as_times(t, trajectories, default_dt, listed=isinstance(x, (list, tuple)) and not multiple)
    return Trajectories(trajectories, times, _as_inputs(u, trajectories, multiple), multiple)


def restore(values: list, multiple: bool):
    """A list of per-trajectory values as the caller gave them: the list, or its only item."""
    return list(values) if multiple else values[0]


def check_derivatives(x_dot, data: Trajectories) -> list[np.ndarray]:
    """Given derivatives, validated against the trajectories ``data`` (one array per trajectory).

    Examples
    --------
    >>> data = as_trajectories(np.zeros((5, 2)), t=0.1)
    >>> [d.shape for d in check_derivatives(np.ones((5, 2)), data)]
    [(5, 2)]
    """
    derivs, multiple = check_trajectories(x_dot, "x_dot")
    if multiple != data.multiple:
        raise InvalidParameterError(
            "x_dot must have the same trajectories as x: both one array, or both lists of arrays"
        )
    if len(derivs) != len(data.x):
        raise ValueError(f"x_dot must have the same trajectories as x: {len(derivs)} against {len(data.x)}")
    for i, (d, xi) in enumerate(zip(derivs, data.x)):
        if d.shape != xi.shape:
            raise ValueError(f"x_dot[{i}] has shape {d.shape} but x[{i}] has shape {xi.shape}")
    return derivs


def refuse_unsupported(x, library) -> None:
    """PDE, weak-form and implicit (SINDy-PI) problems are PySINDy's: a clear
    :class:`~sindy_impulse.exceptions.UnsupportedProblemError` (a ``NotImplementedError``).

    Refused: PySINDy's PDE, weak-form and SINDy-PI libraries (also inside a composition such as a
    ``ParameterizedLibrary``)
    and states with more than two axes (spatiotemporal fields).

    Examples
    --------
    >>> refuse_unsupported(np.zeros((10, 10, 2)), None)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    sindy_impulse.exceptions.UnsupportedProblemError: x must be 1-D or 2-D, got an array of shape...
    """
    for lib in _libraries_in(library):
        kind = type(lib).__name__
        if kind in UNSUPPORTED_LIBRARIES:
            raise UnsupportedProblemError(
                f"{kind} (PDE, weak-form or implicit SINDy) is not supported: the models "
                "here are ordinary differential equations x' = f(x, u); use pysindy.SINDy"
            )
    arrays = x if isinstance(x, (list, tuple)) and x and all(hasattr(a, "shape") for a in x) else [x]
    for a in arrays:
        if np.ndim(a) > 2:
            raise UnsupportedProblemError(
                f"x must be 1-D or 2-D, got an array of shape {np.shape(a)} (time by states; spatiotemporal "
                "or PDE data are not supported: use pysindy.SINDy)"
            )


def _libraries_in(library) -> list:
    """A library and every library it is composed of."""
    if library is None:
        return []
    out = [library]
    for attr in ("libraries", "libraries_full_"):
        for sub in getattr(library, attr, None) or []:
            out += _libraries_in(sub)
    return out

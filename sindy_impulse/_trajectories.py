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

from ._validation import check_signal, check_time, time_vector

__all__ = ["Trajectories", "check_trajectories", "as_trajectories", "as_times", "restore"]


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


def as_times(t, trajectories: list[np.ndarray], default: float = 1.0) -> list[np.ndarray]:
    """One validated, strictly increasing time vector per trajectory.

    Examples
    --------
    >>> [v.tolist() for v in as_times(0.5, [np.zeros((3, 1))])]
    [[0.0, 0.5, 1.0]]
    """
    if t is None:
        t = default
    per_trajectory = isinstance(t, (list, tuple)) and (
        len(trajectories) > 1 or (len(t) == 1 and np.ndim(t[0]) == 1)
    )
    if per_trajectory:
        if len(t) != len(trajectories):
            raise ValueError(f"t has {len(t)} time vectors but x has {len(trajectories)} trajectories")
        checked = [check_time(ti, len(xi), f"t[{i}]") for i, (ti, xi) in enumerate(zip(t, trajectories))]
    else:
        checked = [check_time(t, len(xi), "t") for xi in trajectories]
    return [time_vector(ti, len(xi)) for ti, xi in zip(checked, trajectories)]


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
    times = as_times(t, trajectories, default_dt)
    return Trajectories(trajectories, times, _as_inputs(u, trajectories, multiple), multiple)


def restore(values: list, multiple: bool):
    """A list of per-trajectory values as the caller gave them: the list, or its only item."""
    return list(values) if multiple else values[0]

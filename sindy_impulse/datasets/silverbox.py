"""The Silverbox benchmark's free ring-downs, shipped with the package (real measurements)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["SilverboxWindows", "load_silverbox"]


@dataclass(frozen=True)
class SilverboxWindows:
    """Free ring-downs of the Silverbox benchmark (see :func:`load_silverbox`).

    Attributes
    ----------
    windows : list of ndarray (n_i,)
        The output voltage ``V2`` (the displacement) of each free ring-down.
    inputs : list of ndarray (n_i,)
        The input voltage ``V1`` over the same samples (held at its quiet level).
    dt : float
        Sampling step in seconds, ``2**14 / 10**7`` (610.35 Hz).
    start_rows : ndarray of int
        Row of each window's first sample in ``SNLS80mV.csv`` (0-based, header not counted).
    quiet_level : float
        The input's quiet level (V) the windows were detected from.
    """

    windows: list
    inputs: list
    dt: float
    start_rows: np.ndarray
    quiet_level: float

    def __len__(self) -> int:
        return len(self.windows)

    def times(self) -> list:
        """Time vector of each window, starting at 0."""
        return [np.arange(w.size) * self.dt for w in self.windows]

    def __repr__(self) -> str:
        lengths = [w.size for w in self.windows]
        return f"SilverboxWindows(n_windows={len(self)}, lengths={lengths}, dt={self.dt})"


def load_silverbox() -> SilverboxWindows:
    """Ten measured free ring-downs of the Silverbox, an electronic Duffing oscillator (real data).

    The Silverbox is an electronic circuit that behaves like a mass-spring-damper with a cubic stiffness,
    ``m y'' + d y' + k(y) y = u`` with ``k(y) = a + b y**2``. In its benchmark record ``SNLS80mV.csv``
    (input ``V1``, output ``V2``, 131,072 samples at 610.35 Hz), every multisine block is followed by a
    short pause in which the input is held at its quiet level (about 0.0062 V) and the output rings down
    freely: 88-96 samples, a few strongly damped periods of about 9 samples (about 68 Hz). The package
    ships those ten windows (rows 40498 to 118814): a window is a maximal run of at least 60 samples
    whose input stays within 0.001 V of the quiet level (the median of the record's first 420 samples).

    Source (cite it when you use these data):

        T. Wigren and J. Schoukens, "Three free data sets for development and benchmarking in nonlinear
        system identification", European Control Conference (ECC) 2013, Zurich, Switzerland.

    Returns
    -------
    SilverboxWindows
        ``windows`` (output ``V2`` per window), ``inputs`` (``V1``), ``dt``, ``start_rows`` and
        ``quiet_level``.

    Examples
    --------
    >>> sb = load_silverbox()
    >>> len(sb), sb.windows[0].size, int(sb.start_rows[0]), round(1 / sb.dt, 2)
    (10, 88, 40498, 610.35)

    One window, delay-embedded (a quarter period is about 2 samples), after removing the static offset
    and scaling to unit amplitude: a linear model whose mode is the Silverbox resonance.

    >>> import pysindy as ps
    >>> from sindy_impulse import DelayEmbedding, ImpulseSINDy
    >>> from sindy_impulse.analysis import modal_parameters, nonlinearity_test
    >>> y = sb.windows[0] - sb.windows[0][-30:].mean()
    >>> q = DelayEmbedding(tau=2, dimension=2).fit(y).transform(y / abs(y).max())
    >>> model = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=3)).fit(q, t=sb.dt)
    >>> f, zeta = modal_parameters(model)
    >>> round(float(f[0]), 1), round(float(zeta[0]), 3)
    (68.3, 0.047)

    The cubic stiffness is weak at these amplitudes: the period-by-period frequency rises only from
    about 68.1 Hz (amplitude < 0.01 V) to 68.5 Hz (amplitude > 0.04 V), and the test for nonlinearity
    does not find it in a single window:

    >>> bool(nonlinearity_test(model, q, sb.dt))
    False
    """
    from importlib.resources import files

    with files("sindy_impulse").joinpath("data", "silverbox_ringdowns.npz").open("rb") as fh:
        data = np.load(fh)
        output, inputs = data["output"], data["input"]
        starts, lengths = data["start_rows"].astype(int), data["lengths"].astype(int)
        dt, level = float(data["dt"]), float(data["quiet_level"])
    bounds = np.concatenate([[0], np.cumsum(lengths)])
    windows = [output[a:b].copy() for a, b in zip(bounds[:-1], bounds[1:])]
    ins = [inputs[a:b].copy() for a, b in zip(bounds[:-1], bounds[1:])]
    return SilverboxWindows(windows, ins, dt, starts, level)

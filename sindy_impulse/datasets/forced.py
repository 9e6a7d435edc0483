"""A forced oscillator with its measured force: the data of a hammer or shaker test of one mode.

``m x'' + c x' + k x = f(t)``, written as ``x' = v, v' = -(k/m) x - (c/m) v + f/m``, driven either by a
band-limited random force (a shaker) or by half-sine hammer hits. The force is the sampled, measured one and
acts between the samples as their linear interpolation (what a zero-order-free data acquisition and the
simulator of :class:`~sindy_impulse.ImpulseSINDy` assume); noise is added to the response only.
"""

from __future__ import annotations

from numbers import Real

import numpy as np
from scipy.integrate import solve_ivp
from scipy.signal import butter, sosfiltfilt

from .._utils.params import Interval, Options, check_param
from ._response import half_sine_force
from .oscillator import MAX_SAMPLES, add_noise

__all__ = ["ForcedResponse", "forced_oscillator"]

_POSITIVE = Interval(Real, 0, None, "neither")


class ForcedResponse:
    """A simulated forced response: time ``t``, states ``x`` (n, 2), force ``u`` (n, 1), clean states."""

    def __init__(self, t: np.ndarray, x: np.ndarray, u: np.ndarray, x_clean: np.ndarray, params: dict):
        self.t, self.x, self.u, self.x_clean, self.params = t, x, u, x_clean, params

    def __iter__(self):  # allows ``t, x, u = forced_oscillator()``
        return iter((self.t, self.x, self.u))

    def __repr__(self) -> str:
        return f"ForcedResponse(n_samples={self.t.size}, params={self.params})"


def _force(kind, t, rms, band_hz, hits, contact_time, rng) -> np.ndarray:
    if kind == "random":
        fs = 1.0 / (t[1] - t[0])
        if not band_hz < fs / 2:
            raise ValueError(f"band_hz={band_hz!r} must be below the Nyquist frequency {fs / 2:g} Hz")
        f = sosfiltfilt(butter(4, band_hz, fs=fs, output="sos"), rng.standard_normal(t.size))
        return f * (rms / np.std(f))
    starts, amplitudes = np.asarray(hits, dtype=float).reshape(-1, 2).T
    return half_sine_force(t, starts, amplitudes, contact_time)


def forced_oscillator(
    k: float = 64.0,
    c: float = 0.8,
    m: float = 1.0,
    force: str = "random",
    *,
    t_end: float = 10.0,
    dt: float = 0.01,
    force_rms: float = 10.0,
    band_hz: float = 4.0,
    hits=((0.5, 50.0), (4.0, -30.0), (7.0, 40.0)),
    contact_time: float = 0.05,
    snr_db: float | None = None,
    random_state=None,
) -> ForcedResponse:
    """Response of ``m x'' + c x' + k x = f(t)`` from rest to a random or impulsive measured force.

    Parameters
    ----------
    k, c, m : float
        Stiffness, viscous damping and mass (defaults: natural frequency 8 rad/s, damping ratio 5 %).
    force : {"random", "hammer"}
        ``"random"``: Gaussian noise low-passed at ``band_hz`` (4th-order zero-phase Butterworth), scaled
        to ``force_rms``. ``"hammer"``: half-sine hits of ``contact_time`` seconds at the ``(time,
        peak)`` pairs of ``hits``.
    t_end, dt : float
        Duration and sampling step.
    snr_db : float, optional
        White Gaussian noise on the response (both states) at this signal-to-noise ratio; the force stays
        exact.
    random_state : int, numpy Generator or None
        Seed of the random force and of the noise.

    Returns
    -------
    ForcedResponse
        ``t`` (n,), ``x`` (n, 2) = ``[x, v]`` (noisy), ``u`` (n, 1) the force, ``x_clean`` and ``params``;
        unpacks as ``t, x, u``.

    Examples
    --------
    >>> t, x, u = forced_oscillator(force="hammer")
    >>> x.shape, u.shape, round(float(u.max()), 1)  # the 50 N peak falls between samples
    ((1001, 2), (1001, 1), 47.6)
    """
    owner = "forced_oscillator"
    for name, value in (("k", k), ("m", m), ("t_end", t_end), ("dt", dt), ("force_rms", force_rms)):
        check_param(name, value, [_POSITIVE], owner)
    check_param("c", c, [Interval(Real, 0, None, "left")], owner)
    check_param("band_hz", band_hz, [_POSITIVE], owner)
    check_param("contact_time", contact_time, [_POSITIVE], owner)
    check_param("force", force, [Options({"random", "hammer"})], owner)
    n = int(round(t_end / dt)) + 1
    if n > MAX_SAMPLES:
        raise ValueError(f"t_end / dt = {t_end / dt:.3g} samples; at most {MAX_SAMPLES:.0e} are generated")
    rng = np.random.default_rng(random_state)
    t = np.arange(n) * dt
    f = _force(force, t, force_rms, band_hz, hits, contact_time, rng)

    def rhs(s, z):
        return [z[1], (np.interp(s, t, f) - c * z[1] - k * z[0]) / m]

    sol = solve_ivp(rhs, (0.0, t[-1]), [0.0, 0.0], t_eval=t, rtol=1e-10, atol=1e-12, max_step=dt / 2)
    clean = sol.y.T.copy()
    x = clean if snr_db is None else add_noise(clean, snr_db, random_state=rng)
    params = {"k": k, "c": c, "m": m, "force": force, "dt": dt, "snr_db": snr_db}
    return ForcedResponse(t, x, f[:, None], clean, params)

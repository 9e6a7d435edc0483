"""The record of a synthetic hammer test (:func:`~sindy_impulse.datasets.impact_record`)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ._backbone import Backbone
from ._chain import SpringMassChain

__all__ = ["ImpactRecord"]


@dataclass(frozen=True, repr=False, eq=False)
class ImpactRecord:
    """A synthetic hammer test (see :func:`impact_record`).

    Attributes
    ----------
    t : ndarray (n_samples,)
        Time (s), starting at 0.
    y : ndarray (n_samples,) or (n_samples, n_channels)
        The sensor signal: response plus ``offset`` plus noise (m, m/s or m/s^2), saturated at
        ``offset -+ clip * max|y_clean|`` when ``params["clip"]`` is not None.
    force : ndarray (n_samples,)
        The hammer force (N), with its own small noise.
    fs : float
        Sampling rate (Hz).
    onset_time : float
        When the (first) contact begins (s). The half-sine is centred on a sample, so ``onset_time`` is
        within half a contact time after the last pre-trigger sample.
    free_decay_index : int
        First sample after the last contact: from here on the record is a free decay.
    modes : numpy.recarray
        The true modal table, one row per mode sorted by frequency: ``frequency_hz`` (undamped natural
        frequency), ``damped_frequency_hz``, ``damping_ratio``, ``amplitude`` and ``phase`` (per channel
        when there are several) such that after the hits the clean response is
        ``sum_i amplitude_i exp(-zeta_i omega_i tau) cos(omega_d,i tau + phase_i)``,
        ``tau = t - onset_time`` (the linear part for a nonlinear record), and ``band_hz`` (the half-power
        band of the mode's displacement receptance, about ``frequency_hz * (1 -+ damping_ratio)``).
    offset, noise_std : float or ndarray (n_channels,)
        The constant added to ``y`` and the standard deviation of its noise (0 without noise).
    y_clean : ndarray
        ``y`` without offset and noise.
    true_backbone : Backbone or None
        For a single-DOF record, ``amplitude -> (frequency_hz, damping_ratio)``; None otherwise.
    chain : SpringMassChain
        The physical chain: masses, springs, stiffness and damping matrices, mass-normalised mode shapes.
    params : dict
        The generating arguments (defaults filled in).
    """

    t: np.ndarray
    y: np.ndarray
    force: np.ndarray
    fs: float
    onset_time: float
    free_decay_index: int
    modes: np.recarray
    offset: float | np.ndarray
    noise_std: float | np.ndarray
    y_clean: np.ndarray
    true_backbone: Backbone | None
    chain: SpringMassChain
    params: dict = field(default_factory=dict)

    @property
    def n_channels(self) -> int:
        return 1 if self.y.ndim == 1 else self.y.shape[1]

    def __repr__(self) -> str:
        p = self.params
        lines = [
            f"ImpactRecord({self.t.size} samples at {self.fs:g} Hz, {p['sensor']} at mass "
            f"{p['sensor_dof']} of {self.chain.masses.size}, tap on mass {p['tap_dof']}, "
            f"onset {self.onset_time:.4g} s, snr_db={p['snr_db']}, offset={p['offset']:g} x peak"
            + (", nonlinear" if _nonlinear(p) else "")
            + (f", clipped at {p['clip']:g} x peak" if p.get("clip") is not None else "")
            + ")",
            "   f_n (Hz)     f_d (Hz)     zeta       amplitude",
        ]
        for m in self.modes:
            amp = (
                f"{m.amplitude:.4g}"
                if np.ndim(m.amplitude) == 0
                else np.array2string(m.amplitude, precision=4)
            )
            lines.append(
                f"  {m.frequency_hz:10.4f}  {m.damped_frequency_hz:10.4f}  {m.damping_ratio:9.5f}  {amp}"
            )
        return "\n".join(lines)


def _nonlinear(p) -> bool:
    return bool(
        p["cubic_stiffness"]
        or p["damping_amplitude"]
        or p["quadratic_damping"]
        or p.get("quadratic_stiffness", 0.0)
    )

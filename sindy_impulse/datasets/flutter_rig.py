"""Measured free-decay records shipped with the package (real data, small excerpts).

Each loader reads one ``.npz`` file from ``sindy_impulse/data`` (its source, licence and the script that cut
it are in ``sindy_impulse/data/README.md``) and returns a frozen container with the sampling rate, the
records in physical units and the source citation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["FlutterRigFreeDecay", "load_flutter_rig"]

#: Length (s) of the quiet end of each record over which :attr:`FlutterRigFreeDecay.rest_level` is taken.
REST_SECONDS = 4.0


@dataclass(frozen=True)
class FlutterRigFreeDecay:
    """Wind-off free decays of a pitch-and-heave aerofoil rig (see :func:`load_flutter_rig`).

    Attributes
    ----------
    y : ndarray (n_records, n_samples, 2)
        The measured heave (m) and pitch angle (rad) of each record, as recorded: static offsets included.
    fs : float
        Sampling rate in Hz (500.0: every 10th sample of the 5 kHz source).
    records : tuple of str
        ``("model-1", "model-2")``: the source's two rig configurations.
    channels, units : tuple of str
        ``("heave", "pitch")`` and ``("m", "rad")``.
    rest_level : ndarray (n_records, 2)
        Mean of each channel over the last 4 s, when the rig is at rest: the zero of the free decay.
    nominal_frequency_hz : ndarray (n_records, 2)
        The source's nominal uncoupled heave and pitch natural frequencies (its ``w_h``, ``w_a`` / 2 pi).
    force : None
        No force was measured: the rig is released from a deflected position.
    """

    y: np.ndarray
    fs: float
    records: tuple
    channels: tuple
    units: tuple
    rest_level: np.ndarray
    nominal_frequency_hz: np.ndarray
    force: None = None

    @property
    def t(self) -> np.ndarray:
        """Time of each sample (s), from 0 at the first sample of the record."""
        return np.arange(self.y.shape[1]) / self.fs

    def centered(self) -> np.ndarray:
        """``y`` minus :attr:`rest_level`: displacements from the rest position (a new array)."""
        return self.y - self.rest_level[:, None, :]

    def __len__(self) -> int:
        return self.y.shape[0]

    def __repr__(self) -> str:
        return (
            f"FlutterRigFreeDecay(records={self.records}, n_samples={self.y.shape[1]}, fs={self.fs}, "
            f"channels={self.channels}, units={self.units})"
        )


def load_flutter_rig() -> FlutterRigFreeDecay:
    """Two measured free decays of a two-degree-of-freedom aerofoil rig (heave and pitch, real data).

    A wing section on a heave spring and a pitch spring (a flutter test rig) vibrates freely from an initial
    deflection in still air (the source identifies its structural parameters from these records with a
    model without aerodynamic stiffness or damping); heave (a displacement sensor, 0.18 m/V) and pitch
    angle (rad) are sampled at 5 kHz for 16 s. The two records are the source's two configurations,
    "model-1" and "model-2" (pitch stiffness 26.0 and 60.3 N m/rad with different inertia, nominal
    frequencies nearly equal). The package ships every 10th sample (500 Hz, 8000 samples per channel),
    values unchanged.

    What a classical look finds (``benchmarks/real_records/flutter_rig_classical.py``): a heave-dominated mode
    at about 2.25 Hz, also strong in pitch, decaying over 8-9 s (about 18 periods, 70 dB above the noise),
    and a pitch-dominated mode at about 2.85 Hz that is gone after about 3 s; the two are coupled. The
    damping is amplitude-dependent, as with dry friction: the period-by-period damping ratio of the first
    mode grows from about 0.02 at the largest amplitude to 0.04-0.05 at a tenth of it, while its frequency
    rises from about 2.2 to 2.3 Hz; the pitch of model-2 stops abruptly after about 5 s.

    Source (cite it when you use these data; MIT licence, whose notice must accompany copies):

        Kyoung Hyun Lee, "System_ID_flutter" (2019), https://github.com/Kyounghyunlee/System_ID_flutter,
        commit 0a20f217, files Linear_system_Identification/Measured_data.mat and Measured_data2.mat.
        Copyright (c) 2019 Kyoung Hyun Lee. The records are the free decays of systems 1 and 2 of "Exploring
        features of a dynamical system near Hopf bifurcation using control based continuation".

    Returns
    -------
    FlutterRigFreeDecay
        ``y`` (2 records, 8000 samples, heave in m and pitch in rad), ``fs`` = 500 Hz, ``t``,
        ``rest_level``, ``centered()``, ``records``, ``channels``, ``units``, ``nominal_frequency_hz``;
        ``force`` is None.

    Examples
    --------
    >>> rig = load_flutter_rig()
    >>> rig.y.shape, rig.fs, rig.channels, rig.units
    ((2, 8000, 2), 500.0, ('heave', 'pitch'), ('m', 'rad'))

    The heave of model-1 starts about 8 cm from rest; its spectrum peaks at about 2.23 Hz:

    >>> heave = rig.centered()[0, :, 0]
    >>> round(float(abs(heave[:100]).max()), 3)
    0.079
    >>> f = np.fft.rfftfreq(2**16, 1 / rig.fs)
    >>> round(float(f[np.argmax(abs(np.fft.rfft(heave[:4500], 2**16)))]), 2)
    2.23
    """
    from importlib.resources import files

    with files("sindy_impulse").joinpath("data", "flutter_rig_free_decay.npz").open("rb") as fh:
        data = np.load(fh, allow_pickle=False)
        heave = data["heave_volts"].astype(np.float64) * float(data["heave_sensitivity_m_per_volt"])
        pitch = data["pitch_rad"].astype(np.float64)
        fs = float(data["fs"])
        records = tuple(str(r) for r in data["record_names"])
        nominal = np.column_stack([data["nominal_heave_frequency_hz"], data["nominal_pitch_frequency_hz"]])
    y = np.stack([heave, pitch], axis=-1)
    rest = y[:, -int(REST_SECONDS * fs) :, :].mean(axis=1)
    return FlutterRigFreeDecay(y, fs, records, ("heave", "pitch"), ("m", "rad"), rest, nominal)

"""Weak modes: the stable pole's frequency and damping ratio where the band's equation disagrees with it.

A mode 20-40 dB below the strongest one of a record has a band SNR of 15-30 dB: its band signal is a few
tens of periods above the noise, cut at the start by the band-pass transient and carrying a little of its
strong neighbours' leakage. The equation fitted on it (:func:`.band_fit.fit_band`) is then the less
accurate estimate of the mode's linear values: its own standard deviations (``frequency_std_hz``,
``damping_ratio_std``) reach 0.4 % in frequency and 50 % in damping ratio. The stabilisation diagram's
stable pole (:func:`~sindy_impulse.poles.stabilisation`: ESPRIT over model orders on the whole free decay,
no band-pass) has no transient and no leakage. Measured on ``python -m benchmarks modes --family b``
(seeds 0 and 1, 120 records): of the modes whose equation disagreed with their stable pole
(:func:`._short.disagreement` over :data:`._short.MODE_POLE_AGREEMENT`), 21 had the pole within the marks
(0.3 % / 10 %) where the equation was not, one the reverse; family a (60 records) had one such mode (both
right), family f (30) none; family g (30 records of nonlinear modes) 13 the reverse: amplitude-dependent
damping, which the pole averages over the decay.

:func:`pole_values` gives such a mode its stable pole's values -- the nearest stable mode of the diagram
found at :data:`._short.PERSISTENCE` of its orders or more, inside the mode's band, whose nearest mode it
is -- when the pole also lies within :data:`MAX_STD_APART` of the equation's own standard deviations: the
band's data cannot tell the two apart, and the pole is the sharper estimate. A mode whose equation is sure
of values far from the pole keeps them (a mode whose damping depends on amplitude has a pole that
averages it over the decay), and so does one whose equation has nonlinear terms at a band SNR of
:data:`MAX_NONLINEAR_SNR_DB` or more. As :mod:`._short` does for short records, the equation stays the
mode's model (backbone, nonlinearity test, ``simulate``) and its own linear mode is written in the mode's
``uncertainty_note``.

:func:`refused_by_poles` gives a stable pole that sits in a refused band with no mode near it (a weak
mode beside a strong one whose own band the filter transient leaves too short) one more fit, on its
peak's band with the other peaks subtracted, reported the same way.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..preprocessing.band import ANALYSER_LIMIT
from ..preprocessing.deflation import deflated_band
from ._nonlinear import has_nonlinear_terms
from ._short import MODE_POLE_AGREEMENT, _near, disagreement, stable_modes
from .band_fit import fit_band
from .result import Mode

__all__ = ["pole_values", "refused_by_poles"]

#: A mode takes its stable pole's values when the pole lies within this many of the equation's own standard
#: deviations of its frequency and of its damping ratio (both known): the band's data cannot tell the two
#: apart. Measured (the module's records): the family b modes whose pole was right and equation wrong were
#: within 4.3 of them; family g's modes whose equation was right and pole wrong (an amplitude-dependent
#: damping averaged over the decay: 1.4-4 times the linear one) at 18.9 or more, a mode both right at 8.4.
MAX_STD_APART = 5.0
#: A mode whose equation has nonlinear terms takes its pole's values only below this band SNR (dB): there
#: the terms are the noise's (family b's weak modes whose pole was right: 15-33 dB). Above it they may be
#: the data's, and the linear coefficients' standard deviations swell with their correlation with the
#: nonlinear ones: an x^2 x' damper's mode at 47 dB (tests/test_modes_nonlinear.py, the contact spike)
#: had a damping ratio of 0.0165 +- 0.010, right, against its pole's amplitude-averaged 0.0183.
MAX_NONLINEAR_SNR_DB = 35.0


def _pole_of(mode: Mode, stable: list):
    """The stable mode nearest ``mode`` in frequency when it lies inside the mode's band, else None."""
    if not stable:
        return None
    pole = min(stable, key=lambda s: abs(np.log(s.frequency_hz / mode.frequency_hz)))
    return pole if mode.band_hz[0] <= pole.frequency_hz <= mode.band_hz[1] else None


def _within_std(mode: Mode, pole) -> bool:
    """Whether the pole lies within :data:`MAX_STD_APART` standard deviations of the mode's equation (False
    when they are not known)."""
    f_std, z_std = mode.frequency_std_hz, mode.damping_ratio_std
    if not (np.isfinite(f_std) and np.isfinite(z_std) and f_std > 0 and z_std > 0):
        return False
    return (abs(mode.frequency_hz - pole.frequency_hz) <= MAX_STD_APART * f_std
            and abs(mode.damping_ratio - pole.damping_ratio) <= MAX_STD_APART * z_std)


def _with_pole(mode: Mode, pole, apart: float) -> Mode:
    """The mode with the pole's frequency and damping ratio, its equation's own in its note."""
    note = (f"frequency and damping ratio from the stabilisation diagram's stable pole ({pole.n_orders} "
            f"orders); the equation's linear mode: {mode.frequency_hz:.6g} Hz, damping ratio "
            f"{mode.damping_ratio:.4g} ({apart:.2g} from the pole)")
    return replace(mode, frequency_hz=float(pole.frequency_hz), damping_ratio=float(pole.damping_ratio),
                   uncertainty_note="; ".join(filter(None, [mode.uncertainty_note, note])))


def _noise_terms(mode: Mode) -> bool:
    """Whether the mode's equation is linear, or weak enough for its nonlinear terms to be the noise's
    (:data:`MAX_NONLINEAR_SNR_DB`); never for a mode the test for nonlinearity has already called
    nonlinear (:func:`._envelope.small_amplitude_damping` gave it its envelope's damping at zero amplitude;
    the test is not run here)."""
    test = mode.__dict__.get("nonlinearity")
    if test is not None and bool(getattr(test, "nonlinear", False)):
        return False
    return not has_nonlinear_terms(mode.model) or mode.snr_db < MAX_NONLINEAR_SNR_DB


def _nearest_mode(modes: list, pole) -> Mode:
    return min(modes, key=lambda m: abs(np.log(m.frequency_hz / pole.frequency_hz)))


def pole_values(modes: list, table, index: int = 0) -> tuple[list, list[str]]:
    """Each mode whose equation disagrees with its stable pole (see the module) given the pole's frequency
    and damping ratio: ``(modes, notes)``.

    Parameters
    ----------
    modes : list of Mode
        One record's modes.
    table : PoleTable
        The record's stabilisation diagram (:func:`.result.pole_table`).
    index : int
        The record's index (for the notes).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> from sindy_impulse.poles import PoleTable
    >>> f, z = np.full(26, 100.0), np.full(26, 0.01)
    >>> table = PoleTable(f, z, np.arange(10, 62, 2), np.ones(26, bool), tuple(range(10, 62, 2)))
    >>> mode = Mode(100.4, 0.008, (90.0, 110.0), 1.0, 0.05, None, np.zeros((1, 2)), np.zeros(1), snr_db=20.0,
    ...             frequency_std_hz=0.3, damping_ratio_std=0.002)
    >>> out, notes = pole_values([mode], table)
    >>> out[0].frequency_hz, out[0].damping_ratio, out[0].uncertainty_note[:36]
    (100.0, 0.01, 'frequency and damping ratio from the')
    """
    stable = stable_modes(table)
    out, notes = [], []
    for mode in modes:
        pole = _pole_of(mode, stable)
        if pole is None or _nearest_mode(modes, pole) is not mode:
            out.append(mode)
            continue
        damped = pole.frequency_hz * np.sqrt(1 - pole.damping_ratio**2)
        apart = disagreement(mode, damped, pole.damping_ratio)
        if not (apart > MODE_POLE_AGREEMENT and _within_std(mode, pole) and _noise_terms(mode)):
            out.append(mode)
            continue
        out.append(_with_pole(mode, pole, apart))
        notes.append(f"record {index}: the mode at {mode.frequency_hz:.5g} Hz (damping ratio "
                     f"{mode.damping_ratio:.3g}, band SNR {mode.snr_db:.0f} dB) disagrees with the stable "
                     f"pole at {pole.frequency_hz:.5g} Hz (damping ratio {pole.damping_ratio:.3g}): the"
                     " pole's values are reported, the equation kept as its model")
    return out, notes


def _apart(mode, pole) -> float:
    """:func:`._short.disagreement` of a mode with a stable pole."""
    return disagreement(mode, pole.frequency_hz * np.sqrt(1 - pole.damping_ratio**2), pole.damping_ratio)


def _refused_holding(pole, stable: list, modes: list, rejected: list):
    """The refused band holding the stable pole when no mode is near it (:func:`._short._near`; a
    harmonic's row excluded)."""
    if _near(modes, pole, stable):
        return None
    return next((r for r in rejected if r.band_hz is not None and "harmonic" not in r.reason
                 and r.band_hz[0] <= pole.frequency_hz <= r.band_hz[1]), None)


def refused_by_poles(pre, modes: list, rejected: list, template, index: int, table,
                     samples_per_period: float = 16.0) -> tuple[list, list, list[str]]:
    """A stable pole inside a refused band that no mode's band holds (a weak mode next to a strong one:
    its own band too narrow for the band-pass transient, its joint and free-decay fits drowned by the
    strong mode or the broadband noise) is identified once more on its peak's band with the other peaks
    subtracted (:func:`~sindy_impulse.preprocessing.deflation.deflated_band`, at least 10 % wide, as
    :func:`.survey._deflated` fits it, there judged against the peak's damped sinusoid; up to fs / 2.56,
    resampled where needed, not only up to fs / 8): the
    equation becomes the mode, with the pole's frequency and damping ratio, when the pole lies within
    :data:`MAX_STD_APART` of its standard deviations; the band's row is then dropped.
    ``(modes, rejected, notes)``."""
    peaks, notes = pre.peaks.frequency_hz, []
    stable = stable_modes(table)
    for pole in stable if len(peaks) > 1 else []:
        refused = _refused_holding(pole, stable, modes, rejected)
        if refused is None or not np.all(np.isfinite(pre.peaks.damping_ratio)):
            continue
        i = int(np.argmin(np.abs(np.log(peaks / pole.frequency_hz))))
        if not refused.band_hz[0] <= peaks[i] <= refused.band_hz[1]:
            continue
        try:
            own = pre.peaks.band_hz[i][1] / peaks[i] - 1
            band = deflated_band(pre, i, samples_per_period=samples_per_period, min_width=max(own, 0.1),
                                 top_hz=ANALYSER_LIMIT * pre.fs)
        except ValueError:  # too few periods above the noise
            continue
        out = fit_band(band, template, onset_time=pre.impact.onset_time, index=index)
        if not isinstance(out, Mode) or not (_within_std(out, pole) and _noise_terms(out)):
            continue
        modes = modes + [replace(_with_pole(out, pole, _apart(out, pole)), band_hz=tuple(refused.band_hz))]
        rejected = [r for r in rejected if r is not refused]
        notes.append(f"record {index}: band {refused.band_hz[0]:.4g}-{refused.band_hz[1]:.4g} Hz was "
                     f"refused ({refused.reason}); its stable pole at {pole.frequency_hz:.5g} Hz was "
                     "identified on the band with the other peaks subtracted, the pole's values reported")
    return modes, rejected, notes

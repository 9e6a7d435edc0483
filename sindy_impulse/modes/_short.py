"""Modes of a short, strongly damped record, from the stable poles of its stabilisation diagram.

A band-pass filter's transient lasts about the inverse of its bandwidth: on a record of 3-15 periods of a
mode with a damping ratio of 2-25 %, a band narrow enough to isolate one mode leaves no period after its
transient is trimmed (``Preprocessed.skipped``: "periods remain"). The stabilisation diagram of the free
decay (:func:`~sindy_impulse.poles.stabilisation`, ESPRIT over model orders) has no such limit: its stable
modes (present at :data:`PERSISTENCE` of its orders or more) are the modes of such a record. Each stable
mode inside a refused band is identified here without band-pass (:func:`fit_free_decay`):

1. the other stable modes are removed from the free decay (:func:`only`: damped sinusoids at the stable
   poles, their amplitudes, phases and a constant fitted by linear least squares, all but the target's
   subtracted), which ends where the target's envelope reaches the noise (:func:`free_decay`);
2. the remainder's states ``[y, dy]`` and their derivatives come from a Savitzky-Golay fit
   (:func:`~._states.free_decay_states`: no transient to trim, every sample kept);
3. the mode's equation is fitted on them (the survey's estimator) and kept when its linear mode agrees with
   the stable pole (:func:`disagreement` at most :data:`POLE_AGREEMENT`): the check that one oscillator
   reproduces that part of the record.

The mode's frequency and damping ratio are the stable pole's (the median over the orders of the diagram):
on a few periods of decay they are the more accurate -- ``python -m benchmarks short_records --poles
--n 30`` (family (d) records 0-29, seed 0; 46 true modes whose stable pole's equation agrees): the pole
within 1.8e-4 in frequency and 1.3e-3 in damping ratio (medians; largest 4.7e-3 and 2.9e-2), the fitted
equation's linear mode within 4.5e-4 and 3.7e-3 (largest 1.5e-2 and 5.0e-2). The pole's values are written
in the mode's ``uncertainty_note``; the equation stays the mode's model (backbone, nonlinearity test,
``simulate``).

A single stable mode in a record without spectral peak (the paper's oscillator: 4 s at 20 % damping) keeps
the paper's single-sensor route (:func:`from_stable_poles`: delay embedding, TVRegDiff,
:func:`.band_fit.fit_direct`).
"""

from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace

import numpy as np

from ..identification.estimator import fit_deferred
from ..optimizers import fresh_copy
from ..preprocessing.sinusoids import fit_amplitudes
from ..preprocessing.stable_poles import PERSISTENCE
from ._states import STATE_NAMES, free_decay_states
from .band_fit import _linear_mode, _uncertainty, fit_direct, fit_error_of, isolated
from .result import Mode, Rejected

__all__ = ["PERSISTENCE", "POLE_AGREEMENT", "checked_by_poles", "disagreement", "fit_free_decay",
           "free_decay", "from_stable_poles", "only", "pole_band", "short_from_poles", "stable_modes"]

#: Half-power half-widths on each side of a stable pole that make its band (the search range of its fit).
POLE_BAND_WIDTHS = 3.0
#: Largest :func:`disagreement` of a short band's fitted equation with its stable pole: loose, as the
#: reported values are the pole's and the check is that one oscillator reproduces that part of the record
#: (family (d) record 4 of ``benchmarks/accuracy/short_records.py``: its 157 Hz mode at a damping ratio of
#: 0.18 was 0.15 from its pole with a quarter-period smoothing window).
POLE_AGREEMENT = 0.3


def disagreement(mode, frequency_hz: float, damping_ratio: float) -> float:
    """How far a mode is from a damped sinusoid of damped frequency ``frequency_hz``: frequency offset in
    half-power half-widths plus the log ratio of the damping ratios.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> round(disagreement(SimpleNamespace(damped_frequency_hz=101.0, damping_ratio=0.1), 100.0, 0.1), 3)
    0.1
    """
    offset = abs(mode.damped_frequency_hz - frequency_hz) / (damping_ratio * frequency_hz)
    return float(offset + abs(np.log(mode.damping_ratio / damping_ratio)))


def stable_modes(table) -> list:
    """The stable modes of a stabilisation diagram present at :data:`PERSISTENCE` of its orders or more.

    Examples
    --------
    >>> from sindy_impulse import impact_record
    >>> from sindy_impulse.poles import stabilisation
    >>> rec = impact_record([50.0], [0.1], fs=1000.0, duration=0.3, snr_db=50, pre_trigger=0, random_state=0)
    >>> [round(m.frequency_hz) for m in stable_modes(stabilisation(rec.y[5:], fs=rec.fs))]
    [50]
    """
    return [m for m in table.modes() if m.n_orders >= PERSISTENCE * len(table.orders)]


def pole_band(mode) -> tuple:
    """The band of :data:`POLE_BAND_WIDTHS` half-power half-widths around a stable mode.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> pole_band(SimpleNamespace(frequency_hz=100.0, damping_ratio=0.1))
    (70.0, 130.0)
    """
    f, half = mode.frequency_hz, POLE_BAND_WIDTHS * mode.damping_ratio * mode.frequency_hz
    return (float(max(f - half, 0.05 * f)), float(f + half))


#: The free decay of a stable mode ends where its fitted envelope falls to this many dB over the noise (the
#: RMS of what the stable modes leave of the ring-down), as a band signal ends at the noise floor.
END_SNR_DB = 10.0
#: ... but it keeps at least this many periods of the mode.
MIN_PERIODS = 2.0


def _components(pre, stable: list):
    """The stable modes' damped sinusoids fitted to the ring-down (amplitudes, phases, a constant)."""
    ring = pre.y[pre.impact.ringdown_index :]
    f = np.array([m.frequency_hz * np.sqrt(1 - m.damping_ratio**2) for m in stable])
    decay = np.array([2 * np.pi * m.damping_ratio * m.frequency_hz for m in stable])
    return ring, fit_amplitudes(ring, pre.fs, f, decay)


def only(pre, stable: list, keep):
    """The record with every stable mode but ``keep`` (and the constant) removed from its ring-down (see
    the module, step 1)."""
    ring, fit = _components(pre, stable)
    others = sum(fit.component(k, ring.size, pre.fs) for k, m in enumerate(stable) if m is not keep)
    y = pre.y.copy()
    y[pre.impact.ringdown_index :] = ring - fit.constant - others
    return replace(pre, y=y)


def free_decay(pre, stable: list, pole) -> tuple:
    """The free decay of one stable mode, ``(y, t)``: the ring-down with the other stable modes and the
    constant removed (:func:`only`), up to where the mode's fitted envelope falls to :data:`END_SNR_DB`
    over the noise (at least :data:`MIN_PERIODS` of its periods): past it the record is noise, which the
    equation would be fitted to."""
    ring, fit = _components(pre, stable)
    k = next(i for i, m in enumerate(stable) if m is pole)
    y = ring - fit.constant - sum(fit.component(i, ring.size, pre.fs) for i in range(len(stable)) if i != k)
    noise = float(np.sqrt(np.mean(fit.residual**2)))
    stop = ring.size
    if noise > 0 and fit.amplitude[k] > 0 and fit.decay_rate[k] > 0:
        floor = np.sqrt(2) * noise * 10 ** (END_SNR_DB / 20)
        seconds = np.log(fit.amplitude[k] / floor) / fit.decay_rate[k]
        least = MIN_PERIODS * pre.fs / pole.frequency_hz
        stop = int(min(ring.size, max(least, seconds * pre.fs)))
    start = pre.impact.ringdown_index
    return y[:stop], pre.t0 + (start + np.arange(stop)) / pre.fs


@isolated(lambda args: pole_band(args[2]))  # the stable pole's band
def fit_free_decay(pre, stable: list, pole, template, *, index: int = 0):
    """Identify the mode of one stable pole of a short record without band-pass (see the module).

    Returns a :class:`Mode` (the stable pole's frequency and damping ratio, the equation fitted on the
    free decay with the other stable modes removed) or a :class:`Rejected` saying why.
    """
    band = pole_band(pole)
    y, t = free_decay(pre, stable, pole)
    states, states_dot, t = free_decay_states(y, t, pole.frequency_hz)
    model = fresh_copy(template)
    x_dot = states_dot if getattr(model, "differentiation_method", None) is None else None
    fit_deferred(model, states, t=t, x_dot=x_dot, feature_names=list(STATE_NAMES))
    found, reason = _linear_mode(model, band)
    if found is None:
        return Rejected(band, f"the equation fitted on the free decay: {reason}", index)
    frequency, zeta = found
    damped = pole.frequency_hz * np.sqrt(1 - pole.damping_ratio**2)
    fitted = SimpleNamespace(damped_frequency_hz=frequency * np.sqrt(1 - zeta**2), damping_ratio=zeta)
    apart = disagreement(fitted, damped, pole.damping_ratio)
    if not apart <= POLE_AGREEMENT:
        return Rejected(band, f"the equation fitted on the free decay (mode at {frequency:.4g} Hz, damping "
                        f"ratio {zeta:.3g}) disagrees with the stable pole ({apart:.2g} > {POLE_AGREEMENT})",
                        index)
    spread = _uncertainty(model, states, t, band, frequency, filtered=False)
    spread["uncertainty_note"] = "; ".join(filter(None, [spread["uncertainty_note"], (
        f"frequency and damping ratio from the stabilisation diagram's stable pole ({pole.n_orders} orders); "
        f"the equation's linear mode: {frequency:.6g} Hz, damping ratio {zeta:.4g}")]))
    period = max(2, int(round(pre.fs / pole.frequency_hz)))
    return Mode(frequency_hz=float(pole.frequency_hz), damping_ratio=float(pole.damping_ratio), band_hz=band,
                amplitude=float(np.max(np.abs(y[:period]))), fit_error=fit_error_of(model), model=model,
                states=states, t=t, record=index, **spread)


def short_from_poles(pre, short: list, template, index: int, table):
    """Bands refused because the band-pass transient leaves too few periods of a short record (``short``:
    [(band, why)]) identified from the stable modes inside them (:func:`fit_free_decay`); a band without
    one that agrees stays refused. (modes, rejected, notes)."""
    stable = stable_modes(table)
    modes, rejected, notes = [], [], []
    for b, why in short:
        inside = [m for m in stable if b[0] <= m.frequency_hz <= b[1]]
        outs = [fit_free_decay(pre, stable, pole, template, index=index) for pole in inside]
        found = [replace(out, band_hz=tuple(float(x) for x in b)) for out in outs if isinstance(out, Mode)]
        modes += found
        notes += [f"record {index}: band {b[0]:.4g}-{b[1]:.4g} Hz is too short for the band-pass; its stable "
                  f"pole at {m.frequency_hz:.4g} Hz (damping ratio {m.damping_ratio:.3g}) was identified on "
                  "the free decay" + (f", the {len(stable) - 1} other stable mode(s) removed"
                                      * (len(stable) > 1)) for m in found]
        if not found:
            extra = "; ".join(out.reason for out in outs) or "no stable pole inside"
            rejected.append(Rejected(b, f"{why}; without band-pass: {extra}", index))
    return modes, rejected, notes


def from_stable_poles(index, pre, template, table):
    """No spectral peak stands above the noise floor: a short, strongly damped record puts one or two
    spectral bins on a mode. One stable mode: the paper's single-sensor route in its band
    (:func:`.band_fit.fit_direct`); several: each on the free decay with the others removed
    (:func:`fit_free_decay`). (modes, rejected, notes)."""
    found = stable_modes(table)
    if not found:
        return [], [], [f"record {index}: no spectral peak significantly above the noise floor (no stable "
                        "pole either)"]
    if len(found) > 1:
        outs = [fit_free_decay(pre, found, m, template, index=index) for m in found]
    else:
        pole, band = found[0], pole_band(found[0])
        outs = [fit_direct(pre, (band[0], min(band[1], pre.fs / 2)), template, index=index)]
        damped = pole.frequency_hz * np.sqrt(1 - pole.damping_ratio**2)
        if not (isinstance(outs[0], Mode)
                and disagreement(outs[0], damped, pole.damping_ratio) <= MODE_POLE_AGREEMENT):
            other = fit_free_decay(pre, found, pole, template, index=index)
            outs = [other] if isinstance(other, Mode) or not isinstance(outs[0], Mode) else [
                Rejected(outs[0].band_hz, f"the direct fit disagrees with the stable pole; {other.reason}",
                         index)]
    notes = [f"record {index}: no spectral peak above the noise floor; the stabilisation diagram's stable "
             f"mode at {m.frequency_hz:.4g} Hz (damping ratio {m.damping_ratio:.3g}, {m.n_orders} orders) "
             "was identified without band-pass" for m in found]
    return ([o for o in outs if isinstance(o, Mode)], [o for o in outs if not isinstance(o, Mode)], notes)


#: A record is short for a stable mode when its ring-down holds at most this many periods of it (family (d)
#: of ``benchmarks/accuracy/modes.py``: 3-15 periods of the lowest mode, the others up to 4 times higher).
SHORT_PERIODS = 60.0
#: Least damping ratio of a stable mode checked by :func:`checked_by_poles`: below it a band-pass keeps
#: enough of a short record (family (d) draws 0.02-0.25) and the band's own fit stands.
MIN_SHORT_DAMPING = 0.01
#: Largest :func:`disagreement` of a mode of a short record with the stable pole nearest it before the pole
#: is identified on the free decay instead (:func:`checked_by_poles`; family (d) record 20: a joint fit 1.2 %
#: high at a damping ratio of 0.079 was 0.29 from its pole).
MODE_POLE_AGREEMENT = 0.1


def _near(modes: list, pole, stable: list) -> list:
    """The modes within the stable pole's band (:func:`pole_band`) whose nearest stable pole it is."""
    lo, hi = pole_band(pole)
    poles = np.array([m.frequency_hz for m in stable])
    return [m for m in modes if lo <= m.frequency_hz <= hi
            and stable[int(np.argmin(np.abs(np.log(poles / m.frequency_hz))))] is pole]


def checked_by_poles(pre, modes: list, rejected: list, template, index: int, table):
    """On a record short for a strongly damped stable mode (at most :data:`SHORT_PERIODS` of its periods in
    the ring-down, damping ratio at least :data:`MIN_SHORT_DAMPING`):
    the modes near it that disagree with it (:func:`disagreement` over :data:`MODE_POLE_AGREEMENT`), or a
    refused band holding it without a mode near it (not a harmonic), are identified on the free decay
    instead (:func:`fit_free_decay`) when that mode agrees with the pole. (modes, rejected, notes)."""
    stable = stable_modes(table)
    duration = (pre.y.size - pre.impact.ringdown_index) / pre.fs
    notes = []
    for pole in (m for m in stable if m.frequency_hz * duration <= SHORT_PERIODS
                 and m.damping_ratio >= MIN_SHORT_DAMPING):
        damped = pole.frequency_hz * np.sqrt(1 - pole.damping_ratio**2)
        near = _near(modes, pole, stable)
        if any(disagreement(m, damped, pole.damping_ratio) <= MODE_POLE_AGREEMENT for m in near):
            continue
        refused = [r for r in rejected if r.band_hz is not None and "harmonic" not in r.reason
                   and r.band_hz[0] <= pole.frequency_hz <= r.band_hz[1]]
        if not near and not refused:
            continue  # no peak there
        out = fit_free_decay(pre, stable, pole, template, index=index)
        if not isinstance(out, Mode):
            continue
        band = near[0].band_hz if near else refused[0].band_hz
        modes = [m for m in modes if all(m is not x for x in near)] + [replace(out, band_hz=tuple(band))]
        rejected = [r for r in rejected if all(r is not x for x in refused)]
        notes.append(f"record {index}: the stable pole at {pole.frequency_hz:.4g} Hz (damping ratio "
                     f"{pole.damping_ratio:.3g}) of this short record was identified on the free decay "
                     + (f"(the mode at {near[0].frequency_hz:.4g} Hz disagreed with it)" if near
                        else f"(its band was refused: {refused[0].reason})"))
    return modes, rejected, notes

"""The small-amplitude damping ratio of a nonlinear mode whose model lost its amplitude-dependent damping.

A mode's damping ratio is its model's linear damping: the value at vanishing amplitude. When the data's
damping grows with amplitude (a joint, an ``x^2 x'`` damper) but the threshold sweep dropped the term that
says so -- the segment-wise error measure of a long band hardly sees a slow change of the decay rate -- the
linear damping term absorbs the amplitude-dependent part: the reported damping ratio is an average over the
decay, not its small-amplitude value (measured on ``python -m benchmarks modes --family g``, seed 0: +11 %
and +15 % on two lightly damped modes whose damping was 50-70 % higher at the start of the record).

:func:`small_amplitude_damping` checks every mode identified on its ``[y, dy]`` states against their decay
envelope: the decay rate measured over windows of a few periods, regressed on the squared
amplitude (first-order averaging: an ``x^2 x'`` or ``x'^3`` damper adds a rate proportional to ``a^2``), and
the same change predicted by the model's nonlinear terms (their power balance over one period). Where the
data's change over the decay is significant, the model reproduces less than half of it and the
mode is nonlinear by the test for nonlinearity (:attr:`~.result.Mode.nonlinear`, run only on the modes
that pass the first checks: it searches the terms the sweep dropped), the mode's damping ratio becomes the
regression's intercept (the rate at zero amplitude over the model's natural frequency) and its standard
deviation the intercept's; a note says so. The model, its frequency and its verdict stay.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..feature_library.terms import term_table

__all__ = ["envelope_decay", "small_amplitude_damping"]

#: Periods per window of the decay-rate measurement (half-overlapping windows).
WINDOW_PERIODS = 4.0
#: Smallest change of the damping ratio over the decay (relative to its small-amplitude value) acted on.
MIN_CHANGE = 0.05
#: The data's change must exceed this many standard errors.
MIN_SIGNIFICANCE = 1.5
#: The model reproduces less than this share of the data's change: its amplitude-dependent damping is missing.
MODEL_SHARE = 0.5
#: Smallest number of windows, and largest smallest-to-largest squared amplitude, of a usable regression.
MIN_WINDOWS, MAX_RANGE = 8, 0.5


def envelope_decay(y: np.ndarray, dy: np.ndarray, dt: float, omega: float):
    """The decay rate against the squared amplitude of a free decay of one mode: windows of
    :data:`WINDOW_PERIODS` periods of the envelope ``sqrt(y^2 + (dy / omega)^2)``; a straight line of the
    rate (1/s) on the squared amplitude relative to its largest, weighted by the amplitude.

    Returns ``(intercept, slope, intercept_se, slope_se, smallest, largest_amplitude)`` or None when the
    decay is too short or covers too little amplitude (:data:`MIN_WINDOWS`, :data:`MAX_RANGE`).

    Examples
    --------
    >>> t = np.arange(20000) / 2000.0  # a decay rate 0.5 + 2 a^2 (1/s), from a = 1:
    >>> a = np.sqrt(0.5 / ((0.5 + 2.0) * np.exp(2 * 0.5 * t) - 2.0))
    >>> y, dy = a * np.cos(2 * np.pi * 50 * t), -a * 2 * np.pi * 50 * np.sin(2 * np.pi * 50 * t)
    >>> fit = envelope_decay(y, dy, 1 / 2000.0, 2 * np.pi * 50)
    >>> round(fit[0], 1)  # the rate at zero amplitude
    0.5
    """
    amplitude = np.sqrt(y**2 + (dy / omega) ** 2)
    n = max(4, int(round(WINDOW_PERIODS * 2 * np.pi / omega / dt)))
    starts = np.arange(0, amplitude.size - n, max(1, n // 2))
    if starts.size < MIN_WINDOWS or not np.all(amplitude > 0):
        return None
    tt = np.arange(n) * dt
    logs = np.log(amplitude[starts[:, None] + np.arange(n)])
    rate = -np.polyfit(tt, logs.T, 1)[0]
    a2 = np.mean(np.exp(2 * logs), axis=1)
    x = a2 / a2.max()
    if x.min() > MAX_RANGE:
        return None
    w = np.sqrt(x)
    design = np.column_stack([np.ones_like(x), x]) * w[:, None]
    coef, *_ = np.linalg.lstsq(design, rate * w, rcond=None)
    resid = rate * w - design @ coef
    dof = max(1, x.size - 2)
    cov = np.linalg.pinv(design.T @ design) * float(resid @ resid) / dof
    # windows overlap by half: about half as many independent ones
    se = np.sqrt(np.maximum(np.diag(cov), 0) * 2)
    top = float(np.sqrt(a2.max()))
    return float(coef[0]), float(coef[1]), float(se[0]), float(se[1]), float(x.min()), top


def _model_rate_change(model, omega: float, amplitude: float) -> float | None:
    """Change of the decay rate (1/s) the model's nonlinear terms of its ``dy'`` equation give between zero
    amplitude and ``amplitude`` (power balance over one period of ``y = a cos``); None if unknown."""
    try:
        coef = np.asarray(model.coefficients(), float)
        library = getattr(model, "feature_library_", None) or model.feature_library
        terms = term_table(library, coef.shape[0])
    except (AttributeError, TypeError, ValueError):
        return None
    if coef.shape[0] != 2 or terms.powers.shape[1] != 2:
        return None
    theta = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    x, v = amplitude * np.cos(theta), -amplitude * omega * np.sin(theta)
    force = sum(c * x**p * v**q for c, (p, q), lin in zip(coef[1], terms.powers, terms.linear) if not lin)
    return float(-np.mean(force * v) / (2 * np.mean(v**2))) if np.ndim(force) else 0.0


def small_amplitude_damping(modes: list) -> tuple[list, list]:
    """Each mode whose decay shows an amplitude-dependent damping that its model lacks, and that the test
    for nonlinearity calls nonlinear (:attr:`~.result.Mode.nonlinear`, run only on those), gets the
    damping ratio of its envelope at zero amplitude (module docstring): ``(modes, notes)``."""
    out, notes = [], []
    for mode in modes:
        found = _missing_damping(mode)
        if found is None or not mode.nonlinear:
            out.append(mode)
            continue
        zeta, zeta_std, change, model_change = found
        notes.append(
            f"record {mode.record}: mode at {mode.frequency_hz:.6g} Hz: its decay rate changes by "
            f"{change:+.0%} over the decay, its model's terms give {model_change:+.0%}; the damping ratio "
            f"{zeta:.4g} is the decay envelope's at zero amplitude (the model's linear part: "
            f"{mode.damping_ratio:.4g})"
        )
        new = replace(mode, damping_ratio=zeta, damping_ratio_std=zeta_std)
        new.__dict__["nonlinearity"] = mode.nonlinearity  # computed once
        out.append(new)
    return out, notes


def _missing_damping(mode):
    """``(damping ratio at zero amplitude, its std, data's relative change, model's)`` when the mode's
    ``[y, dy]`` states show a significant change of the decay rate over the decay that its model reproduces
    less than :data:`MODEL_SHARE` of; else None."""
    states = np.asarray(mode.states)
    if states.ndim != 2 or states.shape[1] != 2 or mode.coordinate_ != 0 or len(mode.t) < 3:
        return None
    omega = 2 * np.pi * mode.frequency_hz
    fit = envelope_decay(states[:, 0], states[:, 1], float(np.median(np.diff(mode.t))), omega)
    if fit is None:
        return None
    s0, s1, se0, se1, smallest, top = fit
    change = s1 * (1 - smallest)
    model_change = _model_rate_change(mode.model, omega, top)
    if (s0 <= 0 or model_change is None or abs(change) < MIN_SIGNIFICANCE * se1 * (1 - smallest)
            or abs(change) < MIN_CHANGE * s0 or abs(model_change) >= MODEL_SHARE * abs(change)):
        return None
    return s0 / omega, se0 / omega, change / s0, model_change / s0

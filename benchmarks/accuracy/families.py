"""Seeded random hammer-test configurations for the modal-table acceptance study
(benchmarks/accuracy/modes.py).

Each generator takes a numpy Generator and returns a *case*: ``{"family", "config", ...}`` where ``config``
holds the keyword arguments of :func:`sindy_impulse.datasets.impact_record` (frequencies, damping ratios,
amplitudes, fs, duration, sensor, pre-trigger, offset, SNR, seed, and the family's own terms) and the other
keys say how the record is scored (``f_tol`` / ``z_tol`` marks, ``kind`` and ``harmonic`` for family e,
``min_band_snr_db`` for family b). Common to every family unless its line says otherwise: fs one of 1,000,
2,048, 5,000, 10,000 or 25,600 Hz; 2,000-40,000 samples; damping ratios 0.1-3 % (log-uniform); amplitudes
within 20 dB of the strongest; SNR 30-60 dB (white noise, against the RMS of the first 10 % of the
ring-down); offset 0-5x the peak; pre-trigger 0-10 %; displacement, velocity or acceleration sensor; modes
between 2 and 25 % of the Nyquist frequency, at least 3 % apart with non-overlapping half-power bands.

====== ==============================================================================================
family what is drawn
====== ==============================================================================================
a      the study's original records (1-4 modes; :func:`family_a`)
high   (c) 1-3 modes up to fs / 2.56, at least one above fs / 8 (:func:`family_high`)
b      2-4 modes; one at 0 dB, at least one weak mode 20-40 dB below it (each further mode weak or within
       20 dB with even odds). A mode is scored only where its own band SNR (its energy over the noise's in
       its half-power band, at least 3 bins wide) is >= 20 dB (:func:`band_snr_db`)
d      1-3 modes, damping ratios 2-25 % (log-uniform), 3-15 periods of the lowest mode after the hit (at
       12-100 samples per period of the lowest mode, more where needed for at least 150 samples), the
       others 1.1-4 times its frequency (below fs / 4), spacing at least 10 % and the half-power bands
       apart, the three sensors in turn; marks 0.5 % / 10 %. ``benchmarks/accuracy/modes.py`` adds the paper's
       oscillator (seeds 0-99 at 40 dB, ``benchmarks/accuracy/short_decays.py``)
e      a 1:2 or 1:3 near-resonant linear pair (the second frequency 0.5-2 % above or below the exact ratio,
       the second mode 0-20 dB weaker; damping independent, or equal ratios) against one nonlinear
       oscillator with a quadratic spring (its second harmonic 26-40 dB below the fundamental in
       displacement) or a cubic spring (third harmonic 40-50 dB below, hardening or softening); the
       lowest frequency 2-8 % (1:3) or 2-12 % (1:2) of Nyquist. Pairs must give two modes; a harmonic
       record one mode and a rejected row naming ``harmonic 2`` / ``harmonic 3`` where the harmonic's band
       SNR (:func:`harmonic_snr_db`: within 1 % of the harmonic or its half-power band) is >= 20 dB
f      a close pair 1-3 half-power bandwidths apart (``f2 - f1 = k (zeta1 f1 + zeta2 f2)``), amplitudes
       within 10 dB, the record at least 2 / (f2 - f1) long; with even odds a third mode well apart
g      1-4 modes and a nonlinear element at mass 0: a cubic spring (the linear frequency squared moved by
       2-10 % at the initial amplitude, hardening or softening), an amplitude-dependent damper (the damping
       ratio 20-100 % higher at the initial amplitude), or both; scored on the linear (small-amplitude)
       frequency and damping ratio
h      family a's records clipped at 0.3-0.9 of the clean peak (``clip``)
====== ==============================================================================================

:func:`random_config` draws the configurations of the exception run (``python -m benchmarks soak_modes``):
1-4 modes up to fs / 2.56, damping 0.05-8 %, any sensor and sensor mass (or several), offset, pre-trigger,
clipping, white or pink noise at 15-60 dB, nonlinear terms.
"""

from __future__ import annotations

import numpy as np

from sindy_impulse import impact_record

FS_CHOICES = (1000.0, 2048.0, 5000.0, 10000.0, 25600.0)
SENSORS = ("displacement", "velocity", "acceleration")
FAMILIES = ("a", "high", "b", "d", "e", "f", "g", "h")
#: Records per family in the full study (``python -m benchmarks modes --family all``).
FAMILY_SIZES = {"a": 200, "high": 60, "b": 60, "d": 100, "e": 80, "f": 60, "g": 60, "h": 60}


def _log_uniform(rng, low, high, size=None):
    return np.exp(rng.uniform(np.log(low), np.log(high), size))


def _separated(f, z, min_gap=0.03) -> bool:
    """At least ``min_gap`` apart (relative) with non-overlapping half-power bands."""
    return all(
        f[i + 1] / f[i] - 1 >= min_gap and f[i + 1] - f[i] > z[i] * f[i] + z[i + 1] * f[i + 1]
        for i in range(len(f) - 1)
    )


def _record_terms(rng, fs, n_samples, sensor=None) -> dict:
    return dict(
        fs=float(fs),
        duration=n_samples / fs,
        sensor=str(sensor or rng.choice(SENSORS)),
        pre_trigger=float(rng.uniform(0, 0.1)),
        offset=float(rng.uniform(0, 5)),
        snr_db=float(rng.uniform(30, 60)),
        random_state=int(rng.integers(2**31)),
    )


def _case(family, f, z, a, terms, **score) -> dict:
    config = dict(frequencies_hz=[float(v) for v in f], damping_ratios=[float(v) for v in z],
                  amplitudes=[float(v) for v in a], **terms)
    return {"family": family, "config": config, "f_tol": 0.003, "z_tol": 0.10, **score}


def _draw_modes(rng, n_modes, lo, hi, z_range=(1e-3, 3e-2), min_gap=0.03, need_above=None):
    for _ in range(1000):  # the draws in the order of the original families.random_case
        f = np.sort(rng.uniform(lo, hi, n_modes))
        if need_above is not None and f[-1] <= need_above:
            continue
        z = _log_uniform(rng, *z_range, n_modes)
        if _separated(f, z, min_gap):
            break
    return f, z


def family_a(rng: np.random.Generator, high: bool = False) -> dict:
    """Family (a), or (c) with ``high``: the draw of ``families.random_case`` (kept as it was)."""
    n_samples = int(rng.integers(2000, 40001))
    fs = float(rng.choice(FS_CHOICES))
    nyquist = fs / 2
    n_modes = int(rng.integers(1, 4 if high else 5))
    top = 2 / 2.56 if high else 0.25
    f, z = _draw_modes(rng, n_modes, 0.02 * nyquist, top * nyquist,
                       need_above=0.25 * nyquist if high else None)
    a = 10 ** (-rng.uniform(0, 20, n_modes) / 20)
    terms = _record_terms(rng, fs, n_samples)
    return _case("high" if high else "a", f, z, a, terms)


def random_case(rng: np.random.Generator, family: str = "a") -> dict:
    """Parameters of one random record satisfying the study's constraints (family ``"a"`` or ``"high"``;
    the draw is :func:`family_a`)."""
    return family_a(rng, high=family == "high")["config"]


def family_high(rng: np.random.Generator) -> dict:
    """Family (c): 1-3 modes up to fs / 2.56, at least one above fs / 8."""
    return family_a(rng, high=True)


def family_b(rng: np.random.Generator) -> dict:
    """Family (b): weak modes 20-40 dB below the strongest."""
    n_samples = int(rng.integers(2000, 40001))
    fs = float(rng.choice(FS_CHOICES))
    n_modes = int(rng.integers(2, 5))
    f, z = _draw_modes(rng, n_modes, 0.01 * fs, 0.125 * fs)
    levels = [0.0, rng.uniform(20, 40)] + [
        rng.uniform(20, 40) if rng.random() < 0.5 else rng.uniform(0, 20) for _ in range(n_modes - 2)
    ]
    a = 10 ** (-rng.permutation(levels) / 20)
    return _case("b", f, z, a, _record_terms(rng, fs, n_samples), min_band_snr_db=20.0)


def family_d(rng: np.random.Generator, index: int = 0) -> dict:
    """Family (d): short, strongly damped records (sensor ``SENSORS[index % 3]``)."""
    fs = float(rng.choice(FS_CHOICES))
    n_modes = int(rng.integers(1, 4))
    periods = rng.uniform(3, 15)
    pre_trigger = float(rng.uniform(0, 0.1))
    samples_per_period = max(_log_uniform(rng, 12, 100), 150 * (1 - pre_trigger) / periods)
    f1 = fs / samples_per_period
    for _ in range(1000):
        f = f1 * np.concatenate([[1.0], np.sort(rng.uniform(1.1, 4.0, n_modes - 1))])
        z = _log_uniform(rng, 0.02, 0.25, n_modes)
        if f[-1] < 0.25 * fs and _separated(f, z, 0.1):
            break
    else:
        return family_d(rng, index)
    n_samples = int(np.ceil(periods * samples_per_period / (1 - pre_trigger)))
    a = 10 ** (-rng.uniform(0, 20, n_modes) / 20)
    terms = _record_terms(rng, fs, n_samples, sensor=SENSORS[index % 3])
    terms["pre_trigger"] = pre_trigger
    return _case("d", f, z, a, terms, f_tol=0.005, periods=float(periods))


def displacement_amplitude(amplitude: float, f_hz: float, sensor: str) -> float:
    """Displacement amplitude of a mode whose ``sensor`` amplitude is ``amplitude``."""
    return amplitude / (2 * np.pi * f_hz) ** SENSORS.index(sensor)


def _harmonic_case(rng, kind: str) -> dict:
    fs = float(rng.choice(FS_CHOICES))
    f = rng.uniform(0.01, 0.04 if kind == "cubic" else 0.06) * fs
    z = float(_log_uniform(rng, 1e-3, 3e-2))
    terms = _record_terms(rng, fs, int(rng.integers(2000, 40001)))
    omega = 2 * np.pi * f
    a = displacement_amplitude(1.0, f, terms["sensor"])
    if kind == "quadratic":  # 2nd harmonic k2 a^2 / (6 omega^2) = rho a
        rho = 10 ** (-rng.uniform(26, 40) / 20)
        terms["quadratic_stiffness"] = float(rng.choice([-1, 1]) * 6 * omega**2 * rho / a)
    else:  # 3rd harmonic about k3 a^2 / (32 omega^2) = rho a
        rho = 10 ** (-rng.uniform(42, 52) / 20)
        terms["cubic_stiffness"] = float(rng.choice([-1, 1]) * 32 * omega**2 * rho / a**2)
    order = 2 if kind == "quadratic" else 3
    return _case("e", [f], [z], [1.0], terms, kind=kind, harmonic=order,
                 harmonic_db=float(20 * np.log10(rho)))


def family_e(rng: np.random.Generator, index: int = 0) -> dict:
    """Family (e): near-resonant 1:2 / 1:3 pairs, single oscillators with a harmonic (kind by ``index``)."""
    kind = ("pair 1:2", "pair 1:3", "pair 1:2 equal damping", "pair 1:3 equal damping",
            "quadratic", "cubic", "quadratic", "cubic")[index % 8]
    if not kind.startswith("pair"):
        return _harmonic_case(rng, kind)
    ratio = 2 if "1:2" in kind else 3
    fs = float(rng.choice(FS_CHOICES))
    f1 = rng.uniform(0.01, 0.06 if ratio == 2 else 0.04) * fs
    detune = rng.choice([-1, 1]) * rng.uniform(0.005, 0.02)
    f = [f1, ratio * f1 * (1 + detune)]
    z1 = float(_log_uniform(rng, 1e-3, 3e-2))
    z = [z1, z1 if "equal" in kind else float(_log_uniform(rng, 1e-3, 3e-2))]
    a = [1.0, 10 ** (-rng.uniform(0, 20) / 20)]
    terms = _record_terms(rng, fs, int(rng.integers(2000, 40001)))
    return _case("e", f, z, a, terms, kind=kind, detune=float(detune))


def family_f(rng: np.random.Generator) -> dict:
    """Family (f): a close pair 1-3 half-power bandwidths apart, sometimes with a third mode."""
    for _ in range(1000):
        fs = float(rng.choice(FS_CHOICES))
        f1 = rng.uniform(0.01, 0.1) * fs
        z = _log_uniform(rng, 1e-3, 3e-2, 2)
        k = rng.uniform(1, 3)
        f2 = f1 * (1 + k * z[0]) / (1 - k * z[1])  # f2 - f1 = k (z1 f1 + z2 f2)
        shortest = int(np.ceil(2 * fs / (f2 - f1)))
        if shortest <= 40000:
            break
    n_samples = int(rng.integers(max(2000, shortest), 40001))
    f, zz = [f1, f2], list(z)
    if rng.random() < 0.5:
        for _ in range(1000):
            f3 = rng.uniform(0.01, 0.125) * fs
            z3 = float(_log_uniform(rng, 1e-3, 3e-2))
            if _separated(*zip(*sorted([(f1, z[0]), (f3, z3)]))) and _separated(
                    *zip(*sorted([(f2, z[1]), (f3, z3)]))):
                f, zz = f + [f3], zz + [z3]
                break
    a = 10 ** (-rng.uniform(0, 10, len(f)) / 20)
    order = np.argsort(f)
    return _case("f", np.asarray(f)[order], np.asarray(zz)[order], a[order],
                 _record_terms(rng, fs, n_samples), bandwidths=float(k))


def element_displacement(config: dict) -> float:
    """Upper bound of the displacement at the nonlinear element's place (mass 0) after the hit: the sum of
    the modal amplitudes there (:func:`element_shares`)."""
    return float(sum(element_shares(config)))


#: The nonlinear element's coefficients in ``impact_record``'s configuration.
ELEMENT = ("cubic_stiffness", "damping_amplitude")


def lone_mode_record(config: dict, i: int, element_scale: dict | None = None) -> np.ndarray:
    """The record of ``config`` (family g: a nonlinear element at mass 0) with the hit exciting mode ``i``
    only: the same structure (chain, element, sensor), the same noise and offset, every other mode at rest,
    each of the element's coefficients multiplied by its factor in ``element_scale`` (``{name: factor}``).

    ``impact_record`` shapes its chain from the modes' amplitudes, so scaling the other modes' amplitudes
    would change the structure; here the hit's modal gains of the other modes are set to zero instead.
    """
    from dataclasses import replace
    from inspect import signature

    from sindy_impulse.datasets._impact_args import check_impact_args
    from sindy_impulse.datasets.impact import _design_chain, _simulate

    _check_mode(config, i)
    rec = impact_record(**config)
    factors = element_scale or {}
    scaled = dict(config, **{k: config[k] * factors.get(k, 1.0) for k in ELEMENT if config.get(k)})
    defaults = {k: p.default for k, p in signature(impact_record).parameters.items()}
    a = check_impact_args(**{**defaults, **scaled})
    chain, unit = _design_chain(a)
    shapes = chain.mode_shapes.copy()
    others = np.arange(shapes.shape[1]) != i
    shapes[a.tap_dof, others] = 0.0  # no modal gain from the hit: those modes stay at rest
    lone = _simulate(a, replace(chain, mode_shapes=shapes), unit, rec.t)[:, 0]
    return lone + (np.asarray(rec.y, float) - np.asarray(rec.y_clean, float))


def _check_mode(config: dict, i) -> None:
    """``i`` must index a mode of ``config``."""
    n = len(np.atleast_1d(config["frequencies_hz"]))
    if isinstance(i, bool) or not isinstance(i, (int, np.integer)) or not 0 <= i < n:
        raise ValueError(f"mode must be an index of the record's {n} mode(s), got {i!r}")


def element_shares(config: dict) -> np.ndarray:
    """Each mode's displacement amplitude at the element's place (mass 0) at the hit, of a record of
    ``config`` (the linear modal amplitudes there)."""
    linear = {k: v for k, v in config.items() if k not in ("snr_db", "clip", *ELEMENT)}
    rec = impact_record(**linear, sensor_dof=0)
    return np.array([displacement_amplitude(abs(a), f, config["sensor"])
                     for a, f in zip(rec.modes.amplitude, rec.modes.frequency_hz)])


def element_variants(config: dict, i: int) -> dict:
    """Records of ``config`` (family g) that take the element's coupling of the modes away from mode ``i``
    (``{name: (y, fs)}``):

    - ``"alone"``: the hit excites mode ``i`` only (:func:`lone_mode_record`): the element moves it through
      its own amplitude only;
    - ``"alone, element as strong"``: as ``"alone"``, with the element's coefficients multiplied by ``1 + 2
      sum_j a_j**2 / a_i**2`` (``a``: the modes' displacement amplitudes at the element's place at the hit,
      :func:`element_shares`). Averaged, ``k x**3`` moves mode ``i``'s squared frequency by ``3 k / 4
      (a_i**2 + 2 sum_j a_j**2)`` and ``c x**2 x'`` its decay rate by ``c / 8 (a_i**2 + 2 sum_j a_j**2)``
      (each times the mode's shape there squared): the others' amplitudes count twice. So the lone mode is
      moved at the hit as much as in the record, through its own amplitude;
    - ``"no element"``: the record without the element.
    """
    _check_mode(config, i)
    a2 = element_shares(config) ** 2
    if not a2[i] > 0:
        raise ValueError(f"mode {i} does not move the element's place (mass 0): no share to scale by")
    factor = 1.0 + 2.0 * (a2.sum() - a2[i]) / a2[i]
    scale = {k: factor for k in ELEMENT}
    linear = impact_record(**{k: v for k, v in config.items() if k not in ELEMENT})
    fs = float(config["fs"])
    return {"alone": (lone_mode_record(config, i), fs),
            "alone, element as strong": (lone_mode_record(config, i, scale), fs),
            "no element": (np.asarray(linear.y, float), fs)}


def nonlinear_terms(rng: np.random.Generator, config: dict, kinds=("cubic", "damper", "both")) -> dict:
    """A cubic spring moving the lowest mode's frequency squared by 2-10 % (hardening or softening) at the
    initial amplitude of mass 0, an amplitude-dependent damper raising its damping ratio by 20-100 %, or
    both."""
    kind = str(rng.choice(kinds))
    a0 = element_displacement(config)
    omega = 2 * np.pi * config["frequencies_hz"][0]
    zeta = config["damping_ratios"][0]
    terms = {}
    if kind in ("cubic", "both"):
        shift = rng.uniform(0.02, 0.10) * rng.choice([-1, 1])
        terms["cubic_stiffness"] = float(4 / 3 * shift * omega**2 / a0**2)
    if kind in ("damper", "both"):
        terms["damping_amplitude"] = float(8 * omega * zeta * rng.uniform(0.2, 1.0) / a0**2)
    return terms


def family_g(rng: np.random.Generator) -> dict:
    """Family (g): 1-4 modes with a nonlinear element at mass 0."""
    case = family_a(rng)
    case["family"] = "g"
    case["config"].update(nonlinear_terms(rng, case["config"]))
    return case


def family_h(rng: np.random.Generator) -> dict:
    """Family (h): family a's records clipped at 0.3-0.9 of the clean peak."""
    case = family_a(rng)
    case["family"] = "h"
    case["config"]["clip"] = float(rng.uniform(0.3, 0.9))
    return case


def draw(family: str, rng: np.random.Generator, index: int = 0) -> dict:
    """One case of ``family`` (one of :data:`FAMILIES`); ``index`` rotates the sensor (d) or kind (e)."""
    if family in ("d", "e"):
        return {"d": family_d, "e": family_e}[family](rng, index)
    return {"a": family_a, "high": family_high, "b": family_b, "f": family_f, "g": family_g,
            "h": family_h}[family](rng)


def band_snr_db(rec) -> np.ndarray:
    """Per mode: its energy over the noise's in its half-power band (at least 3 FFT bins), in dB (channel 0;
    the record unclipped)."""
    y = rec.y if rec.y.ndim == 1 else rec.y[:, 0]
    clean = rec.y_clean if rec.y_clean.ndim == 1 else rec.y_clean[:, 0]
    noise = np.fft.rfft(y - np.atleast_1d(rec.offset)[0] - clean)
    freqs = np.fft.rfftfreq(y.size, 1 / rec.fs)
    tau = rec.t - rec.onset_time
    out = []
    for row in rec.modes:
        amp, phase = np.atleast_1d(row.amplitude)[0], np.atleast_1d(row.phase)[0]
        sigma = row.damping_ratio * 2 * np.pi * row.frequency_hz
        s = np.where(tau >= 0, amp * np.exp(-sigma * np.clip(tau, 0, None))
                     * np.cos(2 * np.pi * row.damped_frequency_hz * tau + phase), 0.0)
        half = max(row.damping_ratio * row.frequency_hz, 1.5 * rec.fs / y.size)
        band = np.abs(freqs - row.damped_frequency_hz) <= half
        signal = np.sum(np.abs(np.fft.rfft(s)[band]) ** 2)
        out.append(10 * np.log10(signal / max(np.sum(np.abs(noise[band]) ** 2), 1e-300)))
    return np.asarray(out)


def _band_energy(rec, centre: float, half: float, of_noise: bool = False) -> float:
    """Energy of the clean ring-down (or of the noise) of channel 0 within ``centre -+ half`` Hz."""
    y = rec.y if rec.y.ndim == 1 else rec.y[:, 0]
    clean = rec.y_clean if rec.y_clean.ndim == 1 else rec.y_clean[:, 0]
    if of_noise:
        x = y - np.atleast_1d(rec.offset)[0] - clean
    else:
        start = int(np.searchsorted(rec.t, rec.onset_time))
        x = np.where(np.arange(y.size) >= start, clean - np.mean(clean[start:]), 0.0)
    band = np.abs(np.fft.rfftfreq(y.size, 1 / rec.fs) - centre) <= half
    return float(np.sum(np.abs(np.fft.rfft(x)[band]) ** 2))


def harmonic_snr_db(rec, order: int) -> float:
    """Is the harmonic there to be named? The energy that the nonlinear terms add to the clean record in a
    band about ``order`` times its single mode's frequency (the record's minus that of the same record
    without them: the mode's own spectral skirt left out), over the noise's in that band, in dB (channel
    0). The band: ``order`` times the mode's half-power band, at least 1 % of the harmonic and 3 bins."""
    f, zeta = float(rec.modes.frequency_hz[0]), float(rec.modes.damping_ratio[0])
    half = max(order * zeta * f, 1.5 * rec.fs / rec.t.size, 0.01 * order * f)
    linear = impact_record(**{k: v for k, v in rec.params.items() if k in _LINEAR_ARGS})
    added = _band_energy(rec, order * f, half) - _band_energy(linear, order * f, half)
    noise = _band_energy(rec, order * f, half, of_noise=True)
    return float(10 * np.log10(max(added, 1e-300) / max(noise, 1e-300)))


_LINEAR_ARGS = ("frequencies_hz", "damping_ratios", "amplitudes", "fs", "duration", "sensor",
                "pre_trigger", "offset", "contact_time", "force_amplitude", "double_hit")


def random_config(seed: int) -> dict:
    """Keyword arguments of one random ``impact_record`` for the exception run (module docstring)."""
    rng = np.random.default_rng(seed)
    fs = float(rng.choice(FS_CHOICES))
    n_modes = int(rng.integers(1, 5))
    for _ in range(1000):
        f = np.sort(rng.uniform(0.002 * fs, fs / 2.56, n_modes))
        if n_modes == 1 or np.min(np.diff(f) / f[1:]) > 2e-3:
            break
    config = dict(
        frequencies_hz=f.tolist(), damping_ratios=_log_uniform(rng, 5e-4, 8e-2, n_modes).tolist(),
        amplitudes=(10 ** (-rng.uniform(0, 30, n_modes) / 20)).tolist(), fs=fs,
        duration=int(rng.integers(500, 40001)) / fs, sensor=str(rng.choice(SENSORS)),
        pre_trigger=float(rng.uniform(0, 0.3)), offset=float(rng.uniform(0, 10)),
        snr_db=float(rng.uniform(15, 60)), noise=str(rng.choice(["white", "pink"])), random_state=seed,
    )
    if n_modes > 1 and rng.random() < 0.3:
        config["tap_dof"] = int(rng.integers(n_modes))
        config["sensor_dof"] = ([int(d) for d in rng.permutation(n_modes)[: rng.integers(1, n_modes + 1)]]
                                if rng.random() < 0.5 else int(rng.integers(n_modes)))
    if rng.random() < 0.3:
        config["clip"] = float(rng.uniform(0.3, 1.0))
    if rng.random() < 0.3:
        linear = {k: v for k, v in config.items() if k not in ("sensor_dof", "tap_dof")}
        config.update(nonlinear_terms(rng, linear))
    return config

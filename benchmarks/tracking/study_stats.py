"""The tracker's tests by simulation, without surveys: is the false-alarm rate the one asked?

**One test** (:func:`one_test`): 20 reference values and a new one, each test's ± following a hit
strength log-uniform in 0.5-2 (so they differ fourfold), the true noise ``calibration`` times the ± plus
a scatter ``tau`` the ± do not know, or the ± missing. The rate of p < 1 % and of p < 0.0625 % (one test
in a family of 16) against the nominal, and the share of new values shifted by five of their true
standard deviations that are flagged at 0.0625 %, beside the textbook prediction interval's (which is
exact only when the scatter is the same for every test).

**Whole surveys** (:func:`whole_track`): :func:`sindy_impulse.tracking.track` on sequences of 20 + 40
surveys of a 4-mode structure (a common 0.03 % frequency scatter, damping ratios scattering 2 %, the ±
following the hit strength) with the ± right, missing, three times too small or too large: the share of
new surveys flagged at 1 % (the family of 16 tests corrected by Holm) and of sequences with a trend; and
a drift of the second mode's frequency of -0.003 % per new survey (a tenth of the scatter; -0.12 % after
40), which single tests hardly see and the trend should.
"""

from __future__ import annotations

import numpy as np

SCENARIOS = {  # name: (± given, tau, calibration)
    "± missing, scatter the same for every test": (False, 0.0, 1.0),
    "± right, no other scatter": (True, 0.0, 1.0),
    "± right, scatter = ±": (True, 1.0, 1.0),
    "± right, scatter = 10 x ±": (True, 10.0, 1.0),
    "± right, scatter = 50 x ±": (True, 50.0, 1.0),
    "± 3 x too small": (True, 0.0, 3.0),
    "± 10 x too small": (True, 0.0, 10.0),
    "± 3 x too large": (True, 0.0, 1 / 3),
    "± 3 x too small, scatter = ±": (True, 1.0, 3.0),
    "± missing, noise following the hit": ("proxy", 0.0, 1.0),
}


def _draw(rng, n_rows: int, n: int, given, tau: float, calibration: float):
    s = 1 / np.exp(rng.uniform(np.log(0.5), np.log(2), (n_rows, n + 1)))
    if given is False:
        return rng.standard_normal((n_rows, n + 1)), s
    return rng.standard_normal((n_rows, n + 1)) * np.sqrt(tau**2 + (calibration * s) ** 2), s


def _p(x, s, given, n: int, shift=0.0):
    from sindy_impulse.tracking.statistics import fit_scatter, fit_scatter_rows, prediction_test

    if given is True:
        return prediction_test(fit_scatter_rows(x[:, :n], s[:, :n]), x[:, n] + shift, s[:, n])[1]
    if given is False:
        return prediction_test(fit_scatter_rows(x[:, :n]), x[:, n] + shift)[1]
    out = np.empty(x.shape[0])  # the stand-in proportional to the noise: one reference at a time
    for i in range(x.shape[0]):
        ref = fit_scatter(x[i, :n], np.full(n, np.nan), proxy=s[i, :n])
        new = x[i, n] + (shift[i] if np.ndim(shift) else shift)
        out[i] = prediction_test(ref, [new], [np.nan], [s[i, n]])[1][0]
    return out


def one_test(reps: int = 100_000, n: int = 20, seed: int = 0) -> dict:
    rng = np.random.default_rng(seed)
    out = {}
    for name, (given, tau, k) in SCENARIOS.items():
        m = reps if given != "proxy" else min(reps, 20_000)
        x, s = _draw(rng, m, n, given, tau, k)
        sd = np.sqrt(tau**2 + (k * s[:, n]) ** 2) if given is not False else np.ones(m)
        p0, p5 = _p(x, s, given, n), _p(x, s, given, n, shift=5 * sd)
        from sindy_impulse.tracking.statistics import fit_scatter_rows, prediction_test

        textbook = prediction_test(fit_scatter_rows(x[:, :n]), x[:, n] + 5 * sd)[1]
        out[name] = {
            "reps": m,
            "fa_1pct": float(np.mean(p0 < 0.01)),
            "fa_tail": float(np.mean(p0 < 0.000625)),
            "power_5sd": float(np.mean(p5 < 0.000625)),
            "textbook_power_5sd": float(np.mean(textbook < 0.000625)),
        }
    return out


def synthetic_survey(rng, f0, calibration, missing, factor, drift=0.0):
    from sindy_impulse.tracking import ModeValues, SurveyValues

    strength = np.exp(rng.uniform(np.log(0.5), np.log(2)))
    modes = []
    for f in f0:
        f_std, z_std = 2e-5 * f / strength, 1e-3 * 0.01 / strength
        fr = f * factor * (1 + drift if f == f0[1] else 1) + calibration * f_std * rng.standard_normal()
        zeta = 0.01 * (1 + 0.02 * rng.standard_normal()) + calibration * z_std * rng.standard_normal()
        if missing:
            f_std = z_std = np.nan
        modes.append(ModeValues(fr, f_std, zeta, z_std, strength, 40 + 20 * np.log10(strength)))
    return SurveyValues(modes)


def whole_track(n_sequences: int = 200, seed: int = 1) -> dict:
    from sindy_impulse.tracking import track

    rng = np.random.default_rng(seed)
    f0 = (90.0, 210.0, 340.0, 515.0)
    out = {}
    for name, (calibration, missing, rate) in {
        "± right": (1.0, False, 0.0),
        "± missing": (1.0, True, 0.0),
        "± 3 x too small": (3.0, False, 0.0),
        "± 3 x too large": (1 / 3, False, 0.0),
        "slow drift, -0.003 % per survey": (1.0, False, -3e-5),
    }.items():
        flagged, trends = [], 0
        for _ in range(n_sequences):
            surveys = [
                synthetic_survey(rng, f0, calibration, missing, 1 + 3e-4 * rng.standard_normal(),
                        rate * max(k - 19, 0)) for k in range(60)
            ]
            result = track(surveys, reference=20)
            flagged.append(result.changed[20:].mean())
            trends += bool(result.trend_alarms)
        out[name] = {
            "sequences": n_sequences,
            "flagged": float(np.mean(flagged)),
            "trend": trends / n_sequences,
        }
    return out


def print_tables(one: dict, whole: dict) -> None:
    print("  one test against 20 reference values (nominal 1 % and 0.0625 %):")
    for name, v in one.items():
        print(
            f"    {name:45s} p<1 %: {100 * v['fa_1pct']:.2f} %   p<0.0625 %: {100 * v['fa_tail']:.3f} % "
            f"({v['fa_tail'] / 0.000625:.2f} x)   flags a 5-sd shift: {100 * v['power_5sd']:.1f} % "
            f"(textbook {100 * v['textbook_power_5sd']:.1f} %)  [{v['reps']} draws]"
        )
    print("  track() on 20 + 40 surveys of 4 modes (nominal 1 % per survey, 1 % per sequence for trends):")
    for name, v in whole.items():
        print(
            f"    {name:20s} flagged {100 * v['flagged']:.2f} % of new surveys, trend in "
            f"{100 * v['trend']:.1f} % of {v['sequences']} sequences"
        )

"""A prototype for family g: every candidate of a record read together under one nonlinear element's
first-order coupling, its values taken where that reading moves them beyond their errors.

Not used by the survey: it measures whether the model the missed records ask for
(``docs/modal-families-results.md``, "Why family g's records are missed") recovers them. One cubic spring
or amplitude-dependent damper at one place moves mode ``k``'s frequency and decay rate by ``C_km a_m^2``
and ``D_km a_m^2`` (``a_m`` mode ``m``'s measured amplitude), with ``C_km = (2 - delta_km) G_k E_m`` and
``D_km = (2 - delta_km) H_k E_m``. The reading fits, to the record's free decay with the hidden components
removed, ``y(t) = sum_k Re[c_k exp(-sigma_k t + i omega_k t + sum_m (2 - delta_km) (i G_k - H_k) E_m
I_m(t))]``, ``I_m`` the integral of mode ``m``'s linear squared amplitude, by Gauss-Newton from the
candidates' linear decays (``G = H = 0``, ``E = 1``): ``3 n`` parameters beyond the linear ones, where the
survey's joint reading (:func:`sindy_impulse.modes._envelope.joint_dependence`) fits each ``C_km`` and
``D_km`` as a free term.

In a record where the survey classifies a candidate nonlinear (2-6 candidates that decay), and where the
reading describes the decay (its residual at most 3 times the noise), a mode's frequency and damping ratio
are replaced by the reading's when either moved by more than ``--sigmas`` of the reading's standard
deviations. The benchmark counts family g's records right (the modes benchmark's marks) with the survey's
values and with these.

Measured at seed 131 (100 records, the seed it was written on): the survey 85 right; with the reading at
3 standard deviations 87 (7 records gained, 5 lost), at 5 86, at 8 85. At 3 standard deviations on the
seeds it was not written on: 197 88 -> 88 (4 gained, 4 lost), 199 88 -> 92 (5, 1), 211 94 -> 96 (4, 2).

    python -m benchmarks one_element --seed 131 --n 100 --sigmas 3
"""

from __future__ import annotations

import argparse
import warnings

import numpy as np

from benchmarks.accuracy.families import draw
from benchmarks.accuracy.scoring import judge
from sindy_impulse import identify_modes, impact_record
from sindy_impulse.modes._envelope import ENVELOPE_MISFIT, _joint_stride, _linear_integral, _scaled_normal
from sindy_impulse.modes.band_fit import default_estimator
from sindy_impulse.modes.classify import MAX_TOGETHER, _audible
from sindy_impulse.modes.kinds import Kind
from sindy_impulse.modes.pipeline import Pipeline
from sindy_impulse.modes.signals import deflated
from sindy_impulse.modes.survey import SURVEY, SurveyOptions, SurveyState

#: Gauss-Newton steps at most (a step that does not lower the residual is halved, up to 4 times each).
ITERATIONS = 40


def one_element_reading(y: np.ndarray, fs: float, components: list) -> dict:
    """The reading of the module on the free decay ``y`` of ``components`` (``(complex amplitude, decay
    rate, damped frequency_hz)`` of each one's linear decay): per component the small-amplitude
    ``frequency_hz`` and ``damping_ratio`` with their standard deviations, and the residual's RMS."""
    stride = _joint_stride(fs, components, y.size)
    y, fs = np.asarray(y, float)[::stride], fs / stride
    t = np.arange(y.size) / fs
    n = len(components)
    integrals = np.array([_linear_integral(abs(complex(c)) ** 2, rate, t) for c, rate, _ in components])
    weight = 2.0 - np.eye(n)  # (2 - delta_km)
    x = np.concatenate([np.concatenate([[complex(c).real, complex(c).imag, rate, 2 * np.pi * f]
                                        for c, rate, f in components]), np.zeros(2 * n), np.ones(n)])

    def signals(x):
        amplitudes = x[0:4 * n:4] + 1j * x[1:4 * n:4]
        pull, drive = x[4 * n:5 * n] * 1j - x[5 * n:6 * n], x[6 * n:]
        coupling = (weight * pull[:, None] * drive) @ integrals
        exponents = np.outer(-x[2:4 * n:4] + 1j * x[3:4 * n:4], t) + coupling
        with np.errstate(over="ignore", invalid="ignore"):
            return amplitudes[:, None] * np.exp(exponents)

    def jacobian(x, ce):
        amplitudes = x[0:4 * n:4] + 1j * x[1:4 * n:4]
        z = ce / np.where(amplitudes == 0, 1, amplitudes)[:, None]
        pull, drive = x[4 * n:5 * n] * 1j - x[5 * n:6 * n], x[6 * n:]
        columns = []
        for k in range(n):
            columns += [z[k].real, -z[k].imag, -t * ce[k].real, -t * ce[k].imag]
        moved = (weight * drive) @ integrals  # d exponent_k / d pull_k
        columns += [(1j * moved[k] * ce[k]).real for k in range(n)]
        columns += [(-moved[k] * ce[k]).real for k in range(n)]
        columns += [sum((weight[k, m] * pull[k] * integrals[m] * ce[k]).real for k in range(n))
                    for m in range(n)]
        return np.column_stack(columns)

    cost, best, step = np.inf, None, None
    for _ in range(4 * ITERATIONS):
        ce = signals(x)
        with np.errstate(over="ignore", invalid="ignore"):
            residual = y - ce.real.sum(axis=0)
            new = float(residual @ residual)
        if not np.isfinite(new) or new > cost:
            if step is None:
                break
            step = step / 2
            x = best[0] + step
            continue
        settled = cost - new < 0.1 * new / y.size
        cost, best = new, (x, residual, ce)
        if settled:
            break
        normal, scale, scaled = _scaled_normal(jacobian(x, ce), scaled=True)
        step = np.linalg.lstsq(normal, scaled.T @ residual, rcond=1e-10)[0] / scale  # (G E: one scale free)
        x = x + step
    x, residual, ce = best
    normal, scale = _scaled_normal(jacobian(x, ce))
    cov = np.linalg.pinv(normal) / np.outer(scale, scale) * (cost / max(y.size - x.size, 1))
    sd = np.sqrt(np.abs(np.diag(cov)))
    sigma, omega = x[2:4 * n:4], x[3:4 * n:4]
    wn = np.hypot(omega, sigma)
    return {"frequency_hz": wn / (2 * np.pi), "damping_ratio": sigma / wn,
            "frequency_std_hz": sd[3:4 * n:4] / (2 * np.pi), "damping_ratio_std": sd[2:4 * n:4] / wn,
            "rms": float(np.sqrt(np.mean(residual**2)))}


def with_one_element(rec, sigmas: float) -> tuple[list, list]:
    """The survey's (frequency, damping ratio) per mode of ``rec``, and the same with the reading's values
    where the module takes them."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        found = [(m.frequency_hz, m.damping_ratio) for m in identify_modes(rec.y, fs=rec.fs).modes]
        state = SurveyState(0, np.asarray(rec.y, float)[:, None], None, rec.fs, None,
                            SurveyOptions(template=default_estimator()))
        Pipeline(SURVEY[:4])(state)  # read, poles, candidates, classify
    cands = state.candidates
    read = [k for k, c in enumerate(cands) if c.kind in (Kind.NONLINEAR, Kind.LINEAR) and c.decay_rate > 0]
    if not any(cands[k].kind is Kind.NONLINEAR for k in read) or not 2 <= len(read) <= MAX_TOGETHER:
        return found, found
    n = state.pre.y.size - state.start
    stop = max(min(_audible(cands[k], state.pre.fs) or n, n) for k in read)
    y = deflated(state, read[0], keep=read[1:])[state.start:][:stop]
    reading = one_element_reading(y, state.pre.fs, [(complex(cands[k].amplitude[0]), cands[k].decay_rate,
                                                     cands[k].damped_frequency_hz) for k in read])
    if not reading["rms"] <= ENVELOPE_MISFIT * min(cands[k].noise_std for k in read):
        return found, found
    out = list(found)
    for i, k in enumerate(read):
        near = [abs(g / cands[k].frequency_hz - 1) for g, _ in found]
        if not near or min(near) >= 0.01:
            continue
        j = int(np.argmin(near))
        f, z = reading["frequency_hz"][i], reading["damping_ratio"][i]
        if (abs(f - found[j][0]) > sigmas * reading["frequency_std_hz"][i]
                or abs(z - found[j][1]) > sigmas * reading["damping_ratio_std"][i]):
            out[j] = (float(f), float(z))
    return found, out


def right(case: dict, found: list) -> bool:
    """Every mode within the case's marks and no spurious one (the modes benchmark's :func:`judge`)."""
    f_true, z_true = case["config"]["frequencies_hz"], case["config"]["damping_ratios"]
    return judge(case, f_true, z_true, np.ones(len(f_true), bool), found)["passed"]


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--n", type=int, default=100, help="records of family g (default 100)")
    parser.add_argument("--quick", action="store_true", help="10 records")
    parser.add_argument("--sigmas", type=float, default=3.0, help="standard deviations a value must move")
    args = parser.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    records, survey, reading, changed = 0, 0, 0, []
    for index in range(10 if args.quick else args.n):
        case = draw("g", rng, index)
        try:
            rec = impact_record(**case["config"])
        except ValueError:  # as the modes benchmark: a record the generator refuses is left out
            continue
        found, out = with_one_element(rec, args.sigmas)
        a, b = right(case, found), right(case, out)
        records, survey, reading = records + 1, survey + a, reading + b
        if a != b:
            changed.append(index)
            print(f"  [g #{index}] survey {'right' if a else 'WRONG'}, with the reading "
                  f"{'right' if b else 'WRONG'}", flush=True)
    print(f"family g, seed {args.seed}: {records} records; right with the survey's values {survey}, with the "
          f"one-element reading's where they moved beyond {args.sigmas:g} std {reading}")
    return {"seed": args.seed, "records": records, "survey_right": survey, "reading_right": reading,
            "changed": changed}


if __name__ == "__main__":
    main()

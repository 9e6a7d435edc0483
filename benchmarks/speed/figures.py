"""The speed figures of ``benchmarks/speed/speed.py``: each returns rows ``(figure, ours, baseline, ratio,
goal)``.

Every figure is measured beside a baseline in the same run (so a busy machine shifts both): PySINDy's
``simulate`` of the same model, a minimal hand-written numba RK4, a plain Python loop, one pass of numpy
over the record, or the same work with one worker.
"""

from __future__ import annotations

import time
import warnings
from pathlib import Path

import numpy as np
import pysindy as ps

from benchmarks.speed.cases import (
    PeakMemory,
    best_of,
    feature_study,
    issue26_records,
    long_record,
    median_beside,
    two_dof,
)
from benchmarks.speed.reference import minimal_rk4, python_rk4
from sindy_impulse import ImpulseSINDy, SINDyFeatures, damped_oscillator, identify_modes, impact_record
from sindy_impulse.analysis import esprit
from sindy_impulse.simulation import integrators
from sindy_impulse.simulation.compile import _FIRST, _NO_WEIGHTS
from sindy_impulse.simulation.program import pack, propagators
from sindy_impulse.simulation.two_state_cubic import dense_coefficients, integrate_cubic2


def _pysindy_simulate_time(model: ImpulseSINDy, x0, t) -> float:
    """One ``pysindy.SINDy.simulate`` of the model's coefficients (the baseline of a fit)."""
    lib = ps.PolynomialLibrary(degree=3)
    plain = ps.SINDy(feature_library=lib, optimizer=ps.STLSQ(threshold=0.0))
    x = model.x_filtered_
    plain.fit(x, t=model.t_, x_dot=model.model_.rhs(x))
    plain.optimizer.coef_ = np.asarray(model.coefficients(), dtype=float).copy()
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        plain.simulate(x0, t)
    return time.perf_counter() - start


def _kernel_call(model, t, force_stages: bool = False):
    """The bare kernel call of ``model.simulate(x0, t)`` (arrays prepared once): ``integrate_cubic2`` for
    a two-state cubic model, as ``CompiledModel`` does."""
    steps = model.substeps(t)
    prog, vals = pack(model.program, model.coef[None])
    dt = float(t[1] - t[0])
    props = propagators(model.program, model.coef[None], dt, steps)
    props = integrators.NO_PROPAGATOR if force_stages else props
    x0 = np.array([[1.0, 0.0]])
    out, errors, rows = np.empty((len(t), 2)), np.empty(1), np.empty(1, dtype=np.int64)
    bound = model.bound * 10
    if model._dense_positions is not None:
        dense = dense_coefficients(model.coef[None], model._dense_positions)

        def call():
            integrate_cubic2(x0, t, _FIRST, _NO_WEIGHTS, steps, props, dense, bound, model._scratch, out,
                             errors, rows)
    else:

        def call():
            integrators.integrate(
                x0, t, _FIRST, _NO_WEIGHTS, steps, prog, vals, props, bound, integrators.NO_INPUT,
                model._scratch, out, errors, rows,
            )  # fmt: skip

    return call, steps


def simulation(quick: bool) -> list:
    """One simulation of the paper's 3-term model and of a 4-term Duffing model, 401 samples."""
    t = np.arange(401) * 0.01
    rows = []
    for label, k_nl in (("3-term linear", 0.0), ("4-term Duffing", 10.0)):
        ring = damped_oscillator(k_nl=k_nl)
        fitted = ImpulseSINDy().fit(ring.x, t=ring.t, x_dot=ring.x_dot)
        model = fitted.model_
        names, coef = fitted.get_feature_names(), fitted.coefficients()
        truth = {key: coef[row, names.index(term)] for key, row, term in
                 (("a", 0, "x1"), ("b", 1, "x0"), ("c", 1, "x1"), ("d", 1, "x0^3"))}
        call, steps = _kernel_call(model, t)
        same = np.max(np.abs(fitted.simulate([1.0, 0.0], t) - minimal_rk4(truth, [1.0, 0.0], t, steps)))
        rows += _simulation_rows(f"{label}, max difference {same:.0e}", fitted, truth, call, steps, quick)
    return rows


def _simulation_rows(label, fitted, truth, call, steps, quick) -> list:
    t = np.arange(401) * 0.01
    repeat, number = (3, 200) if quick else (7, 1000)
    reference = best_of(lambda: minimal_rk4(truth, [1.0, 0.0], t, steps), repeat, number)
    kernel = best_of(call, repeat, number)
    public = best_of(lambda: fitted.simulate([1.0, 0.0], t), repeat, number // 4)
    naive = best_of(lambda: python_rk4(truth, [1.0, 0.0], t, steps), 1, 2)
    pysindy = _pysindy_simulate_time(fitted, [1.0, 0.0], t)
    name = f"simulate {label} ({steps} RK4 sub-steps/sample)"
    rows = [(f"{name}: kernel / minimal numba RK4", kernel, reference, kernel / reference, "<= 1.5")]
    if fitted.model_.is_linear:
        stages = best_of(_kernel_call(fitted.model_, t, force_stages=True)[0], repeat, number)
        rows.append((f"{name}: kernel stage by stage / minimal RK4", stages, reference, stages / reference,
                     "(info)"))
    return rows + [
        (f"{name}: public simulate() / minimal RK4", public, reference, public / reference,
         "(reported: validation included)"),
        (f"{name}: public simulate() vs PySINDy simulate", public, pysindy, pysindy / public, "(x faster)"),
        (f"{name}: public simulate() vs Python loop RK4", public, naive, naive / public, "(x faster)"),
    ]


def paper_fit(quick: bool) -> list:
    """Fits of the paper's oscillator at 40 dB (warm process)."""
    seeds = range(3 if quick else 11)
    times = []
    for seed in seeds:
        ring = damped_oscillator(snr_db=40, random_state=seed)
        start = time.perf_counter()
        model = ImpulseSINDy().fit(ring.x, t=ring.t)
        times.append(time.perf_counter() - start)
    base = _pysindy_simulate_time(model, ring.x[0], ring.t)
    median = float(np.median(times))
    name = "fit, paper's oscillator 40 dB (median, warm) vs one PySINDy simulate"
    return [(name, median, base, base / median, "(x faster)")]


def many_states(quick: bool) -> list:
    """The 4-state 2-DOF fit, 1500 samples, clean and at 40 dB."""
    rows = []
    for snr in (None, 40):
        t, x = two_dof(snr_db=snr)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            model = ImpulseSINDy().fit(x, t=t)  # (also loads the kernels)
            elapsed = best_of(lambda x=x, t=t: ImpulseSINDy().fit(x, t=t), 1 if quick else 3)
        cut = ", CUT SHORT" if any("budget" in str(w.message) for w in caught) else ""
        base = _pysindy_simulate_time(model, x[0], t)
        label = "clean" if snr is None else f"{snr} dB"
        name = (f"fit 2-DOF, 4 states, 1500 samples, {label}: {model.complexity} terms, budget used "
                f"{model.budget_used_:.0%}{cut} vs one PySINDy simulate")
        rows.append((name, elapsed, base, base / elapsed, "<= 0.5 s (40 dB)"))
    return rows


def long_records(quick: bool) -> list:
    """The paper's oscillator over 4 s at growing sampling rates (40 dB): time, memory, model."""
    rows = []
    reference = ImpulseSINDy().fit(*reversed(long_record(401)))
    ref_k = -reference.coefficients()[1, 1]
    for n in (10_001, 100_001) + (() if quick else (1_000_001,)):
        t, x = long_record(n)
        with PeakMemory() as memory:
            start = time.perf_counter()
            model = ImpulseSINDy().fit(x, t=t)
            elapsed = time.perf_counter() - start
        one_pass = best_of(lambda x=x, t=t: np.gradient(x, t, axis=0), 3)
        k = -model.coefficients()[1, 1]
        same = "same" if model.complexity == reference.complexity else "NOT the same"
        name = (f"fit {n - 1:,} samples (dt = {4 / (n - 1):.0e} s): +{memory.extra_mb:.0f} MB, "
                f"{model.complexity} terms ({same} model as dt = 0.01, k {k:.2f} vs {ref_k:.2f}) vs one "
                "np.gradient pass")
        goal = "<= 5 s, <= 300 MB" if n > 500_000 else "linear in n"
        rows.append((name, elapsed, one_pass, elapsed / one_pass, goal))
    return rows


def feature_study_rows(quick: bool) -> list:
    """The paper's Fig. 14 feature study with SINDyFeatures, 2 processes against 1 (fresh worker pool)."""
    from joblib.externals.loky import get_reusable_executor

    series = feature_study(24 if quick else 80)
    timings = {}
    for n_jobs in (1, 2):
        get_reusable_executor().shutdown(wait=True)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            start = time.perf_counter()
            SINDyFeatures(dt=0.01, n_jobs=n_jobs).fit_transform(series)
            timings[n_jobs] = time.perf_counter() - start
    name = f"feature study, {len(series)} ring-downs, n_jobs=2 (fresh workers) vs n_jobs=1"
    return [(name, timings[2], timings[1], timings[1] / timings[2], "<= 5 s (80 series)")]


def _survey_record():
    """A 3 s hammer test at 5 kHz with two modes (120 and 240 Hz; 0.05 % and 0.2 % damping), 45 dB."""
    return impact_record([120.0, 240.0], [5e-4, 2e-3], amplitudes=[1.0, 0.5], fs=5000.0, duration=3.0,
                         sensor="velocity", offset=2.0, pre_trigger=0.05, snr_db=45, random_state=0)


def _cold_survey() -> float:
    """``identify_modes`` on the survey record in a fresh process (import excluded; kernels cached)."""
    import subprocess
    import sys

    code = (
        "import time, warnings; warnings.simplefilter('ignore'); import benchmarks.speed.figures as p; "
        "rec = p._survey_record(); s = time.perf_counter(); "
        "p.identify_modes(rec.y, fs=rec.fs); print(time.perf_counter() - s)"
    )
    root = Path(__file__).resolve().parents[2]  # the folder holding the benchmarks package
    out = subprocess.run([sys.executable, "-c", code], cwd=root, capture_output=True, text=True, check=True)
    return float(out.stdout.strip().splitlines()[-1])


def modal_survey(quick: bool) -> list:
    """The two-mode survey, warm (median) and in a fresh process, against ESPRIT on the same record."""
    rec = _survey_record()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        survey = identify_modes(rec.y, fs=rec.fs)  # (also loads the kernels)
        times = []
        for _ in range(3 if quick else 7):
            start = time.perf_counter()
            identify_modes(rec.y, fs=rec.fs)
            times.append(time.perf_counter() - start)
    onset = rec.free_decay_index + int(0.002 * rec.fs)  # skip the hammer's contact, as the modes study does
    base = best_of(lambda: esprit(rec.y[onset:], fs=rec.fs), 3)
    median = float(np.median(times))
    found = ", ".join(f"{m.frequency_hz:.2f} Hz" for m in survey.modes)
    name = f"identify_modes, 3 s at 5 kHz, two modes ({found}), median warm vs ESPRIT on the record"
    rows = [(name, median, base, base / median, "<= 2 s")]
    cold = _cold_survey()
    rows.append(("identify_modes in a fresh process (kernels cached) vs warm", cold, median, median / cold,
                 "(info)"))
    return rows


def _esprit_of(rec):
    """ESPRIT on the record's free decay (after the hammer's contact, as the modes benchmark does)."""
    onset = rec.free_decay_index + int(0.002 * rec.fs)
    return lambda: esprit(rec.y[onset:], fs=rec.fs)


def survey_speed(quick: bool) -> list:
    """Issue 26's goals: identify_modes on four records and the 2-DOF fit at 100 and 500 Hz, each the
    median of warm runs beside ESPRIT on the same record."""
    repeat = 3 if quick else 5
    records = issue26_records()
    rows = []
    goals = {"nonlinear": "<= 1 s", "two modes": "<= 0.5 s", "three modes": "<= 0.5 s",
             "three modes, clipped": "<= 0.5 s"}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name, rec in records.items():
            survey = lambda rec=rec: identify_modes(rec.y, fs=rec.fs)  # noqa: E731
            ours, base, cpu = median_beside(survey, _esprit_of(rec), repeat, cpu=True)
            found = ", ".join(f"{m.frequency_hz:.1f} Hz" for m in identify_modes(rec.y, fs=rec.fs).modes)
            figure = f"identify_modes, {name} ({found}; CPU {cpu:.2f} s) vs ESPRIT"
            rows.append((figure, ours, base, base / ours, goals[name]))
        rec = records["nonlinear"]

        def verdict():
            return [mode.nonlinear for mode in identify_modes(rec.y, fs=rec.fs).modes]

        ours, base, cpu = median_beside(verdict, _esprit_of(rec), repeat, cpu=True)
        name = f"identify_modes and the nonlinear verdict ({verdict()}; CPU {cpu:.2f} s) vs ESPRIT"
        rows.append((name, ours, base, base / ours, "<= 2 s"))
        for rate in (100, 500):
            t, x = two_dof(dt=1.0 / rate)
            baseline = lambda x=x, rate=rate: esprit(x[:, 0], fs=rate)  # noqa: E731
            fit = lambda x=x, t=t: ImpulseSINDy().fit(x, t=t)  # noqa: E731
            ours, base, cpu = median_beside(fit, baseline, repeat, cpu=True)
            name = (f"fit 2-DOF, 4 states, 1500 samples at {rate} Hz, 40 dB (CPU {cpu:.2f} s) vs ESPRIT on "
                    "its first state")
            rows.append((name, ours, base, base / ours, "<= 0.5 s"))
    return rows

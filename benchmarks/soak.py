"""Soak test (not CI): many random ring-downs, each fit under a hard watchdog.

Run:  python benchmarks/soak.py [--n 1000] [--timeout 60] [--jobs 2] [--seed 0]

Each case draws an oscillator -- linear ``x2' = -k x1 - c x2``, Duffing (``- k_nl x1**3``) or friction-like
(``- mu tanh(x2 / eps)``) -- with random stiffness, damping, amplitude (1e-4 to 1e4: units), time step,
length (50 to 2000 samples) and noise (none, or 15 to 60 dB SNR), and fits either both states or the first
state alone after a :class:`~sindy_impulse.DelayEmbedding`, with a polynomial or a mechanical library.

Every fit runs in a worker process; the parent kills a worker that exceeds ``--timeout`` seconds and
starts a fresh one. Outcomes:

- ``ok``: a model (warnings are counted by message);
- ``refusal``: a ``ValueError``/``TypeError`` with a message (bad or unusable data, refused clearly);
- ``crash``: any other exception (a bug);
- ``hang``: over the time limit (a bug).

The run must end with 0 crashes and 0 hangs.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import sys
import time
import traceback
import warnings
from collections import Counter
from queue import Empty

import numpy as np

SYSTEMS = ("linear", "duffing", "friction")


# --------------------------------------------------------------------------------------------------------
# cases
# --------------------------------------------------------------------------------------------------------
def make_case(seed: int) -> dict:
    """Parameters of case ``seed`` (drawn independently of every other case)."""
    rng = np.random.default_rng([seed, 20191])
    system = SYSTEMS[seed % 3]
    omega = float(np.exp(rng.uniform(np.log(0.5), np.log(500.0))))  # rad / time unit
    zeta = float(np.exp(rng.uniform(np.log(0.005), np.log(0.5))))
    n = int(np.exp(rng.uniform(np.log(50), np.log(2000))))
    samples_per_period = float(np.exp(rng.uniform(np.log(4.0), np.log(200.0))))
    dt = 2 * np.pi / omega / samples_per_period
    amplitude = float(10 ** rng.uniform(-4, 4))
    case = {
        "seed": seed,
        "system": system,
        "k": omega**2,
        "c": 2 * zeta * omega,
        "k_nl": 0.0,
        "mu": 0.0,
        "eps": 1.0,
        "amplitude": amplitude,
        "n": n,
        "dt": dt,
        "snr_db": None if rng.random() < 0.25 else float(rng.uniform(15, 60)),
        "embed": bool(rng.random() < 0.35),
        "library": "mechanical" if rng.random() < 0.3 else "polynomial",
        "nonuniform": bool(rng.random() < 0.1),
    }
    if system == "duffing":
        # cubic force up to 3x the linear one at the initial amplitude; softening occasionally
        # (a softening spring below 0.6x the linear force at the initial amplitude stays in its well)
        softening = rng.random() < 0.15
        ratio = -rng.uniform(0.1, 0.6) if softening else rng.uniform(0.1, 3.0)
        case["k_nl"] = ratio * omega**2 / amplitude**2
    elif system == "friction":
        case["mu"] = rng.uniform(0.01, 0.3) * omega**2 * amplitude
        case["eps"] = rng.uniform(1e-3, 0.1) * omega * amplitude
    return case


def simulate_case(case: dict):
    """Time vector and noisy states (n, 2) of a case."""
    from scipy.integrate import solve_ivp

    from sindy_impulse.datasets import add_noise

    k, c, k_nl, mu, eps = (case[key] for key in ("k", "c", "k_nl", "mu", "eps"))
    rng = np.random.default_rng([case["seed"], 7])
    n, dt = case["n"], case["dt"]
    if case["nonuniform"]:
        t = np.concatenate([[0.0], np.cumsum(dt * rng.uniform(0.5, 1.5, n - 1))])
    else:
        t = np.arange(n) * dt

    def rhs(_t, y):
        return [y[1], -k * y[0] - c * y[1] - k_nl * y[0] ** 3 - mu * np.tanh(y[1] / eps)]

    amp = case["amplitude"]
    sol = solve_ivp(rhs, (0.0, t[-1]), [amp, 0.0], t_eval=t, method="LSODA", rtol=1e-9, atol=1e-12 * amp)
    x = sol.y.T
    if x.shape[0] != n or not np.all(np.isfinite(x)):  # the (softening) system escaped: keep what exists
        x = np.vstack([x, np.full((n - x.shape[0], 2), np.nan)]) if x.shape[0] < n else x
    if case["snr_db"] is not None and np.all(np.isfinite(x)):
        x = add_noise(x, case["snr_db"], random_state=rng)
    return t, x


def run_case(case: dict) -> dict:
    """Fit one case; returns the outcome (never raises)."""
    import pysindy as ps

    from sindy_impulse import DelayEmbedding, ImpulseSINDy, MechanicalLibrary

    start = time.perf_counter()
    caught: list[str] = []
    try:
        t, x = simulate_case(case)
        with warnings.catch_warnings(record=True) as record:
            warnings.simplefilter("always")
            library = MechanicalLibrary(degree=3) if case["library"] == "mechanical" else None
            if library is None:
                library = ps.PolynomialLibrary(degree=3)
            model = ImpulseSINDy(feature_library=library)
            if case["embed"]:
                signal = x[:, 0]
                embedding = DelayEmbedding().fit(signal)
                states = embedding.transform(signal)
                model.fit(states, t=embedding.transform_time(t))
            else:
                model.fit(x, t=t)
            if not np.all(np.isfinite(model.coefficients())):
                raise AssertionError("non-finite coefficients")
        caught = sorted({_short(str(w.message)) for w in record})
        outcome = {"kind": "ok", "terms": model.complexity, "gamma": model.gamma_}
    except (ValueError, TypeError) as err:
        outcome = {"kind": "refusal" if str(err) else "crash", "error": f"{type(err).__name__}: {err}"}
    except Exception as err:  # noqa: BLE001 - a soak test records everything
        outcome = {
            "kind": "crash",
            "error": f"{type(err).__name__}: {err}",
            "traceback": traceback.format_exc(limit=6),
        }
    outcome["time"] = time.perf_counter() - start
    outcome["warnings"] = caught
    outcome["seed"] = case["seed"]
    return outcome


def _short(message: str) -> str:
    return message.split(";")[0].split("(")[0].strip()[:90]


# --------------------------------------------------------------------------------------------------------
# watchdog
# --------------------------------------------------------------------------------------------------------
def _worker(tasks, results):
    import sindy_impulse.estimator  # noqa: F401 - import (and numba cache load) before timing

    while True:
        case = tasks.get()
        if case is None:
            return
        results.put(run_case(case))


class Worker:
    """A process fitting one case at a time; killed and replaced when a fit exceeds the time limit."""

    def __init__(self, ctx):
        self.ctx = ctx
        self.tasks = ctx.Queue()
        self.results = ctx.Queue()
        self.process = ctx.Process(target=_worker, args=(self.tasks, self.results), daemon=True)
        self.process.start()
        self.case = None
        self.started = 0.0

    def submit(self, case):
        self.case = case
        self.started = time.perf_counter()
        self.tasks.put(case)

    def poll(self, timeout: float):
        """The finished outcome, a hang outcome, or None while the fit runs."""
        if self.case is None:
            return None
        try:
            outcome = self.results.get_nowait()
        except Empty:
            elapsed = time.perf_counter() - self.started
            if elapsed > timeout:
                self.kill()
                return {"kind": "hang", "time": elapsed, "warnings": [], "seed": self.case["seed"]}
            if not self.process.is_alive():
                self.process = None
                return {
                    "kind": "crash",
                    "error": "worker process died",
                    "time": elapsed,
                    "warnings": [],
                    "seed": self.case["seed"],
                }
            return None
        self.case = None
        return outcome

    def kill(self):
        if self.process is not None and self.process.is_alive():
            self.process.kill()
            self.process.join()
        self.process = None

    def stop(self):
        if self.process is not None and self.process.is_alive():
            self.tasks.put(None)
            self.process.join(timeout=5)
            self.kill()


def soak(n: int, timeout: float, jobs: int, seed: int, verbose: bool = False) -> list[dict]:
    ctx = mp.get_context("spawn")
    cases = [make_case(seed + i) for i in range(n)]
    pending = list(reversed(cases))
    workers = [Worker(ctx) for _ in range(jobs)]
    outcomes = []
    by_seed = {c["seed"]: c for c in cases}
    while pending or any(w.case is not None for w in workers):
        for i, w in enumerate(workers):
            if w.process is None:  # killed after a hang, or died: replace
                workers[i] = w = Worker(ctx)
            if w.case is None and pending:
                w.submit(pending.pop())
            out = w.poll(timeout)
            if out is not None:
                out["case"] = by_seed[out["seed"]]
                outcomes.append(out)
                if verbose or out["kind"] in ("crash", "hang"):
                    print(_line(out), flush=True)
                if w.process is None:
                    workers[i] = Worker(ctx)
                if pending:
                    workers[i].submit(pending.pop())
        time.sleep(0.005)
    for w in workers:
        w.stop()
    return outcomes


def _line(out: dict) -> str:
    c = out["case"]
    what = (
        f"seed={c['seed']} {c['system']} n={c['n']} dt={c['dt']:.3g} snr={c['snr_db']} "
        f"embed={c['embed']} lib={c['library']} nonuniform={c['nonuniform']} amp={c['amplitude']:.3g}"
    )
    detail = out.get("error", f"{out.get('terms')} terms, Gamma {out.get('gamma', np.nan):.3g}")
    text = f"[{out['kind']:7s}] {out['time']:6.2f}s {what}: {detail}"
    if "traceback" in out:
        text += "\n" + out["traceback"]
    return text


def report(outcomes: list[dict], timeout: float) -> None:
    kinds = Counter(o["kind"] for o in outcomes)
    times = np.array([o["time"] for o in outcomes if o["kind"] != "hang"])
    print(f"\n{len(outcomes)} fits, watchdog {timeout:g} s per fit")
    for kind in ("ok", "refusal", "crash", "hang"):
        print(f"  {kind:8s} {kinds.get(kind, 0):5d}")
    if times.size:
        print(
            f"time per fit (s): median {np.median(times):.3f}, p95 {np.percentile(times, 95):.3f}, "
            f"max {times.max():.3f}, total {times.sum():.0f}"
        )
    by_system = Counter((o["case"]["system"], o["case"]["embed"], o["kind"]) for o in outcomes)
    print("outcomes by system (states | embedded):")
    for system in SYSTEMS:
        for embed in (False, True):
            row = ", ".join(f"{k} {by_system.get((system, embed, k), 0)}" for k in ("ok", "refusal"))
            print(f"  {system:9s} {'embedded' if embed else 'states  '}: {row}")
    refusals = Counter(_short(o["error"]) for o in outcomes if o["kind"] == "refusal")
    if refusals:
        print("clean refusals by message:")
        for msg, count in refusals.most_common():
            print(f"  {count:4d}  {msg}")
    warns = Counter(w for o in outcomes for w in o["warnings"])
    if warns:
        print("warnings (fits that raised each):")
        for msg, count in warns.most_common():
            print(f"  {count:4d}  {msg}")
    bad = [o for o in outcomes if o["kind"] in ("crash", "hang")]
    if bad:
        print("crashes and hangs:")
        for o in bad:
            print("  " + _line(o))
    slow = sorted((o for o in outcomes if o["kind"] != "hang"), key=lambda o: -o["time"])[:5]
    print("slowest fits:")
    for o in slow:
        print("  " + _line(o))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--n", type=int, default=1000, help="number of random ring-downs")
    parser.add_argument("--timeout", type=float, default=60.0, help="hard limit per fit (s)")
    parser.add_argument("--jobs", type=int, default=2, help="worker processes")
    parser.add_argument("--seed", type=int, default=0, help="first case seed")
    parser.add_argument("--verbose", action="store_true", help="print every fit")
    args = parser.parse_args(argv)
    start = time.perf_counter()
    outcomes = soak(args.n, args.timeout, args.jobs, args.seed, args.verbose)
    report(outcomes, args.timeout)
    print(f"wall time {time.perf_counter() - start:.0f} s")
    kinds = Counter(o["kind"] for o in outcomes)
    return 1 if kinds.get("crash", 0) or kinds.get("hang", 0) else 0


if __name__ == "__main__":
    sys.exit(main())

"""Data of the speed figures of ``benchmarks/speed/speed.py`` and the timing helpers they share."""

from __future__ import annotations

import os
import threading
import time

import numpy as np
from scipy.integrate import solve_ivp

from sindy_impulse import damped_oscillator
from sindy_impulse.datasets import add_noise


def load() -> float:
    """The machine's 1-minute load average (how busy it was; 0 where unknown)."""
    try:
        return os.getloadavg()[0]
    except OSError:  # pragma: no cover - not on Windows
        return 0.0


def best_of(function, repeat: int = 5, number: int = 1) -> float:
    """Best wall time of ``number`` calls, over ``repeat`` rounds (seconds per call)."""
    function()
    best = np.inf
    for _ in range(repeat):
        start = time.perf_counter()
        for _ in range(number):
            function()
        best = min(best, (time.perf_counter() - start) / number)
    return best


class PeakMemory:
    """Peak resident memory above the level at entry (MB), sampled every 5 ms (Linux /proc)."""

    def __enter__(self):
        self.base = self.peak = _rss()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._watch, daemon=True)
        self._thread.start()
        return self

    def _watch(self):
        while not self._stop.wait(0.005):
            self.peak = max(self.peak, _rss())

    def __exit__(self, *exc):
        self._stop.set()
        self._thread.join()
        self.peak = max(self.peak, _rss())
        self.extra_mb = (self.peak - self.base) / 1e6


def _rss() -> float:
    try:
        with open("/proc/self/statm") as fh:
            return int(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except OSError:  # pragma: no cover - not on Linux
        return 0.0


def two_dof(n: int = 1500, dt: float = 0.01, snr_db: float | None = 40.0, seed: int = 0):
    """Free decay of two masses between three springs, proportional damping: 4 measured states.

    ``x0'' = -40 x0 + 20 x2 - 0.6 x0' + 0.2 x2'``, ``x2'' = 20 x0 - 40 x2 + 0.2 x0' - 0.6 x2'`` (natural
    frequencies 0.71 and 1.23 Hz, damping ratios 4.5 % and 5.2 %), released from ``x0 = 1``.
    """
    K = np.array([[40.0, -20.0], [-20.0, 40.0]])
    C = np.array([[0.6, -0.2], [-0.2, 0.6]])

    def rhs(_t, y):
        a = -K @ y[[0, 2]] - C @ y[[1, 3]]
        return [y[1], a[0], y[3], a[1]]

    t = np.arange(n) * dt
    x0 = [1.0, 0.0, 0.0, 0.0]
    x = solve_ivp(rhs, (0, t[-1]), x0, t_eval=t, method="DOP853", rtol=1e-12, atol=1e-12).y.T
    return t, (x if snr_db is None else add_noise(x, snr_db, random_state=seed))


def long_record(n: int, snr_db: float = 40.0, seed: int = 0):
    """The paper's oscillator over its 4 s sampled with ``n`` samples (dt = 4 s / (n - 1))."""
    ring = damped_oscillator(dt=4.0 / (n - 1), snr_db=snr_db, random_state=seed)
    return ring.t, ring.x


def feature_study(n_series: int = 80):
    """The 80 ring-downs of the paper's Fig. 14: k ~ U[36, 400], k_nl in {0, 50} (half each), both states."""
    rng = np.random.default_rng(0)
    ks = rng.uniform(36, 400, n_series)
    k_nl = np.repeat([0.0, 50.0], [n_series // 2, n_series - n_series // 2])
    return [damped_oscillator(k=k, c=3.2, k_nl=kn).x for k, kn in zip(ks, k_nl)]


def issue26_records() -> dict:
    """The records of issue 26's speed goals (a modal survey in the time a hammer hit takes).

    ``nonlinear``: one mode at 122.4 Hz (damping ratio 0.1 %) whose cubic spring raises the frequency by
    0.1 % and whose ``x^2 x'`` damper doubles the damping ratio at the displacement amplitude 1e-4
    (``impact_record``'s formulas: ``sqrt(omega**2 + 3/4 k3 a**2)`` and ``c2 a**2 / (8 omega)``);
    ``two modes``, ``three modes`` and ``three modes, clipped`` as in the issue.
    """
    from sindy_impulse import impact_record

    omega, a = 2 * np.pi * 122.4, 1e-4
    k3 = (1.001**2 - 1) * omega**2 / (0.75 * a**2)
    c2 = 8 * 0.001 * omega / a**2
    three = dict(fs=50000, duration=0.11, pre_trigger=0.005, sensor="acceleration", snr_db=40, random_state=3)
    return {
        "nonlinear": impact_record(122.4, 0.001, [1e-4], fs=5000, duration=3, sensor="displacement",
                                   snr_db=50, cubic_stiffness=k3, damping_amplitude=c2, random_state=5),
        "two modes": impact_record([88.6, 156.7], [0.002, 0.004], fs=5120, duration=3, sensor="displacement",
                                   offset=0.3, snr_db=50, random_state=9),
        "three modes": impact_record([804.0, 2400.0, 4800.0], [0.01, 0.005, 0.006], **three),
        "three modes, clipped": impact_record([804.0, 2400.0, 4800.0], [0.01, 0.005, 0.006], clip=0.6,
                                              **three),
    }


def median_beside(function, baseline, repeat: int = 5, cpu: bool = False) -> tuple:
    """Medians of ``repeat`` warm runs of ``function``, each followed by one of ``baseline`` (seconds); with
    ``cpu``, also the median CPU time of ``function``'s runs (this process, all its threads): on a shared
    machine the wall time grows with the load, the CPU time much less."""
    function()
    baseline()
    ours, base, cpu_times = [], [], []
    for _ in range(repeat):
        start, start_cpu = time.perf_counter(), time.process_time()
        function()
        ours.append(time.perf_counter() - start)
        cpu_times.append(time.process_time() - start_cpu)
        start = time.perf_counter()
        baseline()
        base.append(time.perf_counter() - start)
    medians = (float(np.median(ours)), float(np.median(base)))
    return (*medians, float(np.median(cpu_times))) if cpu else medians

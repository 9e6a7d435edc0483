"""Worker processes under a hard time limit, for the soak and the bad-input matrix.

A task that exceeds the limit is reported as a hang and its worker killed and replaced; a worker that dies
is reported as a crash. Tasks run in spawned processes, so each starts from a clean interpreter.
"""

from __future__ import annotations

import multiprocessing as mp
import time
from queue import Empty


def _worker(tasks, results, target: str, kwargs: dict):
    import importlib

    import sindy_impulse.identification.estimator  # noqa: F401 - import (and numba cache load) before timing

    module, name = target.split(":")
    function = getattr(importlib.import_module(module), name)
    while True:
        task = tasks.get()
        if task is None:
            return
        results.put(function(task, **kwargs))


class Worker:
    """A process running one task at a time; killed and replaced when a task exceeds the time limit."""

    def __init__(self, ctx, target: str, kwargs: dict):
        self.tasks = ctx.Queue()
        self.results = ctx.Queue()
        args = (self.tasks, self.results, target, kwargs)
        self.process = ctx.Process(target=_worker, args=args, daemon=True)
        self.process.start()
        self.task = None
        self.started = 0.0

    def submit(self, task):
        self.task = task
        self.started = time.perf_counter()
        self.tasks.put(task)

    def poll(self, timeout: float, key: str):
        """The finished outcome, a hang or crash outcome, or None while the task runs."""
        if self.task is None:
            return None
        try:
            outcome = self.results.get_nowait()
        except Empty:
            elapsed = time.perf_counter() - self.started
            if elapsed > timeout or not self.process.is_alive():
                kind = "hang" if elapsed > timeout else "crash"
                ident = self.task[key]
                self.kill()
                return {"kind": kind, "time": elapsed, "warnings": [], key: ident, "error": kind}
            return None
        self.task = None
        return outcome

    def kill(self):
        if self.process is not None and self.process.is_alive():
            self.process.kill()
            self.process.join()
        self.process = None
        self.task = None

    def stop(self):
        if self.process is not None and self.process.is_alive():
            self.tasks.put(None)
            self.process.join(timeout=5)
            self.kill()


def run_pool(
    tasks: list[dict], target: str, timeout: float, jobs: int, key: str = "seed", kwargs=None, on_result=None
) -> list[dict]:
    """Run ``target`` ("module:function", called as ``function(task, **kwargs)``) on every task in ``jobs``
    worker processes, each task under ``timeout`` seconds; outcomes keyed by ``task[key]``, in task order."""
    ctx = mp.get_context("spawn")
    pending = list(reversed(tasks))
    workers = [Worker(ctx, target, kwargs or {}) for _ in range(jobs)]
    outcomes = {}
    while pending or any(w.task is not None for w in workers):
        for i, w in enumerate(workers):
            if w.process is None:
                workers[i] = w = Worker(ctx, target, kwargs or {})
            if w.task is None and pending:
                w.submit(pending.pop())
            out = w.poll(timeout, key)
            if out is not None:
                outcomes[out[key]] = out
                if on_result is not None:
                    on_result(out)
        time.sleep(0.005)
    for w in workers:
        w.stop()
    return [outcomes[t[key]] for t in tasks]

"""SINDyFeatures on a dask.distributed LocalCluster with 1 and 2 worker processes.

The same code runs on a multi-node cluster: start ``dask scheduler`` on one machine and ``dask worker
tcp://<scheduler>:8786 --nworkers 2 --nthreads 1`` on each node (with this package installed), then
replace ``LocalCluster(...)`` by the scheduler's address::

    import joblib
    from dask.distributed import Client
    from sindy_impulse import SINDyFeatures

    client = Client("tcp://<scheduler>:8786")
    with joblib.parallel_config(backend="dask"):
        X = SINDyFeatures(dt=0.01, n_jobs=-1).fit_transform(list_of_ring_downs)
"""

from __future__ import annotations

import time
import warnings

import joblib

from benchmarks.speed.cases import feature_study
from sindy_impulse import SINDyFeatures


def _on_cluster(series, n_workers: int) -> float:
    from dask.distributed import Client, LocalCluster

    with LocalCluster(
        n_workers=n_workers, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=40
    ) as cluster, Client(cluster) as client:
        with joblib.parallel_config(backend="dask"):
            SINDyFeatures(dt=0.01, n_jobs=-1).fit_transform(series[:n_workers])  # workers import and load
            client.run(lambda: None)
            start = time.perf_counter()
            SINDyFeatures(dt=0.01, n_jobs=-1).fit_transform(series)
            return time.perf_counter() - start


def dask_rows(quick: bool) -> list:
    """Speed-up of 2 dask workers over 1 and the per-record overhead of the cluster (warm workers)."""
    try:
        import dask.distributed  # noqa: F401
    except ImportError:
        return [("dask: not installed (pip install 'sindy-impulse[dask]')", float("nan"), float("nan"),
                 float("nan"), "")]
    series = feature_study(24 if quick else 80)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        SINDyFeatures(dt=0.01).fit_transform(series[:2])
        start = time.perf_counter()
        SINDyFeatures(dt=0.01).fit_transform(series)
        local = time.perf_counter() - start
        one = _on_cluster(series, 1)
        two = _on_cluster(series, 2)
    n = len(series)
    return [
        (f"dask LocalCluster, {n} ring-downs: 2 workers vs 1 worker", two, one, one / two, "(speed-up)"),
        (f"dask, per-record overhead: (1 worker - in-process) / {n}", (one - local) / n, local / n,
         (one - local) / local, "(fraction of a fit)"),
    ]

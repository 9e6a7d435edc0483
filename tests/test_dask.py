"""SINDyFeatures on a real dask.distributed cluster (two worker processes), through joblib's dask backend."""

import numpy as np
import pytest

distributed = pytest.importorskip("dask.distributed")

import joblib  # noqa: E402

from sindy_impulse import SINDyFeatures, damped_oscillator  # noqa: E402

CASES = [(64, 0), (100, 0), (150, 0), (64, 50), (100, 50), (150, 50)]  # (k, k_nl)
SERIES = [damped_oscillator(k=k, k_nl=k_nl).x for k, k_nl in CASES]


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=40
    )
    with cluster, distributed.Client(cluster) as c:
        yield c


@pytest.mark.slow  # starts a local dask cluster (6 s): in CI's second step (pytest -m slow)
def test_features_computed_by_two_dask_workers_equal_the_local_ones(client):
    local = SINDyFeatures(dt=0.01).fit_transform(SERIES)
    with distributed.get_task_stream(client) as stream, joblib.parallel_config(backend="dask"):
        remote = SINDyFeatures(dt=0.01, n_jobs=-1).fit_transform(SERIES)
    np.testing.assert_array_equal(remote, local)
    assert len(stream.data) >= len(SERIES) / 2  # the fits ran as cluster tasks (batches of series) ...
    assert {task["worker"] for task in stream.data} == set(client.scheduler_info()["workers"])  # on both
    assert not np.isnan(remote).any()

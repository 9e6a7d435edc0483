"""Many records, one survey each (``survey_many``): serial, two joblib worker processes, a dask cluster.

The records of issue 26: 50 accelerometer hits of a three-mode structure (804, 2400, 4800 Hz; damping
ratios 1, 0.5, 0.6 %), 50 kHz, 0.11 s each with 5 ms of pre-trigger, 40 dB, seeds 0-49. Each way runs
cold, as a user's first call does: the two joblib workers and the two dask workers start (and import the
package) inside the timed call. The three results are compared number for number.

Run alone (``python -m benchmarks batch [--n 50]``) or as the ``batch`` section of
``benchmarks/speed/speed.py``. On a cluster, replace ``LocalCluster(...)`` by the scheduler's address::

    import joblib
    from dask.distributed import Client
    from sindy_impulse import survey_many

    client = Client("tcp://<scheduler>:8786")
    surveys = survey_many(records, fs=50000.0, n_jobs=-1, backend="dask")
"""

from __future__ import annotations

import argparse
import time
import warnings

from sindy_impulse import impact_record, survey_many


def issue_records(n: int = 50) -> list:
    """Issue 26's batch: ``n`` three-mode accelerometer records, seeds 0..n-1."""
    return [
        impact_record([804.0, 2400.0, 4800.0], [0.01, 0.005, 0.006], fs=50000, duration=0.11,
                      pre_trigger=0.005, sensor="acceleration", snr_db=40, random_state=seed).y
        for seed in range(n)
    ]


def _numbers(surveys) -> str:
    """Every table value and coefficient, as exact text (repr: every digit; NaN equals NaN)."""
    return repr([(s.table(), [m.model.coefficients().tolist() for m in s.modes]) for s in surveys])


def _timed(call):
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        out = call()
    return time.perf_counter() - start, out


def _on_dask(records):
    from dask.distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=40) as cluster, Client(cluster):
        return survey_many(records, fs=50000.0, n_jobs=-1, backend="dask")


def batch_rows(quick: bool, n: int | None = None) -> list:
    """Rows ``(figure, ours, baseline, ratio, goal)``: n_jobs=2 and dask against the serial run."""
    n = n or (10 if quick else 50)
    records = issue_records(n)
    _timed(lambda: survey_many(records[:1], fs=50000.0))  # kernels loaded in this process
    serial, reference = _timed(lambda: survey_many(records, fs=50000.0))
    two, by_two = _timed(lambda: survey_many(records, fs=50000.0, n_jobs=2))
    rows = [
        (f"survey_many, {n} records (3 modes, 50 kHz, 0.11 s): n_jobs=2 (workers started) vs serial", two,
         serial, serial / two, "<= 15 s for 50"),
    ]
    same = _numbers(by_two) == _numbers(reference)
    try:
        dask, by_dask = _timed(lambda: _on_dask(records))
    except ImportError:
        rows.append(("dask: not installed (pip install 'sindy-impulse[dask]')", float("nan"), serial,
                     float("nan"), ""))
    else:
        rows.append((f"survey_many, {n} records, dask LocalCluster of 2 workers (started) vs serial", dask,
                     serial, serial / dask, "(speed-up)"))
        same = same and _numbers(by_dask) == _numbers(reference)
    rows.append((f"serial time per record; every way the same numbers to the last digit: {same}",
                 serial / n, float("nan"), float("nan"), "(info)"))
    return rows


def main(argv=None) -> dict:
    formatter = argparse.RawDescriptionHelpFormatter
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=formatter)
    parser.add_argument("--n", type=int, default=None, help="records (default 50, quick 10)")
    parser.add_argument("--quick", action="store_true", help="10 records")
    args = parser.parse_args(argv)
    rows = batch_rows(args.quick, args.n)
    for name, ours, base, ratio, goal in rows:
        print(f"{name}: {ours:.3g} s, serial {base:.3g} s, ratio {ratio:.3g} (goal {goal})")
    return {"rows": [dict(zip(("figure", "ours", "baseline", "ratio", "goal"), row)) for row in rows]}


if __name__ == "__main__":
    main()

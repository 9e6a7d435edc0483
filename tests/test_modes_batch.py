"""survey_many: one survey per record over many records; the same numbers however it runs."""

import warnings

import numpy as np
import pytest

from sindy_impulse import identify_modes, impact_record, survey_many
from sindy_impulse.exceptions import DataWarning
from sindy_impulse.io import Record
from sindy_impulse.modes import FailedRecord, ModalSurvey

FS = 5000.0


def _record(seed, f=(120.0, 240.0)):
    return impact_record(list(f), [0.005, 0.01], fs=FS, duration=0.6, snr_db=50, random_state=seed)


@pytest.fixture(scope="module")
def records():
    return [_record(0).y, _record(1, (150.0, 330.0)).y, _record(2).y]


@pytest.fixture(scope="module")
def serial(records):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return survey_many(records, fs=FS)


def _numbers(survey):
    """Everything numeric a survey hands back: table rows, models' coefficients, onsets; as exact text
    (repr: every digit, and a NaN equals a NaN)."""
    return repr((
        survey.table(),
        [np.asarray(m.model.coefficients()).tolist() for m in survey.modes],
        [m.states.tolist() for m in survey.modes],
        [p.impact.onset_index for p in survey.preprocessing],
    ))


def test_each_record_gets_its_own_survey_equal_to_identify_modes(records, serial):
    assert [type(s) for s in serial] == [ModalSurvey] * 3
    assert [[round(m.frequency_hz) for m in s.modes] for s in serial] == [[120, 240], [150, 330], [120, 240]]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        alone = identify_modes(records[1], fs=FS)
    assert _numbers(alone) == _numbers(serial[1])


def test_parallel_threads_give_the_serial_numbers_to_the_last_digit(records, serial):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        threads = survey_many(records, fs=FS, n_jobs=2, backend="threading")
    assert [_numbers(s) for s in threads] == [_numbers(s) for s in serial]


@pytest.mark.slow  # starts two worker processes (loky)
def test_worker_processes_give_the_serial_numbers_to_the_last_digit(records, serial):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        processes = survey_many(records, fs=FS, n_jobs=2)
    assert [_numbers(s) for s in processes] == [_numbers(s) for s in serial]


def test_a_bad_record_becomes_a_failed_record_and_the_others_stand(records, serial):
    batch = [records[0], np.full(1000, np.nan), records[2][:10]]
    with pytest.warns(DataWarning, match="2 of 3 records gave no survey") as caught:
        out = survey_many(batch, fs=FS, names=["a.csv", "b.csv", "c.csv"])
    assert _numbers(out[0]) == _numbers(serial[0])
    assert isinstance(out[1], FailedRecord) and isinstance(out[2], FailedRecord)
    assert (out[1].index, out[1].name, out[1].error) == (1, "b.csv", "ValueError")
    assert "non-finite" in out[1].message and "10 samples" in out[2].message
    assert out[2].modes == [] and out[2].table() == [] and len(out[2]) == 0
    assert any(str(w.message).startswith("2 of 3") and "b.csv: ValueError" in str(w.message) for w in caught)


def test_record_warnings_come_back_named_after_their_record():
    rng = np.random.default_rng(0)
    noise = rng.standard_normal(3000)
    with pytest.warns(Warning) as caught:
        out = survey_many([noise], fs=FS, names=["noise.csv"])
    assert len(out[0].modes) == 0
    assert caught and all(str(w.message).startswith("noise.csv: ") for w in caught)


def test_records_bring_their_own_rate_force_and_name():
    rec = impact_record([150.0], [0.01], fs=2000, duration=1.0, snr_db=50, random_state=0)
    record = Record(np.column_stack([rec.y, rec.force]), fs=2000.0, channel_names=("acc", "hammer"),
                    force_channel=1, source="tap.npz")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        (out,) = survey_many([record], sensor="acceleration")
        direct = identify_modes(rec.y, fs=2000.0, force=rec.force, sensor="acceleration")
    assert out.modes[0].residue is not None
    assert _numbers(out) == _numbers(direct)
    with pytest.warns(DataWarning, match="tap.npz: ValueError"):
        survey_many([Record(np.zeros((10, 1)), fs=2000.0, source="tap.npz")])


@pytest.mark.parametrize(
    "kwargs, exc, match",
    [
        ({"sensor": "laser"}, ValueError, "sensor"),
        ({"max_periods": 1}, ValueError, "max_periods"),
        ({"n_mode": 2}, TypeError, "unknown keyword"),
        ({"n_jobs": 1.5}, TypeError, "n_jobs"),
        ({"names": ["only one"]}, ValueError, "names has 1 entries but there are 2 records"),
        ({"fs": [FS]}, ValueError, "fs has 1 entries"),
        ({"force": np.zeros(10)}, ValueError, "force has 10 entries"),
    ],
)
def test_options_for_the_whole_batch_are_refused_before_any_work(kwargs, exc, match, monkeypatch):
    from sindy_impulse.modes import batch

    monkeypatch.setattr(batch, "identify_modes", lambda *a, **k: pytest.fail("a record was surveyed"))
    kwargs = {"fs": FS, **kwargs}
    with pytest.raises(exc, match=match):
        survey_many([np.zeros(100), np.zeros(100)], **kwargs)


@pytest.mark.parametrize("records, match", [(np.zeros((100, 2)), "list of records"), ([], "empty")])
def test_records_must_be_a_non_empty_list(records, match):
    with pytest.raises((TypeError, ValueError), match=match):
        survey_many(records, fs=FS)


def test_no_progress_bar_by_default_off_a_terminal_one_when_asked(records, capsys, monkeypatch):
    from sindy_impulse.modes import batch

    monkeypatch.setattr(batch, "identify_modes", lambda *a, **k: ModalSurvey([], [], []))
    survey_many(records, fs=FS)
    assert capsys.readouterr().err == ""  # pytest's stderr is not a terminal
    survey_many(records, fs=FS, progress=True)
    err = capsys.readouterr().err
    assert "records" in err and "3/3" in err


def test_the_nonlinearity_test_runs_with_the_survey_when_asked(records):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        (out,) = survey_many(records[:1], fs=FS, nonlinearity=True)
    assert all("nonlinearity" in vars(m) for m in out.modes)  # computed (cached) where the survey ran
    assert [row["nonlinear"] for row in out.table(nonlinear=True)] == [False, False]


# ----------------------------------------------------------------------------------------------------
# issue 26's batch: 50 three-mode accelerometer records at 50 kHz (timed by benchmarks/speed/batch.py)
# ----------------------------------------------------------------------------------------------------
def _issue_records(n=50):
    return [
        impact_record([804.0, 2400.0, 4800.0], [0.01, 0.005, 0.006], fs=50000, duration=0.11,
                      pre_trigger=0.005, sensor="acceleration", snr_db=40, random_state=seed).y
        for seed in range(n)
    ]


@pytest.mark.slow  # 50 surveys three times (serial, 2 processes, a 2-worker dask cluster): minutes
def test_fifty_records_on_two_processes_and_on_a_dask_cluster_equal_the_serial_run():
    distributed = pytest.importorskip("dask.distributed")
    records = _issue_records()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        serial = survey_many(records, fs=50000.0)
        processes = survey_many(records, fs=50000.0, n_jobs=2)
        cluster = distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=40
        )
        with cluster, distributed.Client(cluster):
            on_dask = survey_many(records, fs=50000.0, n_jobs=-1, backend="dask")
    expected = [_numbers(s) for s in serial]
    assert [_numbers(s) for s in processes] == expected
    assert [_numbers(s) for s in on_dask] == expected
    assert all(len(s.modes) == 3 for s in serial)

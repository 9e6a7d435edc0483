"""A failure inside one band's, group's or record's identification stays that band's or record's: it
becomes a `Rejected` row with the error as its evidence and the rest of the survey stands. Interrupts still
stop the survey, and bad input still gets its clear error."""

import json
import warnings

import numpy as np
import pytest

from sindy_impulse import identify_modes, impact_record
from sindy_impulse.exceptions import NoDynamicsWarning
from sindy_impulse.modes import Rejected, band_fit, linear, survey
from sindy_impulse.modes.pipeline import Pipeline, Stage

FS = 2048.0


def _record(seed=0):
    return impact_record([80.0, 190.0], [0.005, 0.008], fs=FS, duration=1.5, snr_db=50, random_state=seed)


def _survey(y, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return identify_modes(y, fs=FS, **kwargs)


DIVERGED = "every candidate model diverged when simulated"


def _failing_above(hz, error=None):
    """derivative_states that raises for bands centred above ``hz`` (a band fit failing deep inside)."""
    original = band_fit.derivative_states
    error = RuntimeError(DIVERGED) if error is None else error

    def states(y, t):
        rate = 1.0 / float(np.median(np.diff(t)))
        spectrum = np.abs(np.fft.rfft(y - np.mean(y)))
        if np.fft.rfftfreq(len(y), 1.0 / rate)[np.argmax(spectrum)] > hz:
            raise error
        return original(y, t)

    return states


def _break_states(monkeypatch, states):
    """Every route's band states fail alike (a linear mode's and the paper's fit's)."""
    for module in (band_fit, linear):
        monkeypatch.setattr(module, "derivative_states", states)


def _break_record(monkeypatch, failing):
    """The survey's ``candidates`` stage raises ``failing(state)`` when it gives an exception."""
    original = next(s.run for s in survey.SURVEY if s.name == "candidates")

    def run(state):
        error = failing(state)
        if error is not None:
            raise error
        original(state)

    stages = [Stage(s.name, run) if s.name == "candidates" else s for s in survey.SURVEY]
    monkeypatch.setattr(survey, "SURVEY", Pipeline(stages))


def test_a_failing_band_becomes_a_rejected_row_and_the_other_mode_stands(monkeypatch):
    _break_states(monkeypatch, _failing_above(130.0))
    result = _survey(_record().y)
    assert [round(m.frequency_hz) for m in result.modes] == [80]
    failed = [r for r in result.rejected if r.evidence]
    assert len(failed) == 1 and failed[0].band_hz[0] < 190.0 < failed[0].band_hz[1]
    assert failed[0].evidence == {"error": "RuntimeError", "message": DIVERGED}
    assert "identification failed (RuntimeError" in failed[0].reason
    assert "Hz: the identification failed (RuntimeError" in str(result)  # the text table


def test_every_band_failing_gives_an_empty_table_and_a_warning_not_an_exception(monkeypatch):
    _break_states(monkeypatch, _failing_above(0.0, FloatingPointError("overflow")))
    with pytest.warns(NoDynamicsWarning, match="no mode found"):
        result = identify_modes(_record().y, fs=FS)
    assert result.modes == [] and result.rejected
    assert all(r.evidence.get("error") == "FloatingPointError" for r in result.rejected if r.evidence)


def test_a_failing_group_fit_rejects_each_of_its_peaks():
    class Broken:
        def fit(self, *args, **kwargs):
            raise np.linalg.LinAlgError("SVD did not converge")

    @band_fit.isolated(lambda args: list(args[1]))
    def group(band, peak_bands, template, *, onset_time, index=0):
        Broken().fit()

    rows = group(None, [(90.0, 100.0), (100.0, 110.0)], None, onset_time=0.0, index=2)
    assert [r.band_hz for r in rows] == [(90.0, 100.0), (100.0, 110.0)]
    assert all(r.record == 2 and r.evidence["error"] == "LinAlgError" for r in rows)


def test_a_failing_record_is_one_row_without_band_and_the_other_hits_stand(monkeypatch):
    _break_record(monkeypatch, lambda state: RuntimeError(DIVERGED) if state.index == 1 else None)
    result = _survey([_record(0).y, _record(1).y, _record(2).y])
    assert [round(m.frequency_hz) for m in result.modes] == [80, 190]
    assert all(len(m.hits) == 2 for m in result.modes)  # hits 0 and 2
    rows = [r for r in result.rejected if r.band_hz is None]
    assert len(rows) == 1 and rows[0].record == 1 and rows[0].evidence["error"] == "RuntimeError"
    assert "rejected record: the identification of record 1 failed" in str(result)


def test_record_rows_go_through_the_table_the_json_and_the_plot(monkeypatch, tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    from sindy_impulse.cli import main

    _break_record(monkeypatch, lambda state: ValueError("broken"))
    rec = _record()
    path = tmp_path / "hit.csv"
    np.savetxt(path, np.column_stack([rec.t, rec.y]), delimiter=",", header="t,y", comments="")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        outputs = ["--json", str(tmp_path / "modes.json"), "--plot", str(tmp_path / "m.png")]
        assert main(["modes", str(path), *outputs]) == 2  # no mode: an error unless --allow-empty
        assert not (tmp_path / "modes.json").exists()
        code = main(["modes", str(path), *outputs, "--allow-empty"])
    assert code in (0, 1)
    report = json.loads((tmp_path / "modes.json").read_text())
    assert report["rejected"] == [
        {"band_hz": None, "reason": "the identification of record 0 failed (ValueError: broken)", "record": 0}
    ]
    assert (tmp_path / "m.png").stat().st_size > 0


def test_an_interrupt_is_not_swallowed(monkeypatch):
    _break_states(monkeypatch, _failing_above(0.0, KeyboardInterrupt()))
    with pytest.raises(KeyboardInterrupt):
        _survey(_record().y)


def test_bad_input_still_gets_its_clear_error():
    with pytest.raises(ValueError, match="NaN|finite"):
        identify_modes(np.full(1000, np.nan), fs=FS)


def test_rejected_rows_compare_without_their_evidence():
    assert Rejected((1.0, 2.0), "why", 0, {"error": "X"}) == Rejected((1.0, 2.0), "why", 0)

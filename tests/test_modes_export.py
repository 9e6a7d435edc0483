"""A survey's files and frames: band signals and free decays as UFF 58, the modal table as a DataFrame."""

import sys
import warnings

import numpy as np
import pytest

from sindy_impulse import identify_modes, impact_record
from sindy_impulse.io import Record, write_record
from sindy_impulse.modes.export import FRAME_COLUMNS, signal_records


@pytest.fixture(scope="module")
def survey():
    rec = impact_record([120.0, 240.0], [0.005, 0.01], fs=5000, duration=1.0, snr_db=50, random_state=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return identify_modes(rec.y, fs=rec.fs)


def _expected(survey):
    """Per mode: (band signal, free decay, t) computed directly from the modes."""
    out = []
    for m in survey.modes:
        sim = m.model.simulate(m.states[0], m.t)[:, m.coordinate_]
        out.append((m.states[:, m.coordinate_], sim, m.t))
    return out


@pytest.mark.parametrize("binary", [False, True])
def test_uff58_holds_the_band_signals_and_free_decays_to_the_written_digits(survey, tmp_path, binary):
    pyuff = pytest.importorskip("pyuff")
    path = survey.to_uff58(tmp_path / "signals.unv", binary=binary)
    sets = pyuff.UFF(str(path)).read_sets()
    assert len(sets) == 2 * len(survey.modes) == 4
    for k, (band, decay, t) in enumerate(_expected(survey)):
        band_set, decay_set = sets[2 * k], sets[2 * k + 1]
        assert band_set["id1"].startswith(f"mode {k + 1} ") and band_set["id1"].endswith("band signal")
        assert decay_set["id1"].endswith("model free decay")
        for got, want in ((band_set, band), (decay_set, decay)):
            assert got["func_type"] == 1 and len(got["data"]) == len(want)
            if binary:  # doubles: every bit
                np.testing.assert_array_equal(got["data"], want)
            else:  # ASCII: the 12 significant digits written (%.11e), exactly
                np.testing.assert_array_equal(got["data"], [float(f"{v:.11e}") for v in want])
            np.testing.assert_allclose(got["x"], t, rtol=1e-5)  # 6-digit abscissa fields: t0 and step
        # the free decay follows the band it was fitted on (a wrong state or clock would not)
        assert np.max(np.abs(decay - band)) < 0.2 * np.max(np.abs(band))


def test_uff58_is_never_overwritten_without_overwrite(survey, tmp_path):
    pytest.importorskip("pyuff")
    path = tmp_path / "signals.uff"
    path.write_text("mine")
    with pytest.raises(FileExistsError):
        survey.to_uff58(path)
    assert path.read_text() == "mine"
    survey.to_uff58(path, overwrite=True)
    assert path.stat().st_size > 1000


def test_signal_records_put_band_and_model_on_the_fitted_clock(survey):
    records = signal_records(survey)
    for k, m in enumerate(survey.modes):
        band, decay = records[2 * k], records[2 * k + 1]
        assert band.fs == decay.fs == pytest.approx(m.fitted_fs)
        assert band.t0 == decay.t0 == m.t[0]
        np.testing.assert_allclose(band.t, m.t, rtol=0, atol=1e-9 * m.t[-1])


def test_a_list_of_records_goes_only_to_uff_files(tmp_path):
    recs = [Record(np.ones(4), fs=10.0), Record(np.ones(3), fs=20.0, channel_names=("b",))]
    with pytest.raises(TypeError, match="only a UFF file holds several records"):
        write_record(recs, tmp_path / "two.csv")
    with pytest.raises(TypeError, match="Record"):
        write_record([1, 2], tmp_path / "two.uff")


def test_a_survey_without_modes_has_no_signals_to_write(tmp_path):
    rng = np.random.default_rng(0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        empty = identify_modes(rng.standard_normal(4000), fs=4000.0)
    assert len(empty) == 0
    with pytest.raises(ValueError, match="no mode"):
        empty.to_uff58(tmp_path / "none.unv")


def test_to_frame_has_one_row_per_mode_with_the_table_columns(survey):
    pd = pytest.importorskip("pandas")
    frame = survey.to_frame()
    assert isinstance(frame, pd.DataFrame) and frame.index.name == "mode"
    assert list(frame.columns) == list(FRAME_COLUMNS) == list(survey.table()[0])
    for row, (_, got) in zip(survey.table(), frame.iterrows()):
        assert got.to_dict() == row


def test_to_frame_without_pandas_says_how_to_install_it(survey, monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)  # makes `import pandas` raise ImportError
    with pytest.raises(ImportError, match="pip install pandas"):
        survey.to_frame()

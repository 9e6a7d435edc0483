"""sindy_impulse.io: every format written and read back, what each file gives, and the errors.

Tolerances of the round trips: binary formats (UFF 58b, TDMS, MAT, NPZ) are exact; CSV and LVM are text
written with 17 significant digits, so they are exact too; UFF 58 ASCII holds 12 significant digits
(``%20.11e``: relative 1e-11 per sample). UFF 55 holds 6 significant digits (``E13.5``) for shapes and
eigenvalues, and this package's exact frequency and damping ratio in an ID line.
"""

from __future__ import annotations

import os
import sys
from types import SimpleNamespace

import numpy as np
import pytest

from sindy_impulse.datasets import impact_record
from sindy_impulse.exceptions import DataWarning
from sindy_impulse.io import Record, read_record, read_uff55, write_record, write_uff55

FS = 2048.0
NAMES = ("hammer", "acc 1", "acc 2")
UNITS = ("N", "m/s^2", "m/s^2")
NODES = (2, 1, 2)
DIRECTIONS = (-3, 3, 2)
# suffix, write options, exact data?, holds nodes and directions?
FORMATS = {
    "uff-ascii": (".uff", {}, False, True),
    "uff-binary": (".unv", {"binary": True}, True, True),
    "lvm": (".lvm", {}, True, True),
    "tdms": (".tdms", {}, True, True),
    "mat": (".mat", {}, True, True),
    "npz": (".npz", {}, True, True),
    "csv": (".csv", {}, True, False),
}


@pytest.fixture(scope="module")
def record() -> Record:
    test = impact_record([120.0, 310.0], [0.01, 0.02], fs=FS, duration=1.0, sensor_dof=[0, 1], random_state=0)
    data = np.column_stack([test.force, test.y])
    return Record(
        data,
        fs=FS,
        t0=-0.1,
        channel_names=NAMES,
        units=UNITS,
        nodes=NODES,
        directions=DIRECTIONS,
        force_channel=0,
        source="impact_record",
        meta={"rig": "chain"},
    )


@pytest.mark.parametrize("fmt", list(FORMATS))
def test_round_trip(record, tmp_path, fmt):
    suffix, options, exact, holds_nodes = FORMATS[fmt]
    path = write_record(record, tmp_path / f"tap{suffix}", **options)
    assert sorted(os.listdir(tmp_path)) == [path.name]  # no temporary file left behind
    back = read_record(path)
    assert back.data.shape == record.data.shape
    if exact:
        np.testing.assert_array_equal(back.data, record.data)
    else:
        np.testing.assert_allclose(back.data, record.data, rtol=1e-11, atol=0)
    assert back.fs == FS
    assert back.t0 == pytest.approx(-0.1, abs=1e-12)
    assert back.channel_names == NAMES
    assert back.units == UNITS
    assert back.force_channel == 0
    np.testing.assert_array_equal(back.force, back.data[:, 0])
    assert back.response.shape == (record.n_samples, 2)
    if holds_nodes:
        assert (back.nodes, back.directions) == (NODES, DIRECTIONS)
    else:
        assert (back.nodes, back.directions) == ((-1,) * 3, (0,) * 3)
    assert back.source == str(path)
    assert back.meta["format"] == {".unv": "uff58", ".uff": "uff58"}.get(suffix, suffix[1:])


def test_record_without_force_reads_back_without(record, tmp_path):
    plain = Record(record.data[:, 1:], fs=FS, channel_names=("a", "b"))
    for suffix in (".uff", ".lvm", ".tdms", ".mat", ".npz", ".csv"):
        assert read_record(write_record(plain, tmp_path / f"p{suffix}")).force_channel is None


def test_foreign_uff_without_our_tags(record, tmp_path):
    """A UFF 58 file written by pyuff alone: fs from the 6-digit spacing, names from nodes, force by type."""
    pyuff = pytest.importorskip("pyuff")
    sets = []
    for i, (node, direction) in enumerate(zip(NODES, DIRECTIONS)):
        sets.append(
            pyuff.prepare_58(
                func_type=1,
                rsp_node=node,
                rsp_dir=direction,
                ref_node=2,
                ref_dir=-3,
                data=record.data[:, i].copy(),
                x=record.t,
                abscissa_spacing=1,
                abscissa_min=record.t0,
                abscissa_inc=1 / FS,
                abscissa_spec_data_type=17,
                ordinate_spec_data_type=13 if i == 0 else 12,
                ordinate_axis_units_lab=UNITS[i],
                orddenom_spec_data_type=0,
                z_axis_spec_data_type=0,
            )  # fmt: skip
        )
    pyuff.UFF(str(tmp_path / "x.uff")).write_sets(sets, mode="add")
    back = read_record(tmp_path / "x.uff")
    assert back.fs == FS  # 1 / 4.88281e-04 = 2048.0008, snapped
    assert back.channel_names == ("2-Z", "1+Z", "2+Y")
    assert back.force_channel == 0 and back.units == UNITS
    assert read_record(tmp_path / "x.uff", force_channel="1+Z").force_channel == 1


def test_csv_without_time_needs_fs(tmp_path):
    path = tmp_path / "plain.csv"
    path.write_text("# a hammer test\nF;acc (g)\n1;0.5\n0;0.25\n0;0.125\n")
    with pytest.raises(ValueError, match="fs="):
        read_record(path)
    rec = read_record(path, fs=500)
    assert (rec.fs, rec.channel_names, rec.units, rec.force_channel) == (500.0, ("F", "acc"), ("", "g"), 0)
    with pytest.raises(ValueError, match="unequal sampling"):
        (tmp_path / "uneven.csv").write_text("time,a\n0,1\n0.001,2\n0.003,3\n")
        read_record(tmp_path / "uneven.csv")
    (tmp_path / "ms.csv").write_text("time [ms],a\n0,1\n0.5,2\n1,3\n")
    assert read_record(tmp_path / "ms.csv").fs == 2000.0
    with pytest.raises(ValueError, match="says fs"):
        read_record(tmp_path / "ms.csv", fs=1000)


def test_plain_arrays_in_npz_and_mat(tmp_path):
    t = np.arange(100) / 1000.0
    np.savez(tmp_path / "a.npz", t=t, acc=np.sin(t), hammer=np.cos(t))
    rec = read_record(tmp_path / "a.npz")
    assert (rec.fs, rec.channel_names, rec.force_channel) == (1000.0, ("acc", "hammer"), 1)
    np.savez(tmp_path / "b.npz", fs=1000.0, a=np.ones(100), b=np.ones(99))
    with pytest.raises(ValueError, match="unequal channel lengths"):
        read_record(tmp_path / "b.npz")
    from scipy.io import savemat

    savemat(tmp_path / "c.mat", {"Fs": 100.0, "data": np.ones((50, 3)), "force_channel": 2})
    rec = read_record(tmp_path / "c.mat")
    assert (rec.fs, rec.n_channels, rec.n_samples, rec.force_channel) == (100.0, 3, 50, 1)


def _mat73(path, data: np.ndarray, fs: float, names: list[str]) -> None:
    h5py = pytest.importorskip("h5py")
    with h5py.File(path, "w", userblock_size=512) as f:
        f.create_dataset("data", data=data.T).attrs["MATLAB_class"] = np.bytes_("double")
        f.create_dataset("fs", data=np.array([[fs]])).attrs["MATLAB_class"] = np.bytes_("double")
        refs = f.create_group("#refs#")
        cells = []
        for i, name in enumerate(names):
            ds = refs.create_dataset(str(i), data=np.array([[ord(c)] for c in name], dtype=np.uint16))
            ds.attrs["MATLAB_class"] = np.bytes_("char")
            cells.append(ds.ref)
        cell = f.create_dataset("channel_names", data=np.array([cells], dtype=h5py.ref_dtype))
        cell.attrs["MATLAB_class"] = np.bytes_("cell")
    header = (
        b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Mon Jan  1 00:00:00 2024 HDF5 schema 1.00 ."
    )
    with open(path, "r+b") as fh:
        fh.write(header.ljust(116) + b"\0" * 8 + b"\x00\x02" + b"IM")


def test_mat_v73_through_h5py(tmp_path):
    data = np.arange(12.0).reshape(4, 3)
    _mat73(tmp_path / "v73.mat", data, 256.0, ["acc1", "Hammer", "acc2"])
    rec = read_record(tmp_path / "v73.mat")
    np.testing.assert_array_equal(rec.data, data)
    assert (rec.fs, rec.channel_names, rec.force_channel) == (256.0, ("acc1", "Hammer", "acc2"), 1)


def test_tdms_unequal_sampling(tmp_path):
    nptdms = pytest.importorskip("nptdms")
    channels = [
        nptdms.ChannelObject("g", "a", np.ones(10), properties={"wf_increment": 0.001}),
        nptdms.ChannelObject("g", "b", np.ones(10), properties={"wf_increment": 0.002}),
    ]
    with nptdms.TdmsWriter(str(tmp_path / "u.tdms")) as writer:
        writer.write_segment([nptdms.RootObject(), nptdms.GroupObject("g"), *channels])
    with pytest.raises(ValueError, match="unequal sampling"):
        read_record(tmp_path / "u.tdms")


def test_several_force_candidates_warn(tmp_path):
    np.savez(
        tmp_path / "two.npz", fs=10.0, data=np.ones((5, 2)), channel_names=np.array(["force 1", "force 2"])
    )
    with pytest.warns(DataWarning, match="several channels"):
        assert read_record(tmp_path / "two.npz").force_channel is None


def test_file_errors(record, tmp_path):
    with pytest.raises(ValueError, match="suffix '.xyz'"):
        read_record(tmp_path / "r.xyz")
    with pytest.raises(ValueError, match="suffix"):
        write_record(record, tmp_path / "r.xyz")
    with pytest.raises(FileNotFoundError, match="no such file"):
        read_record(tmp_path / "missing.uff")
    path = write_record(record, tmp_path / "r.npz")
    with pytest.raises(FileExistsError, match="overwrite=True"):
        write_record(record, path)
    smaller = Record(record.data[:10], fs=FS)
    write_record(smaller, path, overwrite=True)
    assert read_record(path).n_samples == 10 and sorted(os.listdir(tmp_path)) == ["r.npz"]
    with pytest.raises(ValueError, match="binary=True"):
        write_record(record, tmp_path / "r.csv", binary=True)
    with pytest.raises(ValueError, match="not a readable UFF"):
        (tmp_path / "junk.uff").write_bytes(b"    -1\n    58\nnonsense\n    -1\n")
        read_record(tmp_path / "junk.uff")


@pytest.mark.parametrize("suffix", [".npz", ".csv", ".lvm", ".mat", ".uff"])
def test_written_files_get_the_users_umask_and_a_replaced_one_keeps_its_mode(record, tmp_path, suffix):
    import stat

    if suffix == ".uff":
        pytest.importorskip("pyuff")
    if suffix == ".mat":
        pytest.importorskip("scipy.io")
    old = os.umask(0o027)
    try:
        path = write_record(record, tmp_path / f"r{suffix}")
        assert stat.S_IMODE(os.stat(path).st_mode) == 0o640  # 0o666 less the umask, not 0o600
        os.chmod(path, 0o604)
        write_record(record, path, overwrite=True)
        assert stat.S_IMODE(os.stat(path).st_mode) == 0o604
    finally:
        os.umask(old)
    assert sorted(os.listdir(tmp_path)) == [f"r{suffix}"]  # atomic: no temporary file left


def test_the_html_report_is_written_atomically_with_the_umask(tmp_path):
    import stat

    from sindy_impulse.report import write_html

    old = os.umask(0o022)
    try:
        path = write_html(tmp_path / "r.html", "<p>x</p>")
        assert stat.S_IMODE(os.stat(path).st_mode) == 0o644
        with pytest.raises(FileExistsError, match="overwrite=True"):
            write_html(path, "<p>y</p>")
    finally:
        os.umask(old)
    assert (tmp_path / "r.html").read_text() == "<p>x</p>" and os.listdir(tmp_path) == ["r.html"]


@pytest.mark.parametrize(
    "module, suffix", [("pyuff", ".uff"), ("nptdms", ".tdms"), ("lvm_read", ".lvm"), ("h5py", ".mat")]
)
def test_missing_optional_package(record, tmp_path, monkeypatch, module, suffix):
    if module == "h5py":
        _mat73(tmp_path / "x.mat", np.ones((4, 1)), 10.0, ["a"])
        path = tmp_path / "x.mat"
    else:
        path = write_record(record, tmp_path / f"x{suffix}")
    monkeypatch.setitem(sys.modules, module, None)  # import fails
    with pytest.raises(ImportError, match=r'pip install "sindy-impulse\[io\]"'):
        read_record(path)
    if module in ("pyuff", "nptdms"):  # LVM is written without lvm-read
        with pytest.raises(ImportError, match=r"sindy-impulse\[io\]"):
            write_record(record, tmp_path / f"y{suffix}")
        assert not (tmp_path / f"y{suffix}").exists()
    if module == "pyuff":
        with pytest.raises(ImportError, match=r"sindy-impulse\[io\]"):
            write_uff55(tmp_path / "m.uff", [{"frequency_hz": 1.0, "damping_ratio": 0.0}])


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"fs": float("nan")}, "fs must be finite"),
        ({"fs": -1.0}, "fs must be positive"),
        ({"channel_names": ("a", "b")}, "channel_names has 2 entries for 3 channels"),
        ({"channel_names": ("a", "a", "b")}, "distinct"),
        ({"units": ("N",)}, "units has 1 entries"),
        ({"directions": (7, 0, 0)}, "directions must be in -6..6"),
        ({"force_channel": 3}, "force_channel 3"),
    ],
)
def test_record_validation(kwargs, message):
    with pytest.raises(ValueError, match=message):
        Record(np.zeros((4, 3)), **{"fs": 10.0, **kwargs})


def test_record_data_checks():
    with pytest.raises(ValueError, match="ragged"):
        Record([[1.0, 2.0], [3.0]], fs=1.0)
    with pytest.raises(ValueError, match="non-finite values .first at sample 1, channel 0"):
        Record([[0.0], [np.inf]], fs=1.0)
    rec = Record(np.arange(3.0), fs=2.0)
    assert rec.data.shape == (3, 1) and not rec.data.flags.writeable and rec.force is None
    np.testing.assert_array_equal(rec.t, [0.0, 0.5, 1.0])


def test_uff55_round_trip(tmp_path):
    shape1 = np.array([1.0, 0.523456 - 0.101234j, -0.25 + 0.3j])
    modes = [
        {"frequency_hz": 120.123456789, "damping_ratio": 0.0123456789, "shape": shape1},
        SimpleNamespace(frequency_hz=310.5, damping_ratio=0.02, shape=None),  # a Mode-like object
        {"frequency_hz": 455.0, "damping_ratio": 0.0, "shape": [0.5, 1j, -1.0], "nodes": [7, 7, 9],
         "directions": [1, 2, 3]},
    ]  # fmt: skip
    path = write_uff55(tmp_path / "modes.uff", modes, nodes=[1, 2, 3], directions=[3, 3, 3])
    back = read_uff55(path)
    assert [m["frequency_hz"] for m in back] == [120.123456789, 310.5, 455.0]
    assert [m["damping_ratio"] for m in back] == [0.0123456789, 0.02, 0.0]
    np.testing.assert_allclose(back[0]["shape"], shape1, rtol=1e-5)
    assert (back[0]["nodes"], back[0]["directions"]) == ([1, 2, 3], [3, 3, 3])
    assert (back[1]["shape"].tolist(), back[1]["nodes"], back[1]["directions"]) == ([1 + 0j], [1], [3])
    np.testing.assert_allclose(back[2]["shape"], [0.5, 1j, -1.0], rtol=1e-5)
    assert (back[2]["nodes"], back[2]["directions"]) == ([7, 7, 9], [1, 2, 3])
    with pytest.raises(FileExistsError):
        write_uff55(path, modes)

    # without the exact values in ID line 4: from the 6-digit eigenvalue
    text = path.read_text().replace("sindy-impulse {", "NONE            {")
    (tmp_path / "plain.uff").write_text(text)
    plain = read_uff55(tmp_path / "plain.uff")
    np.testing.assert_allclose([m["frequency_hz"] for m in plain], [120.123456789, 310.5, 455.0], rtol=1e-5)
    np.testing.assert_allclose([m["damping_ratio"] for m in plain], [0.0123456789, 0.02, 0.0], atol=1e-6)


def test_uff55_bad_modes(tmp_path):
    with pytest.raises(ValueError, match="directions"):
        write_uff55(
            tmp_path / "m.uff", [{"frequency_hz": 1.0, "damping_ratio": 0.1, "shape": [1], "directions": [4]}]
        )
    with pytest.raises(ValueError, match="damping_ratio"):
        write_uff55(tmp_path / "m.uff", [{"frequency_hz": 1.0, "damping_ratio": 1.5}])
    with pytest.raises(ValueError, match="2 shape values but 1 nodes"):
        write_uff55(
            tmp_path / "m.uff", [{"frequency_hz": 1.0, "damping_ratio": 0.1, "shape": [1, 2], "nodes": [1]}]
        )
    with pytest.raises(ValueError, match="no modes"):
        write_uff55(tmp_path / "m.uff", [])
    assert not os.listdir(tmp_path)
    (tmp_path / "r.uff").write_text("")
    with pytest.raises(ValueError, match="no mode data set 55"):
        read_uff55(tmp_path / "r.uff")


# ---------------------------------------------------------------------------------------------------------
# the modal survey written as UFF 55 (survey.to_uff, sindy-impulse modes --uff)
# ---------------------------------------------------------------------------------------------------------
def _two_channel_survey():
    import warnings

    from sindy_impulse import identify_modes, impact_record

    rec = impact_record([90.0, 210.0], [0.005, 0.008], fs=2048, duration=1.5, snr_db=50,
                        sensor_dof=[0, 1], random_state=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return identify_modes(rec.y, fs=rec.fs), rec


def test_a_survey_written_as_uff55_reads_back_with_its_modes_and_shapes(tmp_path):
    pytest.importorskip("pyuff")
    survey, _ = _two_channel_survey()
    assert len(survey.modes) == 2 and all(m.shape is not None for m in survey.modes)
    path = survey.to_uff(tmp_path / "modes.unv", nodes=[11, 12])
    back = read_uff55(path)
    assert [b["frequency_hz"] for b in back] == [m.frequency_hz for m in survey.modes]
    assert [b["damping_ratio"] for b in back] == [m.damping_ratio for m in survey.modes]
    for b, m in zip(back, survey.modes):
        assert list(b["nodes"]) == [11, 12]
        np.testing.assert_allclose(b["shape"], m.shape, rtol=1e-5, atol=1e-6 * np.max(np.abs(m.shape)))
    with pytest.raises(FileExistsError):
        survey.to_uff(path)


def test_the_modes_command_writes_the_uff55_table(tmp_path):
    pytest.importorskip("pyuff")
    import warnings

    from sindy_impulse.cli import main

    _, rec = _two_channel_survey()
    csv = tmp_path / "hit.csv"
    np.savetxt(csv, np.column_stack([rec.t, rec.y]), delimiter=",", header="t,a,b", comments="")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["modes", str(csv), "--no-nonlinearity", "--uff", str(tmp_path / "modes.unv")]) == 0
    back = read_uff55(tmp_path / "modes.unv")
    assert [round(b["frequency_hz"]) for b in back] == [90, 210]


@pytest.mark.parametrize("suffix", [".npz", ".uff", ".tdms", ".lvm", ".mat"])
def test_the_modes_command_reads_modal_testing_files_as_it_reads_csv(tmp_path, suffix):
    import json
    import warnings

    from sindy_impulse.cli import main

    if suffix in (".uff", ".tdms", ".lvm"):
        pytest.importorskip({".uff": "pyuff", ".tdms": "nptdms", ".lvm": "lvm_read"}[suffix])
    rec = impact_record([90.0, 210.0], [0.005, 0.008], fs=2048, duration=1.5, snr_db=50, random_state=0)
    data = np.column_stack([rec.y, rec.force])
    record = Record(data, rec.fs, channel_names=("acc", "hammer"), force_channel=1)
    write_record(record, tmp_path / f"hit{suffix}")
    csv = tmp_path / "hit.csv"
    table = np.column_stack([rec.t, data])
    np.savetxt(csv, table, delimiter=",", header="t,acc,hammer", comments="", fmt="%.17g")
    reports = []
    for path, extra in ((csv, ["--force", "hammer"]), (tmp_path / f"hit{suffix}", [])):
        out = tmp_path / f"{path.suffix[1:]}.json"
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            assert main(["modes", str(path), "--no-nonlinearity", "--json", str(out), *extra]) == 0
        reports.append(json.loads(out.read_text()))
    assert reports[1]["channels"] == ["acc"]
    by_csv, by_file = ([m["frequency_hz"] for m in r["modes"]] for r in reports)
    assert [round(f) for f in by_csv] == [90, 210]
    np.testing.assert_allclose(by_file, by_csv, rtol=1e-4)


def test_the_modes_command_names_a_missing_channel(tmp_path, capsys):
    from sindy_impulse.cli import main

    rec = impact_record(90.0, 0.005, fs=2048, duration=1.0, random_state=0)
    write_record(Record(rec.y[:, None], rec.fs, channel_names=("acc",)), tmp_path / "hit.npz")
    assert main(["modes", str(tmp_path / "hit.npz"), "--force", "F"]) != 0
    assert "no channel 'F'" in capsys.readouterr().err


def _labview_lvm(path, fs: float, n: int, delta_text: str) -> None:
    """A one-channel LVM as LabVIEW writes it: Delta_X and the X column printed to few digits."""
    head = [
        "LabVIEW Measurement\t", "Writer_Version\t2", "Reader_Version\t2", "Separator\tTab",
        "Decimal_Separator\t.", "Multi_Headings\tYes", "X_Columns\tMulti", "Time_Pref\tAbsolute",
        "***End_of_Header***\t", "\t", "Channels\t1\t", f"Samples\t{n}\t", "Y_Unit_Label\tg\t",
        "X_Dimension\tTime\t", "X0\t0.0000000000000000E+0\t", f"Delta_X\t{delta_text}\t",
        "***End_of_Header***\t\t", "X_Value\tAcceleration\tComment",
    ]
    t = np.arange(n) / fs
    y = np.exp(-2.0 * t) * np.sin(2 * np.pi * 40.0 * t)
    path.write_text("\n".join(head + [f"{a:.6f}\t{b:.6f}" for a, b in zip(t, y)]) + "\n")


def test_lvm_rounded_delta_x_gives_way_to_the_x_column(tmp_path):
    pytest.importorskip("lvm_read")
    fs = 51200.0 / 31.0  # Delta_X printed as 0.000605: 1 / Delta_X is 0.08 % off
    _labview_lvm(tmp_path / "tap.lvm", fs, 20000, "0.000605")
    assert read_record(tmp_path / "tap.lvm").fs == pytest.approx(fs, rel=1e-7)
    _labview_lvm(tmp_path / "exact.lvm", 2048.0, 500, "4.882812500000000E-4")  # exact: kept
    assert read_record(tmp_path / "exact.lvm").fs == 2048.0

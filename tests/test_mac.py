"""The Modal Assurance Criterion (analysis.mac) and its picture (plotting.plot_mac)."""

import warnings

import matplotlib
import numpy as np
import pytest

from sindy_impulse.analysis import MacResult, mac_result
from sindy_impulse.analysis.mac import (
    mac,
)  # the function (a doctest run may rebind analysis.mac to the module)
from sindy_impulse.exceptions import DataWarning
from sindy_impulse.modes import Mode
from sindy_impulse.plotting import plot_mac

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after choosing the non-interactive backend)


def _mode(f, shape):
    return Mode(f, 0.01, (f - 1.0, f + 1.0), 1.0, 0.0, model=None, states=None, t=None, shape=shape)


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def test_orthogonal_shapes_give_the_identity():
    rng = np.random.default_rng(0)
    Q, _ = np.linalg.qr(rng.standard_normal((6, 6)) + 1j * rng.standard_normal((6, 6)))
    np.testing.assert_allclose(mac(Q.T[:4]), np.eye(4), atol=1e-12)
    np.testing.assert_allclose(mac(Q.T[:4], Q.T), np.eye(4, 6), atol=1e-12)


def test_complex_scaling_does_not_change_mac():
    rng = np.random.default_rng(1)
    a = rng.standard_normal(5) + 1j * rng.standard_normal(5)
    for c in (3.0, -0.2j, 1e-200 * (2 - 5j), 1e150 * np.exp(1j * 0.7)):
        assert mac(a, c * a)[0, 0] == pytest.approx(1.0, abs=1e-12)


def test_auto_mac_is_symmetric_with_a_unit_diagonal():
    rng = np.random.default_rng(2)
    shapes = rng.standard_normal((5, 8)) + 1j * rng.standard_normal((5, 8))
    m = mac(shapes)
    np.testing.assert_array_equal(m, m.T)
    np.testing.assert_allclose(np.diag(m), 1.0, rtol=1e-12)
    assert np.all((m >= 0) & (m <= 1))
    np.testing.assert_allclose(mac(shapes[::-1], shapes), mac(shapes, shapes[::-1]).T, rtol=1e-12)


def test_known_value_of_two_real_vectors():
    assert mac([1.0, 2.0, 3.0], [1.0, 0.0, -1.0])[0, 0] == pytest.approx(4 / 28, rel=1e-14)
    assert mac([1.0, 0.0], [1.0, 1.0])[0, 0] == 0.5
    assert mac([[1.0, 0.0]], [[0.0, 1.0]])[0, 0] == 0.0


def test_none_entries_are_left_out_with_a_warning():
    a = [np.array([1.0, 0.0, 0.0]), None, np.array([0.0, 1.0, 1.0])]
    b = [_mode(120.34, np.array([1.0, 0.1, 0.0], dtype=complex)), _mode(250.0, None)]
    with pytest.warns(DataWarning) as record:
        res = mac_result(a, b)
    text = " ".join(str(w.message) for w in record)
    assert "shapes_a[1]" in text and "shapes_b[1] (1: 250 Hz)" in text
    assert isinstance(res, MacResult) and res.shape == (2, 1)
    assert res.rows.tolist() == [0, 2] and res.columns.tolist() == [0]
    assert res.dropped_a == (1,) and res.dropped_b == (1,)
    assert res.labels_b == ["0: 120.3 Hz"] and res.labels_a == ["0", "2"]
    assert res.matrix[0, 0] == pytest.approx(1 / 1.01)
    with pytest.warns(DataWarning):
        assert mac(a).shape == (2, 2)


def test_modes_are_not_mistaken_for_arrays():
    """Arrays have ``.shape`` too: only objects with ``frequency_hz`` are read as modes."""
    shapes = np.array([[1.0, 1j], [1.0, -1j]])
    modes = [_mode(10.0, shapes[0]), _mode(20.0, shapes[1])]
    np.testing.assert_allclose(mac(modes), mac(shapes), atol=1e-15)
    assert mac(modes[0], shapes[0])[0, 0] == pytest.approx(1.0)


@pytest.mark.parametrize(
    "a, b, error, match",
    [
        (np.ones((2, 3)), np.ones((2, 4)), ValueError, "shapes_a has 3 channels but shapes_b has 4"),
        ([[1.0, 0.0], [0.0, 0.0]], None, ValueError, r"shapes_a\[1\] is zero"),
        ([[1.0, 0.0]], [[0.0, 0.0]], ValueError, r"shapes_b\[0\] is zero"),
        ([[1.0, np.nan]], None, ValueError, "non-finite"),
        ([[1.0, 2.0], [1.0, 2.0, 3.0]], None, ValueError, r"shapes_a\[1\] has 3 channels"),
        ([None, None], None, ValueError, "none of its 2 modes"),
        ([], None, ValueError, "no mode shape"),
        (np.ones((2, 2, 2)), None, ValueError, "2-D"),
        ([["a", "b"]], None, TypeError, "numeric"),
        (None, None, TypeError, "shapes_a"),
    ],
)
def test_bad_shapes_are_named(a, b, error, match):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DataWarning)
        with pytest.raises(error, match=match):
            mac(a, b)


def test_plot_mac_draws_the_matrix_with_annotations_and_a_colorbar():
    shapes = np.array([[1.0, 1.0, 0.0], [1.0, -1.0, 0.0], [0.5, 0.0, 1.0]])
    fig, ax = plt.subplots()
    out = plot_mac(shapes, shapes[:2], ax=ax)
    assert out is ax
    image = ax.images[0].get_array()
    assert image.shape == (3, 2)
    np.testing.assert_allclose(image, mac(shapes, shapes[:2]))
    texts = [t.get_text() for t in ax.texts]
    assert len(texts) == 6 and texts[0] == "1.00" and texts[1] == "0.00"
    assert len(fig.axes) == 2 and fig.axes[1].get_ylabel() == "MAC"  # the colorbar
    assert [t.get_text() for t in ax.get_yticklabels()] == ["0", "1", "2"]
    assert ax.images[0].get_clim() == (0.0, 1.0)


def test_plot_mac_labels_modes_and_takes_matrices():
    modes = [_mode(120.34, np.array([1.0, 0.2j])), None, _mode(310.0, np.array([0.1, 1.0]))]
    with pytest.warns(DataWarning):
        ax = plot_mac(modes, annotate=False)
    assert ax.images[0].get_array().shape == (2, 2) and len(ax.texts) == 0
    assert [t.get_text() for t in ax.get_xticklabels()] == ["0: 120.3 Hz", "2: 310 Hz"]
    assert ax.get_title() == "auto-MAC"
    ax = plot_mac(np.array([[1.0, 0.2, 0.0]]), labels_a=["x"], labels_b=["p", "q", "r"])
    assert ax.images[0].get_array().shape == (1, 3)
    assert [t.get_text() for t in ax.get_xticklabels()] == ["p", "q", "r"]
    res = mac_result(np.eye(3) + 0.1j)
    assert plot_mac(res).images[0].get_array().shape == (3, 3)


def test_plot_mac_refuses_bad_input():
    with pytest.raises(ValueError, match=r"\[0, 1\]"):
        plot_mac(np.array([[1.0, 2.0], [0.5, 1.0]]))
    with pytest.raises(ValueError, match="labels_b"):
        plot_mac(np.eye(2), labels_b=["a"])
    with pytest.raises(TypeError, match="ax"):
        plot_mac(np.eye(2), ax="axes")
    with pytest.raises(TypeError, match="annotate"):
        plot_mac(np.eye(2), annotate="yes")


def test_mac_of_two_repeated_surveys():
    from sindy_impulse import identify_modes
    from sindy_impulse.datasets import impact_record

    surveys, true = [], None
    for seed in (0, 1):
        rec = impact_record(
            [40.0, 130.0],
            [0.01, 0.01],
            fs=1000.0,
            duration=1.5,
            sensor_dof=[0, 1],
            snr_db=50,
            random_state=seed,
        )
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            surveys.append(identify_modes(rec.y, fs=rec.fs))
        true = rec.modes
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DataWarning)
        res = mac_result(surveys[0], surveys[1])
    assert res.matrix.size >= 1
    np.testing.assert_allclose(np.diag(res.matrix), 1.0, atol=1e-3)  # the same shapes hit after hit
    true_shapes = true.amplitude * np.exp(1j * true.phase)
    for k, mode in enumerate(surveys[0].modes):
        if mode.shape is not None:
            nearest = int(np.argmin(np.abs(true.frequency_hz - mode.frequency_hz)))
            assert mac(mode, true_shapes[nearest])[0, 0] > 0.99, k

import numpy as np
import pytest

from sindy_impulse._utils.trajectories import check_trajectories
from sindy_impulse._utils.validation import check_signal, check_time


def test_check_signal_reshapes_1d():
    assert check_signal([1.0, 2.0, 3.0]).shape == (3, 1)


@pytest.mark.parametrize(
    "bad, exc, match",
    [
        ([1.0, np.nan, 2.0], ValueError, "NaN"),
        ([1.0, np.inf], ValueError, "inf"),
        ([], ValueError, "empty"),
        (np.array([1 + 1j, 2]), ValueError, "complex"),
        (np.zeros((5, 0)), ValueError, "0 feature"),
        (np.array(["a", "b"]), TypeError, "non-numeric"),
        (np.zeros((2, 2, 2)), ValueError, "1-D or 2-D"),
    ],
)
def test_check_signal_rejects(bad, exc, match):
    with pytest.raises(exc, match=match):
        check_signal(bad, "x")


def test_check_signal_min_samples_names_numbers():
    with pytest.raises(ValueError, match="3 samples; at least 10"):
        check_signal(np.zeros(3), "x", min_samples=10)


def test_check_time():
    assert check_time(0.5, 3) == 0.5
    np.testing.assert_array_equal(check_time([0, 1, 2], 3), [0, 1, 2])
    with pytest.raises(ValueError, match="strictly increasing"):
        check_time([0, 2, 1], 3)
    with pytest.raises(ValueError, match="3 entries but the data have 4"):
        check_time([0, 1, 2], 4)
    with pytest.raises(ValueError, match="positive"):
        check_time(-1.0, 3)


def test_check_trajectories():
    trajs, multi = check_trajectories([np.zeros((5, 2)), np.ones((4, 2))])
    assert multi and len(trajs) == 2
    one, multi = check_trajectories([[1.0, 2.0], [3.0, 4.0]])
    assert not multi and one[0].shape == (2, 2)
    with pytest.raises(ValueError, match="same number of states"):
        check_trajectories([np.zeros((5, 2)), np.ones((4, 3))])


def test_sparse_refused():
    from scipy import sparse

    with pytest.raises(TypeError, match="sparse"):
        check_signal(sparse.csr_matrix(np.eye(3)), "x")


def test_check_array_keeps_the_layout_and_names_the_argument():
    from sindy_impulse._utils.validation import check_array

    assert check_array([[[1, 0]], [[2, 0]]], "coefficients", ndim=(3,)).shape == (2, 1, 2)
    assert check_array(np.array([1, 2], dtype=object), "values").dtype == float
    message = r"values contains 1 non-finite value\(s\) \(inf first at index \(1,\)\)$"
    with pytest.raises(ValueError, match=message):
        check_array([1.0, np.inf], "values")
    with pytest.raises(ValueError, match="values is complex"):
        check_array([1j, 1.0], "values")
    with pytest.raises(ValueError, match=r"m must be 2-D, got an array of shape \(3,\)$"):
        check_array([1.0, 2.0, 3.0], "m", ndim=(2,))
    with pytest.raises(ValueError, match=r"x is ragged"):
        check_array([[1.0, 2.0], [3.0]], "x")
    assert check_array([np.nan, np.inf], "x", allow_nan=True, allow_inf=True).shape == (2,)

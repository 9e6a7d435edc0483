"""The robust standard deviation shared by every noise estimate."""

import numpy as np
import pytest

from sindy_impulse._utils.robust import MAD_TO_STD, robust_std


def test_gaussian_noise_reads_its_standard_deviation():
    x = np.random.default_rng(1).normal(3.0, 0.5, 200_000)
    assert robust_std(x) == pytest.approx(0.5, rel=0.01)


def test_spikes_and_offset_do_not_move_it():
    x = np.random.default_rng(2).normal(0.0, 1.0, 5_000)
    spiked = x.copy()
    spiked[::100] = 1e4
    assert robust_std(spiked + 7.0) == pytest.approx(robust_std(x), rel=0.05)
    assert np.std(spiked) > 100


def test_along_an_axis_each_column_has_its_own():
    rng = np.random.default_rng(3)
    x = np.column_stack([rng.normal(0, 1, 20_000), rng.normal(5, 3, 20_000)])
    spread = robust_std(x, axis=0)
    assert spread.shape == (2,)
    np.testing.assert_allclose(spread, [1.0, 3.0], rtol=0.03)
    assert spread[1] == pytest.approx(robust_std(x[:, 1]))


def test_scale_is_the_gaussian_one():
    assert MAD_TO_STD == pytest.approx(1 / 0.6744897501960817, rel=1e-4)


def test_a_centre_given_is_the_median_not_computed_again():
    rng = np.random.default_rng(4)
    x = rng.normal(2.0, 1.5, (3000, 3))
    assert robust_std(x[:, 0], centre=float(np.median(x[:, 0]))) == robust_std(x[:, 0])
    np.testing.assert_array_equal(robust_std(x, axis=0, centre=np.median(x, axis=0)), robust_std(x, axis=0))

import numpy as np
import pytest

from sindy_impulse import gamma


def test_gamma_definition():
    x = np.array([[2.0, -4.0], [1.0, 0.0], [0.0, 1.0]])
    recon = x + np.array([[0.2, 0.4], [0.0, -0.4], [0.0, 0.0]])
    # state 0: 0.2 / 2 ; state 1: (0.4 + 0.4) / 4
    assert gamma(x, recon) == pytest.approx(0.1 + 0.2)


def test_gamma_scale_free_and_inf_on_divergence():
    x = np.random.default_rng(0).normal(size=(50, 2))
    r = x + 0.01
    assert gamma(x * 1e6, r * 1e6) == pytest.approx(gamma(x, r))
    r[10] = np.nan
    assert gamma(x, r) == np.inf


def test_gamma_lists_and_errors():
    x = np.ones((5, 1))
    assert gamma([x, x], [x + 1, x]) == pytest.approx(5.0)
    with pytest.raises(ValueError, match="shape"):
        gamma(np.ones((5, 2)), np.ones((4, 2)))
    with pytest.raises(ValueError, match="NaN"):
        gamma([1.0, np.nan], [1.0, 1.0])

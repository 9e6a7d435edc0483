"""modal_parameters: eigenvalues of the linear part, physical and delay-embedded states."""

import numpy as np
import pysindy as ps
import pytest

from sindy_impulse import DelayEmbedding, ImpulseSINDy, damped_oscillator
from sindy_impulse.analysis import ModalParameters, modal_parameters
from sindy_impulse.feature_library import TermTable
from sindy_impulse.poles.modal import jacobian_at_origin
from sindy_impulse.simulation import CompiledModel

F_TRUE = 8.0 / (2 * np.pi)


def test_known_matrix():
    modes = modal_parameters([[0.0, 1.0], [-64.0, -3.2]])
    assert isinstance(modes, ModalParameters)
    f, zeta = modes
    np.testing.assert_allclose(f, [F_TRUE], rtol=1e-12)
    np.testing.assert_allclose(zeta, [0.2], rtol=1e-12)


def test_two_modes_sorted_and_real_eigenvalues_dropped():
    # block diagonal: a 3 Hz mode, a 1 Hz mode and a real (overdamped) eigenvalue
    w1, w2 = 2 * np.pi * 3.0, 2 * np.pi * 1.0
    A = np.zeros((5, 5))
    A[0:2, 0:2] = [[0, 1], [-(w1**2), -2 * 0.05 * w1]]
    A[2:4, 2:4] = [[0, 1], [-(w2**2), -2 * 0.1 * w2]]
    A[4, 4] = -7.0
    f, zeta = modal_parameters(A)
    np.testing.assert_allclose(f, [1.0, 3.0], rtol=1e-10)
    np.testing.assert_allclose(zeta, [0.1, 0.05], rtol=1e-10)


def test_no_oscillatory_mode():
    f, zeta = modal_parameters(np.diag([-1.0, -2.0]))
    assert f.size == 0 and zeta.size == 0


def test_invariant_under_change_of_coordinates():
    A = np.array([[0.0, 1.0], [-64.0, -3.2]])
    T = np.array([[2.0, -1.0], [0.5, 3.0]])
    B = T @ A @ np.linalg.inv(T)
    np.testing.assert_allclose(modal_parameters(B).frequencies_hz, modal_parameters(A).frequencies_hz)
    np.testing.assert_allclose(modal_parameters(B).damping_ratios, modal_parameters(A).damping_ratios)


def test_compiled_model_with_cubic_term_uses_linear_part():
    terms = TermTable.polynomial([[1, 0], [0, 1], [3, 0]])
    model = CompiledModel([[0.0, 1.0, 0.0], [-64.0, -3.2, -10.0]], terms)
    np.testing.assert_allclose(jacobian_at_origin(model), [[0, 1], [-64, -3.2]], atol=1e-8)
    np.testing.assert_allclose(modal_parameters(model).frequencies_hz, [F_TRUE], rtol=1e-9)


def test_fitted_model_both_states():
    ring = damped_oscillator(snr_db=40, random_state=3)
    model = ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=3)).fit(ring.x, t=ring.t)
    f, zeta = modal_parameters(model)
    assert f.shape == (1,)
    assert abs(f[0] / F_TRUE - 1) < 0.005
    assert abs(zeta[0] / 0.2 - 1) < 0.05


def test_fitted_model_delay_embedded():
    ring = damped_oscillator(snr_db=40, random_state=4)
    emb = DelayEmbedding().fit(ring.x[:, 0])
    model = ImpulseSINDy().fit(emb.transform(ring.x[:, 0]), t=0.01)
    f, zeta = modal_parameters(model)
    assert abs(f[0] / F_TRUE - 1) < 0.005
    assert abs(zeta[0] / 0.2 - 1) < 0.05


def test_plain_pysindy_model():
    t, x, x_dot = damped_oscillator()
    model = ps.SINDy(feature_library=ps.PolynomialLibrary(degree=1)).fit(x, t=t, x_dot=x_dot)
    np.testing.assert_allclose(modal_parameters(model).frequencies_hz, [F_TRUE], rtol=1e-3)


def test_errors():
    with pytest.raises(ValueError, match="square"):
        modal_parameters(np.zeros((2, 3)))
    with pytest.raises(ValueError, match="NaN"):
        modal_parameters([[np.nan, 1.0], [0.0, 1.0]])
    with pytest.raises(TypeError, match="ImpulseSINDy"):
        modal_parameters("model")
    with pytest.raises(ValueError, match="fitted"):
        modal_parameters(ImpulseSINDy())

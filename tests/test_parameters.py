"""parameter_dependency: relative change of the coefficients along a control parameter."""

import numpy as np
import pysindy as ps
import pytest

from sindy_impulse import ImpulseSINDy, damped_oscillator
from sindy_impulse.analysis import ParameterDependency, parameter_dependency


def _stack(deltas):
    return np.array([[[0.0, 1.0], [-64.0, -16.0 * d]] for d in deltas])


def test_damping_term_flagged_only():
    deltas = [0.3, 0.1, 0.2, 0.25, 0.15]  # unsorted on purpose
    dep = parameter_dependency(_stack(deltas), deltas, reference=0.2, feature_names=["x0", "x1"])
    assert isinstance(dep, ParameterDependency)
    np.testing.assert_allclose(dep.values, sorted(deltas))
    assert dep.values[dep.reference_index] == 0.2
    assert dep.varying_terms == ["x1' : x1"]
    assert dep.invariant_terms == ["x0' : x1", "x1' : x0"]
    np.testing.assert_allclose(dep.ratio[:, 1, 1], np.array(sorted(deltas)) / 0.2)
    np.testing.assert_allclose(dep.relative_change[:, 1, 1], np.array(sorted(deltas)) / 0.2 - 1)
    np.testing.assert_allclose(dep.max_change[1, 1], 0.5)
    np.testing.assert_allclose(dep.elasticity[1, 1], 1.0)
    np.testing.assert_allclose(dep.elasticity[1, 0], 0.0, atol=1e-12)
    assert np.isnan(dep.elasticity[0, 0])
    assert "x1' : x1" in repr(dep)


def test_zero_in_reference_and_threshold():
    stack = _stack([0.1, 0.2, 0.3])
    stack[2, 0, 0] = 0.5  # a term that appears away from the reference
    stack[0, 1, 0] *= 1.005  # 0.5 % change: below the default 1 %
    dep = parameter_dependency(stack, [0.1, 0.2, 0.3])  # default reference: the median, 0.2
    assert dep.reference_index == 1
    assert np.isposinf(dep.relative_change[2, 0, 0]) and dep.varies[0, 0]
    assert dep.relative_change[0, 0, 0] == 0.0  # zero in both
    assert not dep.varies[1, 0]
    assert parameter_dependency(stack, [0.1, 0.2, 0.3], threshold=0.001).varies[1, 0]


def test_fitted_models():
    deltas = [0.1, 0.2, 0.3]
    lib = ps.PolynomialLibrary(degree=1)
    models = [ImpulseSINDy(feature_library=lib).fit(damped_oscillator(c=16 * d).x, t=0.01) for d in deltas]
    dep = parameter_dependency(models, deltas, reference=0.2)
    assert dep.varying_terms == ["x1' : x1"]
    assert dep.feature_names == ["1", "x0", "x1"]


def test_errors():
    stack = _stack([0.1, 0.2])
    with pytest.raises(ValueError, match="one value per model"):
        parameter_dependency(stack, [0.1, 0.2, 0.3])
    with pytest.raises(ValueError, match="NaN"):
        parameter_dependency(stack, [0.1, np.nan])
    with pytest.raises(ValueError, match="not one of the values"):
        parameter_dependency(stack, [0.1, 0.2], reference=0.15)
    with pytest.raises(ValueError, match="threshold"):
        parameter_dependency(stack, [0.1, 0.2], threshold=-1)

import pickle

import numpy as np
import pysindy as ps
import pytest
from sklearn.base import clone

from sindy_impulse import ImpulseSINDy, MechanicalLibrary


def test_names_and_values():
    x = np.array([[2.0, -0.5], [-1.0, 0.25]])
    lib = MechanicalLibrary(degree=2).fit(x)
    names = lib.get_feature_names(["x", "v"])
    assert names == ["x", "v", "x^2", "x v", "v^2", "x|x|", "v|v|", "sgn(x)", "sgn(v)"]
    theta = lib.transform(x)
    np.testing.assert_allclose(theta[:, names.index("v|v|")], x[:, 1] * np.abs(x[:, 1]))
    np.testing.assert_allclose(theta[:, names.index("sgn(x)")], np.tanh(x[:, 0] / (0.01 * 2.0)))


def test_options_and_errors():
    x = np.ones((4, 2))
    assert MechanicalLibrary(degree=1, quadratic_damping=False, friction=False).fit(x).n_output_features_ == 2
    assert MechanicalLibrary(degree=1, include_bias=True).fit(x).n_output_features_ == 7
    with pytest.raises(ValueError, match="degree"):
        MechanicalLibrary(degree=-1).fit(x)
    with pytest.raises(ValueError, match="friction_width"):
        MechanicalLibrary(friction_width=0).fit(x)
    lib = MechanicalLibrary().fit(x)
    with pytest.raises(ValueError, match="3 states"):
        lib.transform(np.ones((4, 3)))
    assert pickle.loads(pickle.dumps(clone(lib))).degree == 3


def test_identifies_quadratic_damping():
    # x'' = -64 x - 0.8 x'|x'|: the quadratic damping term must be found with plain PySINDy too
    from scipy.integrate import solve_ivp

    t = np.arange(401) * 0.01
    sol = solve_ivp(lambda _t, y: [y[1], -64 * y[0] - 0.8 * y[1] * abs(y[1])], (0, 4), [1.0, 0.0],
                    t_eval=t, rtol=1e-12, atol=1e-12).y.T
    x_dot = np.column_stack([sol[:, 1], -64 * sol[:, 0] - 0.8 * sol[:, 1] * np.abs(sol[:, 1])])
    model = ImpulseSINDy(feature_library=MechanicalLibrary(degree=1), refine=False)
    model.fit(sol, t=t, x_dot=x_dot, feature_names=["x", "v"])
    names = model.get_feature_names()
    coef = model.coefficients()
    assert set(np.array(names)[coef[1] != 0]) == {"x", "v|v|"}
    assert coef[1, names.index("v|v|")] == pytest.approx(-0.8, rel=1e-4)
    plain = ps.SINDy(feature_library=MechanicalLibrary(degree=1), optimizer=ps.STLSQ(threshold=0.1))
    plain.fit(sol, t=t, x_dot=x_dot)
    assert plain.coefficients()[1, names.index("v|v|")] == pytest.approx(-0.8, rel=1e-3)

import pickle

import numpy as np
import pysindy as ps
import pytest
from scipy.integrate import solve_ivp
from sklearn.base import clone

from sindy_impulse import ImpulseSINDy, MechanicalLibrary
from sindy_impulse.feature_library import term_table
from sindy_impulse.simulation import CompiledModel, FallbackModel, compile_model

DEFAULT_NAMES = ["x", "v", "x^3", "x^2 v", "x v^2", "v^3", "x|x|", "v|v|", "|x| v", "sgn(v)"]


def _ring(rhs, x0=(1.0, 0.0), n=401, dt=0.01):
    t = np.arange(n) * dt
    sol = solve_ivp(lambda _t, y: [y[1], rhs(*y)], (0, t[-1]), x0, t_eval=t, rtol=1e-12, atol=1e-12).y.T
    return t, sol, np.column_stack([sol[:, 1], rhs(sol[:, 0], sol[:, 1])])


def test_default_terms_for_a_single_mode():
    x = np.array([[2.0, -0.5], [-1.0, 0.25], [0.5, 1.0]])
    lib = MechanicalLibrary().fit(x)
    names = lib.get_feature_names(["x", "v"])
    assert names == DEFAULT_NAMES
    theta = lib.transform(x)
    xx, vv = x[:, 0], x[:, 1]
    expected = {
        "x^2 v": xx**2 * vv,
        "v|v|": vv * np.abs(vv),
        "|x| v": np.abs(xx) * vv,
        "sgn(v)": np.tanh(vv / (0.01 * 1.0)),
    }
    for name, values in expected.items():
        np.testing.assert_allclose(theta[:, names.index(name)], values)


def test_every_term_is_odd():
    x = np.random.default_rng(0).normal(size=(20, 2))
    lib = MechanicalLibrary().fit(x)
    np.testing.assert_allclose(lib.transform(-x), -lib.transform(x))


def test_options():
    x = np.ones((4, 2))
    off = dict(quadratic_damping=False, amplitude_damping=False, friction=False)
    assert MechanicalLibrary(degree=1, **off).fit(x).n_output_features_ == 2
    assert MechanicalLibrary(degree=3, **off).fit(x).n_output_features_ == 6  # odd terms only
    assert MechanicalLibrary(degree=3, odd=False, **off).fit(x).n_output_features_ == 9
    assert MechanicalLibrary(degree=1, include_bias=True).fit(x).get_feature_names()[0] == "1"
    three = MechanicalLibrary(degree=1, quadratic_damping=False, friction=False).fit(np.ones((4, 3)))
    assert three.n_output_features_ == 3 + 6  # |x_j| x_k for the 6 ordered pairs: every state a velocity
    assert MechanicalLibrary(degree=1).fit(np.ones((4, 1))).get_feature_names() == ["x0", "x0|x0|", "sgn(x0)"]


def test_velocities():
    x = np.ones((4, 2))
    every = MechanicalLibrary(degree=1, quadratic_damping=False, velocities=None).fit(x)
    assert every.get_feature_names(["x", "v"]) == ["x", "v", "|v| x", "|x| v", "sgn(x)", "sgn(v)"]
    first = MechanicalLibrary(degree=1, quadratic_damping=False, velocities=[0]).fit(x)
    assert first.get_feature_names(["v", "x"]) == ["v", "x", "|x| v", "sgn(v)"]
    assert first.velocities_.tolist() == [0]
    four = MechanicalLibrary(degree=1, quadratic_damping=False, velocities=[2, 3]).fit(np.ones((4, 4)))
    assert four.n_output_features_ == 4 + 6 + 2
    for bad in ([2], [], [0.5], "x"):
        with pytest.raises(ValueError, match="velocities"):
            MechanicalLibrary(velocities=bad).fit(x)


def test_errors_and_cloning():
    x = np.ones((4, 2))
    with pytest.raises(ValueError, match="degree"):
        MechanicalLibrary(degree=-1).fit(x)
    with pytest.raises(ValueError, match="friction_width"):
        MechanicalLibrary(friction_width=0).fit(x)
    with pytest.raises(ValueError, match="odd"):
        MechanicalLibrary(odd="yes").fit(x)
    with pytest.raises(ValueError, match="reshape"):
        MechanicalLibrary().fit(np.ones(4))
    lib = MechanicalLibrary().fit(x)
    with pytest.raises(ValueError, match="3 states"):
        lib.transform(np.ones((4, 3)))
    assert pickle.loads(pickle.dumps(clone(lib))).degree == 3


def test_compiled_simulator_path():
    t, x, _ = _ring(lambda x, v: -64 * x - 0.5 * np.abs(x) * v)
    lib = MechanicalLibrary().fit(x)
    table = term_table(lib, 2)
    np.testing.assert_allclose(table.evaluate(x), lib.transform(x))
    coef = np.zeros((2, lib.n_output_features_))
    names = lib.get_feature_names(["x", "v"])
    coef[0, names.index("v")] = 1.0
    coef[1, names.index("x")], coef[1, names.index("|x| v")] = -64.0, -0.5
    compiled = compile_model(coef, table, x)
    assert isinstance(compiled, CompiledModel)
    fallback = FallbackModel(coef, lib.transform, 2, x)
    np.testing.assert_allclose(compiled.simulate(x[0], t), x, atol=1e-4)  # |x| has a kink: RK4 ~1e-5
    np.testing.assert_allclose(fallback.simulate(x[0], t), compiled.simulate(x[0], t), atol=1e-4)


@pytest.mark.parametrize(
    ("term", "rhs"),
    [
        ("v|v|", lambda x, v: -64 * x - 0.8 * v * np.abs(v)),
        ("|x| v", lambda x, v: -64 * x - 0.8 * np.abs(x) * v),
        ("x^2 v", lambda x, v: -64 * x - 0.8 * x**2 * v),
    ],
)
def test_identifies_amplitude_dependent_damping(term, rhs):
    t, x, x_dot = _ring(rhs)
    model = ImpulseSINDy(feature_library=MechanicalLibrary(), refine=False)
    model.fit(x, t=t, x_dot=x_dot, feature_names=["x", "v"])
    names = model.get_feature_names()
    coef = model.coefficients()
    assert set(np.array(names)[coef[1] != 0]) == {"x", term}
    assert coef[1, names.index(term)] == pytest.approx(-0.8, rel=1e-4)


def test_plain_pysindy_finds_quadratic_damping():
    t, x, x_dot = _ring(lambda x, v: -64 * x - 0.8 * v * np.abs(v))
    lib = MechanicalLibrary(degree=1, amplitude_damping=False)
    plain = ps.SINDy(feature_library=lib, optimizer=ps.STLSQ(threshold=0.1)).fit(x, t=t, x_dot=x_dot)
    names = plain.get_feature_names()
    assert plain.coefficients()[1, names.index("x1|x1|")] == pytest.approx(-0.8, rel=1e-3)


def test_no_terms_is_refused():
    with pytest.raises(ValueError, match="no terms"):
        MechanicalLibrary(degree=0, quadratic_damping=False, amplitude_damping=False, friction=False).fit(
            np.ones((4, 2))
        )
    assert MechanicalLibrary(degree=0).fit(np.ones((4, 2))).get_feature_names()[0] == "x0|x0|"

import numpy as np
import pysindy as ps
import pytest
from scipy.integrate import solve_ivp

from sindy_impulse.datasets import damped_oscillator
from sindy_impulse.feature_library import MechanicalLibrary, TermTable
from sindy_impulse.simulation import CompiledModel


def _poly_model(coef_entries, x, degree=3):
    lib = ps.PolynomialLibrary(degree=degree).fit(x)
    names = lib.get_feature_names()
    coef = np.zeros((2, len(names)))
    for (row, name), value in coef_entries.items():
        coef[row, names.index(name)] = value
    return CompiledModel(coef, TermTable.polynomial(lib.powers_), reference=x), coef, lib


@pytest.mark.parametrize("k_nl", [0.0, 10.0])
def test_agrees_with_solve_ivp(k_nl):
    t, x, _ = damped_oscillator(k_nl=k_nl, x0=(2.0, 0.0))
    model, _, _ = _poly_model({(0, "x1"): 1.0, (1, "x0"): -64, (1, "x1"): -3.2, (1, "x0^3"): -k_nl}, x)
    sim = model.simulate(x[0], t)
    ref = solve_ivp(
        lambda _t, y: [y[1], -64 * y[0] - 3.2 * y[1] - k_nl * y[0] ** 3], (0, 4), x[0], t_eval=t,
        rtol=1e-10, atol=1e-12,
    ).y.T
    rel = np.max(np.abs(sim - ref), axis=0) / np.max(np.abs(ref), axis=0)
    assert np.all(rel < 1e-6)


def test_rhs_matches_library_transform():
    t, x, _ = damped_oscillator()
    model, coef, lib = _poly_model({(0, "x1"): 1.0, (1, "x0"): -64, (1, "x0 x1^2"): 0.5, (1, "1"): 0.1}, x)
    np.testing.assert_allclose(model.rhs(x), lib.transform(x) @ coef.T, rtol=1e-12, atol=1e-12)


def test_mechanical_terms_match_solve_ivp():
    t, x, _ = damped_oscillator()
    lib = MechanicalLibrary(degree=1).fit(x)
    names = lib.get_feature_names()
    coef = np.zeros((2, len(names)))
    coef[0, names.index("x1")] = 1
    coef[1, names.index("x0")] = -64
    coef[1, names.index("x1|x1|")] = -0.4
    coef[1, names.index("sgn(x1)")] = -0.5
    model = CompiledModel(coef, lib.term_table_, reference=x)
    w = lib.friction_scale_[1]
    ref = solve_ivp(
        lambda _t, y: [y[1], -64 * y[0] - 0.4 * y[1] * abs(y[1]) - 0.5 * np.tanh(y[1] / w)], (0, 4), x[0],
        t_eval=t, rtol=1e-10, atol=1e-12,
    ).y.T
    sim = model.simulate(x[0], t)
    assert np.max(np.abs(sim - ref)) / np.max(np.abs(ref)) < 1e-6
    np.testing.assert_allclose(model.rhs(x), lib.transform(x) @ coef.T, rtol=1e-12, atol=1e-12)


def test_divergence_is_stopped_with_nan():
    t, x, _ = damped_oscillator()
    model, _, _ = _poly_model({(0, "x1"): 1.0, (1, "x0"): -64, (1, "x0^3"): 500.0, (1, "x0^2"): 80.0}, x)
    sim = model.simulate(x[0], t)
    assert np.isnan(sim[-1]).all()
    first_nan = np.argmax(np.isnan(sim[:, 0]))
    assert np.all(np.isfinite(sim[:first_nan]))


def test_unit_invariant_substeps():
    t, x, _ = damped_oscillator()
    a, _, _ = _poly_model({(0, "x1"): 1.0, (1, "x0"): -64, (1, "x1"): -3.2}, x)
    b, _, _ = _poly_model({(0, "x1"): 1.0, (1, "x0"): -64, (1, "x1"): -3.2}, x * 1e6)
    assert a.substeps(t) == b.substeps(t)


def test_shape_errors():
    terms = TermTable.polynomial([[1, 0], [0, 1]])
    with pytest.raises(ValueError, match="columns"):
        CompiledModel(np.zeros((2, 3)), terms)
    model = CompiledModel([[0, 1.0], [-1.0, 0]], terms)
    with pytest.raises(ValueError, match="x0 has 3 entries"):
        model.simulate([1, 2, 3], np.arange(3.0))


def _gamma_plan(x):
    scale = np.max(np.abs(x), axis=0)
    return np.zeros(1, dtype=np.int64), (1.0 / scale)[None, :]


def test_fused_gamma_equals_gamma_of_simulation():
    # the kernel accumulates Gamma while integrating (the hot path); it must equal metrics.gamma
    from sindy_impulse import gamma

    t, x, _ = damped_oscillator(snr_db=30, random_state=1)
    model, coef, _ = _poly_model({(0, "x1"): 1.0, (1, "x0"): -63, (1, "x1"): -3.0, (1, "x0^3"): -1.0}, x)
    g, rows = model.weighted_l1(x, t, *_gamma_plan(x))
    assert rows[0] == len(t) - 1
    assert g[0] == pytest.approx(gamma(x, model.simulate(x[0], t)), rel=1e-12)
    batch = np.stack([model.coef, 2 * model.coef])
    gb, _ = model.weighted_l1(x, t, *_gamma_plan(x), coefs=batch)
    assert gb[0] == pytest.approx(g[0], rel=1e-12)
    assert gb[1] == pytest.approx(gamma(x, model.simulate(x[0], t, coef=2 * model.coef)), rel=1e-12)


def test_fused_gamma_is_inf_on_divergence():
    t, x, _ = damped_oscillator()
    model, _, _ = _poly_model({(0, "x1"): 1.0, (1, "x0"): -64, (1, "x0^3"): 500.0, (1, "x0^2"): 80.0}, x)
    g, rows = model.weighted_l1(x, t, *_gamma_plan(x))
    assert g[0] == np.inf and rows[0] < len(t) - 1


def test_linear_model_simulated_by_its_propagator_equals_rk4_stages():
    from sindy_impulse.simulation import integrators
    from sindy_impulse.simulation.program import pack

    t, x, _ = damped_oscillator()
    model, _, _ = _poly_model({(0, "x1"): 1.0, (1, "x0"): -64, (1, "x1"): -3.2, (1, "1"): 0.1}, x)
    assert model.is_linear
    fast = model.simulate(x[0], t)
    stages = np.empty_like(fast)
    prog, vals = pack(model.program, model.coef[None])
    integrators.integrate(
        x[0][None], t, np.zeros(1, np.int64), np.zeros((1, 0)), model.substeps(t), prog, vals,
        integrators.NO_PROPAGATOR, model.bound, integrators.NO_INPUT, model._scratch, stages, np.empty(1),
        np.empty(1, np.int64),
    )
    np.testing.assert_allclose(fast, stages, rtol=0, atol=1e-12)


def test_long_record_is_scored_at_a_stride_with_the_same_value():
    from sindy_impulse.simulation import Gamma

    t, x, _ = damped_oscillator(dt=1e-4)  # 40,001 samples in a few periods: compared at a stride
    model, _, _ = _poly_model({(0, "x1"): 1.0, (1, "x0"): -63, (1, "x1"): -3.0}, x)
    measure = Gamma().bind([x], [t])
    assert measure.strides_[0] > 10
    full = np.sum(np.abs(model.simulate(x[0], t) - x) / np.max(np.abs(x), axis=0))
    assert measure(model)[0] == pytest.approx(full, rel=1e-3)


def test_read_only_data_are_simulated():
    t, x, _ = damped_oscillator()
    model, _, _ = _poly_model({(0, "x1"): 1.0, (1, "x0"): -64, (1, "x0^3"): -1.0}, x)
    x_ro, t_ro = x.copy(), t.copy()
    x_ro.flags.writeable = t_ro.flags.writeable = False
    errors, _ = model.weighted_l1(x_ro, t_ro, *_gamma_plan(x))
    assert errors[0] == model.weighted_l1(x, t, *_gamma_plan(x))[0]


def test_a_reference_object_gives_the_model_of_its_array():
    from sindy_impulse.simulation import Reference

    t, x, _ = damped_oscillator()
    model, coef, lib = _poly_model({(0, "x1"): 1.0, (1, "x0"): -64, (1, "x0^3"): -1.0}, x)
    shared = CompiledModel(coef, TermTable.polynomial(lib.powers_), reference=Reference(x))
    np.testing.assert_array_equal(shared.bound, model.bound)
    assert shared.spectral_radius == model.spectral_radius


def test_a_batch_stepped_together_scores_as_one_by_one():
    t, x, _ = damped_oscillator(k_nl=10.0)
    model, _, _ = _poly_model({(0, "x1"): 1.0, (1, "x0"): -64, (1, "x1"): -3.2, (1, "x0^3"): -10.0}, x)
    coefs = model.coef[None] * np.array([1.0, 1.01, 0.99, -1.0])[:, None, None]  # the last one diverges
    together, rows = model.weighted_l1(x, t, *_gamma_plan(x), coefs=coefs)
    alone = [model.weighted_l1(x, t, *_gamma_plan(x), coefs=c[None]) for c in coefs]
    np.testing.assert_array_equal(together, [a[0][0] for a in alone])
    np.testing.assert_array_equal(rows, [a[1][0] for a in alone])
    assert together[-1] == np.inf


def _rk4_reference(rhs, x0, t, substeps):
    """Plain numpy RK4 with the kernels' sub-steps (the reference of the compiled paths)."""
    out = [np.asarray(x0, dtype=float)]
    for s in range(1, len(t)):
        h, x = (t[s] - t[s - 1]) / substeps, out[-1]
        for _ in range(substeps):
            k1 = rhs(x)
            k2 = rhs(x + 0.5 * h * k1)
            k3 = rhs(x + 0.5 * h * k2)
            k4 = rhs(x + h * k3)
            x = x + h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
        out.append(x)
    return np.array(out)


@pytest.mark.parametrize(
    "entries",
    [
        # every term of both equations: constant, linear, quadratic, cubic
        {(0, "1"): 0.01, (0, "x0"): 0.1, (0, "x1"): 1.0, (0, "x0^2"): 0.2, (0, "x0 x1"): -0.1,
         (0, "x1^2"): 0.02, (0, "x0^3"): -0.3, (0, "x0^2 x1"): 0.1, (0, "x0 x1^2"): -0.02,
         (0, "x1^3"): 0.001, (1, "1"): -0.2, (1, "x0"): -64.0, (1, "x1"): -3.2, (1, "x0^2"): 3.0,
         (1, "x0 x1"): 0.4, (1, "x1^2"): -0.05, (1, "x0^3"): -10.0, (1, "x0^2 x1"): -2.0,
         (1, "x0 x1^2"): 0.03, (1, "x1^3"): -0.001},
        # only some: a cubic term in one equation, a quadratic one in the other
        {(0, "x1"): 1.0, (0, "x0^2"): 0.3, (1, "x0"): -64.0, (1, "x1"): -3.2, (1, "x0 x1^2"): -0.5},
    ],
)
def test_two_state_cubic_models_are_integrated_as_rk4_on_their_equations(entries):
    # the two-state cubic path (monomials in registers) against numpy RK4 on the library's terms, over
    # the first second (100 samples: every step is checked; the numpy reference takes 4 s a second)
    t, x, _ = damped_oscillator()
    model, coef, lib = _poly_model(entries, x)
    t, x = t[:101], x[:101]
    assert not model.is_linear
    steps = model.substeps(t)
    ref = _rk4_reference(lambda z: (lib.transform(z[None]) @ coef.T)[0], x[0], t, steps)
    sim = model.simulate(x[0], t)
    assert np.all(np.isfinite(sim))
    np.testing.assert_allclose(sim, ref, rtol=0, atol=1e-10 * np.max(np.abs(ref)))
    # the gradient batch of the refinement steps the same arithmetic
    starts, weights = np.zeros(1, np.int64), np.ones((1, 2))
    batch = np.repeat(coef[None, :, np.any(coef != 0, axis=0)], 4, axis=0)
    together, _ = model.weighted_l1(x, t, starts, weights, coefs=batch)
    alone, _ = model.weighted_l1(x, t, starts, weights, coefs=batch[:1])
    np.testing.assert_array_equal(together, np.full(4, alone[0]))


@pytest.mark.parametrize("affine", [False, True])
def test_the_linear_kernel_is_the_general_loop_with_propagators(affine):
    """integrate_linear (a linear model's simulation beyond two states) gives the general kernel's errors,
    rows and trajectories bit for bit: segments, a constant term, a batch, and a model that diverges."""
    from sindy_impulse.simulation import integrators
    from sindy_impulse.simulation.program import build_program, pack, propagators

    rng = np.random.default_rng(5)
    n, n_t = 3, 400
    powers = np.vstack([np.zeros((1, n), int), np.eye(n, dtype=int)]) if affine else np.eye(n, dtype=int)
    program = build_program(TermTable.polynomial(powers), n)
    A = rng.standard_normal((4, n, n)) - 3 * np.eye(n)
    A[-1] += 8 * np.eye(n)  # the batch's last model grows until it leaves the bounds
    coefs = np.concatenate([rng.standard_normal((4, n, 1)), A], axis=2) if affine else A
    t = np.arange(n_t) * 0.01
    props = propagators(program, coefs, 0.01, 3)
    ref = rng.standard_normal((n_t, n))
    starts, weights = np.array([0, 150, 290]), rng.uniform(0.5, 2, (3, n))
    bound = np.full(n, 50.0)
    for batch, out in ((slice(None), np.empty((0, 0))), (slice(0, 1), np.empty((n_t, n))),
                       (slice(3, 4), np.empty((n_t, n)))):
        if out.size:  # a simulation from one state: ref holds the start only
            ref, starts = ref[:1], np.zeros(1, np.int64)
        p = np.ascontiguousarray(props[batch])
        got = [np.empty(p.shape[0]), np.empty(p.shape[0], dtype=np.int64), out.copy()]
        want = [np.empty(p.shape[0]), np.empty(p.shape[0], dtype=np.int64), out.copy()]
        integrators.integrate_linear(ref, t, starts, weights, p, bound, got[2], got[0], got[1])
        work = np.empty(integrators.scratch_size(n, program.n_values))
        prog, vals = pack(program, np.ascontiguousarray(coefs[batch]))
        integrators.integrate(ref, t, starts, weights, 3, prog, vals, p, bound, np.empty((n_t, 0)), work,
                              want[2], want[0], want[1])
        for a, b in zip(got, want):
            assert np.array_equal(a, b, equal_nan=True)
    assert not np.isfinite(got[0][0]) and np.isnan(got[2][-1]).all()  # the diverging model


def test_a_linear_batch_is_scored_by_its_propagators_alone():
    """A linear model's batch of three states on a uniform grid needs no kernel program (not packed), and
    scores as its models one by one; a two-state one keeps the two-state kernel (the first fit's)."""
    t, x2, _ = damped_oscillator()
    x = np.column_stack([x2, np.exp(-t)])
    terms = TermTable.polynomial([[1, 0, 0], [0, 1, 0], [0, 0, 1]])
    model = CompiledModel([[0.0, 1.0, 0.0], [-64.0, -3.2, 0.0], [0.0, 0.0, -1.0]], terms, x)
    batch = model.coef[None] * np.array([1.0, 1.01, 0.99])[:, None, None]
    prog, vals, props, dense = model._packed(batch, 0.01, model.substeps(t))
    assert prog is None and dense is None and props.shape == (3, 3, 3)
    together = model.weighted_l1(x, t, [0], np.ones((1, 3)), batch)[0]
    alone = [model.weighted_l1(x, t, [0], np.ones((1, 3)), c[None])[0][0] for c in batch]
    assert np.array_equal(together, alone)
    two = CompiledModel([[0.0, 1.0], [-64.0, -3.2]], TermTable.polynomial([[1, 0], [0, 1]]), x2)
    assert two._packed(two.coef[None], 0.01, two.substeps(t))[3] is not None


@pytest.mark.parametrize("affine", [False, True])
def test_propagators_are_the_rk4_polynomial_power_bit_for_bit(affine):
    """The propagators, the identity broadcast by the additions, are the stacked identity's ``eye + hA @
    (...)`` to the last bit."""
    from sindy_impulse.simulation.program import build_program, propagators

    powers = [[0, 0, 0, 0]] * affine + [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
    program = build_program(TermTable.polynomial(powers), 4)
    rng = np.random.default_rng(3)
    for n_models in (1, 7):
        coefs = 30 * rng.normal(size=(n_models, 4, len(powers)))
        coefs[rng.random(coefs.shape) < 0.3] = 0.0
        for substeps in (1, 2, 3, 4, 5, 11, 64):
            m = 5 if affine else 4
            A = np.zeros((n_models, m, m))
            for k, j in enumerate(program.linear_state):
                if j >= 0 or m > 4:
                    A[:, :4, 4 if j < 0 else j] += coefs[:, :, k]
            hA = A * (0.01 / substeps)
            eye = np.broadcast_to(np.eye(m), A.shape)
            P = eye + hA @ (eye + hA @ (eye + hA @ (eye + hA / 4.0) / 3.0) / 2.0)
            expected = np.linalg.matrix_power(P, substeps)
            np.testing.assert_array_equal(propagators(program, coefs, 0.01, substeps), expected)

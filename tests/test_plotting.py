"""sindy_impulse.plotting: one function per figure of the paper, on small fitted objects.

Each function runs on fitted objects, draws the expected artists, uses the Axes passed in (no new figure),
never calls ``plt.show()`` and refuses bad input with a clear ValueError/TypeError.
"""

from __future__ import annotations

import dataclasses

import matplotlib
import numpy as np
import pysindy as ps
import pytest
from scipy import sparse

import sindy_impulse.plotting as plotting
from sindy_impulse import DelayEmbedding, ImpulseSINDy, TVRegDiff, damped_oscillator
from sindy_impulse.analysis import complexity_error, consensus, nonlinearity_test, parameter_dependency
from sindy_impulse.identification.estimator import SweepPath
from sindy_impulse.plotting import (
    plot_alpha_curve,
    plot_complexity_error,
    plot_consensus,
    plot_embedding,
    plot_feature_space,
    plot_filtering,
    plot_linear_vs_nonlinear,
    plot_parameter_dependency,
    plot_reconstruction,
    plot_refinement,
    plot_sweep,
)

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after choosing the non-interactive backend)

COEF = np.array([[0.0, 1.0], [-64.0, -3.2]])


# ------------------------------------------------------------------------------------------------------
# fixtures (module scope: every fit once)
# ------------------------------------------------------------------------------------------------------
@pytest.fixture(autouse=True)
def _close_figures():
    plt.close("all")  # figures another module's tests left open in this worker are not counted
    yield
    plt.close("all")


@pytest.fixture(autouse=True)
def _no_show(monkeypatch):
    def show(*args, **kwargs):
        raise AssertionError("plt.show() called")

    monkeypatch.setattr(plt, "show", show)


@pytest.fixture(scope="module")
def linear():
    return damped_oscillator(snr_db=30, random_state=0)


@pytest.fixture(scope="module")
def duffing():
    return damped_oscillator(k_nl=50.0, x0=(2.0, 0.0), snr_db=40, random_state=0)


@pytest.fixture(scope="module")
def model(linear):
    return ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=2)).fit(linear.x, t=linear.t)


@pytest.fixture(scope="module")
def cubic_models(linear, duffing):
    lib = ps.PolynomialLibrary(degree=3)
    return (
        ImpulseSINDy(feature_library=lib).fit(linear.x, t=linear.t),
        ImpulseSINDy(feature_library=lib).fit(duffing.x, t=duffing.t),
    )


@pytest.fixture(scope="module")
def nonlinearity(cubic_models, duffing):
    return nonlinearity_test(cubic_models[1], duffing.x, duffing.t)


@pytest.fixture(scope="module")
def embedding(linear):
    return DelayEmbedding().fit(linear.x[:, 0])


@pytest.fixture(scope="module")
def complexity(linear, duffing):
    estimators = {p: ImpulseSINDy(feature_library=ps.PolynomialLibrary(degree=p)) for p in (1, 2)}
    return complexity_error(estimators, {"linear": linear.x, "duffing": duffing.x}, t=0.01)


@pytest.fixture(scope="module")
def dependency():
    damping = np.array([2.4, 3.2, 4.0])
    stack = np.array([[[0.0, 1.0], [-64.0, -c]] for c in damping])
    return parameter_dependency(stack, damping / 16, reference=0.2, feature_names=["x0", "x1"])


@pytest.fixture(scope="module")
def agreement():
    rng = np.random.default_rng(0)
    stack = COEF * (1 + 0.01 * rng.standard_normal((36, 2, 2)))
    return consensus(stack, feature_names=["x0", "x1"])


def _n_figures() -> int:
    return len(plt.get_fignums())


# ------------------------------------------------------------------------------------------------------
# module
# ------------------------------------------------------------------------------------------------------
def test_all_lists_one_function_per_figure():
    assert len(plotting.__all__) == 17  # 11 figures of the paper, backbone curves, modal survey and one
    # mode's decay, MAC, stabilisation chart, tracking's control charts
    for name in plotting.__all__:
        func = getattr(plotting, name)
        assert callable(func)
        assert "Examples" in func.__doc__ and 'matplotlib.use("Agg")' in func.__doc__


@pytest.mark.parametrize("bad", ["ax", 3, object()])
def test_a_non_axes_ax_is_refused(model, bad):
    with pytest.raises(TypeError, match=r"ax must be a matplotlib Axes"):
        plot_sweep(model, ax=bad)


@pytest.mark.parametrize("bad", [[1, 2], ["a", "b"]])
def test_a_sequence_of_non_axes_is_refused(model, bad):
    with pytest.raises(TypeError, match=r"ax must contain matplotlib Axes only"):
        plot_reconstruction(model, ax=bad)


# ------------------------------------------------------------------------------------------------------
# Figure 7a: alpha curve
# ------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("criterion", ["error", "gcv", "consistency", "residual", "dof"])
def test_alpha_curve_draws_curve_and_chosen_alpha(model, criterion):
    fig, ax = plt.subplots()
    out = plot_alpha_curve(model, column=1, criterion=criterion, ax=ax)
    assert out is ax and _n_figures() == 1
    assert len(ax.lines) == 3  # curve, chosen point, vertical line
    curve = model.differentiation_method_.alpha_curve_[1]
    np.testing.assert_allclose(ax.lines[0].get_xdata(), curve["alpha"])
    chosen = model.differentiation_method_.alpha_[1]
    assert ax.lines[1].get_xdata()[0] == pytest.approx(chosen)
    assert ax.get_xscale() == "log"


def test_alpha_curve_takes_a_tvregdiff(linear):
    diff = TVRegDiff(alpha_selection="consistency")
    diff(linear.x, linear.t)
    ax = plot_alpha_curve(diff)
    assert len(ax.lines) == 3 and "consistency" in ax.get_ylabel()


@pytest.mark.parametrize(
    "kwargs, exc, regex",
    [
        ({"column": 2}, ValueError, r"column=2 is out of range"),
        ({"column": 0.5}, TypeError, r"column must be an int"),
        ({"criterion": "aic"}, ValueError, r"criterion must be one of"),
    ],
)
def test_alpha_curve_refuses_bad_arguments(model, kwargs, exc, regex):
    with pytest.raises(exc, match=regex):
        plot_alpha_curve(model, **kwargs)


def test_alpha_curve_refuses_unusable_objects(linear):
    with pytest.raises(TypeError, match=r"tvregdiff_or_model must be a TVRegDiff or an ImpulseSINDy"):
        plot_alpha_curve(np.zeros(3))
    with pytest.raises(ValueError, match=r"not fitted"):
        plot_alpha_curve(TVRegDiff())
    with pytest.raises(ValueError, match=r"not fitted"):
        plot_alpha_curve(ImpulseSINDy())
    given = TVRegDiff(alpha=1e-3)
    given(linear.x, linear.t)
    with pytest.raises(ValueError, match=r"column 0 has no alpha curve: alpha was given"):
        plot_alpha_curve(given)
    other = ImpulseSINDy(differentiation_method=ps.FiniteDifference()).fit(damped_oscillator().x, t=0.01)
    with pytest.raises(TypeError, match=r"not a TVRegDiff"):
        plot_alpha_curve(other)


# ------------------------------------------------------------------------------------------------------
# Figure 7b / A1: filtering
# ------------------------------------------------------------------------------------------------------
def test_filtering_from_arrays_uses_the_axes_given(linear, model):
    fig, axes = plt.subplots(2, 1)
    out = plot_filtering(linear.x, model.x_filtered_, linear.t, ax=axes)
    assert list(out) == list(axes) and _n_figures() == 1
    assert [len(a.lines) for a in axes] == [2, 2]
    np.testing.assert_allclose(axes[1].lines[1].get_ydata(), model.x_filtered_[:, 1])


def test_filtering_from_model_and_tvregdiff(linear, model):
    axes = plot_filtering(linear.x, model, clean=damped_oscillator().x)
    assert len(axes) == 2 and [len(a.lines) for a in axes] == [3, 3]
    np.testing.assert_allclose(axes[0].lines[0].get_xdata(), linear.t)  # t from the model
    diff = TVRegDiff()
    diff(linear.x[:, :1], linear.t)
    fig, ax = plt.subplots()
    out = plot_filtering(linear.x[:, 0], diff, ax=ax)
    assert out[0] is ax and ax.get_xlabel() == "sample"


def test_filtering_refuses_bad_input(linear, model):
    with pytest.raises(ValueError, match=r"filtered has shape \(401, 1\) but x has shape \(401, 2\)"):
        plot_filtering(linear.x, linear.x[:, :1], linear.t)
    with pytest.raises(ValueError, match=r"x contains 1 non-finite"):
        bad = linear.x.copy()
        bad[3, 1] = np.nan
        plot_filtering(bad, model)
    with pytest.raises(ValueError, match=r"t has 10 entries"):
        plot_filtering(linear.x, model, linear.t[:10])
    with pytest.raises(ValueError, match=r"clean has shape"):
        plot_filtering(linear.x, model, clean=linear.x[:5])
    with pytest.raises(ValueError, match=r"unfitted TVRegDiff"):
        plot_filtering(linear.x, TVRegDiff())
    fig, ax = plt.subplots()
    with pytest.raises(ValueError, match=r"ax has 1 axes but 2 are needed"):
        plot_filtering(linear.x, model, ax=ax)


# ------------------------------------------------------------------------------------------------------
# Figure 6a: sweep
# ------------------------------------------------------------------------------------------------------
def test_sweep_marks_the_selected_candidate(model):
    fig, ax = plt.subplots()
    out = plot_sweep(model, ax=ax)
    assert out is ax and _n_figures() == 1
    assert len(ax.lines) == 2  # candidates, selected (no candidate diverged)
    path = model.path_
    assert ax.lines[1].get_xdata()[0] == path.n_terms[path.selected]
    assert ax.lines[1].get_ydata()[0] == pytest.approx(path.gamma[path.selected])
    assert ax.get_yscale() == "log"


def test_sweep_shows_diverged_candidates_and_thresholds():
    path = SweepPath(
        threshold=np.array([0.0, 0.01, 0.1, 0.5]),
        score=np.array([np.inf, 0.0, 2.0, 40.0]),
        n_terms=np.array([6, 3, 2, 1]),
        coefficients=np.zeros((4, 2, 3)),
        selected=1,
    )
    ax = plot_sweep(path, x="threshold")
    assert len(ax.lines) == 3
    diverged = ax.lines[1]
    assert diverged.get_xdata().tolist() == [0.0] and diverged.get_ydata()[0] > 40.0
    assert ax.lines[2].get_ydata()[0] > 0  # Gamma = 0 is raised onto the log axis
    assert ax.get_xscale() == "symlog"


def test_sweep_refuses_bad_input(model):
    with pytest.raises(TypeError, match=r"model_or_path must be a fitted ImpulseSINDy or a SweepPath"):
        plot_sweep({"gamma": [1.0]})
    with pytest.raises(ValueError, match=r"not fitted"):
        plot_sweep(ImpulseSINDy())
    with pytest.raises(ValueError, match=r"x must be one of"):
        plot_sweep(model, x="gamma")
    diverged = dataclasses.replace(model.path_, score=np.full(len(model.path_), np.inf))
    with pytest.raises(ValueError, match=r"no candidate has a finite score"):
        plot_sweep(diverged)


# ------------------------------------------------------------------------------------------------------
# Figures 6b, 8a, 8d: reconstruction
# ------------------------------------------------------------------------------------------------------
def test_reconstruction_draws_input_and_model_per_state(model, linear):
    fig, axes = plt.subplots(2, 1)
    out = plot_reconstruction(model, ax=axes)
    assert list(out) == list(axes) and _n_figures() == 1
    assert [len(a.lines) for a in axes] == [2, 2]
    assert axes[0].get_ylabel() == "x0" and axes[0].get_title().startswith("Gamma = ")
    out = plot_reconstruction(model, x=linear.x, t=0.01, state_names=["x", "v"])
    np.testing.assert_allclose(out[0].lines[0].get_xdata(), linear.t)
    assert out[1].get_ylabel() == "v"


@pytest.mark.parametrize(
    "x, t, exc, regex",
    [
        (np.zeros((401, 3)), 0.01, ValueError, r"x has 3 states \(columns\) but the model has 2"),
        ("x", 0.01, TypeError, r"x has non-numeric dtype"),
        (sparse.csr_matrix(np.ones((401, 2))), 0.01, TypeError, r"x is a sparse matrix"),
        (np.ones((401, 2)) + 1j, 0.01, ValueError, r"x is complex"),
        (np.ones((401, 2)), None, ValueError, r"t is required when x is given"),
        (np.ones((401, 2)), np.arange(400.0), ValueError, r"t has 400 entries"),
        (np.ones((401, 2)), -0.01, ValueError, r"t \(time step\) must be a positive"),
        (np.ones((1, 2)), 0.01, ValueError, r"x has 1 sample; at least 2"),
    ],
)
def test_reconstruction_refuses_bad_input(model, x, t, exc, regex):
    with pytest.raises(exc, match=regex):
        plot_reconstruction(model, x=x, t=t)


def test_reconstruction_refuses_unfitted_or_foreign_models():
    with pytest.raises(ValueError, match=r"model is not fitted"):
        plot_reconstruction(ImpulseSINDy())
    with pytest.raises(TypeError, match=r"model must be a fitted ImpulseSINDy"):
        plot_reconstruction(np.zeros((3, 2)))


# ------------------------------------------------------------------------------------------------------
# Figures 8b, 8e: refinement
# ------------------------------------------------------------------------------------------------------
def test_refinement_draws_gamma_and_each_nonzero_coefficient(model):
    fig, axes = plt.subplots(2, 1)
    out = plot_refinement(model, axes=axes)
    assert list(out) == list(axes) and _n_figures() == 1
    history = model.refinement_history_
    assert len(axes[0].lines) == 1 and len(axes[0].lines[0].get_xdata()) == len(history["score"])
    n_active = int(np.count_nonzero(np.any(np.asarray(history["coefficients"]) != 0, axis=0)))
    assert len(axes[1].lines) == n_active >= 2
    assert axes[1].lines[0].get_ydata()[0] == pytest.approx(1.0)  # relative to the SINDy value
    absolute = plot_refinement(history, relative=False)
    first = np.asarray(history["coefficients"])[:, 0, :]
    k = int(np.flatnonzero(first[0] != 0)[0])
    np.testing.assert_allclose(absolute[1].lines[0].get_ydata(), first[:, k])


def test_refinement_refuses_missing_history(linear):
    unrefined = ImpulseSINDy(refine=False).fit(linear.x, t=linear.t)
    with pytest.raises(ValueError, match=r"model has no refinement history \(fitted with refine=False"):
        plot_refinement(unrefined)
    with pytest.raises(ValueError, match=r"must have the keys 'score' and 'coefficients'"):
        plot_refinement({"score": [1.0]})
    with pytest.raises(TypeError, match=r"relative must be True or False"):
        plot_refinement({"score": [1.0], "coefficients": [COEF]}, relative="yes")
    with pytest.raises(ValueError, match=r"history\['coefficients'\] must be 3-D"):
        plot_refinement({"score": [1.0], "coefficients": [1.0]})


# ------------------------------------------------------------------------------------------------------
# Figure 9: embedding
# ------------------------------------------------------------------------------------------------------
def test_embedding_panels_mark_tau_and_m(embedding, linear):
    fig, axes = plt.subplots(1, 3)
    out = plot_embedding(embedding, signal=linear.x[:, 0], axes=axes)
    assert list(out) == list(axes) and _n_figures() == 1
    assert len(axes[0].lines) == 3  # ACF, zero level, tau
    assert axes[0].lines[2].get_xdata()[0] == embedding.tau_
    assert len(axes[1].lines) == 3  # FNN fraction, threshold, m
    assert axes[1].lines[2].get_xdata()[0] == embedding.dimension_
    q = embedding.transform(linear.x[:, 0])
    np.testing.assert_allclose(axes[2].lines[0].get_xdata(), q[:, 0])
    assert axes[2].get_xlabel() == "q1"
    assert len(plot_embedding(embedding)) == 2


def test_embedding_other_estimators_and_given_parameters(linear):
    s = linear.x[:, 0]
    axes = plot_embedding(DelayEmbedding(delay_method="mutual_information", dimension_method="cao").fit(s))
    assert axes[0].get_ylabel() == "AMI (nats)" and axes[1].get_ylabel() == "Cao E1"
    given = DelayEmbedding(tau=10, dimension=1).fit(s)
    axes = plot_embedding(given, signal=s)
    assert len(axes[0].texts) == 1 and len(axes[1].texts) == 1
    np.testing.assert_allclose(axes[2].lines[0].get_ydata(), s[10:])


def test_embedding_refuses_bad_input(embedding, linear):
    with pytest.raises(TypeError, match=r"embedding must be a fitted DelayEmbedding"):
        plot_embedding(linear.x)
    with pytest.raises(ValueError, match=r"embedding is not fitted"):
        plot_embedding(DelayEmbedding())
    with pytest.raises(ValueError, match=r"signal has 2 columns"):
        plot_embedding(embedding, signal=linear.x)
    with pytest.raises(ValueError, match=r"signal contains 1 non-finite"):
        plot_embedding(embedding, signal=np.r_[np.nan, linear.x[1:, 0]])
    with pytest.raises(ValueError, match=r"signal has 5 samples"):
        plot_embedding(embedding, signal=np.ones(5))
    with pytest.raises(ValueError, match=r"axes has 2 axes but 3 are needed"):
        plot_embedding(embedding, signal=linear.x[:, 0], axes=plt.subplots(1, 2)[1])


# ------------------------------------------------------------------------------------------------------
# Figure 10: complexity-error plane
# ------------------------------------------------------------------------------------------------------
def test_complexity_error_colors_by_label_and_marks_the_front(complexity):
    fig, ax = plt.subplots()
    out = plot_complexity_error(complexity, ax=ax)
    assert out is ax and _n_figures() == 1
    assert len(ax.collections) == 2  # degrees 1 and 2
    assert sum(len(c.get_offsets()) for c in ax.collections) == len(complexity)
    front = complexity.pareto_front()
    np.testing.assert_array_equal(ax.lines[0].get_xdata(), complexity.n_terms[front])
    assert [t.get_text() for t in ax.get_legend().get_texts()][:2] == ["estimator 1", "estimator 2"]
    ax = plot_complexity_error(complexity, color_by="input", metric="gamma_filtered")
    assert len(ax.collections) == 2 and ax.get_ylabel() == "Gamma_filtered"


def test_complexity_error_leaves_out_failed_fits(complexity):
    gamma = complexity.gamma.copy()
    gamma[0] = np.inf
    ax = plot_complexity_error(dataclasses.replace(complexity, gamma=gamma))
    assert sum(len(c.get_offsets()) for c in ax.collections) == len(complexity) - 1
    assert ax.get_title() == "1 failed or diverged model(s) not shown"
    with pytest.raises(ValueError, match=r"no successful model with a finite gamma"):
        plot_complexity_error(dataclasses.replace(complexity, gamma=np.full(len(complexity), np.inf)))


def test_complexity_error_refuses_bad_input(complexity):
    with pytest.raises(TypeError, match=r"result must be a ComplexityError"):
        plot_complexity_error({"gamma": [1.0]})
    with pytest.raises(ValueError, match=r"color_by must be one of"):
        plot_complexity_error(complexity, color_by="degree")
    with pytest.raises(ValueError, match=r"metric must be one of"):
        plot_complexity_error(complexity, metric="aic")


# ------------------------------------------------------------------------------------------------------
# Figure 11: parameter dependency
# ------------------------------------------------------------------------------------------------------
def test_parameter_dependency_highlights_varying_terms(dependency):
    fig, ax = plt.subplots()
    out = plot_parameter_dependency(dependency, ax=ax)
    assert out is ax and _n_figures() == 1
    assert len(ax.lines) == 3 + 2  # 3 non-zero coefficients, level 1, reference
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert legend == dependency.varying_terms == ["x1' : x1"]
    varying = [ln for ln in ax.lines if ln.get_label() == "x1' : x1"][0]
    np.testing.assert_allclose(varying.get_ydata(), [0.75, 1.0, 1.25])
    assert ax.lines[-1].get_xdata()[0] == pytest.approx(0.2)
    ax = plot_parameter_dependency(dependency, quantity="relative_change")
    np.testing.assert_allclose(ax.lines[2].get_ydata(), [-0.25, 0.0, 0.25])


def test_parameter_dependency_refuses_bad_input(dependency):
    with pytest.raises(TypeError, match=r"result must be a ParameterDependency"):
        plot_parameter_dependency(np.zeros(3))
    with pytest.raises(ValueError, match=r"quantity must be one of"):
        plot_parameter_dependency(dependency, quantity="elasticity")


# ------------------------------------------------------------------------------------------------------
# Figure 12: consensus
# ------------------------------------------------------------------------------------------------------
def test_consensus_draws_one_histogram_per_nonzero_coefficient(agreement):
    keys = sorted(agreement.histograms)
    assert len(keys) == 3
    fig, axes = plt.subplots(1, 3)
    out = plot_consensus(agreement, axes=axes, true_coefficients=COEF)
    assert list(out) == list(axes) and _n_figures() == 1
    for a, key in zip(axes, keys):
        assert len(a.patches) == len(agreement.histograms[key].counts)
        assert len(a.lines) == 2  # consensus, true value
        assert a.lines[0].get_xdata()[0] == pytest.approx(agreement.coefficients[key])
        assert a.get_title() == agreement.names()[key]
    assert len(plot_consensus(agreement)[0].lines) == 1


def test_consensus_refuses_bad_input(agreement):
    with pytest.raises(TypeError, match=r"result must be a Consensus"):
        plot_consensus(COEF)
    with pytest.raises(ValueError, match=r"result has no histograms"):
        plot_consensus(dataclasses.replace(agreement, histograms={}))
    with pytest.raises(ValueError, match=r"true_coefficients has shape \(1, 2\)"):
        plot_consensus(agreement, true_coefficients=[[1.0, 2.0]])
    with pytest.raises(ValueError, match=r"true_coefficients contains 1 non-finite"):
        plot_consensus(agreement, true_coefficients=[[np.nan, 1.0], [2.0, 3.0]])
    with pytest.raises(ValueError, match=r"axes has 2 axes but 3 are needed"):
        plot_consensus(agreement, axes=plt.subplots(1, 2)[1])


# ------------------------------------------------------------------------------------------------------
# Figure 13: linear vs nonlinear
# ------------------------------------------------------------------------------------------------------
def test_linear_vs_nonlinear_from_signals(linear, duffing):
    fig, ax = plt.subplots()
    out = plot_linear_vs_nonlinear(linear.t, linear.x, duffing.x, ax=ax, column=1)
    assert out is ax and _n_figures() == 1
    assert len(ax.lines) == 2
    np.testing.assert_allclose(ax.lines[1].get_ydata(), duffing.x[:, 1])


def test_linear_vs_nonlinear_from_models_and_from_a_test_result(cubic_models, nonlinearity):
    axes = plot_linear_vs_nonlinear(*cubic_models)
    assert len(axes) == 2 and len(axes[0].lines) == 2
    shown = np.count_nonzero((cubic_models[0].coefficients() != 0) | (cubic_models[1].coefficients() != 0))
    assert len(axes[1].patches) == 2 * shown
    fig, ax = plt.subplots()
    out = plot_linear_vs_nonlinear(nonlinearity, ax=ax)
    assert out is ax
    shown = np.count_nonzero(
        (nonlinearity.linear_coefficients != 0) | (nonlinearity.nonlinear_coefficients != 0)
    )
    assert len(ax.patches) == 2 * shown
    assert ax.get_title().startswith("nonlinear")
    assert "x1' : x0^3" in [t.get_text() for t in ax.get_xticklabels()]


def test_linear_vs_nonlinear_refuses_bad_input(linear, duffing, cubic_models, nonlinearity, model):
    with pytest.raises(ValueError, match=r"x_nonlinear has shape \(400, 2\) but x_linear has shape"):
        plot_linear_vs_nonlinear(linear.t, linear.x, duffing.x[:400])
    with pytest.raises(TypeError, match=r"pass t, x_linear and x_nonlinear"):
        plot_linear_vs_nonlinear(linear.t, linear.x)
    with pytest.raises(ValueError, match=r"x_linear contains 1 non-finite"):
        plot_linear_vs_nonlinear(linear.t, np.r_[[[np.inf, 0.0]], linear.x[1:]], duffing.x)
    with pytest.raises(ValueError, match=r"t has 3 entries"):
        plot_linear_vs_nonlinear([0.0, 1.0, 2.0], linear.x, duffing.x)
    with pytest.raises(ValueError, match=r"column=2 is out of range"):
        plot_linear_vs_nonlinear(linear.t, linear.x, duffing.x, column=2)
    with pytest.raises(ValueError, match=r"different libraries"):
        plot_linear_vs_nonlinear(model, cubic_models[1])
    with pytest.raises(TypeError, match=r"pass the nonlinear model as second argument"):
        plot_linear_vs_nonlinear(model, duffing.x)
    with pytest.raises(TypeError, match=r"with a NonlinearityResult, pass no x_linear"):
        plot_linear_vs_nonlinear(nonlinearity, linear.x)
    with pytest.raises(ValueError, match=r"labels must be a pair"):
        plot_linear_vs_nonlinear(linear.t, linear.x, duffing.x, labels="ab")


# ------------------------------------------------------------------------------------------------------
# Figure 14: feature space
# ------------------------------------------------------------------------------------------------------
def test_feature_space_one_scatter_per_label():
    points = np.random.default_rng(0).standard_normal((30, 2))
    points[4] = np.nan  # a failed reconstruction
    labels = np.array(["linear"] * 15 + ["Duffing"] * 15)
    fig, ax = plt.subplots()
    out = plot_feature_space(points, labels, ax=ax)
    assert out is ax and _n_figures() == 1
    assert len(ax.collections) == 2
    assert [len(c.get_offsets()) for c in ax.collections] == [14, 15]
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["linear", "Duffing"]
    assert ax.get_title() == "1 row(s) with NaN not shown"
    ax = plot_feature_space(points[5:])
    assert len(ax.collections) == 1 and ax.get_legend() is None and ax.get_xlabel() == "PC1"


@pytest.mark.parametrize(
    "features, labels, exc, regex",
    [
        (np.zeros((5, 3)), None, ValueError, r"features_2d must have 2 columns.*PCA"),
        (np.zeros(5), None, ValueError, r"features_2d must be 2-D"),
        (np.zeros((5, 2)), [0, 1], ValueError, r"labels must be 1-D with one label per row"),
        (np.full((5, 2), np.inf), None, ValueError, r"features_2d contains 10 non-finite"),
        (np.full((5, 2), np.nan), None, ValueError, r"features_2d has no row without NaN"),
        (np.full((5, 2), "a"), None, TypeError, r"features_2d has non-numeric dtype"),
        (np.zeros((5, 2)) + 1j, None, ValueError, r"features_2d is complex"),
    ],
)
def test_feature_space_refuses_bad_input(features, labels, exc, regex):
    with pytest.raises(exc, match=regex):
        plot_feature_space(features, labels)

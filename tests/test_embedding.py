import pickle
import warnings

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.decomposition import PCA
from sklearn.linear_model import LinearRegression
from sklearn.pipeline import make_pipeline

from sindy_impulse import DelayEmbedding
from sindy_impulse.datasets import add_noise, damped_oscillator


@pytest.fixture(scope="module")
def ring_down():
    return damped_oscillator()


@pytest.fixture(scope="module")
def x1(ring_down):
    return ring_down.x[:, 0]


def test_paper_parameters_on_x1(x1):
    emb = DelayEmbedding().fit(x1)
    assert (emb.tau_, emb.dimension_) == (18, 2)
    assert emb.offset_ == 18
    # diagnostics for Fig. 9a
    assert emb.acf_[0] == pytest.approx(1.0)
    assert emb.acf_[18] > 0 > emb.acf_[19]
    assert 18 <= emb.acf_zero_crossing_ < 18.5
    np.testing.assert_array_equal(emb.candidate_dimensions_, np.arange(1, 11))
    assert emb.fnn_fraction_.shape == (10,)
    assert emb.fnn_fraction_[0] > 0.9 and emb.fnn_fraction_[1] < 0.01
    assert emb.mutual_information_ is None and emb.cao_e1_ is None


def test_accepts_list_and_column(x1):
    ref = DelayEmbedding().fit_transform(x1)
    for variant in (list(x1), x1[:, None], x1[:, None].tolist()):
        np.testing.assert_array_equal(DelayEmbedding().fit_transform(variant), ref)


def test_accepts_pandas(x1):
    pd = pytest.importorskip("pandas")
    ref = DelayEmbedding().fit_transform(x1)
    for variant in (pd.Series(x1), pd.DataFrame({"x1": x1})):
        np.testing.assert_array_equal(DelayEmbedding().fit_transform(variant), ref)


def test_transform_column_order_matches_paper():
    s = np.arange(20.0) ** 1.5  # not constant, distinct values: each entry identifies its sample
    emb = DelayEmbedding(tau=3, dimension=3).fit(s)
    q = emb.transform(s)
    assert q.shape == (20 - 6, 3)
    # row for sample n is [s_(n-2 tau), s_(n-tau), s_n], first row n = (m-1) tau = 6
    np.testing.assert_array_equal(q[0], s[[0, 3, 6]])
    np.testing.assert_array_equal(q[:, -1], s[6:])
    np.testing.assert_array_equal(q[:, 0], s[:-6])
    assert q.flags.writeable and q.flags.c_contiguous
    assert emb.get_feature_names_out().tolist() == ["q1", "q2", "q3"]
    assert emb.delay_labels() == ["s(t-6)", "s(t-3)", "s(t)"]
    assert emb.delay_labels(dt=0.01, name="x1") == ["x1(t-0.06)", "x1(t-0.03)", "x1(t)"]


def test_time_vector_alignment(ring_down, x1):
    emb = DelayEmbedding().fit(x1)
    q = emb.transform(x1)
    t_q = emb.transform_time(ring_down.t)
    assert t_q.shape == (q.shape[0],)
    assert t_q[0] == pytest.approx(0.18)
    # the last column is the undelayed signal at those times, the first is delayed by tau * dt
    np.testing.assert_array_equal(q[:, -1], x1[np.rint(t_q / 0.01).astype(int)])
    np.testing.assert_array_equal(q[:, 0], x1[np.rint((t_q - 0.18) / 0.01).astype(int)])
    np.testing.assert_allclose(emb.transform_time(0.01, n_samples=x1.size), t_q, atol=1e-12)
    with pytest.raises(ValueError, match="n_samples"):
        emb.transform_time(0.01)


def test_given_ints_skip_estimation(x1):
    emb = DelayEmbedding(tau=5, dimension=4).fit(x1)
    assert (emb.tau_, emb.dimension_) == (5, 4)
    assert emb.acf_ is None and emb.fnn_fraction_ is None
    assert emb.transform(x1).shape == (401 - 15, 4)
    only_tau = DelayEmbedding(tau=18).fit(x1)
    assert only_tau.dimension_ == 2 and only_tau.acf_ is None
    only_m = DelayEmbedding(dimension=3).fit(x1)
    assert only_m.tau_ == 18 and only_m.fnn_fraction_ is None


def test_mutual_information_option(x1):
    emb = DelayEmbedding(delay_method="mutual_information").fit(x1)
    # quarter period of the damped oscillation: 2 pi / (8 sqrt(1 - 0.2**2)) / 4 / 0.01 = 20.0 samples
    assert 17 <= emb.tau_ <= 23
    mi = emb.mutual_information_
    assert mi.size >= 2 * emb.tau_ + 1
    assert mi[emb.tau_] < mi[emb.tau_ - 1] and mi[emb.tau_] <= mi[emb.tau_ + 1]
    assert emb.dimension_ == 2


def test_mutual_information_beats_equal_width_pitfall(x1):
    """The first minimum is near the quarter period, not at 2-5 samples, on a noisy decaying signal."""
    noisy = add_noise(x1, 30, random_state=1)
    emb = DelayEmbedding(delay_method="mutual_information", dimension=2).fit(noisy)
    assert 15 <= emb.tau_ <= 25


def test_cao_option(x1):
    emb = DelayEmbedding(dimension_method="cao").fit(x1)
    assert (emb.tau_, emb.dimension_) == (18, 2)
    assert emb.cao_e1_.shape == emb.candidate_dimensions_.shape
    assert emb.cao_e1_[0] < 0.1 and abs(emb.cao_e1_[1] - 1) < 0.1
    assert emb.fnn_fraction_ is None


def test_theiler_window_option_runs(x1):
    emb = DelayEmbedding(theiler_window=5).fit(x1)
    assert emb.dimension_ == 2


@pytest.mark.parametrize("beta", [0.0, 0.25, 0.5, 0.75, 1.0])
def test_mixed_signal(ring_down, beta):
    s = beta * ring_down.x[:, 0] + (1 - beta) * ring_down.x[:, 1]
    emb = DelayEmbedding().fit(s)
    assert 17 <= emb.tau_ <= 24  # about a quarter period whatever the phase mix
    assert emb.dimension_ == 2
    assert emb.transform(s).shape == (401 - emb.tau_, 2)


def test_noisy_signal_gives_sane_values(x1):
    noisy = add_noise(x1, 40, random_state=0)
    emb = DelayEmbedding().fit(noisy)
    assert emb.tau_ == 18
    assert 2 <= emb.dimension_ <= 3


def test_pipeline_with_downstream_estimator(x1):
    pipe = make_pipeline(DelayEmbedding(), PCA(n_components=2))
    z = pipe.fit_transform(x1)
    assert z.shape == (401 - 18, 2)
    assert pipe[0].tau_ == 18
    assert pipe.get_feature_names_out().tolist() == ["pca0", "pca1"]
    # a downstream regressor on the embedded states: predict s(t) from s(t - tau) and s(t)
    reg = make_pipeline(DelayEmbedding(tau=18, dimension=2), LinearRegression())
    q = DelayEmbedding(tau=18, dimension=2).fit_transform(x1)
    reg.fit(x1, q[:, -1])
    assert reg.score(x1, q[:, -1]) == pytest.approx(1.0)


def test_clone_and_pickle(x1):
    emb = DelayEmbedding(delay_method="mutual_information", max_dimension=6)
    cloned = clone(emb)
    assert cloned.get_params() == emb.get_params()
    emb.fit(x1)
    restored = pickle.loads(pickle.dumps(emb))
    assert (restored.tau_, restored.dimension_) == (emb.tau_, emb.dimension_)
    np.testing.assert_array_equal(restored.transform(x1), emb.transform(x1))
    assert not hasattr(clone(emb), "tau_")


def test_deterministic(x1):
    noisy = add_noise(x1, 30, random_state=3)
    a = DelayEmbedding(dimension_method="cao").fit(noisy)
    b = DelayEmbedding(dimension_method="cao").fit(noisy)
    assert (a.tau_, a.dimension_) == (b.tau_, b.dimension_)
    np.testing.assert_array_equal(a.cao_e1_, b.cao_e1_)


def test_long_slowly_decaying_signal():
    s = damped_oscillator(c=0.02, t_end=200.0).x[:, 0]
    emb = DelayEmbedding().fit(s)
    assert s.size == 20001
    assert 19 <= emb.tau_ <= 21 and emb.dimension_ == 2


# ------------------------------------------------------------------------------------------ bad input
@pytest.mark.parametrize(
    "bad, match",
    [
        ([1.0, np.nan, 2.0, 3.0], "NaN"),
        ([1.0, np.inf, 2.0, 3.0], "inf"),
        (np.ones(50), "constant"),
        (np.zeros((50, 2)), "channel 0 of s is constant"),
        (np.zeros((12, 0)), "0 feature"),
        (np.zeros((2, 2, 2)), "1-D or 2-D"),
        (np.array([1 + 1j, 2.0, 3.0]), "Complex"),
        ([], "empty"),
    ],
)
def test_fit_rejects_bad_signal(bad, match):
    with pytest.raises(ValueError, match=match):
        DelayEmbedding(tau=1, dimension=2).fit(bad)


def test_too_short_names_needed_and_got():
    s = np.sin(np.arange(30.0))
    with pytest.raises(ValueError, match=r"30 samples, but tau=18 and dimension=3 need at least 37"):
        DelayEmbedding(tau=18, dimension=3).fit(s)
    emb = DelayEmbedding(tau=18, dimension=2).fit(s)
    with pytest.raises(ValueError, match=r"10 samples, but tau=18 and dimension=2 need at least 19"):
        emb.transform(s[:10])
    with pytest.raises(ValueError, match=r"too short to estimate the dimension with tau=18: at least 28"):
        DelayEmbedding(tau=18).fit(s[:27])


def test_transform_rejects_bad_signal(x1):
    emb = DelayEmbedding().fit(x1)
    with pytest.raises(ValueError, match="NaN"):
        emb.transform(np.where(np.arange(401) == 7, np.nan, x1))
    with pytest.raises(ValueError, match="X has 2 features, but DelayEmbedding is expecting 1 features"):
        emb.transform(np.column_stack([x1, x1]))


def test_sparse_input_refused():
    sparse = pytest.importorskip("scipy.sparse")
    with pytest.raises(TypeError, match="sparse"):
        DelayEmbedding().fit(sparse.csr_matrix(np.ones((10, 1))))


def test_no_zero_crossing_is_reported():
    with pytest.raises(ValueError, match="no zero crossing within lags 0..10"):
        DelayEmbedding(max_lag=10).fit(np.exp(-np.arange(101) / 30.0))


@pytest.mark.parametrize(
    "params, match",
    [
        ({"tau": 0}, r"DelayEmbedding: tau must be one of 'auto' or an integer in \[1, inf\); got 0"),
        ({"tau": 2.5}, "tau must be"),
        ({"tau": True}, "tau must be"),
        ({"dimension": "three"}, "dimension must be"),
        ({"delay_method": "ami"}, "delay_method must be one of"),
        ({"dimension_method": "pca"}, "dimension_method must be one of"),
        ({"max_lag": 0}, "max_lag"),
        ({"max_dimension": 0}, "max_dimension"),
        ({"theiler_window": -1}, "theiler_window"),
        ({"fnn_fraction_threshold": 0.0}, "fnn_fraction_threshold"),
        ({"fnn_ratio_threshold": np.nan}, "fnn_ratio_threshold"),
        ({"mi_bins": 1}, "mi_bins"),
    ],
)
def test_bad_parameters_raise_in_fit(x1, params, match):
    emb = DelayEmbedding(**params)  # stored untouched
    assert emb.get_params()[next(iter(params))] is next(iter(params.values()))
    with pytest.raises(ValueError, match=match):
        emb.fit(x1)


def test_unfitted_transform_raises(x1):
    from sklearn.exceptions import NotFittedError

    with pytest.raises(NotFittedError):
        DelayEmbedding().transform(x1)


def test_noise_only_warns_and_still_returns_a_dimension():
    noise = np.random.default_rng(0).standard_normal(300)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        emb = DelayEmbedding(max_dimension=4, denoise=False).fit(noise)
    assert any("no dimension in 1..4" in str(w.message) for w in caught)
    assert 1 <= emb.dimension_ <= 4


@pytest.mark.parametrize("snr", [40, 30])
def test_denoise_keeps_paper_parameters_on_noisy_x1(snr):
    raw_dims = []
    for seed in range(5):
        s = damped_oscillator(snr_db=snr, random_state=seed).x[:, 0]
        emb = DelayEmbedding().fit(s)
        assert (emb.tau_, emb.dimension_) == (18, 2)
        raw_dims.append(DelayEmbedding(denoise=False).fit(s).dimension_)
    if snr == 30:  # the raw signal's false neighbours are noise: the reason for denoise=True
        assert max(raw_dims) == 3


def test_denoise_does_not_change_transform():
    s = damped_oscillator(snr_db=30, random_state=0).x[:, 0]
    emb = DelayEmbedding().fit(s)
    q = emb.transform(s)
    np.testing.assert_array_equal(q[:, -1], s[emb.offset_ :])
    with pytest.raises(TypeError, match="denoise"):
        DelayEmbedding(denoise="yes").fit(s)


# ---------------------------------------------------------------- several channels
def test_channels_are_embedded_side_by_side_channel_major():
    s = np.column_stack([np.arange(20.0) ** 1.5, -np.arange(20.0) ** 1.2])
    emb = DelayEmbedding(tau=3, dimension=3).fit(s)
    q = emb.transform(s)
    assert q.shape == (14, 6) and emb.n_features_in_ == 2
    # [c0 q1 q2 q3, c1 q1 q2 q3]: each block is the channel's own embedding
    np.testing.assert_array_equal(q[:, :3], DelayEmbedding(tau=3, dimension=3).fit_transform(s[:, 0]))
    np.testing.assert_array_equal(q[:, 3:], DelayEmbedding(tau=3, dimension=3).fit_transform(s[:, 1]))
    np.testing.assert_array_equal(q[0], s[[0, 3, 6, 0, 3, 6], [0, 0, 0, 1, 1, 1]])
    assert emb.get_feature_names_out().tolist() == ["x0_q1", "x0_q2", "x0_q3", "x1_q1", "x1_q2", "x1_q3"]
    assert emb.get_feature_names_out(["x", "v"]).tolist()[3:] == ["v_q1", "v_q2", "v_q3"]
    assert emb.delay_labels()[:3] == ["s0(t-6)", "s0(t-3)", "s0(t)"]
    assert emb.delay_labels(dt=0.5, name=["x", "v"])[3:] == ["v(t-3)", "v(t-1.5)", "v(t)"]
    with pytest.raises(ValueError, match=r"input_features has 1 name\(s\) but DelayEmbedding was fitted"):
        emb.get_feature_names_out(["x"])
    with pytest.raises(ValueError, match="a 1-D array is one signal: Reshape your data to"):
        emb.transform(s[:, 0])


def test_channels_share_the_median_delay_and_the_largest_dimension(ring_down):
    # displacement and velocity of the paper's oscillator, plus a slower ring-down on a third channel
    slow = damped_oscillator(k=16.0).x[:, 0]
    s = np.column_stack([ring_down.x, slow])
    emb = DelayEmbedding().fit(s)
    alone = [DelayEmbedding().fit(s[:, j]) for j in range(3)]
    np.testing.assert_array_equal(emb.channel_taus_, [a.tau_ for a in alone])
    assert emb.tau_ == int(np.median(emb.channel_taus_))
    assert emb.dimension_ == emb.channel_dimensions_.max()
    assert emb.transform(s).shape == (401 - emb.offset_, 3 * emb.dimension_)
    assert isinstance(emb.acf_, list) and len(emb.acf_) == 3
    np.testing.assert_array_equal(emb.acf_[0], alone[0].acf_)


def test_one_channel_keeps_the_single_signal_attributes(x1):
    emb = DelayEmbedding().fit(x1[:, None])
    assert emb.get_feature_names_out().tolist() == ["q1", "q2"]
    assert emb.channel_taus_.tolist() == [18] and emb.channel_dimensions_.tolist() == [2]
    assert isinstance(emb.acf_, np.ndarray) and emb.delay_labels() == ["s(t-18)", "s(t)"]


def test_constant_channel_is_named():
    s = np.column_stack([np.sin(np.arange(100.0)), np.ones(100)])
    with pytest.raises(ValueError, match=r"channel 1 of s is constant"):
        DelayEmbedding(tau=2, dimension=2).fit(s)

"""The averaged equations of several modes read together (``modes/_envelope.py``, :func:`joint_dependence`),
and the survey's use of that reading (``modes/classify.py``, ``_read_jointly``)."""

import warnings

import numpy as np
import pytest

from sindy_impulse import identify_modes, impact_record
from sindy_impulse.modes import _envelope
from sindy_impulse.modes.classify import MAX_BEYOND

FS = 2000.0


def _integral(a2: float, rate: float, t: np.ndarray) -> np.ndarray:
    return a2 * -np.expm1(-2 * rate * t) / (2 * rate)


def _two_modes(seed: int, shift: float = -0.004, self_shift: float = 0.0, rate1: float = 1.0,
               rate2: float = 4.0, n: int = 12000, noise: float = 1e-4):
    """A strong 40 Hz mode (amplitude 1, decay rate ``rate1``) and a weak 90 Hz one (0.3, ``rate2``) whose
    frequency moves by ``shift`` (relative) at the strong one's largest squared amplitude and by
    ``self_shift`` at its own; white noise of std ``noise``."""
    t = np.arange(n) / FS
    w1, w2 = 2 * np.pi * 40.0, 2 * np.pi * 90.0
    phase2 = (w2 * t + shift * w2 * _integral(1.0, rate1, t)
              + self_shift * w2 / 0.09 * _integral(0.09, rate2, t))
    y = np.exp(-rate1 * t) * np.cos(w1 * t) + 0.3 * np.exp(-rate2 * t) * np.cos(phase2)
    y = y + noise * np.random.default_rng(seed).standard_normal(n)
    linear2 = 90.0 * (1 + shift * 0.5 + self_shift * 0.5)  # where a linear decay fit would put it
    return y, [(1.0 + 0j, rate1, 40.0), (0.3 + 0j, rate2, linear2)], [n, n]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_mode_moved_by_another_modes_amplitude_is_read_with_that_amplitude_gone(seed):
    """The weak mode's frequency follows the strong mode's squared amplitude, not its own: the joint reading
    puts its change on the strong mode's amplitude (``drivers``), gives its frequency with every amplitude
    gone within three standard errors, and leaves the strong mode linear."""
    y, components, stops = _two_modes(seed)
    strong, weak = _envelope.joint_dependence(y, FS, components, 1e-4, stops)
    assert weak.drivers == (0,)
    assert abs(weak.coefficients[0] - 2 * np.pi * 90.0) < 3 * weak.coefficients_std[0]
    assert weak.frequency_change == pytest.approx(-0.004, rel=0.05)
    assert weak.nonlinear and weak.beyond < 0.01  # the strong mode's decay shows its amplitude nearly gone
    assert strong.drivers == () and strong.frequency_change == 0.0 and not strong.nonlinear
    assert abs(strong.coefficients[0] - 2 * np.pi * 40.0) < 3 * strong.coefficients_std[0]
    assert strong.misfit < 1.5


@pytest.mark.parametrize("seed", [0, 1])
def test_linear_decays_read_together_take_no_terms(seed):
    """Two linear decays: no amplitude moves either (no term passes the selection's score), and their
    frequencies and decay rates are the linear ones within three standard errors."""
    y, components, stops = _two_modes(seed, shift=0.0)
    readings = _envelope.joint_dependence(y, FS, components, 1e-4, stops)
    for e, (f, rate) in zip(readings, [(40.0, 1.0), (90.0, 4.0)]):
        assert e.drivers == () and e.coefficients[1] == 0.0 and e.frequency_change == 0.0
        assert abs(e.coefficients[0] - 2 * np.pi * f) < 3 * e.coefficients_std[0]
        assert abs(e.coefficients[2] - rate) < 3 * e.coefficients_std[2]


def test_a_chirp_that_follows_its_own_decay_is_put_on_its_own_amplitude():
    """Another mode decaying exactly as fast explains the chirp as well as the mode's own amplitude: where
    the data cannot tell them apart, the mode's own amplitude moves it (no ``drivers``), the simpler
    explanation, and its own slope carries the change."""
    y, components, stops = _two_modes(0, shift=0.0, self_shift=0.004, rate1=4.0, rate2=4.0)
    strong, weak = _envelope.joint_dependence(y, FS, components, 1e-4, stops)
    assert weak.drivers == () and weak.coefficients[1] != 0.0
    assert weak.frequency_change == pytest.approx(0.004, rel=0.1)
    assert abs(weak.coefficients[0] - 2 * np.pi * 90.0) < 3 * weak.coefficients_std[0]


def test_values_far_beyond_the_stretch_read_are_measured():
    """A weak mode heard for 0.5 s beside a driver whose squared amplitude falls by a quarter meanwhile: its
    frequency with every amplitude gone lies beyond the change the record shows, by the share of the
    driver's squared amplitude left at the stretch's end over the share gone (``beyond`` over
    :data:`~sindy_impulse.modes.classify.MAX_BEYOND`: the survey does not use such a reading); heard while
    the driver decays (the first test's record), it lies within the record's reach."""
    rate, n = 0.29, 1000
    y, components, stops = _two_modes(0, shift=-0.02, rate1=rate, rate2=10.0, n=n)
    weak = _envelope.joint_dependence(y, FS, components, 1e-4, stops)[1]
    left = np.exp(-2 * rate * n / FS)
    assert weak.drivers == (0,) and weak.beyond == pytest.approx(left / (1 - left), rel=1e-9)
    assert weak.beyond > MAX_BEYOND
    y, components, stops = _two_modes(0)
    assert _envelope.joint_dependence(y, FS, components, 1e-4, stops)[1].beyond < MAX_BEYOND


def test_survey_reads_a_mode_moved_by_a_stronger_ones_amplitude_with_it_gone():
    """A hammer record of four modes with a softening cubic spring at mass 0: the 39.9 Hz mode decays fast
    (damping 1.9 %) beside the lightly damped 31.6 and 32.9 Hz modes, whose amplitudes move their
    frequencies as they ring on; removed by their linear decays, they leave their chirps in its free
    decay, and its linear decay fit puts its damping ratio 38 % high. Read together with their averaged
    equations, every mode's frequency and damping ratio are within 0.3 % and 10 % of the truth, and the
    trace says which modes were read together."""
    rec = impact_record([31.599246459836472, 32.94823188676221, 39.88456310025765, 104.58796130253954],
                        [0.0013480250240744938, 0.006065531526848966, 0.0194882477275887,
                         0.0010005530421846795],
                        [0.20985096588258004, 0.3142197286384647, 0.17022098985710968, 0.26147398001872546],
                        fs=1000.0, duration=24.642, sensor="velocity", pre_trigger=0.041430246877832026,
                        offset=3.7783556620339427, snr_db=39.26011321996916, random_state=1183139822,
                        cubic_stiffness=-3522646713333.87)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        survey = identify_modes(rec.y, fs=rec.fs)
    found = np.array([m.frequency_hz for m in survey.modes])
    for f, zeta in zip(rec.modes.frequency_hz, rec.modes.damping_ratio):
        mode = survey.modes[int(np.argmin(abs(found - f)))]
        assert mode.frequency_hz == pytest.approx(f, rel=3e-3)
        assert mode.damping_ratio == pytest.approx(zeta, rel=0.1)
    third = survey.modes[int(np.argmin(abs(found - rec.modes.frequency_hz[2])))]
    assert third.source == "envelope" and "read together" in third.uncertainty_note
    assert any("read together" in d for stage in survey.trace for d in stage.decisions)


def _candidate(frequency_hz, damping_ratio, stable, explained=False):
    from types import SimpleNamespace

    from sindy_impulse.modes.kinds import Kind

    rate = damping_ratio * 2 * np.pi * frequency_hz
    return SimpleNamespace(frequency_hz=frequency_hz, damped_frequency_hz=frequency_hz,
                           damping_ratio=damping_ratio, decay_rate=rate, stable=stable, explained=explained,
                           amplitude=np.array([1.0 + 0j]), kind=Kind.LINEAR, parent=None, evidence={})


def test_a_broad_component_between_two_confirmed_modes_does_not_merge_them():
    """A broad component (damping 11 %) whose half-power band overlaps two modes 17 % apart, each a stable
    pole of the diagram: it is a piece of the stronger one, and the other stays a mode of its own (a run of
    overlapping bands joined them through it). Two overlapping components the diagram does not confirm,
    and stable ones within a chirp's sweep (5 %) of the strongest, are still one mode's pieces."""
    from sindy_impulse.modes.classify import _pieces
    from sindy_impulse.modes.kinds import Kind

    low, broad = _candidate(616.8, 0.0134, True), _candidate(682.8, 0.115, True)
    high = _candidate(725.9, 0.0048, True)
    low.amplitude = np.array([3.0 + 0j])
    _pieces([low, broad, high])
    assert broad.kind is Kind.MERGED and broad.parent == 0
    assert high.kind is Kind.LINEAR and low.kind is Kind.NONLINEAR
    a, b = _candidate(100.0, 0.01, False), _candidate(100.5, 0.01, False)
    _pieces([a, b])
    assert {a.kind, b.kind} == {Kind.NONLINEAR, Kind.MERGED}
    chirp = [_candidate(69.86, 0.017, True), _candidate(70.44, 0.0075, True), _candidate(71.17, 0.004, True)]
    chirp[0].amplitude = np.array([3.0 + 0j])
    _pieces(chirp)
    assert [c.kind for c in chirp] == [Kind.NONLINEAR, Kind.MERGED, Kind.MERGED]


def test_joint_dependence_refuses_what_it_cannot_read():
    """No component, a stop missing, or a 2-D decay: a ValueError that names what was given."""
    y = np.zeros(100)
    with pytest.raises(ValueError, match="0 component"):
        _envelope.joint_dependence(y, FS, [], 1e-4, [])
    with pytest.raises(ValueError, match="1 stop"):
        _envelope.joint_dependence(y, FS, [(1.0, 1.0, 40.0), (1.0, 1.0, 90.0)], 1e-4, [100])
    with pytest.raises(ValueError, match="shape"):
        _envelope.joint_dependence(np.zeros((100, 2)), FS, [(1.0, 1.0, 40.0)], 1e-4, [100])


@pytest.mark.parametrize("iterations", [1, 3])
def test_a_joint_fit_takes_at_most_its_iterations_in_steps(iterations, monkeypatch):
    """A fit asked for ``iterations`` Gauss-Newton steps takes at most that many (one Jacobian per point
    accepted: the start and each step's end), and each step lowers the squared residual."""
    y, components, _ = _two_modes(0)
    decay = _envelope._JointDecay(y, FS, components, [(1.0, 1.0, 0), (0.09, 4.0, 1)])
    points = []
    jacobian = decay.jacobian
    monkeypatch.setattr(decay, "jacobian", lambda x, *rest: points.append(x) or jacobian(x, *rest))
    start = decay.start * (1 + 1e-3)  # (away from the optimum: every step counts)
    cost, best = decay.fit(start, [], iterations)
    assert 1 < len(points) <= iterations + 1
    costs = [float(np.sum((y - decay.signals(x, []).real.sum(axis=0)) ** 2)) for x in points]
    assert all(b < a for a, b in zip(costs, costs[1:])) and cost == pytest.approx(costs[-1])


def test_a_joint_fit_of_one_component_holds_the_others():
    """A fit with ``free=k`` moves only component k's parameters and its terms' slopes, lowers the squared
    residual, and returns the normal matrix of every parameter (the selection's scores project on all)."""
    y, components, _ = _two_modes(0)
    decay = _envelope._JointDecay(y, FS, components, [(1.0, 1.0, 0), (0.09, 4.0, 1)])
    terms = [(1, 0)]
    start = np.concatenate([decay.start, [0.0, 0.0]])
    cost, best = decay.fit(start, terms, 5, free=1)
    moved = np.flatnonzero(best[0] != start)
    assert set(moved) <= set(decay.parameters_of(1, terms)) and set(moved) & {8, 9}
    first = float(np.sum((y - decay.signals(start, terms).real.sum(axis=0)) ** 2))
    assert cost < first and best[2].shape == (start.size, start.size)


def test_a_free_components_signal_alone_recomputed_equals_all_recomputed():
    """With ``held`` signals, only the free component's row is computed: the same numbers, bit for bit, as
    every row computed (a fit of one component then decides exactly as a fit computing them all), and
    ``held`` itself is not changed."""
    y, components, _ = _two_modes(0)
    decay = _envelope._JointDecay(y, FS, components, [(1.0, 1.0, 0), (0.09, 4.0, 1)])
    terms = [(1, 0), (0, 0)]
    x = np.concatenate([decay.start, [3.0, 0.2, -1.0, 0.1]])
    held = decay.signals(x, terms)
    kept = held.copy()
    moved = x.copy()
    moved[decay.parameters_of(1, terms)] *= 1.001
    fast = decay.signals(moved, terms, held, 1)
    assert np.array_equal(fast, decay.signals(moved, terms))
    assert np.array_equal(fast[0], held[0]) and not np.array_equal(fast[1], held[1])
    assert np.array_equal(held, kept)


def test_a_joint_fit_that_overflows_says_nothing_and_fails_cleanly():
    """A start whose exponent overflows (a growing component) gives ``(inf, None)`` without a NumPy
    RuntimeWarning reaching the user."""
    y, components, _ = _two_modes(0)
    decay = _envelope._JointDecay(y, FS, components, [(1.0, 1.0, 0), (0.09, 4.0, 1)])
    start = decay.start.copy()
    start[2] = -1e5  # (the first component grows as exp(1e5 t))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cost, best = decay.fit(start, [])
    assert cost == np.inf and best is None


def test_a_harmonic_of_a_nonlinear_mode_read_together_is_not_made_a_mode():
    """A linear candidate within a harmonic's reach of twice or three times a nonlinear one read with it,
    moved by that one's amplitude or its own, is left to the harmonic tests; one away from every order, or
    moved by another candidate too, is not."""
    import types

    from sindy_impulse.modes.classify import _at_their_harmonic
    from sindy_impulse.modes.kinds import Kind

    def cand(f, kind):
        return types.SimpleNamespace(damped_frequency_hz=f, damping_ratio=0.005, kind=kind, explained=True)

    cands = [cand(158.56, Kind.NONLINEAR), cand(468.04, Kind.LINEAR), cand(400.0, Kind.LINEAR),
             cand(250.0, Kind.LINEAR)]
    read = [0, 1, 2, 3]
    assert _at_their_harmonic(cands, 1, read, (0,)) and _at_their_harmonic(cands, 1, read, ())
    assert not _at_their_harmonic(cands, 2, read, (0,))  # 2.52 times: no order
    assert not _at_their_harmonic(cands, 1, read, (0, 3))  # a linear candidate moves it too
    assert not _at_their_harmonic(cands, 1, [1, 2, 3], ())  # its parent is not read with it

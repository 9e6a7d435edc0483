"""The record generators of the modal-table families (benchmarks/accuracy/families.py) and the scorer of
the modal-table benchmarks (benchmarks/accuracy/scoring.py): valid configurations with each family's stated
properties, no survey run."""

from __future__ import annotations

import numpy as np
import pytest
from benchmark_helpers import helper

from sindy_impulse import impact_record

mf = helper("accuracy.families")
judge, random_case = helper("accuracy.scoring").judge, mf.random_case

NONLINEAR = ("quadratic_stiffness", "cubic_stiffness", "damping_amplitude", "quadratic_damping")


def _build(config: dict):
    """The record of ``config``; a nonlinear one over its first 0.05 s only (the RK4 run is the slow part,
    and every argument check is the same)."""
    if any(config.get(k) for k in NONLINEAR):
        config = dict(config, duration=min(config["duration"], 0.05))
    return impact_record(**config)


def _cases(family: str, n: int = 4, seed: int = 3) -> list[dict]:
    rng = np.random.default_rng(seed)
    return [mf.draw(family, rng, i) for i in range(n)]


@pytest.mark.parametrize("family", mf.FAMILIES)
def test_every_family_draws_valid_reproducible_configs(family):
    cases = _cases(family)
    assert [c["config"] for c in _cases(family)] == [c["config"] for c in cases]  # seeded
    for case in cases:
        assert case["family"] == family and 0 < case["f_tol"] <= 0.005 and case["z_tol"] == 0.10
        cfg = case["config"]
        rec = _build(cfg)
        assert len(rec.modes) == len(cfg["frequencies_hz"])
        assert np.all(np.asarray(cfg["frequencies_hz"]) < cfg["fs"] / 2.56)
        assert 30 <= cfg["snr_db"] <= 60


def test_family_a_is_the_original_draw():
    rng, again = np.random.default_rng(0), np.random.default_rng(0)
    for _ in range(5):
        assert random_case(rng) == mf.family_a(again)["config"]


def test_family_b_has_a_weak_mode_and_band_snrs():
    for case in _cases("b"):
        levels = -20 * np.log10(case["config"]["amplitudes"])
        assert levels.min() == pytest.approx(0.0) and np.any((levels >= 20) & (levels <= 40))
        snr = mf.band_snr_db(impact_record(**case["config"]))
        assert snr.shape == levels.shape and np.all(np.isfinite(snr))
        # the strongest mode stands farther above the noise in its band than the weakest one
        assert snr[np.argmin(levels)] > snr[np.argmax(levels)]


def test_family_d_is_short_and_strongly_damped_on_every_sensor():
    cases = _cases("d", n=6)
    assert {c["config"]["sensor"] for c in cases} == set(mf.SENSORS)
    for case in cases:
        cfg = case["config"]
        assert all(0.02 <= z <= 0.25 for z in cfg["damping_ratios"]) and case["f_tol"] == 0.005
        periods = cfg["duration"] * (1 - cfg["pre_trigger"]) * cfg["frequencies_hz"][0]
        assert 3 <= periods <= 15.5 and cfg["duration"] * cfg["fs"] >= 150


def test_family_e_pairs_are_near_resonant_and_harmonics_named():
    for case in _cases("e", n=8):
        cfg = case["config"]
        if case["kind"].startswith("pair"):
            ratio = 2 if "1:2" in case["kind"] else 3
            off = abs(cfg["frequencies_hz"][1] / (ratio * cfg["frequencies_hz"][0]) - 1)
            assert 0.005 <= off <= 0.02 and "harmonic" not in case
            if "equal" in case["kind"]:
                assert cfg["damping_ratios"][0] == cfg["damping_ratios"][1]
        else:
            assert len(cfg["frequencies_hz"]) == 1 and case["harmonic"] in (2, 3)
            key = "quadratic_stiffness" if case["harmonic"] == 2 else "cubic_stiffness"
            assert cfg[key] != 0


def test_family_f_pairs_are_one_to_three_bandwidths_apart():
    for case in _cases("f"):
        f, z = np.asarray(case["config"]["frequencies_hz"]), np.asarray(case["config"]["damping_ratios"])
        gaps = [(f[i + 1] - f[i]) / (z[i] * f[i] + z[i + 1] * f[i + 1]) for i in range(f.size - 1)]
        assert min(gaps) == pytest.approx(case["bandwidths"]) and 1 <= min(gaps) <= 3
        assert case["config"]["duration"] >= 2 / (np.min(np.diff(f)))


def test_families_g_and_h_add_nonlinearity_and_clipping():
    assert all(any(c["config"].get(k) for k in NONLINEAR) for c in _cases("g"))
    assert all(0.3 <= c["config"]["clip"] <= 0.9 for c in _cases("h"))


def test_random_configs_of_the_exception_run_are_accepted():
    for seed in range(8):
        cfg = mf.random_config(seed)
        assert cfg == mf.random_config(seed)
        assert 15 <= cfg["snr_db"] <= 60 and max(cfg["frequencies_hz"]) <= cfg["fs"] / 2.56
        _build(cfg)


def test_the_scorer_matches_one_to_one_and_names_what_is_wrong():
    case = {"f_tol": 0.003, "z_tol": 0.1}
    truth = (np.array([100.0, 100.4]), np.array([0.001, 0.001]), np.array([True, True]))
    one = judge(case, *truth, [(100.2, 0.001)])  # one mode for a close pair: the other is missed
    assert not one["passed"] and any("missed" in p for p in one["problems"])
    both = judge(case, *truth, [(100.0, 0.00101), (100.41, 0.00099)])
    assert both["passed"] and both["spurious"] == 0
    extra = judge(case, *truth, [(100.0, 0.001), (100.4, 0.001), (250.0, 0.01)])
    assert not extra["passed"] and extra["spurious"] == 1
    harmonic = dict(case, harmonic=2)
    rows = [type("Row", (), {"reason": "harmonic 2 of the nonlinear mode at 100 Hz"})()]
    single = (np.array([100.0]), np.array([0.001]), np.array([True]))
    assert judge(harmonic, *single, [(100.0, 0.001)], rows)["passed"]
    assert not judge(harmonic, *single, [(100.0, 0.001)], [])["passed"]


def test_harmonic_snr_sees_the_quadratic_springs_second_harmonic():
    case = next(c for c in _cases("e", n=8) if c["kind"] == "quadratic")
    cfg = dict(case["config"], duration=min(case["config"]["duration"], 0.5), snr_db=50.0)
    f = cfg["frequencies_hz"][0]
    a = mf.displacement_amplitude(1.0, f, cfg["sensor"])
    cfg["quadratic_stiffness"] = 6 * (2 * np.pi * f) ** 2 * 10 ** (-32 / 20) / a  # harmonic 32 dB down
    linear = {k: v for k, v in cfg.items() if k != "quadratic_stiffness"}
    with_harmonic = mf.harmonic_snr_db(impact_record(**cfg), 2)
    assert with_harmonic > 15 and with_harmonic > mf.harmonic_snr_db(impact_record(**linear), 2) + 15


def test_the_nonlinear_bound_shrinks_with_the_noise_and_matches_the_linear_one_without_the_element():
    """Family g's Cramer-Rao bound (benchmarks/accuracy/family_bounds.py) from the generator's own
    parameters: ten times the noise, ten times the standard deviations; with no nonlinear element it is the
    damped-sinusoid bound of the linear families (the phase is known to it, so it is not above that one)."""
    fb = helper("accuracy.bounds")
    config = dict(frequencies_hz=[50.0, 120.0], damping_ratios=[0.01, 0.005], amplitudes=[1.0, 0.5],
                  fs=1000.0, duration=1.0, sensor="displacement", snr_db=40.0, random_state=1,
                  cubic_stiffness=2e8)
    f40, z40 = fb.nonlinear_bound(config)
    f20, z20 = fb.nonlinear_bound(dict(config, snr_db=20.0))
    assert np.all(f40 > 0) and np.all(z40 > 0)
    np.testing.assert_allclose(f20 / f40, 10.0, rtol=0.05)
    np.testing.assert_allclose(z20 / z40, 10.0, rtol=0.05)
    linear = dict(config, cubic_stiffness=0.0)
    f_nl, z_nl = fb.nonlinear_bound(linear)
    f_lin, z_lin = fb.bound(impact_record(**linear))
    assert np.all(f_nl <= f_lin * 1.01) and np.all(z_nl <= z_lin * 1.01)
    assert np.all(f_nl >= 0.3 * f_lin) and np.all(z_nl >= 0.3 * z_lin)

"""Sizes and work that depend on the data stay bounded (issue 25: nothing hangs or exhausts memory)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from sindy_impulse import ImpulseSINDy, damped_oscillator
from sindy_impulse.diagnostics import terms
from sindy_impulse.exceptions import DataWarning


def _dense_ssr(r0, columns, keep):
    """Least squared residual of ``r0 + J d`` over the columns ``keep`` (reference: plain lstsq)."""
    J = np.column_stack([columns[k] for k in keep])
    d = np.linalg.lstsq(J, -r0, rcond=None)[0]
    return float(np.sum((r0 + J @ d) ** 2))


def test_segment_starts_profiled_out_match_the_dense_columns():
    """The nuisance columns (one per segment and state, zero outside their segment) are never built
    densely; profiling them out gives the least squares of the dense formulation."""
    rng = np.random.default_rng(0)
    n_rows, n_states, n_segments = 600, 2, 5
    owner = np.repeat(np.repeat(np.arange(n_segments), n_rows // n_states // n_segments), n_states)
    sensitivity = rng.standard_normal((n_rows, n_states))
    r0 = rng.standard_normal(n_rows)
    active = [rng.standard_normal(n_rows) for _ in range(3)]
    dense = [np.where(owner == k, sensitivity[:, j], 0.0) for j in range(n_states) for k in range(n_segments)]
    gram = terms._Gram(r0, active, terms._Segments(owner, sensitivity))
    everything = list(range(len(active) + len(dense)))
    all_columns = active + dense
    assert gram.ssr(np.arange(3)) == pytest.approx(_dense_ssr(r0, all_columns, everything), rel=1e-9)
    without_first = [k for k in everything if k != 0]
    assert gram.ssr(np.arange(1, 3)) == pytest.approx(_dense_ssr(r0, all_columns, without_first), rel=1e-9)
    extra = rng.standard_normal(n_rows)
    G, b = gram.extended(extra)
    assert gram.ssr(np.arange(4), G=G, b=b) == pytest.approx(
        _dense_ssr(r0, all_columns + [extra], everything + [len(all_columns)]), rel=1e-9
    )


def test_term_tests_compare_at_most_max_test_samples(monkeypatch):
    """A record longer than the cap is compared every k-th sample, with a DataWarning saying so."""
    monkeypatch.setattr(terms, "MAX_TEST_SAMPLES", 150)
    seen = []
    original = terms._Sensitivity.__init__

    def spy(self, *args, **kwargs):
        original(self, *args, **kwargs)
        seen.append((self.stride, len(self.fitted.filtered[0]), self.r0))

    monkeypatch.setattr(terms._Sensitivity, "__init__", spy)
    rd = damped_oscillator(t_end=4.0, snr_db=40, random_state=0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ImpulseSINDy().fit(rd.x, t=rd.t)
    assert seen, "the term tests did not run"
    stride, n, r0 = seen[0]
    assert -(-n // stride) <= 150
    assert r0 is None or r0.size <= 150 * rd.x.shape[1]
    assert any(issubclass(w.category, DataWarning) and "term tests compare" in str(w.message) for w in caught)


def _stiff_model():
    """A linear model with a fast, strongly damped pole (rho * dt ~ 1e3): RK4 would need thousands of
    sub-steps, so it is simulated with the adaptive integrator."""
    from sindy_impulse.simulation import CompiledModel, TermTable

    model = CompiledModel([[0.0, 1.0], [-4.0e4, -2.0e5]], TermTable.polynomial([[1, 0], [0, 1]]),
                          reference=[[1.0, 0.0], [0.0, 1.0]])
    t = np.arange(301) * 0.01
    return model, t


def test_adaptive_simulations_are_charged_per_call():
    """Each right-hand-side evaluation through SciPy costs the call's overhead, not only its terms."""
    from sindy_impulse.simulation.base import ADAPTIVE_CALL_COST

    model, t = _stiff_model()
    assert model.is_stiff(t)
    reference = model.simulate([1.0, 0.0], t)
    assert np.all(np.isfinite(reference))
    assert model.work_done >= ADAPTIVE_CALL_COST  # at least one evaluation, at its real price


def test_a_batch_of_adaptive_scores_stops_at_the_budget():
    """Once a budget has charged a model, a batch of its adaptive simulations stops where the remaining
    budget (plus the overrun) is spent: the rest score inf instead of running on."""
    from sindy_impulse.simulation import WorkBudget
    from sindy_impulse.simulation.base import ADAPTIVE_CALL_COST
    from sindy_impulse.simulation.budget import OVERRUN

    model, t = _stiff_model()
    reference = model.simulate([1.0, 0.0], t)
    starts, weights = np.array([0]), np.ones((1, len(t) - 1, 2))
    single = model.work_done
    budget = WorkBudget(4 * single)
    budget.charge_model(model)  # one simulation's worth spent: the limit is 3 + 4 * OVERRUN more
    coefs = np.repeat(model.coef[None], 12, axis=0) * np.linspace(1.0, 1.1, 12)[:, None, None]
    errors, _ = model.weighted_l1(reference, t, starts, weights, coefs=coefs)
    allowed = (3 + 4 * OVERRUN) * single
    assert np.all(np.isinf(errors[-3:]))
    assert np.all(np.isfinite(errors[:2]))
    assert model.work_done - single <= allowed + ADAPTIVE_CALL_COST + 2 * 25.0  # one evaluation over


def test_mode_uncertainty_refuses_a_sensitivity_matrix_past_the_cap(monkeypatch):
    """The sensitivity matrix grows with samples x states x unknowns; past the cap the mode comes without
    standard deviations, with the reason and a DataWarning, instead of exhausting memory."""
    from sindy_impulse import identify_modes, impact_record
    from sindy_impulse.modes import uncertainty

    rec = impact_record([120.0], [0.01], fs=2000, duration=0.5, snr_db=40, random_state=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mode = identify_modes(rec.y, fs=rec.fs).modes[0]
    args = (mode.model, mode.states, mode.t, mode.band_hz, mode.frequency_hz)
    assert np.isfinite(uncertainty.mode_uncertainty(*args).frequency_std_hz)
    n_samples, n_states = mode.states.shape
    monkeypatch.setattr(uncertainty, "MAX_JACOBIAN_SIZE", n_samples * n_states - 1)
    with pytest.warns(DataWarning, match="sensitivity matrix would hold"):
        capped = uncertainty.mode_uncertainty(*args)
    assert np.isnan(capped.frequency_std_hz) and "sensitivity matrix" in capped.reason

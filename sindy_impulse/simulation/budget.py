"""The deterministic work budget of one fit: nothing runs unbounded, and a fit gives the same model on
any machine (a count of work, not wall time)."""

from __future__ import annotations

__all__ = ["WorkBudget", "WORK_BUDGET", "OVERRUN", "OutOfBudget"]

#: Simulation work allowed per fit (the sweep's simulations and every refinement together), counted as
#: term evaluations per RK4 step (see ``CompiledModel.work``). About 4-10 s on one core through the
#: general kernel, less for two-state polynomial models (:mod:`.cubic2`). Measured: at half this budget
#: the refinement of a cubic-spring record with five correlated terms stopped before converging, so the
#: same record rounded to 8 significant digits moved a coefficient by 16 %; at this budget by 4.4e-3.
WORK_BUDGET = 2e8
#: Work a model may do past its budget's remainder before the next charge, as a fraction of the budget (a
#: batch of adaptive simulations stops there).
OVERRUN = 0.25


class OutOfBudget(Exception):
    """Raised by a budgeted objective once the budget is used up (the optimizer stops there)."""


class WorkBudget:
    """A deterministic bound on the simulation work of one fit.

    Models count their own work (``work_done``); :meth:`charge_model` charges what a model did since the
    last charge, so every caller that simulates through the model is accounted for without computing costs
    itself.

    Examples
    --------
    >>> budget = WorkBudget(100.0)
    >>> budget.charge(60.0), budget.charge(60.0), budget.exhausted
    (True, False, True)
    """

    def __init__(self, units: float | None = None):
        self.total = float(WORK_BUDGET if units is None else units)
        self.remaining = self.total
        self.exhausted = False

    @property
    def used(self) -> float:
        """Fraction of the budget spent (may exceed 1 by the last charge)."""
        return (self.total - self.remaining) / self.total if self.total > 0 else 1.0

    def charge(self, units: float) -> bool:
        """Spend ``units``; False (and ``exhausted``) once the budget is used up."""
        self.remaining -= units
        if self.remaining < 0:
            self.exhausted = True
        return not self.exhausted

    def charge_model(self, model) -> bool:
        """Charge the work ``model`` did since it was last charged, and bound what it may do before the
        next charge: the remaining budget plus :data:`OVERRUN` of the whole (``model.work_limit``; the
        scoring's adaptive simulations stop there), so one batch of simulations cannot run far past an
        exhausted budget while the simulation of a best point found still can.

        Examples
        --------
        >>> from types import SimpleNamespace
        >>> model, budget = SimpleNamespace(work_done=30.0), WorkBudget(100.0)
        >>> budget.charge_model(model), model.work_limit
        (True, 125.0)
        """
        done = float(getattr(model, "work_done", 0.0))
        charged = getattr(model, "_work_charged", 0.0)
        model._work_charged = done
        ok = self.charge(done - charged)
        model.work_limit = done + max(self.remaining, 0.0) + OVERRUN * self.total
        return ok

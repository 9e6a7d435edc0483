"""The fast part of the bad-input matrix (``python -m benchmarks bad_inputs`` runs all of it under a
watchdog).

Every case states its expectation (right terms and coefficients within a tolerance, a named warning or a
named error); none may end as a silent wrong answer or a crash. Here: every scikit-learn style call and
every 25th of the other cases, so each group is represented.
"""

from __future__ import annotations

import pytest
from benchmark_helpers import helper

matrix, cases = helper("robustness.bad_input_matrix"), helper("robustness.bad_input_cases")
FAILURES, run_case = cases.FAILURES, cases.run_case
CASES = matrix.all_cases()
FAST = [c for c in CASES if c["group"] == "sklearn"] + [c for c in CASES if c["group"] != "sklearn"][::25]


def test_the_matrix_has_at_least_400_cases_each_with_an_expectation():
    assert len(CASES) >= 400
    assert len({c["id"] for c in CASES}) == len(CASES)
    kinds = {c["expect"]["type"] for c in CASES}
    assert kinds <= {"right", "right_or_warn", "warn", "raise"}


@pytest.mark.parametrize("case", FAST, ids=[c["id"] for c in FAST])
def test_bad_input_case_meets_its_expectation(case):
    out = run_case(case)
    assert out["outcome"] not in FAILURES, out["detail"]

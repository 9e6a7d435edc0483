"""The fast part of the bad-input matrix (benchmarks/bad_inputs.py runs all of it under a watchdog).

Every case states its expectation (right terms and coefficients within a tolerance, a named warning or a
named error); none may end as a silent wrong answer or a crash. Here: every scikit-learn style call and
every 25th of the other cases, so each group is represented.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parent.parent / "benchmarks"
sys.path.insert(0, str(BENCHMARKS))

from bad_input_matrix import all_cases  # noqa: E402
from bad_inputs import FAILURES, run_case  # noqa: E402

CASES = all_cases()
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

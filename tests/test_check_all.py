"""`mech check --hard` inside the test suite: every registered exercise, defaults and hard cases.

Each case is its own test, so a failure names the exercise and the case.
"""

import pytest

from mech.studies.checking import plan, run_case
from mech.problems import registry

CASES = plan(list(registry.all_exercises().values()), hard=True)


@pytest.mark.parametrize("case", CASES, ids=[f"{c.exercise.id}-{c.label.replace(' ', '')}" for c in CASES])
def test_cross_check(case):
    done = run_case(case)
    assert done.ok, f"{case.exercise.id} {case.label}: {done.detail}"

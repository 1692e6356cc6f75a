"""`mech check --hard` inside the test suite: every registered exercise, defaults and hard cases.

Each case is its own test, so a failure names the exercise and the case.  Where the exercise has a batched
route (what `mech sweep` and the charts use), the same test holds that route's value at the case, computed
with all of the exercise's cases in one batch, to the case's cross-check: within both error bars.
"""

import functools

import numpy as np
import pytest

from mech.studies import checking
from mech.studies.checking import plan
from mech.problems import registry

from hard_cases import alone, batch

CASES = plan(list(registry.all_exercises().values()), hard=True)


@functools.lru_cache(maxsize=None)
def _batched(ex_id: str):
    """The labels of the exercise's cases, and its batched route's columns over all of them in one batch."""
    ex = registry.get(ex_id)
    cases = [c for c in CASES if c.exercise.id == ex_id]
    if checking.batched(ex):  # the columns of the batch test_check_batched judges, where it made that call
        done, cols = batch(ex_id)
        if cols is not None:
            assert [c.label for c in done] == [c.label for c in cases]
            return [c.label for c in cases], cols
    values = [ex.resolve(c.given) for c in cases]
    P = {p.name: np.array([v[p.name] for v in values]) for p in ex.params}
    return [c.label for c in cases], ex.batched_route.numeric(P, ex.default_rtol, ex.batched_route.outputs)


@pytest.mark.parametrize("case", CASES, ids=[f"{c.exercise.id}-{c.label.replace(' ', '')}" for c in CASES])
def test_cross_check(case):
    done = alone(case.exercise.id, case.label)  # run_case(case), shared with test_check_batched
    assert done.given == case.given and done.exercise is case.exercise
    assert done.ok, f"{case.exercise.id} {case.label}: {done.detail}"
    ex = case.exercise
    if ex.batched_route is None or done.result is None:
        return
    labels, num = _batched(ex.id)
    j = labels.index(case.label)
    single = done.result.as_json()
    for name in ex.batched_route.outputs:
        s = next(x for x in single["quantities"] if x["name"] == name)
        col = num[name]
        assert not col.mask("failed")[j], (case.label, name, col.reason("failed", j))
        if s["numeric"] is None:
            assert col.mask("undefined")[j]
        else:
            err = np.broadcast_to(col.rel, col.value.shape)[j] * abs(col.value[j]) + \
                np.broadcast_to(col.abs, col.value.shape)[j]
            assert abs(col.value[j] - s["numeric"]) <= err + s["numeric_err"], (case.label, name)

"""The one-point cross-check of each `mech check --hard` case, run once a test process.

test_check_all asserts that every case passes and that the batched route agrees with it at the case;
test_check_batched asserts that ``run_batch`` judges each case of a batched exercise as this check does.
Both read the same cross-check: run twice it was about 7 CPU-s of the two files' 22 (measured with the
cputime plugin, -n 0).  Likewise the batch: test_check_batched judges ``run_batch``'s cases, and
test_check_all reads the route's columns over all of the cases from that batch's first call at the
exercise's rtol (equal bit for bit to a call of its own, checked for all 31 batched exercises), where it
made its own call before (about 2.4 CPU-s).  The results are read, never changed."""

import dataclasses
import functools
import inspect

from mech.problems import registry
from mech.studies import checking


@functools.lru_cache(maxsize=None)
def _alone(ex_id: str) -> dict:
    return {c.label: c for c in (checking.run_case(c)
                                 for c in checking.plan([registry.get(ex_id)], hard=True))}


def alone(ex_id: str, label: str | None = None):
    """Case ``label`` of exercise ``ex_id`` cross-checked alone (``checking.run_case``), or all of its cases
    in plan order when no label is given; the first call for an exercise runs all of its cases."""
    done = _alone(ex_id)
    return list(done.values()) if label is None else done[label]


@functools.lru_cache(maxsize=None)
def _batch(ex_id: str):
    ex = registry.get(ex_id)
    route = ex.batched_route
    takes = inspect.signature(route.numeric).parameters
    calls = []

    def numeric(P, rtol, outputs, memo=None, tally=None):  # the route itself, its calls recorded
        kw = {k: v for k, v in (("memo", memo), ("tally", tally)) if k in takes}
        reused = bool(memo)  # a memo the route filled before: not a first call
        cols = route.numeric(P, rtol, outputs, **kw)
        calls.append((rtol, next(iter(P.values())).size, tuple(outputs), reused, cols))
        return cols

    ex.batched_route = dataclasses.replace(route, numeric=numeric)
    try:
        done = checking.run_batch(checking.plan([ex], hard=True))
    finally:
        ex.batched_route = route
    return done, calls


def batch(ex_id: str):
    """The exercise's cases through ``checking.run_batch`` (as `mech check --hard` solves a batched
    exercise's cases), and its route's columns over all of the cases in one call at the exercise's rtol, as
    that batch computed them (the first call, with no memo yet); None for the columns where the batch did not
    make such a call (a direct call of the route gives them then)."""
    ex = registry.get(ex_id)
    done, calls = _batch(ex_id)
    n = len(done)
    first = [c for c in calls if c[0] == ex.default_rtol and c[1] == n and not c[3]
             and set(ex.batched_route.outputs) <= set(c[2])]
    return done, (first[0][4] if first else None)

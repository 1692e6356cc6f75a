"""The one-point cross-check of each `mech check --hard` case, run once a test process.

test_check_all asserts that every case passes and that the batched route agrees with it at the case;
test_check_batched asserts that ``run_batch`` judges each case of a batched exercise as this check does.
Both read the same cross-check: run twice it was about 7 CPU-s of the two files' 22 (measured with the
cputime plugin, -n 0).  The results are read, never changed."""

import functools

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

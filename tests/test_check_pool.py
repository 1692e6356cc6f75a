"""`mech check` over a pool of processes: the same verdicts and numbers as one process, in plan order, and no
worker outlives a killed check."""

import os

import pytest
from conftest import killed_leaves_nothing

from mech.studies import checking
from mech.problems import registry

pytestmark = pytest.mark.skipif(not hasattr(os, "fork") or not os.path.isdir("/proc"),
                                reason="the pool forks its workers (Linux)")

IDS = ["4.1", "4.15", "4.23", "5.1", "5.4", "5.11"]


def _summary(report):
    return [(c.exercise.id, c.label, c.ok, c.detail,
             [(q.name, q.numeric, q.verify_diff, q.agree) for q in c.result.quantities]) for c in report.cases]


def test_pooled_and_serial_checks_agree_to_the_bit():
    exercises = [registry.get(i) for i in IDS]
    serial = checking.run_check(exercises, hard=True, jobs=1)
    pooled = checking.run_check(exercises, hard=True, jobs=2)
    assert len(serial.cases) >= checking.MIN_POOLED_CASES
    assert _summary(pooled) == _summary(serial)
    # the plan's order, whatever order the workers finished in: each exercise's defaults, then its hard cases
    assert [(c.exercise.id, c.label) for c in pooled.cases] == \
           [(c.exercise.id, c.label) for c in checking.plan(exercises, True)]
    assert pooled.passed == len(pooled.cases)


def test_a_case_that_fails_in_a_worker_is_reported(monkeypatch):
    ex = registry.get("4.15")
    good = ex.numeric_solver

    def off_by_a_part_in_a_thousand(p, run):
        values = good(p, run)
        return {**values, "theta_c": values["theta_c"] * (1 + 1e-3)}

    monkeypatch.setattr(ex, "numeric_solver", off_by_a_part_in_a_thousand)  # the fork carries the patch
    report = checking.run_check([registry.get(i) for i in IDS[:1]] + [ex], hard=True, jobs=2)
    bad = [c for c in report.cases if not c.ok]
    assert bad and {c.exercise.id for c in bad} == {"4.15"}
    assert all("theta_c" in c.detail for c in bad)


def test_how_many_processes():
    assert checking.plan_jobs(3, None) == 1  # too few cases to share
    cores = len(os.sched_getaffinity(0))
    # as asked, never more than the cases nor the cores
    assert checking.plan_jobs(3, 2) == min(2, cores) and checking.plan_jobs(3, 8) == min(3, cores)
    assert checking.plan_jobs(1000, 256) == cores
    assert checking.plan_jobs(100, None) == (min(cores, 100) if cores >= 2 else 1)


_CHECK_THEN_HANG = """
import os, sys, time
from mech.studies import checking
from mech.problems import registry
ex = registry.get("4.15")
parent = os.getpid()
def hangs_in_a_worker(p, run):
    if os.getpid() != parent:
        print("worker", flush=True)
        time.sleep(60)
ex.numeric_solver = hangs_in_a_worker
checking.run_check([ex] * 1 + [registry.get(i) for i in ("4.1", "4.2", "4.3", "4.4", "4.6", "4.8", "4.9")],
                   hard=True, jobs=2)
"""


@pytest.mark.parametrize("sig", ["SIGKILL", "SIGTERM"])
def test_the_workers_die_with_a_killed_check(sig):
    """A CI timeout kills mech check (SIGKILL or SIGTERM): none of its pool's workers may outlive it."""
    assert killed_leaves_nothing(_CHECK_THEN_HANG, "worker", sig) == []

"""The rerun at rtol/10 in a forked child (two cores) gives what the serial rerun gives, and fails as loudly."""

import os

import pytest

from conftest import killed_leaves_nothing

from mech.problems import registry
from mech.verification import crosscheck

pytestmark = pytest.mark.skipif(not hasattr(os, "fork"), reason="the parallel rerun needs fork")


def _both(ex, params, monkeypatch):
    monkeypatch.setattr(crosscheck, "_parallel_ok", lambda: True)
    par = crosscheck.cross_check(ex, params).as_json()
    monkeypatch.setattr(crosscheck, "_parallel_ok", lambda: False)
    ser = crosscheck.cross_check(ex, params).as_json()
    return par, ser


def _no_children_left():
    """True when this process has no child at all (running or unreaped)."""
    try:
        os.waitpid(-1, os.WNOHANG)
    except ChildProcessError:
        return True
    return False


@pytest.mark.parametrize("ex_id", ["4.15", "4.23", "5.1", "5.10"])
def test_parallel_and_serial_reruns_agree_to_the_bit(ex_id, monkeypatch):
    ex = registry.get(ex_id)
    par, ser = _both(ex, ex.resolve({}), monkeypatch)
    keys = ("name", "numeric", "verify_diff", "agree", "tol")
    assert [{k: q.get(k) for k in keys} for q in par["quantities"]] == \
           [{k: q.get(k) for k in keys} for q in ser["quantities"]]
    assert par["agree"] is True and par["numeric_info"]["verify_rtol"] == ser["numeric_info"]["verify_rtol"]
    assert _no_children_left()


def test_a_rerun_that_fails_is_reported_in_both_modes(monkeypatch):
    ex = registry.get("4.15")
    good = ex.numeric_solver

    def fails_when_tighter(p, run):
        if run.rtol < ex.default_rtol:
            raise ZeroDivisionError("only at the tighter tolerance")
        return good(p, run)

    monkeypatch.setattr(ex, "numeric_solver", fails_when_tighter)
    par, ser = _both(ex, ex.resolve({}), monkeypatch)
    for d in (par, ser):
        assert d["agree"] is False
        assert any("failed at rtol=1e-11" in e and "only at the tighter tolerance" in e for e in d["errors"])
    assert _no_children_left()


def test_a_claim_the_rerun_does_not_earn_fails_in_both_modes(monkeypatch):
    ex = registry.get("4.15")
    good = ex.numeric_solver

    def drifts_with_rtol(p, run):
        values = good(p, run)
        return {**values, "theta_c": values["theta_c"] * (1 + 1e4 * run.rtol)}  # 100x its claim of 100 rtol

    monkeypatch.setattr(ex, "numeric_solver", drifts_with_rtol)
    par, ser = _both(ex, ex.resolve({}), monkeypatch)
    for d in (par, ser):
        q = next(q for q in d["quantities"] if q["name"] == "theta_c")
        assert d["agree"] is False and q["agree"] is False and "unreliable" in q.get("note", "")


def test_a_failed_solve_leaves_no_rerun_running(monkeypatch):
    ex = registry.get("4.15")

    def broken(p, run):
        raise RuntimeError("the solve itself fails")

    monkeypatch.setattr(ex, "numeric_solver", broken)
    monkeypatch.setattr(crosscheck, "_parallel_ok", lambda: True)
    d = crosscheck.cross_check(ex, ex.resolve({})).as_json()
    assert d["agree"] is False and "the solve itself fails" in d["errors"][0]
    assert _no_children_left()


def _hang():
    import time

    time.sleep(600)


def _misbehaving_in_the_child(ex, misbehave):
    good = ex.numeric_solver
    parent = os.getpid()

    def misbehaves_in_the_child(p, run):
        if os.getpid() != parent:
            misbehave()
        return good(p, run)

    return misbehaves_in_the_child


def test_a_rerun_that_dies_is_done_serially(monkeypatch):
    """A child that dies without answering (as a crash would) is gone: the rerun is done here."""
    ex = registry.get("4.15")
    monkeypatch.setattr(ex, "numeric_solver", _misbehaving_in_the_child(ex, lambda: os._exit(3)))
    monkeypatch.setattr(crosscheck, "_parallel_ok", lambda: True)
    d = crosscheck.cross_check(ex, ex.resolve({})).as_json()
    assert d["agree"] is True and "did not answer" in d["numeric_info"]["verify_parallel_fallback"]
    assert d["numeric_info"]["verify_rtol"] == pytest.approx(1e-11)
    assert _no_children_left()


def test_a_rerun_that_hangs_fails_loudly_within_the_budget(monkeypatch):
    """A child that never answers is stopped by its own time budget: a loud failure, no child left."""
    import time

    ex = registry.get("4.15")
    monkeypatch.setattr(ex, "numeric_solver", _misbehaving_in_the_child(ex, _hang))
    monkeypatch.setattr(crosscheck, "_parallel_ok", lambda: True)
    t0 = time.monotonic()
    d = crosscheck.cross_check(ex, ex.resolve({}), budget_s=1.0).as_json()
    assert time.monotonic() - t0 < 6.0
    assert d["agree"] is False
    assert any("time budget" in e or "did not answer" in e for e in d.get("errors", []) + [
        d["numeric_info"].get("verify_parallel_fallback", "")])
    assert _no_children_left()


def test_no_fork_beside_another_thread(monkeypatch):
    import threading

    monkeypatch.delenv("MECH_SERIAL_VERIFY", raising=False)
    stop = threading.Event()
    t = threading.Thread(target=stop.wait)
    t.start()
    try:
        assert crosscheck._parallel_ok() is False
    finally:
        stop.set()
        t.join()


_SLOW_IN_CHILD = """
import os, sys, time
from mech.problems import registry
from mech.verification import crosscheck
ex = registry.get("4.15")
good = ex.numeric_solver
parent = os.getpid()
def slow(p, run):
    if os.getpid() != parent:
        time.sleep(60)
    return good(p, run)
ex.numeric_solver = slow
crosscheck._parallel_ok = lambda: True
print("ready", flush=True)
crosscheck.cross_check(ex, ex.resolve({}))
"""


@pytest.mark.skipif(not os.path.isdir("/proc"), reason="needs /proc (Linux)")
@pytest.mark.parametrize("sig", ["SIGKILL", "SIGTERM"])
def test_the_rerun_dies_with_a_killed_parent(sig):
    """A CI timeout kills mech (SIGKILL or SIGTERM to its process): its forked rerun must not outlive it."""
    assert killed_leaves_nothing(_SLOW_IN_CHILD, "ready", sig) == []

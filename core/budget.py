"""Budgets: the work a computation may do, and the whole command's wall clock.

A verdict, a draw and a key depend on the inputs alone, so the limits inside a solve or a check count
work, not seconds.  ``check(where, units)`` counts units of work (a DOP853 step its 12 function
evaluations, a call of a scipy integrator's right-hand side one, a pass of a search, a quadrature panel,
a point judged one each); inside ``limit(work=N)`` the unit past N raises ``OutOfWork``, a
``NumericFailure`` naming what ran out.  On a slower or busier machine the same work is done and the
same verdict comes out.  ``SOLVE_WORK`` is a numeric solve's (sized in docs/reliability.md).

The wall clock stops only a whole command: ``limit(seconds)`` (``mech grade --budget``, ``mech sweep
--budget``, ``mech solve``'s ``MECH_BUDGET_S``) makes ``check`` raise ``OutOfTime`` past its deadline;
in the main thread a timer signal backs this up ``_GRACE_S`` later for a loop that never calls
``check`` (a long numpy call between bytecodes).  What a command's clock stopped is not graded, never
judged wrong.

Nested limits keep the earliest deadline and the least work left; only the outermost wall clock
installs the signal.  ``expired()`` says whether the limit now in force is spent: a caller that turned
an ``OutOfBudget`` into a failure of its own re-raises it when the budget spent was an outer one.
"""

from __future__ import annotations

import contextlib
import math
import time

from mech.core.errors import NumericFailure

__all__ = ["OutOfBudget", "OutOfTime", "OutOfWork", "check", "limit", "default_seconds", "remaining",
           "deadline", "expired", "used", "state", "capped", "stop_if_spent", "SOLVE_WORK", "CHECK_WORK"]

deadline = math.inf  # the wall clock of the command (time.monotonic())
_seconds = math.inf
_what = "the numeric solve"
_used = 0  # units of work counted in this process (a forked child goes on from its parent's count)
_cap = math.inf  # the count past which check() raises OutOfWork
_work = math.inf  # the size of the limit that set _cap
_work_what = "the numeric solve"
_GRACE_S = 0.25  # the backup timer: a loop that never calls check() stops this late

# units of work of one numeric solve (its rerun at rtol/10 has as many again): the worst in-bounds input
# met (mech check --hard, shared/tools/draws.py) needs a fifth of it, and a solve that runs into it ends
# in a few seconds on the 2-core machine (docs/reliability.md, "Work, not seconds")
SOLVE_WORK = 500_000
# units of work of checking one formula (its points, mech's values there, high precision, the numeric
# references of a leading-order output: students.formulas.NUMERIC_WORK of it)
CHECK_WORK = 1_000_000


class OutOfBudget(NumericFailure):
    """A computation ran past its budget: ``OutOfWork`` or ``OutOfTime``."""

    what = ""
    where = ""


class OutOfWork(OutOfBudget):
    """A computation did more work than its limit allows: the same on any machine at any load."""


class OutOfTime(OutOfBudget):
    """A command ran past its wall-clock budget: what it did not reach is not judged."""


def default_seconds() -> float:
    """``MECH_BUDGET_S``, or 8 s: ``mech solve``'s whole-command wall clock; ``BadInput`` naming the
    variable when it is not a finite positive number (``nan`` or ``inf`` would switch the budget off)."""
    from mech.core.safeio import budget_seconds

    return budget_seconds()


def remaining() -> float:
    """Seconds left of the current wall clock (inf outside any)."""
    return deadline - time.monotonic()


def used() -> int:
    """Units of work counted so far in this process."""
    return _used


def state() -> tuple[float, float]:
    """The limits now in force (deadline, work cap), for ``expired`` and ``stop_if_spent`` to look at
    later, from inside a limit of one's own."""
    return deadline, _cap


def capped() -> bool:
    """Is a work limit in force?"""
    return math.isfinite(_cap)


def expired(limits: tuple[float, float] | None = None) -> bool:
    """Are the limits in force (or ``limits``, from ``state()``) spent, in work or on the wall clock?"""
    end, cap = (deadline, _cap) if limits is None else limits
    return _used >= cap or time.monotonic() > end


def stop_if_spent(limits: tuple[float, float], exc: BaseException | None = None, where: str = "") -> None:
    """Raise when ``limits`` (from ``state()``) are spent: ``exc`` when it is a budget's own exception, else
    ``OutOfWork`` or ``OutOfTime`` saying which."""
    end, cap = limits
    if not expired(limits):
        return
    if isinstance(exc, OutOfBudget):
        raise exc
    place = f" ({where})" if where else ""
    if _used >= cap:
        raise OutOfWork(f"the work budget in force ran out{place}")
    raise OutOfTime(f"the time budget in force ran out{place}")


def check(where: str = "", units: int = 1) -> None:
    """Count ``units`` of work; raise ``OutOfWork`` past the work limit, ``OutOfTime`` past the deadline."""
    global _used
    _used += units
    if _used > _cap:
        _raise_work(where)
    if time.monotonic() > deadline:
        _raise(where)


def _raise_work(where: str = ""):
    place = f" ({where})" if where else ""
    exc = OutOfWork(f"{_work_what} ran out of its work budget of {_work:,.0f} units (steps, function "
                    f"evaluations, points){place}")
    exc.what, exc.where = _work_what, where
    raise exc


def _raise(where: str = ""):
    place = f" ({where})" if where else ""
    exc = OutOfTime(f"{_what} ran out of its {_seconds:g} s time budget{place}")
    exc.what, exc.where = _what, where
    raise exc


def _on_alarm(signum, frame):
    _raise("stopped by the timer")


@contextlib.contextmanager
def limit(seconds: float | None = None, what: str = "the numeric solve", work: float | None = None):
    """Run the block under a wall clock of ``seconds`` (None: the one in force, if any) and at most
    ``work`` units of work (None: the limit in force, if any)."""
    global deadline, _seconds, _what, _cap, _work, _work_what
    saved = (deadline, _seconds, _what, _cap, _work, _work_what)
    armed = False
    old_handler = None
    if work is not None and _used + float(work) < _cap:
        _cap, _work, _work_what = _used + float(work), float(work), what
    if seconds is not None:
        seconds = float(seconds)
        new_deadline = time.monotonic() + seconds
        outermost = not math.isfinite(deadline)
        if new_deadline < deadline:
            deadline, _seconds, _what = new_deadline, seconds, what
        if outermost and math.isfinite(seconds):
            import signal
            import threading

            if threading.current_thread() is threading.main_thread() and hasattr(signal, "setitimer"):
                old_handler = signal.signal(signal.SIGALRM, _on_alarm)
                signal.setitimer(signal.ITIMER_REAL, seconds + _GRACE_S)
                armed = True
    try:
        yield
    finally:
        if armed:
            import signal

            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, old_handler if old_handler is not None else signal.SIG_DFL)
        deadline, _seconds, _what, _cap, _work, _work_what = saved

"""A wall-clock budget for one numeric solve: every loop ends, with an answer or a loud failure.

The cross-check runs each numeric solve inside ``limit(seconds)``.  Long loops
call ``check(where)`` (mech's DOP853 does at every step, Newton iterations,
continuations and quadratures should at every pass); past the deadline it
raises ``OutOfBudget``, a ``NumericFailure`` naming what ran out.  In the main
thread a timer signal backs this up one second later for loops that never
call ``check`` (a scipy integrator, a long numpy call between bytecodes).

Nested limits keep the earliest deadline; only the outermost installs the
signal.  ``MECH_BUDGET_S`` sets the default budget of a solve (8 s: with the
start-up and the analytic side a command ends within 10 s).
"""

from __future__ import annotations

import contextlib
import math
import time

from mech.core.errors import NumericFailure

__all__ = ["OutOfBudget", "check", "limit", "default_seconds", "remaining", "deadline"]

deadline = math.inf
_seconds = math.inf
_what = "the numeric solve"
_GRACE_S = 0.25  # the backup timer: a loop that never calls check() stops this late


class OutOfBudget(NumericFailure):
    """A solve ran past its wall-clock budget."""


def default_seconds() -> float:
    """``MECH_BUDGET_S``, or 8 s; ``BadInput`` naming the variable when it is not a finite positive number
    (``nan`` or ``inf`` would switch the budget off)."""
    from mech.core.safeio import budget_seconds

    return budget_seconds()


def remaining() -> float:
    """Seconds left of the current budget (inf outside any limit)."""
    return deadline - time.monotonic()


def check(where: str = "") -> None:
    """Raise ``OutOfBudget`` when the current budget is spent."""
    if time.monotonic() > deadline:
        _raise(where)


def _raise(where: str = ""):
    place = f" ({where})" if where else ""
    exc = OutOfBudget(f"{_what} ran out of its {_seconds:g} s time budget{place}")
    exc.what, exc.where = _what, where
    raise exc


def _on_alarm(signum, frame):
    _raise("stopped by the timer")


@contextlib.contextmanager
def limit(seconds: float | None = None, what: str = "the numeric solve"):
    """Run the block under a budget of ``seconds`` (default ``default_seconds()``)."""
    global deadline, _seconds, _what
    seconds = default_seconds() if seconds is None else float(seconds)
    saved = (deadline, _seconds, _what)
    new_deadline = time.monotonic() + seconds
    outermost = not math.isfinite(deadline)
    if new_deadline < deadline:
        deadline, _seconds, _what = new_deadline, seconds, what
    old_handler = None
    armed = False
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
        deadline, _seconds, _what = saved

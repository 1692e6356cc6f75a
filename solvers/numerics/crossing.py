"""One initial-value problem stepped by a scipy method (a stiff one: LSODA, Radau, BDF) up to the first
crossing of one terminal event, the steps taken here rather than inside ``solve_ivp``.

``to_crossing`` is what ``solve_ivp(..., events=[g])`` with ``g.terminal`` does for one event, the same
steps (scipy's ``OdeSolver`` of that method, the same options), the same test for a crossing over a step
(g's signs at its ends, in the event's direction) and the same root on the step's dense output (brentq to 4
machine epsilons), so the same numbers, bit for bit; without ``solve_ivp``'s bookkeeping per step (its
events' list, the solution's lists), which costs twice the steps of a three-component stiff system.  Each
right-hand side evaluation counts a unit of work (``budget.check``), as ``ode.integrate`` counts it.

No physics here; scipy is imported inside the function.
"""

from __future__ import annotations

import math
import time
from typing import Callable

import numpy as np

from mech.core import budget
from mech.core.errors import NumericFailure

__all__ = ["to_crossing"]

_EPS = np.finfo(float).eps


def to_crossing(rhs: Callable, t_span, y0, *, rtol: float, atol, g: Callable, direction: float = 0.0,
                method: str = "LSODA", jac: Callable | None = None, max_step: float = math.inf):
    """``y' = rhs(t, y)`` from ``y0`` at ``t_span[0]`` until ``g(t, y)`` first crosses zero in ``direction``
    (+1 upward, -1 downward, 0 either way) or ``t_span[1]`` is reached.  Returns an ``ode.Trajectory`` of
    two points (the start and where it stopped) whose ``t_events[0]`` holds the crossing (empty if none).
    A failed integration raises ``NumericFailure``, as ``ode.integrate`` does."""
    import scipy.integrate as si

    from mech.solvers.numerics.ode import Trajectory

    where = f"{method} step"

    def fun(t, y):
        budget.check(where)
        return rhs(t, y)

    t0, t1 = float(t_span[0]), float(t_span[1])
    y0 = np.asarray(y0, dtype=float)
    kwargs = {"rtol": rtol, "atol": atol, "max_step": max_step}
    if jac is not None and method in ("Radau", "BDF", "LSODA"):
        kwargs["jac"] = jac
    start = time.perf_counter()
    solver = getattr(si, method)(fun, t0, y0, t1, vectorized=False, **kwargs)
    g_old = g(t0, y0)
    t_ev, y_ev, status, message = [], [], 0, "The solver successfully reached the end of the integration interval."
    while True:
        t_old = solver.t
        msg = solver.step()
        if solver.status == "failed":
            raise NumericFailure(f"{method} integration failed at t={solver.t:.6g}: {msg}")
        g_new = g(solver.t, solver.y)
        up, down = g_old <= 0.0 <= g_new, g_old >= 0.0 >= g_new
        if (up and direction > 0) or (down and direction < 0) or ((up or down) and direction == 0):
            from scipy.optimize import brentq

            sol = solver.dense_output()
            root = brentq(lambda t: g(t, sol(t)), t_old, solver.t, xtol=4 * _EPS, rtol=4 * _EPS)
            t_end, y_end = root, sol(root)
            t_ev, y_ev, status, message = [root], [y_end], 1, "A termination event occurred."
            break
        g_old = g_new
        if solver.status == "finished":
            t_end, y_end = solver.t, solver.y
            break
    wall = time.perf_counter() - start
    return Trajectory(t=np.array([t0, t_end]), y=np.column_stack([y0, y_end]),
                      t_events=[np.array(t_ev)], y_events=[np.array(y_ev).reshape(len(t_ev), y0.size)],
                      nfev=int(solver.nfev), njev=int(solver.njev), nlu=int(solver.nlu), method=method, rtol=rtol,
                      wall_s=wall, status=status, message=message)

"""N variants of one equation of motion followed together, each failing alone.

``follow(make_rhs, t_span, y0, rtol=, atol=, tally=, events=)``: the variants (states n x N) integrated over
one shared ``t_span`` (an exercise scales each variant's time or independent variable onto it) by mech's
DOP853 stepping the ensemble (``batch.integrate_batch``, its events located per variant, a variant whose
step underflows or whose state turns non-finite failing alone).  With an integrator forced (``mech
bench``: the tally's ``integrator``) each variant goes alone through ``ode.integrate``.  ``make_rhs(sel)``:
the right-hand side of the variants ``sel`` (``slice(None)``: states n x N; an int: one variant, states of
n floats).  Events are ``batch.BatchEvent``s (``g(t, y)`` on states n x N; each variant's first crossing).
No physics here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Followed", "follow"]


@dataclass
class Followed:
    """What ``follow`` gives: the end states (n x N, NaN where the variant failed), each variant's failure
    ("" where none), each event's first crossing per variant (times (N,), states n x N; NaN: none) and where
    each variant stopped (its terminal event, or the span's end)."""

    y_end: np.ndarray
    why: np.ndarray
    t_events: list
    y_events: list
    t_stop: np.ndarray


def follow(make_rhs, t_span, y0, *, rtol: float, atol, tally=None, events=()) -> Followed:
    """The variants ``y0`` (n x N) from ``t_span[0]`` to ``t_span[1]`` (``Followed``); ``atol``: n x N (or
    anything that broadcasts to it); ``tally``: takes the integrations (its ``integrator``: forced)."""
    from mech.solvers.numerics.batch import integrate_batch

    y0 = np.asarray(y0, dtype=float)
    n, N = y0.shape
    atol = np.broadcast_to(np.asarray(atol, dtype=float), (n, N))
    integrator = None if tally is None else tally.integrator
    if integrator is not None:
        return _one_by_one(make_rhs, t_span, y0, rtol, atol, tally, events)
    res = integrate_batch(make_rhs(slice(None)), t_span, y0, rtol=rtol, atol=np.array(atol), events=events,
                          on_failure="mark")
    if tally is not None:
        tally.record(res)
    why = np.array(["" if w is None else str(w) for w in res.why], dtype=object)
    y_end = np.array(res.y_end, dtype=float)
    y_end[:, why != ""] = np.nan
    return Followed(y_end, why, list(res.t_events), list(res.y_events), np.asarray(res.t_stop, dtype=float))


def _one_by_one(make_rhs, t_span, y0, rtol, atol, tally, events) -> Followed:
    """Each variant alone through ``ode.integrate`` with the forced integrator (``mech bench``)."""
    from mech.core.budget import OutOfBudget
    from mech.core.errors import NumericFailure
    from mech.solvers.numerics.ode import Event, integrate

    n, N = y0.shape
    out = Followed(np.full((n, N), np.nan), np.full(N, "", dtype=object), [np.full(N, np.nan) for _ in events],
                   [np.full((n, N), np.nan) for _ in events], np.full(N, np.nan))
    for j in range(N):
        def alone(g, j=j):  # an ensemble's event function at variant j alone (the others at their start)
            def fn(t, y):
                Y = y0.copy()
                Y[:, j] = y
                return float(np.asarray(g(t, Y), dtype=float)[j])

            return fn

        evs = [Event(alone(ev.g), terminal=ev.terminal, direction=ev.direction, name=ev.name or "event")
               for ev in events]
        try:
            traj = integrate(make_rhs(j), t_span, y0[:, j], rtol=rtol, atol=atol[:, j], events=evs,
                             integrator=tally.integrator)
        except OutOfBudget:
            raise
        except NumericFailure as exc:
            out.why[j] = str(exc)
            continue
        tally.record(traj)
        out.y_end[:, j], out.t_stop[j] = traj.y_end, traj.t_end
        for k in range(len(events)):
            if len(traj.t_events[k]):
                out.t_events[k][j] = traj.t_events[k][0]
                out.y_events[k][:, j] = traj.y_events[k][0]
    return out

"""N variants of one equation of motion followed together, each failing alone: ``ensemble.follow`` read as
4.15, 4.26, 4.29, 4.30, 4.31 and 4.33 read it.

``follow(make_rhs, t_span, y0, rtol=, atol=, tally=, events=)``: the variants (states n x N) over one shared
``t_span`` (an exercise scales each variant's time or independent variable onto it) by
``solvers.numerics.ensemble.follow`` (mech's DOP853 stepping the ensemble, its events located per variant;
one variant, or an integrator forced by ``mech bench``: the tally's ``integrator``, by ``ode.integrate``),
every failure marked on its variant.  The integrations go to the tally.  What it gives (``Followed``): the
end states NaN where a variant failed and the reasons as texts ("" where none), so that a route masks its
failures with ``why == ""``.  No physics here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Followed", "follow"]


@dataclass
class Followed:
    """The end states (n x N, NaN where the variant failed), each variant's failure ("" where none), each
    event's first crossing per variant (times (N,), states n x N; NaN: none) and where each variant stopped
    (its terminal event, or the span's end)."""

    y_end: np.ndarray
    why: np.ndarray
    t_events: list
    y_events: list
    t_stop: np.ndarray


def follow(make_rhs, t_span, y0, *, rtol: float, atol, tally=None, events=()) -> Followed:
    """The variants ``y0`` (n x N) from ``t_span[0]`` to ``t_span[1]`` (``Followed``); ``atol``: n x N (or
    anything that broadcasts to it); ``tally``: takes the integrations (its ``integrator``: forced)."""
    from mech.solvers.numerics.ensemble import follow as ensemble_follow

    y0 = np.asarray(y0, dtype=float)
    atol = np.array(np.broadcast_to(np.asarray(atol, dtype=float), y0.shape))
    got = ensemble_follow(make_rhs, t_span, y0, rtol=rtol, atol=atol, events=events,
                          integrator=None if tally is None else tally.integrator, on_failure="mark")
    for r in got.records if tally is not None else ():
        tally.record(r)
    why = np.array(["" if w is None else str(w) for w in got.why], dtype=object)
    y_end = np.array(got.y_end, dtype=float)
    y_end[:, why != ""] = np.nan
    return Followed(y_end, why, list(got.t_events), list(got.y_events), np.asarray(got.t_stop, dtype=float))

"""N variants of one equation of motion followed together, each failing alone.

``follow(make_rhs, t_span, y0, rtol=, atol=, tally=)``: the variants (states n x N) integrated over one
shared ``t_span`` (an exercise scales each variant's time or independent variable onto it) by
``floquet.integrate_ensemble`` (mech's DOP853 stepping the ensemble; one variant alone, or an integrator
forced by ``mech bench``, by ``ode.integrate``).  A chunk whose integration fails is followed again variant
by variant, so that a failure (a step size underflowing) is that variant's alone: its end state NaN and its
reason given.  ``make_rhs(sel)``: the right-hand side of the variants ``sel`` (``slice(None)``/an index
array: states n x len; an int: one variant, states of n floats).  No physics here.
"""

from __future__ import annotations

import numpy as np

from mech.core.errors import NumericFailure

__all__ = ["follow"]


def follow(make_rhs, t_span, y0, *, rtol: float, atol, tally=None, chunks=None):
    """(y_end n x N, NaN where the variant failed; why: N reasons, "" where none).  ``atol``: n x N;
    ``chunks``: index arrays integrated apart (all together by default); ``tally``: takes the integrations
    (its ``integrator``: forced by ``mech bench``)."""
    from mech.core.budget import OutOfBudget
    from mech.solvers.mechanics.floquet import integrate_ensemble

    y0 = np.asarray(y0, dtype=float)
    n, N = y0.shape
    atol = np.broadcast_to(np.asarray(atol, dtype=float), (n, N))
    y_end = np.full((n, N), np.nan)
    why = np.full(N, "", dtype=object)
    integrator = None if tally is None else tally.integrator

    def run(idx):
        def sub(sel):
            return make_rhs(int(idx[sel]) if isinstance(sel, (int, np.integer)) else idx)

        try:
            got, runs = integrate_ensemble(sub, t_span, y0[:, idx], rtol=rtol, atol=atol[:, idx],
                                           integrator=integrator)
        except OutOfBudget:
            raise
        except NumericFailure as exc:
            if idx.size == 1:
                why[idx[0]] = str(exc)
            for k in idx if idx.size > 1 else ():
                run(np.array([k]))
            return
        y_end[:, idx] = got
        for r in runs if tally is not None else ():
            tally.record(r)

    for idx in [np.arange(N)] if chunks is None else chunks:
        if len(idx):
            run(np.asarray(idx, dtype=int))
    return y_end, why

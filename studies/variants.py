"""Many variants of one exercise cross-checked at once through its batched route.

A class's personal variants and an assignment's candidates are scattered points of one exercise.  Where
the exercise has a batched route for every output and a tighter rerun to verify by, the points are run
as one sweep over their arrays (``sweep.run_batched`` with ``points``): both solves (at rtol and rtol/10)
over the ensemble, the analytic side on arrays, each variant judged by the cross-check's rule and given
its own ``Solution``, as ``mech solve`` gives it.  Elsewhere the caller cross-checks them one by one.
"""

from __future__ import annotations

from typing import Sequence

__all__ = ["batchable", "cross_check_variants"]


def batchable(ex) -> bool:
    """Does ``ex`` have a batched route giving all its outputs, with a rerun tighter than its rtol?"""
    route = getattr(ex, "batched_route", None)
    if route is None or set(route.outputs) != {o.name for o in ex.outputs}:
        return False
    return max(ex.default_rtol / 10.0, ex.min_rtol) < ex.default_rtol


def cross_check_variants(ex, params: Sequence, total_s: float | None = None) -> list:
    """The cross-checks of ``params`` (resolved parameters of ``ex``, a ``batchable`` exercise), solved
    together: one ``Solution`` each, in order.  ``total_s``: the wall-clock budget of the whole batch (the
    sweep's default otherwise); the solves count work, so a variant solved gets the same verdicts at any
    load.  Raises what the batch raises as a whole (a caller falls back to one by one)."""
    import warnings

    import numpy as np

    from mech.studies.sweep import iter_batched_solutions, run_batched

    def solve(group: Sequence, budget: float | None) -> list:
        P = {p.name: np.array([float(q[p.name]) for q in group]) for p in ex.params}
        with warnings.catch_warnings():  # never a message: the values are judged
            warnings.simplefilter("ignore")
            result = run_batched(ex, [], {}, tuple(o.name for o in ex.outputs), total_s=budget, points=P)
        return list(iter_batched_solutions(result))

    solutions = solve(params, total_s)
    if len(params) > 1:
        # a variant that failed beside others is solved again as the batch of one, as ``mech solve`` solves
        # it: the ensemble shares its steps, so whether a variant is answered must not depend on its company
        for k, sol in enumerate(solutions):
            if sol.agree is False:
                solutions[k] = solve([params[k]], total_s)[0]
    return solutions

"""Many variants of one exercise cross-checked at once through its batched route.

A class's personal variants and an assignment's candidates are scattered points of one exercise.  Where
the exercise has a batched route for every output and a tighter rerun to verify by, the points are run
as one sweep over their arrays (``sweep.run_batched`` with ``points``): both solves (at rtol and rtol/10)
over the ensemble, the analytic side on arrays, each variant judged by the cross-check's rule and given
its own ``Solution``, as ``mech solve`` gives it, its invariants too.  Elsewhere the caller cross-checks
them one by one.
"""

from __future__ import annotations

from typing import Sequence

__all__ = ["batchable", "cross_check_variants", "in_range"]


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
        calls: list = []  # (rtol, variants, Tally) of each call of the route
        with warnings.catch_warnings():  # never a message: the values are judged
            warnings.simplefilter("ignore")
            result = run_batched(_tallied(ex, calls), [], {}, tuple(o.name for o in ex.outputs), total_s=budget,
                                 points=P)
        drifts = _drifts(calls, ex.default_rtol, len(group))
        return [sol.replace(exercise=ex, errors=sol.errors + _invariant_failures(ex, drifts, k))
                for k, sol in enumerate(iter_batched_solutions(result))]

    solutions = solve(params, total_s)
    if len(params) > 1:
        # a variant that failed beside others is solved again as the batch of one, as ``mech solve`` solves
        # it: the ensemble shares its steps, so whether a variant is answered must not depend on its company
        for k, sol in enumerate(solutions):
            if sol.agree is False:
                solutions[k] = solve([params[k]], total_s)[0]
    for k, sol in enumerate(solutions):
        if not in_range(sol):
            from mech.verification.crosscheck import cross_check

            solutions[k] = cross_check(ex, params[k])  # it fails such a value, as ``mech solve`` does
    return solutions


def in_range(solution) -> bool:
    """Is each value of ``solution`` a finite number inside mech's floating-point range, or declared
    undefined?  The one-point cross-check fails any other (``crosscheck._undefine_bad_values``); a batched
    route does not look."""
    import math

    from mech.problems.params import Undefined
    from mech.problems.scales import out_of_range

    return all(v is None or isinstance(v, Undefined) or (isinstance(v, float) and math.isfinite(v)
                                                          and not out_of_range(v))
               for q in solution.quantities for v in (q.analytic, q.numeric))


def _tallied(ex, calls: list):
    """``ex`` with its route handed a ``Tally`` at every call (kept in ``calls``), as the one-point solve
    hands it one: each variant's invariant drifts are then judged as ``mech solve`` judges them."""
    import copy
    import dataclasses
    import inspect

    from mech.problems.batched import Tally

    route = ex.batched_route
    takes = inspect.signature(route.numeric).parameters
    if "tally" not in takes:
        return ex

    def numeric(P, rtol, outputs, memo=None):
        tally = Tally()
        calls.append((rtol, next(iter(P.values())).size, tally))
        return route.numeric(P, rtol, outputs, tally=tally, **({"memo": memo} if "memo" in takes else {}))

    tallied = copy.copy(ex)
    tallied.batched_route = dataclasses.replace(route, numeric=numeric)
    return tallied


def _drifts(calls: list, rtol: float, n: int) -> dict:
    """{invariant: (drift, allowed)} per variant (arrays of ``n``) of the solves at ``rtol`` (the rerun's are not
    judged, as in the cross-check), chunk after chunk.  A NaN drift is not measured at that variant (a
    ``Tally`` keeps the worst over calls with ``fmax``: 5.4 measures one invariant on the variants it
    integrates, another on those it solves by the exact flow); a NaN allowed is the exercise's claim."""
    import numpy as np

    out: dict = {}
    start = 0
    for tol, m, tally in calls:
        if tol != rtol:
            continue
        for name, (drift, allowed) in tally.invariants.items():
            d, a = out.setdefault(name, (np.full(n, np.nan), np.full(n, np.nan)))
            d[start:start + m] = np.broadcast_to(drift, (m,))
            if allowed is not None:
                a[start:start + m] = np.broadcast_to(np.asarray(allowed, dtype=float), (m,))
        start += m
    return out


def _invariant_failures(ex, drifts: dict, k: int) -> tuple:
    """The cross-check's invariant failures (the rule of ``crosscheck._check_invariants``) of variant ``k``."""
    if not drifts:
        return ()
    from mech.problems.motion import Run
    from mech.verification.crosscheck import _check_invariants

    run = Run(rtol=ex.default_rtol)
    for name, (drift, allowed) in drifts.items():
        if drift[k] != drift[k]:
            continue
        run.invariant(name, float(drift[k]), allowed=None if allowed[k] != allowed[k] else float(allowed[k]))
    errors: list = []
    _check_invariants(ex, run, ex.default_rtol, errors)
    return tuple(errors)

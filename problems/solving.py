"""What an exercise's declaration is used for at one point: its parameters resolved and checked (the bounds,
then the joint checks), its analytic answers in the units that suit them, its numeric answers and their
``Run``, a solver's answers checked against the outputs declared.  They read only what ``Exercise``
(problems/spec.py) declares; its ``resolve``, ``solve_analytic`` and ``solve_numeric`` call them."""

from __future__ import annotations

import math
from typing import Mapping

from mech.core.errors import BadInput
from mech.problems.motion import Run
from mech.problems.params import Params, Undefined

__all__ = ["resolve", "constraint_message", "solve_analytic", "solve_numeric", "finish"]


def resolve(ex, given: Mapping[str, float] | None = None) -> Params:
    """Defaults overlaid by the given values, each checked against its bounds, then the joint checks."""
    given = dict(given or {})
    unknown = [k for k in given if k not in ex.param_map]
    if unknown:
        names = ", ".join(ex.param_map)
        raise BadInput(f"unknown parameter '{unknown[0]}' for {ex.id}; its parameters are: {names}")
    values = {}
    for p in ex.params:
        v = float(given.get(p.name, p.default))
        p.check(v)
        values[p.name] = v
    params = Params(values)
    from mech.problems import scales

    for check in ex._constraints:
        try:
            msg = check(params)
        except (OverflowError, ZeroDivisionError) as exc:
            # a joint check that cannot even form its scales: the input is beyond the floating-point range
            where = scales.far_params(ex, params)
            msg = (f"the scales the parameters form{' at ' + where if where else ''} leave the "
                   f"floating-point range ({type(exc).__name__} in the joint checks)")
        if msg:
            raise BadInput(msg)
    msg = scales.representable(ex, params)
    if msg:
        raise BadInput(msg)
    return params


def constraint_message(ex, p) -> str | None:
    """The first joint check's one-line message that ``p`` fails (anything read as ``p.name``), or None."""
    for check in ex._constraints:
        msg = check(p)
        if msg:
            return msg
    return None


def solve_analytic(ex, p: Params) -> dict:
    """The analytic answers; where the parameters are far (beyond ~1e+-9) from their defaults, solved in the
    units, powers of two of kg, m and s, that bring them nearest (``scales.natural_units``) and brought back
    to SI exactly, so that the units chosen do not matter."""
    from mech.problems import scales

    nat = scales.natural_units(ex, p)
    if nat is None:
        return finish(ex, ex.analytic_solver(p), "analytic")
    u, values = nat
    out = finish(ex, ex.analytic_solver(Params(values)), "analytic")
    units = {o.name: o.unit for o in ex.outputs}
    back = {n: v if isinstance(v, Undefined) else scales.from_natural(v, units[n], u) for n, v in out.items()}
    # units that bring the parameters near their defaults can push an output below the doubles' range
    # while its SI value is a normal number (4.29 at t = 2e-200 s: a_lab = 3.2e-200 m/s^2 is 7e-393 in
    # units of 2^-320 s, computed as 0): there the SI solution's value stands, when in the natural
    # units it too lies below the range (so that the 0 was its underflow, not a different answer)
    lost = [n for n, v in out.items() if isinstance(v, float) and abs(v) < scales.TINY]
    if lost:
        try:
            import warnings

            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                si = finish(ex, ex.analytic_solver(p), "analytic")
        except Exception:  # the SI solution overflows or divides by zero: why natural units were taken
            si = {}
        for n in lost:
            w = si.get(n)
            if (isinstance(w, float) and math.isfinite(w) and abs(w) >= scales.TINY
                    and abs(scales.to_natural(w, units[n], u)) < scales.TINY):
                back[n] = w
    return back


def solve_numeric(ex, p: Params, rtol: float | None = None, shared: dict | None = None,
                  keep_trajectories: bool = False, integrator: str | None = None) -> tuple[dict, Run]:
    """The numeric solver's answers and its Run; ``integrator`` forces every ODE integration onto one
    integrator (``mech bench``; see ``Run.integrator``)."""
    run = Run(rtol=float(rtol or ex.default_rtol), keep_trajectories=keep_trajectories, integrator=integrator)
    if shared is not None:
        run.shared = shared
    values = ex.numeric_solver(p, run)
    return finish(ex, values, "numeric"), run


def finish(ex, values: dict, which: str) -> dict:
    """A solver's answers, every declared output present and nothing else, as floats (or Undefined)."""
    names = [o.name for o in ex.outputs]
    missing = [n for n in names if n not in values]
    extra = [n for n in values if n not in names]
    if missing or extra:
        raise RuntimeError(f"{ex.id} {which} solver: missing outputs {missing}, unexpected {extra}")
    return {n: values[n] if isinstance(values[n], Undefined) else float(values[n]) for n in names}

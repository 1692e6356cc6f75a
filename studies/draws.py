"""Random parameter draws across an exercise's declared bounds, for the bounds tests and scripts/draws.py.

Two kinds of draw:

* ``near``: each parameter log-uniform within a factor 30 of its default, clipped into its bounds (the
  ranges a course uses most);
* ``whole``: each parameter log-uniform over its whole declared range (where a bound is open-ended,
  over 1e-6..1e6 times the default), uniform where the range straddles zero.

Joint constraints may refuse a draw; it is then redrawn.  Every draw is seeded by (seed, exercise id).
"""

from __future__ import annotations

import math

from mech.problems.spec import BadInput

__all__ = ["draw_value", "draws"]

_OPEN_SPAN = 1e6  # an open-ended range is drawn over default / 1e6 .. default * 1e6


def _inside(param, x: float) -> bool:
    if param.min is not None and (x < param.min or (param.min_open and x == param.min)):
        return False
    if param.max is not None and (x > param.max or (param.max_open and x == param.max)):
        return False
    return math.isfinite(x)


def _log_uniform(rng, a: float, b: float) -> float:
    return math.exp(rng.uniform(math.log(a), math.log(b))) if b > a else a


def draw_value(param, rng, kind: str = "whole") -> float:
    """One value of ``param``: ``kind`` is ``"near"`` (within 30x of the default) or ``"whole"``."""
    d = param.default
    lo = param.min if param.min is not None else -math.inf
    hi = param.max if param.max is not None else math.inf
    factor = 30.0 if kind == "near" else _OPEN_SPAN
    if d > 0 and lo >= 0:
        if kind == "near":
            a, b = max(d / factor, lo), min(d * factor, hi)
        else:
            a = lo if lo > 0 else d / factor
            b = hi if math.isfinite(hi) else d * factor
        x = _log_uniform(rng, max(a, 1e-300), b)
    elif d < 0 and hi <= 0:
        if kind == "near":
            a, b = max(d * factor, lo), min(d / factor, hi)
        else:
            a = lo if math.isfinite(lo) else d * factor
            b = hi if hi < 0 else d / factor
        x = -_log_uniform(rng, -b, -a)
    else:
        span = (hi - lo) if math.isfinite(hi - lo) else max(1.0, 10 * abs(d))
        if kind == "near":
            a, b = max(lo, d - span / 2), min(hi, d + span / 2)
        else:
            a = lo if math.isfinite(lo) else d - _OPEN_SPAN * max(1.0, abs(d))
            b = hi if math.isfinite(hi) else d + _OPEN_SPAN * max(1.0, abs(d))
        x = rng.uniform(a, b)
    if getattr(param, "integer", False):
        x = round(x)
    return float(x) if _inside(param, x) else float(d)


def draws(ex, n: int, seed: int, kind: str = "whole", max_tries: int = 50) -> list[dict]:
    """``n`` parameter sets for ``ex`` that its bounds and joint constraints accept (fewer if they refuse
    ``max_tries * n`` draws)."""
    import numpy as np

    key = [seed, *map(int, ex.id.split("."))]
    rng = np.random.default_rng(key if kind == "near" else key + [1])
    out: list[dict] = []
    tries = 0
    while len(out) < n and tries < max_tries * n:
        tries += 1
        given = {p.name: draw_value(p, rng, kind) for p in ex.params}
        try:
            ex.resolve(given)
        except BadInput:
            continue
        out.append(given)
    return out

"""Every exercise cross-checked at parameters drawn across its bounds, not only its defaults.

Each parameter is drawn log-uniformly over a factor of 30 either side of its default
(uniformly where the default is 0 or the bounds are tight), clipped into its bounds;
joint constraints may refuse a draw, which is then redrawn.  The draws are seeded, so
the test is deterministic; set MECH_BOUNDS_SEED or MECH_BOUNDS_POINTS to explore more.
"""

import math
import os

import numpy as np
import pytest

from mech.cli.checking import Case, run_case
from mech.problems import registry
from mech.problems.spec import BadInput

POINTS = int(os.environ.get("MECH_BOUNDS_POINTS", "2"))
SEED = int(os.environ.get("MECH_BOUNDS_SEED", "20261121"))


def _draw(param, rng):
    lo = param.min if param.min is not None else -math.inf
    hi = param.max if param.max is not None else math.inf
    d = param.default
    if d > 0 and lo >= 0:
        a, b = max(d / 30, lo if lo > 0 else d / 30), min(d * 30, hi)
        x = math.exp(rng.uniform(math.log(a), math.log(b))) if b > a else d
    elif d < 0 and hi <= 0:
        a, b = max(d * 30, lo), min(d / 30, hi if hi < 0 else d / 30)
        x = -math.exp(rng.uniform(math.log(-b), math.log(-a))) if b > a else d
    else:
        span = (hi - lo) if math.isfinite(hi - lo) else max(1.0, 10 * abs(d))
        a, b = max(lo, d - span / 2), min(hi, d + span / 2)
        x = rng.uniform(a, b)
    if (param.min is not None and (x < param.min or (param.min_open and x == param.min))) or (
            param.max is not None and (x > param.max or (param.max_open and x == param.max))):
        x = d
    return float(x)


def draws(ex, n, seed):
    rng = np.random.default_rng([seed, *map(int, ex.id.split("."))])
    out = []
    tries = 0
    while len(out) < n and tries < 50 * n:
        tries += 1
        given = {p.name: _draw(p, rng) for p in ex.params}
        try:
            ex.resolve(given)
        except BadInput:
            continue
        out.append(given)
    return out


CASES = [(ex, k, given) for ex in registry.all_exercises().values() for k, given in enumerate(draws(ex, POINTS, SEED))]


@pytest.mark.parametrize("ex, k, given", CASES, ids=[f"{ex.id}-{k}" for ex, k, _ in CASES])
def test_cross_check_at_drawn_parameters(ex, k, given):
    case = run_case(Case(ex, f"draw {k}", given))
    if not case.ok and "beyond this solver's budget" in case.detail:
        # a declared computational limit: the tool fails loudly (NumericFailure, exit 1) rather than
        # guess; kept visible as an expected failure until the solver covers it (4.24, weak-force tops)
        pytest.xfail(f"{ex.id} at {given}: {case.detail}")
    assert case.ok, f"{ex.id} at {given}: {case.detail}"

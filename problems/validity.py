"""Where a leading-order theory applies, and what an answer is allowed: read from an exercise's declaration.

The theory applies where its expansion parameter (``@exercise.theory_range``) is below ``RANGE_LIMIT`` and its
neglect estimate (``@exercise.expected_error``) below ``NEGLECT_LIMIT`` relative, at one point or over a batch;
outside, nothing is compared (the judge words the reason).  The allowances at one point: what the theory
neglects, the analytic value's round-off (``@exercise.analytic_error``), and the approximations the statement
asks for beside an exact output (``@exercise.approximations``).  A hook written on arrays (an exercise with a
batched route) is called as the batch of one."""

from __future__ import annotations

import math
from typing import Mapping

from mech.problems.batched import expected_at, label_at, range_at

__all__ = ["RANGE_LIMIT", "NEGLECT_LIMIT", "expected_errors", "theory_ranges", "analytic_errors", "approximations_at",
           "theory_validity", "outside_ranges"]


# A leading-order theory is outside its range where its expansion parameter reaches RANGE_LIMIT or its
# neglect estimate (``expected_error``'s relative part) reaches NEGLECT_LIMIT: nothing is compared there
RANGE_LIMIT = 1.0
NEGLECT_LIMIT = 0.3


def expected_errors(ex, p) -> dict:
    """{output: relative size of what its leading-order theory neglects at ``p``, or (relative, absolute)}."""
    return _hook_at(ex, "expected_error", expected_at, p)


def theory_ranges(ex, p) -> dict:
    """{output: (label, value)}: the expansion parameter of each leading-order output at ``p``."""
    return _hook_at(ex, "theory_range", range_at, p)


def _hook_at(ex, name: str, batch_of_one, p) -> dict:
    """The declared hook ``name`` at the one point ``p`` ({} where none is declared): a hook written on arrays
    read through ``batch_of_one``."""
    hook = getattr(ex, "_" + name)
    if hook is None:
        return {}
    return batch_of_one(hook, p) if name in ex._on_arrays else dict(hook(p))


def analytic_errors(ex, p) -> dict:
    """{output: absolute round-off error of its analytic value at ``p``, SI} where it is ill-conditioned."""
    return dict(ex._analytic_error(p)) if ex._analytic_error else {}


def approximations_at(ex, p) -> dict:
    """{output: [(value, text), ...]}: the approximations the statement asks for next to exact outputs."""
    return dict(ex._approximations(p)) if ex._approximations else {}


def _outside_reason(label: str | None, value: float | None, neglect: float | None) -> str | None:
    """Why a leading-order theory does not apply at a point (``mu/omega0 = 3.3``; the judge words it), or None
    when it does."""
    said = "" if label is None or value is None else f"{label} = {value:.2g}"
    if value is not None and not value < RANGE_LIMIT:
        return said or f"its expansion parameter reaches {RANGE_LIMIT:g}"
    if neglect is not None and not neglect < NEGLECT_LIMIT:
        return f"what it neglects is estimated at {neglect:.2g} relative" + (f" ({said})" if said else "")
    return None


def _rel_part(e):
    if isinstance(e, (tuple, list)):
        e = e[0]
    return None if e is None else float(e)



def _reasons(names, ranges: Mapping, rel: Mapping, n: int) -> dict:
    """{output: (outside mask, reasons)} over n variants, from each output's (label or labels, values) and the
    relative part of its neglect estimate (arrays; NaN: none)."""
    import numpy as np

    out = {}
    for name in names:
        label, vals = ranges.get(name, (None, None))
        r = np.broadcast_to(np.asarray(rel.get(name, np.nan), dtype=float), (n,))
        v = None if vals is None else np.broadcast_to(np.asarray(vals, dtype=float), (n,))
        reasons = [_outside_reason(label_at(label, k), None if v is None or v[k] != v[k] else float(v[k]),
                                   None if r[k] != r[k] else float(r[k])) or "" for k in range(n)]
        out[name] = (np.array([bool(x) for x in reasons], dtype=bool), reasons)
    return out


def theory_validity(ex, p, expected: dict | None = None) -> dict:
    """{output: None | reason} for every leading-order output: the reason why its theory does not apply at
    ``p`` (its expansion parameter reaches 1, or its neglect estimate 0.3 relative), None inside its range.
    ``expected``: ``expected_errors(p)`` where the caller has it already.  ``outside_ranges`` at one point."""
    lead = [o.name for o in ex.outputs if o.theory != "exact"]
    if not lead:
        return {}
    ranges = theory_ranges(ex, p)
    expected = expected_errors(ex, p) if expected is None else expected
    rel = {name: math.nan if _rel_part(expected.get(name)) is None else _rel_part(expected.get(name))
           for name in lead}
    return {name: reasons[0] or None for name, (_, reasons) in _reasons(lead, ranges, rel, 1).items()}


def outside_ranges(ex, P: Mapping, expected: dict) -> dict:
    """``theory_validity`` over arrays of variants: {output: (outside, reasons)}, a boolean array and a list of
    reasons ("" inside), from the exercise's ``theory_range`` on arrays and the batched ``expected``
    ({output: (rel, abs) arrays})."""
    import numpy as np

    route = ex.batched_route
    ranges = route.theory_range(P) if route is not None and route.theory_range else {}
    lead = [name for name in expected if next(o for o in ex.outputs if o.name == name).theory != "exact"]
    n = np.asarray(next(iter(expected.values()))[0]).size if expected else 0
    return _reasons(lead, ranges, {name: expected[name][0] for name in lead}, n)

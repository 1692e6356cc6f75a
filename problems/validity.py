"""Where a leading-order theory applies: its expansion parameter below ``RANGE_LIMIT`` and its neglect
estimate below ``NEGLECT_LIMIT`` relative, at one point or over a batch; outside, nothing is compared
(the judge words the reason)."""

from __future__ import annotations

from typing import Mapping

__all__ = ["RANGE_LIMIT", "NEGLECT_LIMIT", "theory_validity", "theory_validity_batch"]


# A leading-order theory is outside its range where its expansion parameter reaches RANGE_LIMIT or its
# neglect estimate (``expected_error``'s relative part) reaches NEGLECT_LIMIT: nothing is compared there
RANGE_LIMIT = 1.0
NEGLECT_LIMIT = 0.3


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



def theory_validity(ex, p, expected: dict | None = None) -> dict:
    """{output: None | reason} for every leading-order output: the reason why its theory does not apply at
    ``p`` (its expansion parameter reaches 1, or its neglect estimate 0.3 relative), None inside its range.
    ``expected``: ``expected_errors(p)`` where the caller has it already."""
    lead = [o.name for o in ex.outputs if o.theory != "exact"]
    if not lead:
        return {}
    ranges = ex.theory_ranges(p)
    expected = ex.expected_errors(p) if expected is None else expected
    out = {}
    for name in lead:
        label, value = ranges.get(name, (None, None))
        out[name] = _outside_reason(label, None if value is None else float(value), _rel_part(expected.get(name)))
    return out

def theory_validity_batch(ex, P: Mapping, expected: dict) -> dict:
    """The batched form: {output: (outside, reasons)}, a boolean array and a list of reasons ("" inside),
    from the batched route's ``theory_range`` and the batched ``expected`` ({output: (rel, abs) arrays})."""
    import numpy as np

    route = ex.batched_route
    ranges = route.theory_range(P) if route is not None and route.theory_range else {}
    out = {}
    for name, (rel, _abs) in expected.items():
        if next(o for o in ex.outputs if o.name == name).theory == "exact":
            continue
        label, vals = ranges.get(name, (None, None))
        rel = np.asarray(rel, dtype=float)
        vals = None if vals is None else np.broadcast_to(np.asarray(vals, dtype=float), rel.shape)
        reasons = [_outside_reason(label, None if vals is None or vals[k] != vals[k] else float(vals[k]),
                                   None if rel[k] != rel[k] else float(rel[k])) or "" for k in range(rel.size)]
        out[name] = (np.array([bool(r) for r in reasons], dtype=bool), reasons)
    return out

"""Extreme inputs: every positive open-ended parameter at 1e-200 and 1e+200 times its default.

A parameter is open-ended when its declared range is ``min >= 0`` with no ``max``: any positive value
is inside the bounds, so mech owes it an answer within its error bar, a one-line refusal (exit 2)
naming the scale that leaves the floating-point range, or a one-line loud failure (exit 1).  This
module says which points to try (``extreme_points``) and how a run's outcome is classified
(``classify``); scripts/extremes.py runs them through the command line and tests/test_extremes.py
pins the outcome.
"""

from __future__ import annotations

import json
import math

from mech.core.exits import EXIT_INTERNAL

__all__ = ["FACTORS", "open_ended", "extreme_points", "classify", "TIDY"]

FACTORS = (1e-200, 1e200)

# the outcomes the promise allows: an answer that agrees, a one-line refusal, a one-line loud failure
TIDY = ("agree", "refused", "loud")


def open_ended(param) -> bool:
    """A parameter any positive value of which is inside its bounds."""
    return (param.min is not None and param.min == 0.0 and param.max is None and param.default > 0
            and not getattr(param, "integer", False))


def _inside(param, x: float) -> bool:
    if param.min is not None and (x < param.min or (param.min_open and x == param.min)):
        return False
    return param.max is None or x < param.max or (x == param.max and not param.max_open)


def extreme_points(ex) -> list[tuple[str, dict]]:
    """(label, {name: value}) for each open-ended parameter of ``ex`` at each factor, one at a time, then all
    of them together at each factor (when there are two or more)."""
    names = [p for p in ex.params if open_ended(p)]
    points = []
    for p in names:
        for f in FACTORS:
            x = p.default * f
            if math.isfinite(x) and x > 0 and _inside(p, x):
                points.append((f"{p.name}*{f:.0e}", {p.name: x}))
    if len(names) >= 2:
        for f in FACTORS:
            given = {p.name: p.default * f for p in names}
            if all(math.isfinite(x) and x > 0 for x in given.values()):
                points.append((f"all*{f:.0e}", given))
    return points


def classify(code: int, out: str, err: str) -> tuple[str, str]:
    """The kind of one ``mech solve --json`` run and a short detail:

    agree     exit 0, every quantity agrees, nothing on stderr
    refused   exit 2 with exactly one line on stderr
    loud      exit 1 with the solvers' failures named in ``errors`` (or an unearned claim), nothing on stderr
    disagree  exit 1 where both methods answered and some quantity disagrees
    warning   anything written to stderr by a run that did not refuse (a numpy warning, say)
    internal  exit 3 (an internal error), a traceback, a refusal of more than one line, JSON not the contract's
    """
    err_lines = [line for line in err.splitlines() if line.strip()]
    if code == EXIT_INTERNAL or "Traceback" in err:
        return "internal", err_lines[-1] if err_lines else "internal error"
    if code == 2:
        if len(err_lines) != 1:
            return "internal", f"a refusal of {len(err_lines)} lines: {err[:300]!r}"
        return "refused", err_lines[0]
    if err_lines:
        return "warning", err_lines[0]
    try:
        d = json.loads(out, parse_constant=lambda c: (_ for _ in ()).throw(ValueError(c)))
    except ValueError:
        return "internal", f"exit {code}, output is not JSON: {out[:200]!r}"
    if code == 0 and d.get("agree") is True:
        return "agree", ""
    bad = [q for q in d.get("quantities", []) if q.get("agree") is False]
    errors = d.get("errors") or []
    if code == 1 and errors:
        return "loud", "; ".join(errors)
    if code == 1 and bad and all("unreliable" in (q.get("note") or "") or "no finite accuracy" in (q.get("note") or "")
                                 for q in bad):
        return "loud", "; ".join(f"{q['name']}: {q.get('note')}" for q in bad)
    if code == 1 and bad:
        return "disagree", "; ".join(f"{q['name']}: a={q.get('analytic')} n={q.get('numeric')} "
                                     f"rel={q.get('rel_err')} tol={q.get('tol')} {q.get('note') or ''}"
                                     for q in bad)
    return "internal", f"exit {code} with agree={d.get('agree')}"

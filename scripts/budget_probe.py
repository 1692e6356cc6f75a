#!/usr/bin/env python3
"""Does every long loop check the time budget?  The slowest in-bounds inputs of each exercise, and how a
solve stops under a small budget.

    python scripts/budget_probe.py [--budget S] [--draws N] [--seed S] [--span D] [--show K] [ID ...]
    python scripts/budget_probe.py --cli [--budgets 0.2,0.5,1] "ID k=v ..." ...

For each exercise (or the named ones) the numeric solver runs in this process, under
``budget.limit(--budget)``, at: the defaults, the hard cases, every parameter alone at
its lower and upper bound (an open end clipped to 1e-6..1e6 times the default, or
``--span`` decades),
every parameter at both ends at once (each corner of a box is too many: the all-low
and all-high ones), and ``--draws`` random draws over the bounds (the rule of
``/work/shared/tools/draws.py``; a draw that a joint limit refuses is drawn again).
An end that a joint limit refuses is skipped.

A solve that runs out of the budget raises ``budget.OutOfBudget``.  Its message says
where: a ``budget.check(where)`` in a loop, or ``stopped by the timer``, the backup
SIGALRM that fires 0.25 s after the deadline for a loop that never checks.  The
overshoot is the time past the deadline.  Each exercise prints one line: its slowest
input and time, how many runs the budget stopped, the worst overshoot, and any stop
by the timer (an unchecked loop, to fix).  Exit status 1 when any stop came from the
timer or overshot by 0.5 s or more.

``--cli`` times whole commands, ``MECH_BUDGET_S=B mech solve ID -p ...``, for the
cases given (the slow inputs the first mode found) at each budget B: the wall time,
the exit status, where the solve stopped, and the wall time past B less the start-up
of a quick solve (``mech solve 4.15``).  Exit status 1 when that is 0.5 s or more.
"""

from __future__ import annotations

import argparse
import math
import random
import sys
import time


SPAN = 1e6  # an open end of a parameter's range is taken this many times its default (--span)


def draw(p: dict, rng: random.Random) -> float:
    """One value over a parameter's bounds (its ``show --json`` entry): log-uniform where both ends are
    positive, an open end at SPAN times the default (a lower end of 0 at 1/SPAN times it), uniform otherwise."""
    lo, hi, d = p.get("min"), p.get("max"), p["default"]
    scale = abs(d) if d else 1.0
    lo = -scale * SPAN if lo is None else lo
    hi = scale * SPAN if hi is None else hi
    if lo == 0 and d > 0:
        lo = min(d / SPAN, hi)
    if lo > 0 and hi > lo:
        x = math.exp(rng.uniform(math.log(lo), math.log(hi)))
    else:
        x = rng.uniform(lo, hi)
    if (p.get("min_open") and x == p.get("min")) or (p.get("max_open") and x == p.get("max")):
        x = d
    return round(x) if p.get("integer") else x


def candidates(show: dict, ex, n_draws: int, rng: random.Random):
    """(label, given) pairs: defaults, hard cases, each parameter at each end, all at each end, draws."""
    params = show["params"]
    default = {p["name"]: p["default"] for p in params}
    yield "defaults", dict(default)
    for k, case in enumerate(ex.hard_cases):
        yield f"hard {k + 1}", {**default, **dict(case)}
    ends = {}
    for p in params:
        d, lo, hi = p["default"], p.get("min"), p.get("max")
        scale = abs(d) if d else 1.0
        lo = -scale * SPAN if lo is None else (max(lo, d / SPAN) if lo == 0 and d > 0 else lo)
        hi = scale * SPAN if hi is None else hi
        if p.get("min_open") and lo == p.get("min"):
            lo = lo + (abs(lo) * 1e-9 or 1e-12)
        if p.get("max_open") and hi == p.get("max"):
            hi = hi - (abs(hi) * 1e-9 or 1e-12)
        if p.get("integer"):
            lo, hi = math.ceil(lo), math.floor(hi)
        ends[p["name"]] = (lo, hi)
        yield f"{p['name']} low", {**default, p["name"]: lo}
        yield f"{p['name']} high", {**default, p["name"]: hi}
    yield "all low", {n: e[0] for n, e in ends.items()}
    yield "all high", {n: e[1] for n, e in ends.items()}
    for k in range(n_draws):
        yield f"draw {k + 1}", [{p["name"]: draw(p, rng) for p in params} for _ in range(REDRAWS)]


REDRAWS = 20  # a draw that a joint limit refuses is drawn again, up to this many times


def probe(ex_id: str, seconds: float, n_draws: int, seed: str):
    from mech.core import budget
    from mech.core.errors import BadInput
    from mech.problems import registry

    ex = registry.get(ex_id)
    if not ex.has_numeric:
        return None
    show = ex.as_json()
    rng = random.Random(f"{seed}-{ex_id}")
    runs = []
    for label, given in candidates(show, ex, n_draws, rng):
        p = None
        for g in given if isinstance(given, list) else [given]:
            try:
                p = ex.resolve(g)
                break
            except BadInput:
                continue
        if p is None:
            continue
        t0 = time.monotonic()
        stop = None
        try:
            with budget.limit(seconds, what=f"the numeric solve of {ex_id}"):
                ex.solve_numeric(p)
        except budget.OutOfBudget as exc:
            stop = str(exc)
        except Exception:
            pass  # a loud failure of the solver is not this probe's question
        wall = time.monotonic() - t0
        runs.append((wall, label, dict(p), stop))
    return runs


def cli(cases: list[str], budgets: list[float]) -> int:
    """``MECH_BUDGET_S=B mech solve ID -p k=v ...`` for every case ("ID k=v ...") and budget, as a user
    runs it: the wall time, the exit status, the numeric solve's own budget (what the command's
    start-up left of B) and the wall time past B."""
    import os
    import re
    import subprocess
    from pathlib import Path

    exe = Path(sys.executable).parent / "mech"
    start = []
    for _ in range(3):
        t0 = time.monotonic()
        subprocess.run([str(exe), "solve", "4.15"], capture_output=True)
        start.append(time.monotonic() - t0)
    startup = sorted(start)[1]
    print(f"start-up (mech solve 4.15, median of 3): {startup:.2f} s")
    worst = -math.inf
    for case in cases:
        ex_id, *pairs = case.split()
        args = [str(exe), "solve", ex_id] + [x for kv in pairs for x in ("-p", kv)]
        for b in budgets:
            t0 = time.monotonic()
            r = subprocess.run(args, capture_output=True, text=True, env={**os.environ, "MECH_BUDGET_S": str(b)})
            wall = time.monotonic() - t0
            out = r.stdout + r.stderr
            m = re.search(r"ran out of its ([0-9.e+-]+) s time budget(?: \(([^)]*)\))?", out)
            lines = [ln for ln in out.splitlines() if "time budget" in ln]
            trace = "Traceback" in out or "internal error" in out
            over = wall - b - startup
            worst = max(worst, over)
            stop = f"stopped: numeric budget {m.group(1)} s at {m.group(2)}" if m else "answered"
            print(f"{case:40} B={b:<5g} wall {wall:5.2f} s, exit {r.returncode}, {stop}; wall - B = "
                  f"{wall - b:+.2f} s, - start-up = {over:+.2f} s; {len(lines)} budget line(s)"
                  + ("; TRACEBACK" if trace else ""), flush=True)
    print(f"worst wall - budget - start-up: {worst:+.2f} s")
    return 0 if worst < 0.5 else 1


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--budget", type=float, default=0.5)
    ap.add_argument("--draws", type=int, default=20)
    ap.add_argument("--seed", default="2611")
    ap.add_argument("--span", type=float, default=6.0,
                    help="decades beyond the default that an open end of a range reaches [6]")
    ap.add_argument("--show", type=int, default=1, help="the K slowest inputs of each exercise [1]")
    ap.add_argument("--cli", action="store_true",
                    help="time whole commands instead: each argument is a case \"ID k=v ...\", run at --budgets")
    ap.add_argument("--budgets", default="0.2,0.5,1", help="MECH_BUDGET_S values for --cli [0.2,0.5,1]")
    ap.add_argument("ids", nargs="*")
    a = ap.parse_args()
    if a.cli:
        return cli(a.ids, [float(x) for x in a.budgets.split(",")])
    global SPAN
    SPAN = 10.0 ** a.span
    from mech.problems import registry

    # scipy's modules load outside any budget: an import cannot check it (a command pays it once, inside its
    # budget, and the backup timer covers it), and it is not a loop of a solver
    import scipy.integrate  # noqa: F401
    import scipy.linalg  # noqa: F401
    import scipy.optimize  # noqa: F401
    import scipy.special  # noqa: F401

    ids = a.ids or list(registry.all_exercises())
    bad = False
    worst = (0.0, "", "", {})
    for ex_id in ids:
        runs = probe(ex_id, a.budget, a.draws, a.seed)
        if not runs:
            continue
        runs.sort(key=lambda r: -r[0])
        stops = [r for r in runs if r[3]]
        over = max((r[0] - a.budget for r in stops), default=0.0)
        timer = [r for r in stops if "stopped by the timer" in r[3]]
        if timer or over >= 0.5:
            bad = True
        for wall, label, p, stop in runs[: a.show]:
            given = " ".join(f"{n}={v:.6g}" for n, v in p.items())
            print(f"{ex_id:5} slowest {wall:6.3f} s ({label}: {given}); {len(stops)}/{len(runs)} stopped, "
                  f"overshoot {over:+.3f} s" + (f"; TIMER x{len(timer)}: {timer[0][1]}" if timer else ""),
                  flush=True)
        for wall, label, p, stop in stops:
            where = stop.rsplit("(", 1)[-1].rstrip(")") if "(" in stop else "?"
            print(f"      stopped {wall:6.3f} s at {where} ({label})", flush=True)
        if runs[0][0] > worst[0]:
            worst = (runs[0][0], ex_id, runs[0][1], runs[0][2])
    print(f"slowest of all: {worst[1]} {worst[2]} {worst[0]:.3f} s under a {a.budget:g} s budget")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

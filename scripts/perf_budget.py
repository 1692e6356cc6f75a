#!/usr/bin/env python3
"""The performance budget of mech, measured as users meet it: wall time of whole commands.

    python scripts/perf_budget.py [--repeats N] [--hard-repeats N] [--skip-hard] [--markdown]
    python scripts/perf_budget.py --overhead [ID ...]

``--overhead`` instead profiles each exercise's numeric solver in-process
(cProfile, one run after a warm-up) and splits its time between scipy's
solve_ivp machinery (scipy/integrate/_ivp: step control, stage sums, event
search), numpy calls, the exercise's own code (right-hand sides, events) and
the rest: the per-step overhead of solve_ivp for small systems (scipy#8257)
shows as a large first share.  cProfile inflates call-heavy code, so read
the shares, not the absolute times.

Every command runs as a fresh process (the console script next to this
Python), ``--repeats`` times (default 5 for start-up commands, 3 for solve and
check), and the median is compared with its budget:

    mech --help, mech list        <= 0.3 s
    mech solve ID (every ID)      <= 1 s    (the slowest exercise is shown)
    mech check                    <= 20 s
    mech check --hard             <= 120 s

The budgets are for a 2-core machine; the 1-minute load average before and
after is printed, because a loaded machine inflates every figure.  This is a
measurement, not a test: timing in CI is too noisy to assert on, so nothing
here runs under pytest.  Exit status 1 when a median exceeds its budget.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

BUDGET = {"help": 0.3, "list": 0.3, "solve": 1.0, "check": 20.0, "check --hard": 120.0}


def mech_exe() -> list[str]:
    exe = Path(sys.executable).parent / "mech"
    return [str(exe)] if exe.exists() else [sys.executable, "-m", "mech.cli.main"]


TIMEOUT_FACTOR = 10.0  # a run longer than 10x its budget is stopped and counts as infinitely slow


def timed(args: list[str], repeats: int, budget: float) -> tuple[float, float, float, int]:
    """Median, min, max wall seconds of ``mech ARGS`` and the last exit status (-9: stopped, too slow).

    The wait is a blocking waitpid, with the time limit enforced by a timer that kills the process:
    ``subprocess.run(timeout=...)`` polls with sleeps of up to 50 ms, which rounded every figure up
    to the next multiple of about 50 ms (0.27 s and 0.32 s for the same `mech list`).
    """
    import threading

    times, code = [], 0
    for _ in range(repeats):
        t0 = time.perf_counter()
        proc = subprocess.Popen(mech_exe() + args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        timer = threading.Timer(TIMEOUT_FACTOR * budget, proc.kill)
        timer.start()
        try:
            code = proc.wait()
        finally:
            timer.cancel()
        elapsed = time.perf_counter() - t0
        if code == -9:
            times.append(float("inf"))
            break  # a hang does not need repeating
        times.append(elapsed)
    return statistics.median(times), min(times), max(times), code


def exercise_ids() -> list[str]:
    out = subprocess.run(mech_exe() + ["list", "--json"], capture_output=True, text=True, check=True).stdout
    import json

    return [e["id"] for e in json.loads(out)]


def overhead(ids: list[str]) -> int:
    import cProfile
    import pstats
    import warnings

    import scipy.integrate  # noqa: F401

    from mech.problems import registry

    exercises = registry.all_exercises()
    print(f"{'id':<6} {'solve ms':>9} {'nfev':>7} {'us/eval':>8} {'solve_ivp':>9} {'numpy':>6} {'exercise':>8} {'other':>6}")
    for ex_id, ex in exercises.items():
        if ids and ex_id not in ids:
            continue
        p = ex.resolve({})
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ex.solve_numeric(p)
            t0 = time.perf_counter()
            _, run = ex.solve_numeric(p)
            wall = time.perf_counter() - t0
            prof = cProfile.Profile()
            prof.enable()
            ex.solve_numeric(p)
            prof.disable()
        shares = {"ivp": 0.0, "numpy": 0.0, "mech": 0.0, "other": 0.0}
        for (fname, _, _), (_, _, tt, _, _) in pstats.Stats(prof).stats.items():
            if "scipy/integrate/_ivp" in fname:
                shares["ivp"] += tt
            elif "numpy" in fname or fname == "~":
                shares["numpy"] += tt
            elif "/problems/" in fname or "/solvers/" in fname:
                shares["mech"] += tt
            else:
                shares["other"] += tt
        total = sum(shares.values()) or 1.0
        per = f"{wall / run.nfev * 1e6:8.1f}" if run.nfev else f"{'—':>8}"
        print(f"{ex_id:<6} {wall * 1e3:9.1f} {run.nfev:7d} {per} {shares['ivp'] / total:9.0%} "
              f"{shares['numpy'] / total:6.0%} {shares['mech'] / total:8.0%} {shares['other'] / total:6.0%}",
              flush=True)
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=3, help="runs per solve/check figure (median) [3]")
    ap.add_argument("--startup-repeats", type=int, default=5, help="runs of --help and list [5]")
    ap.add_argument("--hard-repeats", type=int, default=3, help="runs of check --hard [3]")
    ap.add_argument("--skip-hard", action="store_true", help="leave out check --hard")
    ap.add_argument("--markdown", action="store_true", help="also print the table as Markdown (for the README)")
    ap.add_argument("--overhead", nargs="*", metavar="ID", help="profile the numeric solvers instead (see above)")
    a = ap.parse_args(argv)
    if a.overhead is not None:
        return overhead(a.overhead)

    load0 = os.getloadavg()[0]
    rows = []  # (command, median, min, max, budget, ok, exit code)

    def add(label, args, repeats, budget):
        med, lo, hi, code = timed(args, repeats, budget)
        rows.append((label, med, lo, hi, budget, med <= budget, code, repeats))
        print(f"{label:<34} median {med:8.3f} s  [{lo:.3f}-{hi:.3f}] x{repeats}  budget {budget:g} s  "
              f"{'ok' if med <= budget else 'OVER'}  (exit {code})", flush=True)

    add("mech --help", ["--help"], a.startup_repeats, BUDGET["help"])
    add("mech list", ["list"], a.startup_repeats, BUDGET["list"])
    solve = []
    for ex_id in exercise_ids():
        med, lo, hi, code = timed(["solve", ex_id], a.repeats, BUDGET["solve"])
        solve.append((med, lo, hi, ex_id, code))
        print(f"  mech solve {ex_id:<6} median {med:6.3f} s  [{lo:.3f}-{hi:.3f}]  (exit {code})", flush=True)
    worst = max(solve)
    over = [s for s in solve if s[0] > BUDGET["solve"]]
    rows.append((f"mech solve ID, slowest ({worst[3]})", worst[0], worst[1], worst[2], BUDGET["solve"],
                 not over, worst[4], a.repeats))
    med_all = statistics.median(s[0] for s in solve)
    rows.append(("mech solve ID, median over IDs", med_all, None, None, BUDGET["solve"], med_all <= BUDGET["solve"],
                 0, a.repeats))
    add("mech check", ["check"], a.repeats, BUDGET["check"])
    if not a.skip_hard:
        add("mech check --hard", ["check", "--hard"], a.hard_repeats, BUDGET["check --hard"])
    load1 = os.getloadavg()[0]

    print()
    print(f"machine: {os.cpu_count()} cpus, 1-min load {load0:.1f} before, {load1:.1f} after; python {sys.version.split()[0]}")
    if over:
        print("over budget: " + ", ".join(f"solve {s[3]} {s[0]:.2f} s" for s in over))
    if a.markdown:
        print()
        print("| command | median wall [s] | range [s] | runs | budget [s] | within |")
        print("|---|---|---|---|---|---|")
        for label, med, lo, hi, budget, ok, code, n in rows:
            rng = f"{lo:.3f}–{hi:.3f}" if lo is not None else "—"
            print(f"| `{label}` | {med:.3f} | {rng} | {n} | {budget:g} | {'yes' if ok else 'no'} |")
    return 0 if all(r[5] for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())

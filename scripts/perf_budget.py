#!/usr/bin/env python3
"""The performance budget of mech, measured as users meet it: wall time of whole commands.

    python scripts/perf_budget.py [--repeats N] [--hard-repeats N] [--skip-hard] [--markdown]
                                  [--before OTHER/.venv/bin/mech] [--no-bytecode-cache]
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


def mech_exe(path: str | None = None) -> list[str]:
    """The console script to time: ``path`` (another checkout's ``.venv/bin/mech``) or the one beside this
    Python."""
    if path:
        return [str(Path(path))]
    exe = Path(sys.executable).parent / "mech"
    return [str(exe)] if exe.exists() else [sys.executable, "-m", "mech.cli.main"]


TIMEOUT_FACTOR = 10.0  # a run longer than 10x its budget is stopped and counts as infinitely slow


def environment(bytecode: bool) -> dict:
    """The environment the commands run in.  ``bytecode``: compiled modules are cached (in a directory of
    their own, as an installed package keeps its .pyc files); without it every process compiles mech's
    sources again, as on a machine that sets PYTHONDONTWRITEBYTECODE (this one does: about 50 ms a
    process for mech's own modules)."""
    env = dict(os.environ)
    if bytecode:
        env.pop("PYTHONDONTWRITEBYTECODE", None)
        env["PYTHONPYCACHEPREFIX"] = env.get("MECH_PERF_PYCACHE") or os.path.join(
            os.environ.get("TMPDIR", "/tmp"), f"mech-perf-pycache-{os.getuid()}")
    else:
        env["PYTHONDONTWRITEBYTECODE"] = "1"
        env.pop("PYTHONPYCACHEPREFIX", None)
    return env


def run_once(exe: list[str], args: list[str], budget: float, env: dict) -> tuple[float, int]:
    """Wall seconds of one ``mech ARGS`` and its exit status (-9: stopped, too slow).

    The wait is a blocking waitpid, with the time limit enforced by a timer that kills the process:
    ``subprocess.run(timeout=...)`` polls with sleeps of up to 50 ms, which rounded every figure up
    to the next multiple of about 50 ms (0.27 s and 0.32 s for the same `mech list`).
    """
    import threading

    t0 = time.perf_counter()
    proc = subprocess.Popen(exe + args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    timer = threading.Timer(TIMEOUT_FACTOR * budget, proc.kill)
    timer.start()
    try:
        code = proc.wait()
    finally:
        timer.cancel()
    elapsed = time.perf_counter() - t0
    return (float("inf") if code == -9 else elapsed), code


def timed(exes: list[list[str]], args: list[str], repeats: int, budget: float, env: dict) -> list[tuple]:
    """Per executable: median, min, max wall seconds of ``mech ARGS`` and the last exit status.

    With two executables (before and after) the runs alternate, so that a change in the machine's load
    during the measurement moves both alike; one unmeasured run of each first fills the bytecode cache."""
    for exe in exes:
        run_once(exe, args, budget, env)
    times: list[list[float]] = [[] for _ in exes]
    codes = [0] * len(exes)
    for _ in range(repeats):
        for k, exe in enumerate(exes):
            if times[k] and times[k][-1] == float("inf"):
                continue  # a hang does not need repeating
            t, codes[k] = run_once(exe, args, budget, env)
            times[k].append(t)
    return [(statistics.median(t), min(t), max(t), c) for t, c in zip(times, codes)]


def exercise_ids(exe: list[str]) -> list[str]:
    out = subprocess.run(exe + ["list", "--json"], capture_output=True, text=True, check=True).stdout
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
    ap.add_argument("--before", metavar="MECH",
                    help="another checkout's console script (e.g. ../base/.venv/bin/mech): time it beside this "
                         "one, runs alternating, and print both medians and their ratio")
    ap.add_argument("--no-bytecode-cache", action="store_true",
                    help="compile mech's sources in every process (PYTHONDONTWRITEBYTECODE=1) instead of caching "
                         "them as an installed package does")
    ap.add_argument("--markdown", action="store_true", help="also print the table as Markdown (docs/performance.md)")
    ap.add_argument("--overhead", nargs="*", metavar="ID", help="profile the numeric solvers instead (see above)")
    a = ap.parse_args(argv)
    if a.overhead is not None:
        return overhead(a.overhead)

    env = environment(bytecode=not a.no_bytecode_cache)
    now = mech_exe()
    exes = [mech_exe(a.before), now] if a.before else [now]
    load0 = os.getloadavg()[0]
    rows = []  # (command, [(median, min, max, code) per exe], budget, repeats)

    def show(label, res, budget, repeats):
        med = res[-1][0]
        before = f"  before {res[0][0]:7.3f} s  ratio {med / res[0][0]:5.2f}" if len(res) > 1 else ""
        rng = f"[{res[-1][1]:.3f}-{res[-1][2]:.3f}]" if res[-1][1] is not None else "(median of medians)"
        print(f"{label:<34} median {med:8.3f} s  {rng} x{repeats}{before}  "
              f"budget {budget:g} s  {'ok' if med <= budget else 'OVER'}  (exit {res[-1][3]})", flush=True)

    def add(label, args, repeats, budget):
        res = timed(exes, args, repeats, budget, env)
        rows.append((label, res, budget, repeats))
        show(label, res, budget, repeats)

    add("mech --help", ["--help"], a.startup_repeats, BUDGET["help"])
    add("mech list", ["list"], a.startup_repeats, BUDGET["list"])
    ids = exercise_ids(now)
    if a.before:
        ids = [i for i in ids if i in set(exercise_ids(exes[0]))]
    solve = []
    for ex_id in ids:
        res = timed(exes, ["solve", ex_id], a.repeats, BUDGET["solve"], env)
        solve.append((ex_id, res))
        show(f"  mech solve {ex_id}", res, BUDGET["solve"], a.repeats)
    worst_id, worst = max(solve, key=lambda s: s[1][-1][0])
    rows.append((f"mech solve ID, slowest ({worst_id})", worst, BUDGET["solve"], a.repeats))
    medians = [statistics.median(s[1][k][0] for s in solve) for k in range(len(exes))]
    rows.append((f"mech solve ID, median over the {len(ids)} exercises", [(m, None, None, 0) for m in medians],
                 BUDGET["solve"], a.repeats))
    show(rows[-1][0], rows[-1][1], BUDGET["solve"], a.repeats)
    over = [(i, r[-1][0]) for i, r in solve if r[-1][0] > BUDGET["solve"]]
    add("mech check", ["check"], a.repeats, BUDGET["check"])
    if not a.skip_hard:
        add("mech check --hard", ["check", "--hard"], a.hard_repeats, BUDGET["check --hard"])
    load1 = os.getloadavg()[0]

    print()
    print(f"machine: {os.cpu_count()} cpus, 1-min load {load0:.1f} before, {load1:.1f} after; python "
          f"{sys.version.split()[0]}; bytecode {'compiled in every process' if a.no_bytecode_cache else 'cached'}")
    if over:
        print("over budget: " + ", ".join(f"solve {i} {t:.2f} s" for i, t in over))
    ok = all(r[1][-1][0] <= r[2] for r in rows)
    if a.markdown:
        print()
        if a.before:
            print("| command | before [s] | now: median wall [s] | now/before | range [s] | runs | budget [s] | within |")
            print("|---|---|---|---|---|---|---|---|")
        else:
            print("| command | median wall [s] | range [s] | runs | budget [s] | within |")
            print("|---|---|---|---|---|---|")
        for label, res, budget, n in rows:
            med, lo, hi, _ = res[-1]
            rng = f"{lo:.3f}–{hi:.3f}" if lo is not None else "—"
            within = "yes" if med <= budget else "no"
            if a.before:
                print(f"| `{label}` | {res[0][0]:.3f} | {med:.3f} | {med / res[0][0]:.2f} | {rng} | {n} | {budget:g} | {within} |")
            else:
                print(f"| `{label}` | {med:.3f} | {rng} | {n} | {budget:g} | {within} |")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())

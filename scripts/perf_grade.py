#!/usr/bin/env python3
"""What grading a class costs when every student has their own parameters: wall time of whole commands.

    python scripts/perf_grade.py [--students 30,300] [--repeats N] [--jobs 1,0] [--shared] [--exercises IDS]
                                 [--before OTHER/.venv/bin/mech] [--markdown]

A class file is written for each class size: every student answers one formula in each of five exercises
(4.15, 4.10, 5.4, 4.23, 5.11: the last two the slowest to cross-check), at their own parameters drawn
across the declared ranges (``formulas.draw``, seeded, so the file is the same every time).  Each file is
graded by ``mech grade FILE`` in a fresh process, ``--repeats`` times; the median wall time is reported,
for each ``--jobs`` value side by side (0: the default, one worker per core).  ``--shared`` also grades
the same answers with every student at one shared point (references solved once).  ``--before`` also
grades each file with another checkout's ``mech`` (its default options), just before this one's; the
CPU time (user + system) moves less with the machine's load than the wall time does.

Budgets (issue 32): 300 students x 5 formulas in at most 20 s, 30 in at most 3 s, on a 2-core machine.
The 1-minute load average before and after each measurement is printed: this machine is shared, and a
load above the cores inflates every figure.  A measurement, not a test; exit status 1 when a default-jobs
median exceeds its budget.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

BUDGETS = {30: 3.0, 300: 20.0}

# (exercise, output, a right formula for it, written from the exercise's statement)
CASES = [
    ("4.15", "theta_c", "asin(2/3*sin(theta0))"),
    ("4.10", "Omega", "sqrt(M*g*l/(I+M*l^2))"),
    ("5.4", "lambda_slow", "omega0/(zeta + sqrt(zeta^2-1))"),
    ("4.23", "Omega", "sqrt(4*g*tan(theta)/(6*R-5*r*sin(theta)))"),
    ("5.11", "mu_th", "4/omega0*sqrt(delta^2+(omega-omega0)^2)"),
]
# more exercises for ``--exercises`` (issue 41's slow five: 5.8, 5.10, 5.9, 4.24, 5.5), each answered by the
# leading-order or exact result the statement asks for
MORE = [
    ("5.8", "A_max", "f0/(2*omega0*delta)"),
    ("5.10", "width", "f0*sqrt(beta)/(2*omega0)"),
    ("5.9", "A", "2/sqrt(beta)"),
    ("4.24", "t_down", "pi*I3*omega_rot/(2*l*F)"),
    ("5.5", "Q", "omega0/(2*delta)"),
]


def class_file(n: int, shared: bool, folder: Path, cases=None) -> Path:
    from mech.problems import registry
    from mech.students.points import draw

    rows: list[tuple[int, int, str]] = []
    for k, (ex_id, out, formula) in enumerate(cases or CASES):
        ex = registry.get(ex_id)
        pts = []
        for p in draw(ex, 2 * n + 8, 7):  # those grade accepts (a few drawn points have an answer
            try:                          # beyond the floating-point range: an invalid entry)
                ex.resolve(p)
            except Exception:
                continue
            pts.append(p)
        pts = pts[:1] if shared else pts[:n]
        for i in range(n):
            p = pts[0 if shared else i]
            params = ", ".join(f'{name} = "{value!r}"' for name, value in p.items())
            rows.append((i, k, f'[[answer]]\nstudent = "s{i + 1}"\nexercise = "{ex_id}"\nparams = {{ {params} }}\n'
                               f'expect = {{ {out} = "{formula}" }}\n'))
    rows.sort()
    path = folder / f"class-{n}{'-shared' if shared else ''}.toml"
    path.write_text("\n".join(r for _, _, r in rows), encoding="utf-8")
    return path


def mech_exe() -> list[str]:
    exe = Path(sys.executable).parent / "mech"
    return [str(exe)] if exe.exists() else [sys.executable, "-m", "mech.cli.main"]


def load() -> float:
    return os.getloadavg()[0]


def timed(args: list[str], repeats: int, exe: list[str] | None = None) -> tuple[float, float, float, int, float, float]:
    """Median wall time, median CPU (user + system of the children), median time grade reported, the exit
    status, and the load average before and after."""
    walls, cpus, said, rc = [], [], [], 0
    before = load()
    for _ in range(repeats):
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        r = subprocess.run((exe or mech_exe()) + args, capture_output=True, text=True, env={**os.environ, "COLUMNS": "200"})
        walls.append(time.perf_counter() - t0)
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpus.append(r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime)
        rc = r.returncode
        tail = r.stdout.strip().splitlines()[-1] if r.stdout.strip() else ""
        said.append(float(tail.rsplit(" in ", 1)[1].split()[0]) if " in " in tail else float("nan"))
    return statistics.median(walls), statistics.median(cpus), statistics.median(said), rc, before, load()


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--students", default="30,300")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--jobs", default="1,0", help="comma-separated -j values; 0 is the default (one per core)")
    ap.add_argument("--shared", action="store_true", help="also grade at one shared point")
    ap.add_argument("--before", metavar="MECH", help="another checkout's mech executable, measured beside this one")
    ap.add_argument("--exercises", help="comma-separated ids, one formula each (default: "
                    + ",".join(c[0] for c in CASES) + "; also " + ",".join(c[0] for c in MORE) + ")")
    ap.add_argument("--markdown", action="store_true")
    a = ap.parse_args()
    known = {c[0]: c for c in CASES + MORE}
    if a.exercises:
        unknown = [i for i in a.exercises.split(",") if i not in known]
        if unknown:
            ap.error(f"--exercises: no case for {', '.join(unknown)} (known: {', '.join(known)})")
    cases = [known[i] for i in a.exercises.split(",")] if a.exercises else CASES
    sizes = [int(s) for s in a.students.split(",")]
    jobs = [int(j) for j in a.jobs.split(",")]
    print(f"cores: {len(os.sched_getaffinity(0))}, load average now: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    rows = []
    failed = False
    with tempfile.TemporaryDirectory() as tmp:
        for n in sizes:
            for shared in ([False, True] if a.shared else [False]):
                path = class_file(n, shared, Path(tmp), cases)
                cells = []
                if a.before:
                    wall, cpu, said, rc, l0, l1 = timed(["grade", str(path)], a.repeats, [a.before])
                    cells.append(("before", wall, cpu, said, rc, l0, l1))
                    print(f"{n:4d} students x {len(cases)} {'shared' if shared else 'own   '} before    : "
                          f"median wall {wall:6.1f} s, CPU {cpu:6.1f} s, grade said {said:6.1f} s, exit {rc}, "
                          f"load {l0:.1f} -> {l1:.1f}", flush=True)
                for j in jobs:
                    args = ["grade", str(path)] + ([] if j == 0 else ["-j", str(j)])
                    wall, cpu, said, rc, l0, l1 = timed(args, a.repeats)
                    cells.append((j, wall, cpu, said, rc, l0, l1))
                    budget = BUDGETS.get(n) if not shared and j == 0 else None
                    if budget is not None and wall > budget:
                        failed = True
                    print(f"{n:4d} students x {len(cases)} {'shared' if shared else 'own   '} -j {j or 'default'}: "
                          f"median wall {wall:6.1f} s, CPU {cpu:6.1f} s, grade said {said:6.1f} s, exit {rc}, "
                          f"load {l0:.1f} -> {l1:.1f}" + (f"  (budget {budget:g} s)" if budget else ""), flush=True)
                rows.append((n, shared, cells))
    if a.markdown:
        cols = (["before"] if a.before else []) + [f"-j {j or 'default'}" for j in jobs]
        head = " | ".join(f"{c} wall / CPU" for c in cols)
        print(f"\n| class | params | {head} | load (1 min) |")
        print("|---|---|" + "---|" * len(cols) + "---|")
        for n, shared, cells in rows:
            vals = " | ".join(f"{w:.1f} s / {c:.1f} s" for _, w, c, *_ in cells)
            loads = ", ".join(f"{l0:.1f}-{l1:.1f}" for *_, l0, l1 in cells)
            print(f"| {n} x {len(cases)} | {'shared' if shared else 'own'} | {vals} | {loads} |")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

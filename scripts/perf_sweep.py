#!/usr/bin/env python3
"""What a sweep point costs: ``mech sweep ID --NAME LO:HI:N`` over the whole command, per integrating exercise.

    python scripts/perf_sweep.py [IDS ...] [--points 200] [--repeats 1] [--before OTHER/.venv/bin/mech]
                                 [--markdown]

For each exercise (default: every one whose numeric route integrates equations of motion) the swept
parameter is its first one that is not a fixed constant, over its typical range (``Param.typical``: the
range ``mech assign`` draws from); the others stay at their defaults.  The command runs in a fresh process:
its wall time and its CPU time (user + system of the child and of its pool's workers, which ``wait``
reaps) are divided by the points, the start-up included ("over the whole command").  ``--before``
measures another checkout's ``mech`` the same way just before this one's, side by side; the exit status
of each run is shown (0: every point agrees; 1: a point failed or was refused).  A measurement, not a test.
"""

from __future__ import annotations

import argparse
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path


def axis(ex) -> tuple[str, float, float] | None:
    """(name, lo, hi) of the swept parameter: the first not fixed whose typical range is not one value."""
    for p in ex.params:
        if p.fixed:
            continue
        lo, hi = p.typical
        if hi > lo:
            return p.name, lo, hi
    return None


def run(mech: str, ex_id: str, name: str, lo: float, hi: float, n: int) -> tuple[float, float, int]:
    """(wall s, CPU s, exit status) of one sweep."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.run([mech, "sweep", ex_id, f"--{name}", f"{lo!r}:{hi!r}:{n}", "--csv"],
                          stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, proc.returncode


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("ids", nargs="*")
    ap.add_argument("--points", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--before", help="another checkout's mech executable, measured side by side")
    ap.add_argument("--markdown", action="store_true")
    args = ap.parse_args()
    from mech.problems import registry

    ids = args.ids or [e.id for e in registry.index() if e.integrates]
    here = str(Path(sys.executable).with_name("mech"))
    mechs = ([("before", args.before)] if args.before else []) + [("now", here)]
    head = ["exercise", "swept"] + [f"{label} {what}" for label, _ in mechs for what in ("wall", "CPU", "exit")]
    rows = []
    for ex_id in ids:
        got = axis(registry.get(ex_id))
        if got is None:
            continue
        name, lo, hi = got
        row = [ex_id, f"{name} {lo:.3g}:{hi:.3g}"]
        for _, mech in mechs:
            runs = [run(mech, ex_id, name, lo, hi, args.points) for _ in range(args.repeats)]
            wall = statistics.median(r[0] for r in runs) / args.points
            cpu = statistics.median(r[1] for r in runs) / args.points
            row += [f"{1000 * wall:.1f} ms", f"{1000 * cpu:.1f} ms", str(max(r[2] for r in runs))]
        rows.append(row)
        print(" | ".join(row), file=sys.stderr, flush=True)
    from perf_assign import table  # beside this script

    table(head, rows, args.markdown, width=16)
    return 0


if __name__ == "__main__":
    sys.exit(main())

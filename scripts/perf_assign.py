#!/usr/bin/env python3
"""What one more variant of an exercise costs: CPU seconds of ``mech assign`` a variant, per exercise.

    python scripts/perf_assign.py [IDS ...] [--n 20] [--seed 5] [--repeats 1]
                                  [--before OTHER/.venv/bin/mech] [--markdown]

``mech assign ID --n N --seed S -j 1`` draws, solves and verifies N variants (each cross-checked by both
methods, with the rerun at rtol/10).  Its CPU time (user + system of the child, which does not move with
the machine's load as the wall time does) is measured at ``--n 1`` and at ``--n N``; the cost of a
variant is the difference over N - 1, so the start-up (imports, the first solve's set-up) is taken off.
``--before`` measures another checkout's ``mech`` the same way, just before this one's, side by side.
Without IDS: every registered exercise.  A measurement, not a test.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path


def cpu_of(cmd: list[str]) -> tuple[float, int]:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, proc.returncode


def per_variant(mech: str, ex_id: str, n: int, seed: int, repeats: int) -> tuple[float | None, str]:
    """CPU seconds a variant (the median over ``repeats``), and a note when a run failed."""
    costs = []
    for _ in range(repeats):
        got = {}
        for k in (1, n):
            with tempfile.TemporaryDirectory() as out:
                cmd = [mech, "assign", ex_id, "--n", str(k), "--seed", str(seed), "-j", "1",
                       "--out", os.path.join(out, "a")]
                got[k], code = cpu_of(cmd)
                if code != 0:
                    return None, f"exit {code}"
        costs.append((got[n] - got[1]) / (n - 1))
    return statistics.median(costs), ""


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("ids", nargs="*")
    ap.add_argument("--n", type=int, default=20)
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--before", help="another checkout's mech, measured just before this one's")
    ap.add_argument("--markdown", action="store_true")
    args = ap.parse_args()
    if args.n < 2:
        ap.error("--n: at least 2 (the cost of a variant is a difference)")
    here = str(Path(sys.executable).with_name("mech"))
    ids = args.ids
    if not ids:
        from mech.problems import registry

        ids = [e.id for e in registry.index()]
    rows = []
    for ex_id in ids:
        row = [ex_id]
        for mech in ([args.before] if args.before else []) + [here]:
            cost, note = per_variant(mech, ex_id, args.n, args.seed, args.repeats)
            row.append(note if cost is None else f"{1000 * cost:.0f} ms")
        if args.before and row[1].endswith(" ms") and row[2].endswith(" ms"):
            b, a = float(row[1].split()[0]), float(row[2].split()[0])
            row.append(f"{a / b:.2f}" if b > 0 else "")
        rows.append(row)
        print(" | ".join(row), file=sys.stderr, flush=True)
    head = ["exercise"] + (["before", "now", "ratio"] if args.before else ["CPU a variant"])
    table(head, rows, args.markdown)
    return 0


def table(head: list[str], rows: list[list[str]], markdown: bool, width: int = 14) -> None:
    """The rows under their head: a Markdown table, or right-aligned columns of ``width``."""
    if markdown:
        print("| " + " | ".join(head) + " |")
        print("|" + "---|" * len(head))
        for r in rows:
            print("| " + " | ".join(r) + " |")
    else:
        for r in [head] + rows:
            print("  ".join(f"{c:>{width}}" for c in r))


if __name__ == "__main__":
    sys.exit(main())

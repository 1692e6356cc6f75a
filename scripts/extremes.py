#!/usr/bin/env python3
"""Every exercise at extreme inputs, run as a user would: each positive open-ended parameter at 1e-200 and
1e+200 times its default, one at a time, then all together (mech.studies.extremes).

usage: python scripts/extremes.py [--timeout T] [--jobs J] [--all] [ID ...]

Each point runs as ``mech solve ID --json -p NAME=VALUE ...`` in a fresh process and is classified
(agree, refused, loud, disagree, warning, internal, timeout; see ``extremes.classify``).  Prints the runs
that are not tidy (with --all, every run), then a last line
  extremes: A agree, R refused, L loud, D disagree, W warning, I internal, T timeout of N runs
Exit 0 when every run is agree, refused or loud.
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import os
import shutil
import subprocess
import sys
import time


def _mech_command() -> list[str]:
    here = os.path.dirname(os.path.abspath(sys.executable))
    local = os.path.join(here, "mech")
    return [local] if os.path.exists(local) else [shutil.which("mech") or "mech"]


def run_one(ex_id: str, label: str, given: dict, timeout: float) -> dict:
    from mech.studies.extremes import classify

    cmd = _mech_command() + ["solve", ex_id, "--json"]
    for name, value in given.items():
        cmd += ["-p", f"{name}={value!r}"]
    t0 = time.monotonic()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        out, err = proc.communicate(timeout=timeout)
        kind, detail = classify(proc.returncode, out, err)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        kind, detail = "timeout", f"no answer within {timeout:g} s"
    return {"id": ex_id, "label": label, "kind": kind, "detail": detail, "seconds": time.monotonic() - t0}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--timeout", type=float, default=20.0, help="seconds before a run is killed [20]")
    ap.add_argument("--jobs", type=int, default=1, help="runs at once [1]")
    ap.add_argument("--all", action="store_true", help="print every run, not only the untidy ones")
    ap.add_argument("ids", nargs="*")
    args = ap.parse_args(argv)

    from mech.problems import registry
    from mech.studies.extremes import TIDY, extreme_points

    exercises = [ex for i, ex in registry.all_exercises().items()
                 if not args.ids or any(i == p or i.startswith(p + ".") or i == p for p in args.ids)]
    jobs = [(ex.id, label, given) for ex in exercises for label, given in extreme_points(ex)]
    results = []
    with cf.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        for res in pool.map(lambda job: run_one(*job, args.timeout), jobs):
            results.append(res)
            if args.all or res["kind"] not in TIDY:
                print(f"{res['id']} {res['label']} {res['kind']} ({res['seconds']:.1f} s): {res['detail'][:300]}",
                      flush=True)
    kinds = ["agree", "refused", "loud", "disagree", "warning", "internal", "timeout"]
    count = {k: sum(r["kind"] == k for r in results) for k in kinds}
    print("extremes: " + ", ".join(f"{count[k]} {k}" for k in kinds) + f" of {len(results)} runs; "
          f"max {max((r['seconds'] for r in results), default=0):.1f} s")
    return 0 if all(r["kind"] in TIDY for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())

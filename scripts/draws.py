#!/usr/bin/env python3
"""Random draws across every exercise's whole declared range, run as a user would: the trust benchmark.

usage: python scripts/draws.py [--n N] [--seed S] [--timeout T] [--jobs J] [--markdown] [ID ...]

For each exercise (or the named ones, by prefix: "4.2" takes 4.2 and every 4.2x), N parameter sets
are drawn over the whole declared range (mech.studies.draws, kind "whole": log-uniform, open ends
at 1e-6..1e6 times the default; a draw the joint constraints refuse is redrawn), and each is run as
``mech solve ID --json -p NAME=VALUE ...`` in a fresh process, killed after T seconds as a CI
timeout would.  Each run is classified (mech.studies.extremes.classify, shared with
scripts/extremes.py):

  agree     exit 0 and every quantity agrees
  loud      exit 1 with a solver's one-line failure (it said it could not answer)
  disagree  exit 1 where both methods answered and some quantity disagrees
  warning   anything on stderr from a run that did not refuse (a numpy warning, say)
  internal  an internal error, a traceback, a refusal of more than one line, or JSON that is not the contract's
  timeout   no answer within T seconds
  orphan    a process the command started still alive 2 s after it ended (counted apart)

Prints the runs that are not "agree", a per-exercise summary with --markdown, and a last line
  draws: A agree, L loud, D disagree, W warning, I internal, T timeout, O orphans of N runs; median ...
Exit 0 when there is no disagreement, warning, internal error, timeout or orphan and the loud failures are
at most 1 % of the runs.
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import os
import shutil
import signal
import statistics
import subprocess
import sys
import time
import uuid


def _mech_command() -> list[str]:
    here = os.path.dirname(os.path.abspath(sys.executable))
    local = os.path.join(here, "mech")
    return [local] if os.path.exists(local) else [shutil.which("mech") or "mech"]


def _tagged(tag: str) -> list[int]:
    """Processes whose environment carries the run's tag (a forked child inherits it)."""
    found = []
    needle = f"MECH_DRAW_TAG={tag}".encode()
    for entry in os.listdir("/proc") if os.path.isdir("/proc") else []:
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/environ", "rb") as fh:
                if needle in fh.read():
                    found.append(int(entry))
        except OSError:
            continue
    return found


def run_one(ex_id: str, given: dict, timeout: float) -> dict:
    tag = uuid.uuid4().hex
    cmd = _mech_command() + ["solve", ex_id, "--json"]
    for name, value in given.items():
        cmd += ["-p", f"{name}={value!r}"]
    env = {**os.environ, "MECH_DRAW_TAG": tag}
    t0 = time.monotonic()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                            start_new_session=True)
    try:
        out, err = proc.communicate(timeout=timeout)
        kind = None
    except subprocess.TimeoutExpired:
        proc.kill()  # the command's own process only, as a CI runner's timeout does
        out, err = proc.communicate()
        kind = "timeout"
    seconds = time.monotonic() - t0
    time.sleep(0.2)
    left = _tagged(tag)
    if left:
        time.sleep(1.8)
        left = _tagged(tag)
    for pid in left:
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:
            pass
    detail = ""
    if kind is None:
        from mech.studies.extremes import classify  # the one classification of a run

        kind, detail = classify(proc.returncode, out, err)
    return {"id": ex_id, "given": given, "kind": kind, "seconds": seconds, "orphans": len(left), "detail": detail}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=5, help="draws per exercise [5]")
    ap.add_argument("--seed", type=int, default=20261124)
    ap.add_argument("--timeout", type=float, default=10.0, help="seconds before a run is killed [10]")
    ap.add_argument("--jobs", type=int, default=1, help="runs at once [1: timings stay honest]")
    ap.add_argument("--markdown", action="store_true", help="a per-exercise table in Markdown (docs/verification.md)")
    ap.add_argument("ids", nargs="*")
    args = ap.parse_args(argv)

    from mech.problems import registry
    from mech.studies.draws import draws

    exercises = [ex for i, ex in registry.all_exercises().items()
                 if not args.ids or any(i == p or i.startswith(p) for p in args.ids)]
    jobs = [(ex.id, g) for ex in exercises for g in draws(ex, args.n, args.seed, kind="whole")]
    results = []
    with cf.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        for res in pool.map(lambda job: run_one(job[0], job[1], args.timeout), jobs):
            results.append(res)
            if res["kind"] not in ("agree", "refused") or res["orphans"]:
                given = " ".join(f"{k}={v:.6g}" for k, v in res["given"].items())
                print(f"{res['id']} {res['kind']} ({res['seconds']:.1f} s, orphans {res['orphans']}): {given} :: "
                      f"{res['detail'][:300]}", flush=True)
    kinds = ["agree", "loud", "disagree", "warning", "internal", "timeout", "refused"]
    count = {k: sum(r["kind"] == k for r in results) for k in kinds}
    orphans = sum(r["orphans"] > 0 for r in results)
    times = [r["seconds"] for r in results if r["kind"] != "timeout"]
    if args.markdown:
        print("\n| exercise | runs | agree | loud | disagree | internal | timeout | orphan | max s |")
        print("|---|---|---|---|---|---|---|---|---|")
        for ex in exercises:
            mine = [r for r in results if r["id"] == ex.id]
            c = {k: sum(r["kind"] == k for r in mine) for k in kinds}
            print(f"| {ex.id} | {len(mine)} | {c['agree']} | {c['loud']} | {c['disagree']} | {c['internal']} | "
                  f"{c['timeout']} | {sum(r['orphans'] > 0 for r in mine)} | "
                  f"{max((r['seconds'] for r in mine), default=0):.1f} |")
    answered = len(results) - count["refused"]
    median = statistics.median(times) if times else 0.0
    print(f"draws: {count['agree']} agree, {count['loud']} loud, {count['disagree']} disagree, "
          f"{count['warning']} warning, {count['internal']} internal, {count['timeout']} timeout, {orphans} orphans of {len(results)} runs "
          f"(seed {args.seed}, {args.n} per exercise); median {median:.2f} s, max {max(times, default=0):.2f} s")
    ok = (count["disagree"] == count["warning"] == count["internal"] == count["timeout"] == orphans == 0
          and count["loud"] <= 0.01 * max(answered, 1))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())

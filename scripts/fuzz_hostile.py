"""A seeded run of tests/test_hostile.py's fuzz, larger than the test's: hostile arguments, answers files and
baselines, each held to what every invocation owes (exit 0, 1 or 2; no traceback or internal error; exit 2
with "mech: error:" lines only; no control character on the terminal).

    python scripts/fuzz_hostile.py --seed 2611 --args 3000 --answers 500 --baselines 300

Prints the counts by exit status and the slowest case; exits 1 at the first invocation that breaks a rule,
printing it.
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import random
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests"))
os.environ.pop("COLUMNS", None)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, default=2611)
    ap.add_argument("--args", type=int, default=3000)
    ap.add_argument("--answers", type=int, default=500)
    ap.add_argument("--baselines", type=int, default=300)
    opts = ap.parse_args()

    import test_hostile as H
    from click.testing import CliRunner

    from mech.cli.main import cli

    rnd = random.Random(opts.seed)
    folder = tempfile.mkdtemp(prefix="mech-fuzz-")
    good = os.path.join(folder, "good.json")
    assert CliRunner().invoke(cli, ["check", "4.15", "--save-baseline", good]).exit_code == 0
    with open(good, encoding="utf-8") as fh:
        good_data = json.load(fh)
    plans = [("arguments", opts.args, lambda: H.run_argv(H.random_argv(rnd))),
             ("answers files", opts.answers, lambda: H.run_answers(H.random_answers(rnd), folder)),
             ("baselines", opts.baselines, lambda: H.run_baseline(H.random_baseline(rnd, good_data), folder))]
    print(f"seed {opts.seed}")
    for name, n, one in plans:
        counts: collections.Counter = collections.Counter()
        slowest = 0.0
        t0 = time.perf_counter()
        for k in range(n):
            t = time.perf_counter()
            try:
                counts[one()] += 1
            except AssertionError as exc:
                print(f"{name} #{k}: a rule broken: {exc}")
                return 1
            slowest = max(slowest, time.perf_counter() - t)
        total = time.perf_counter() - t0
        shown = ", ".join(f"exit {code}: {counts[code]}" for code in sorted(counts))
        print(f"{name}: {n} runs ({shown}); {total:.1f} s, slowest {slowest:.2f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""A seeded run of tests/test_hostile.py's fuzz, larger than the test's: hostile arguments, answers files and
baselines, each held to what every invocation owes (exit 0, 1 or 2; no traceback or internal error; exit 2
with "mech: error:" lines only; no control character on the terminal).

    python scripts/fuzz_hostile.py --seed 2611 --args 3000 --answers 500 --baselines 300 --formulas 400

``--formulas``: hostile formulas given to ``mech solve --expect`` (issue 33): right formulas of
tests/test_formulas_heldout.py with a slip hidden behind a term of 1e10..1e300 that cancels in double
precision (each must be judged wrong, exit 1, or refused, exit 2), and random trees of huge literals,
nested powers, functions at their domains' edges, control characters and juxtapositions (any verdict,
under the same rules).

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
    ap.add_argument("--formulas", type=int, default=400)
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
             ("baselines", opts.baselines, lambda: H.run_baseline(H.random_baseline(rnd, good_data), folder)),
             ("formulas", opts.formulas, lambda: run_formula(rnd, H))]
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


_HIDES = ("({F}) + (({C}*({F}) + {r}*({F})) - {C}*({F}))", "({F})*((({C} + 1 + {r}) - {C}))",
          "({F})*(1 + (({C}*{p}/{p} + {r}) - {C}))", "(({F}) + {C}*({F})*(1 + {r})) - {C}*({F})")
_ATOMS = ("1e308", "1e-308", "5e-324", "0", "1e300", "pi", "2", "0.5")
_FUNS = ("sqrt", "exp", "log", "sin", "asin", "acos", "tan", "sinh", "tanh", "ellipk", "ellipe", "expm1", "abs")
_ODD = ("\x1f", "\x85", "\u200b", "π", "√", "²", " s", " ms", "^1e300", "**-1e300", "/0", ",")
_POOL: list = []


def _right_formulas():
    if not _POOL:
        import importlib.util

        from mech.problems import registry

        spec = importlib.util.spec_from_file_location("heldout", os.path.join(HERE, "..", "tests",
                                                                               "test_formulas_heldout.py"))
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
        for ex_id, cases in mod.CASES.items():
            ex = registry.get(ex_id)
            exact = {o.name for o in ex.outputs if o.theory == "exact"}
            _POOL.extend((ex_id, o, f, [q.name for q in ex.params]) for o, f, want in cases
                         if want is None and o in exact)
    return _POOL


def _random_tree(rnd, names, depth=0) -> str:
    if depth > 3 or rnd.random() < 0.3:
        return rnd.choice(list(_ATOMS) + names)
    k = rnd.random()
    a, b = _random_tree(rnd, names, depth + 1), _random_tree(rnd, names, depth + 1)
    if k < 0.4:
        return f"({a} {rnd.choice('+-*/^')} {b})"
    if k < 0.8:
        return f"{rnd.choice(_FUNS)}({a})"
    return f"{a}{rnd.choice(_ODD)}{b}"


def run_formula(rnd, H) -> int:
    """One hostile formula through ``mech solve --expect``: the invocation's rules, and a hidden slip
    never judged right."""
    from click.testing import CliRunner

    from mech.cli.main import cli

    ex_id, out, F, names = rnd.choice(_right_formulas())
    hide = rnd.random() < 0.5
    if hide:
        C = f"{rnd.uniform(1, 9.99):.6g}e{rnd.randint(10, 300)}"
        text = rnd.choice(_HIDES).format(F=F, C=C, r=f"{10 ** rnd.uniform(-6, 0):.3g}", p=rnd.choice(names))
    else:
        text = _random_tree(rnd, names)
    result = CliRunner().invoke(cli, ["solve", ex_id, "--method", "analytic", "--expect", f"{out}={text}",
                                      "--expect-points", str(rnd.randint(1, 8)), "--expect-seed",
                                      str(rnd.randint(0, 99))])
    H.check_outcome(result)
    assert "Warning" not in (result.stderr or ""), result.stderr
    if hide:
        assert result.exit_code in (1, 2), f"{ex_id} {out}={text}: a hidden slip judged right"
    return result.exit_code


if __name__ == "__main__":
    sys.exit(main())

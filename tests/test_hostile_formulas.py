"""A student's formula is hostile input too (issue 33): no cheat passes, every check is bounded.

Right means right in exact arithmetic.  The cheats below add terms that cancel in double precision (or in
exact arithmetic) to move a formula's round-off bound, not its value; the expected verdicts follow from the
algebra by hand: ``(theta0 + 1e300) - 1e300 + 42`` is exactly ``theta0 + 42``, which is not the ladder's
``asin(2/3 sin theta0)``; ``sqrt(g/l) + (1e20 M - 1e20 M)/M sqrt(g/l)`` is exactly ``sqrt(g/l)``, the
small-I limit of 4.10, not its answer.
"""

from __future__ import annotations

import importlib.util
import math
import os
import pathlib
import random
import subprocess
import sys

import numpy as np
import pytest

from mech.problems import registry
from mech.verification import points as P
from mech.verification.formula_ast import FormulaError, parse_formula
from mech.verification.formulas import judge_formula

HERE = pathlib.Path(__file__).parent


def _mech(*args, env=None, timeout=120):
    e = dict(os.environ, **(env or {}))
    return subprocess.run([sys.executable, "-m", "mech.cli.main", *args], capture_output=True, text=True,
                          timeout=timeout, env=e)


def _verdict(ex_id, output, text, n=4, seed=1):
    """The verdict on ``text`` for ``output`` of ``ex_id`` against the analytic reference at the defaults
    and ``n`` drawn points."""
    ex = registry.get(ex_id)
    out = {o.name: o for o in ex.outputs}[output]
    ps = P.point_set(ex, ex.resolve({}), n, seed)
    f = parse_formula(text, ex)
    given = (float(ps.analytic[output][0]), float(ps.analytic_err[output][0]))
    return judge_formula(f, ex, out, ps, given, None)


# -- the three cheats of the issue ----------------------------------------------------------------------

@pytest.mark.parametrize("ex_id,output,text", [
    ("4.10", "Omega", "sqrt(g/l) + (1e20*M - 1e20*M)/M*sqrt(g/l)"),
    ("4.15", "theta_c", "theta0/2 + (1e20 - 1e20*l/l)"),
    ("4.15", "theta_c", "(theta0 + 1e300) - 1e300 + 42"),
    ("4.15", "theta_c", "asin(2/3*sin(theta0)) + ((1e300 + 1e-3) - 1e300)"),
])
def test_cheats_are_wrong(ex_id, output, text):
    v = _verdict(ex_id, output, text)
    assert not v.match, v.verdict
    assert v.verdict.startswith("wrong"), v.verdict
    assert "ill-conditioned" not in v.verdict


def test_cheat_on_the_command_line_exits_1():
    r = _mech("solve", "4.10", "--expect", "Omega=sqrt(g/l) + (1e20*M - 1e20*M)/M*sqrt(g/l)")
    assert r.returncode == 1, r.stdout + r.stderr
    assert "wrong at" in r.stdout and "ill-conditioned" not in r.stdout


@pytest.mark.parametrize("text", [
    "asin(2/3*sin(theta0)) + (1e300*theta0 - 1e300*theta0)",  # cancels exactly: right in exact arithmetic
    "asin(2/3*sin(theta0))*(1e20*l/l - 1e20 + 1)",
    "asin((1e300*sin(theta0) + 2*sin(theta0) - 1e300*sin(theta0))/3)",
])
def test_exactly_cancelling_terms_stay_right(text):
    v = _verdict("4.15", "theta_c", text)
    assert v.match, v.verdict


# -- the property: right formulas, with a term that hides a slip in double precision ---------------------

def _right_formulas():
    spec = importlib.util.spec_from_file_location("heldout", HERE / "test_formulas_heldout.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    out = []
    for ex_id, cases in mod.CASES.items():
        ex = registry.get(ex_id)
        exact = {o.name for o in ex.outputs if o.theory == "exact"}
        out += [(ex_id, o, f) for o, f, want in cases if want is None and o in exact]
    return out


_HIDES = (
    "({F}) + (({C}*({F}) + {r}*({F})) - {C}*({F}))",  # the slip r F is lost in double beside C F
    "({F})*((({C} + 1 + {r}) - {C}))",
    "({F})*(1 + (({C}*{p}/{p} + {r}) - {C}))",
    "(({F}) + {C}*({F})*(1 + {r})) - {C}*({F})",
    "({F}) + ({C}*{p} - {C}*{p})/{p}*({F}) + {r}*({F})",
)


def test_property_hidden_slips_are_wrong_and_right_formulas_right():
    rng = random.Random(33)
    pool = _right_formulas()
    assert len({e for e, _, _ in pool}) >= 10
    cases = [rng.choice(pool) for _ in range(500)]
    bad_right, bad_wrong = [], []
    seen = {}
    for k, (ex_id, output, F) in enumerate(cases):
        ex = registry.get(ex_id)
        if (ex_id, output, F) not in seen:  # the same formula without the term: right
            v = _verdict(ex_id, output, F, n=3, seed=k % 7)
            seen[(ex_id, output, F)] = v.match
            if not v.match:
                bad_right.append((ex_id, output, F, v.verdict))
        C = f"{rng.uniform(1, 9.99):.6g}e{rng.randint(10, 300)}"
        r = f"{10 ** rng.uniform(-6, 0):.3g}"
        p = rng.choice([q.name for q in ex.params])
        text = rng.choice(_HIDES).format(F=F, C=C, r=r, p=p)
        try:
            v = _verdict(ex_id, output, text, n=3, seed=k % 7)
        except FormulaError:
            continue  # refused
        if v.match:
            bad_wrong.append((ex_id, output, text, v.verdict))
    assert not bad_right, bad_right[:3]
    assert not bad_wrong, (len(bad_wrong), bad_wrong[:3])

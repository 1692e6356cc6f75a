"""One rule decides every verdict: the allowance inequality is written in verification/judge.py only.

The rule (``judge.within``): a distance is within ``rel |scale| + each error bar + round_off |scale| + own``.
Every other module of the verdict floors (verification/, students/, studies/, api/, cli/) calls it with what it holds a value
to; this test reads their source for a comparison of a distance or of a tolerance sum written by hand.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from conftest import parsed

from mech.verification import judge as J

ROOT = Path(__file__).resolve().parents[1]
FLOORS = ("verification", "students", "studies", "api", "cli")

# |x - y| compared with anything, or anything compared with a sum of tolerances and error bars
DISTANCE = re.compile(r"abs\([^()#]*(\([^()]*\))?[^()#]*-[^()#]*\)\)?\s*(<=|<|>=|>)")
# ... or a distance compared with a tolerance computed on an earlier line
HELD = re.compile(r"(?<![-=<>])(<=|>=|<|>)\s*(tol|\w+_tol|allowed|claim|allowance)\b(?!\s*[(.\[])")
TOLERANCE = re.compile(r"(?<![-=<>])(<=|>=|<|>)\s*[^#\"]*\b(tol|rtol|\w+_err|claim|allowed|ROUND_OFF)\b\s*(\*|\+)")


def _offenders():
    out = []
    for floor in FLOORS:
        for path in sorted((ROOT / floor).rglob("*.py")):
            rel = path.relative_to(ROOT).as_posix()
            if rel == "verification/judge.py":
                continue
            for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                code = line.split("#", 1)[0]
                if "``" in code or code.strip().startswith(('"', "'")):
                    continue  # prose in a docstring
                if DISTANCE.search(code) or TOLERANCE.search(code) or HELD.search(code):
                    out.append(f"{rel}:{i}: {line.strip()}")
    return out


def test_the_allowance_inequality_is_written_in_the_judge_only():
    assert _offenders() == []


# a verdict read back from its words: a note searched, split or stripped of a verdict's words
FROM_WORDS = re.compile(r"([\"']\s+in\s+(\w+\.)?notes?\b|\.notes?\[|removeprefix\(prefix|\.split\(\"outside|\"outside its range\" in|"
                        r"\.why\.(startswith|replace)\(|note\.split\()")


def test_no_verdict_is_read_back_from_its_words():
    found = []
    for floor in FLOORS:
        for path in sorted((ROOT / floor).rglob("*.py")):
            for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                code = line.split("#", 1)[0]
                if FROM_WORDS.search(code):
                    found.append(f"{path.relative_to(ROOT).as_posix()}:{i}: {line.strip()}")
    assert found == []


def test_the_words_grep_finds_what_it_replaced():
    for text in ('if "outside its range" in note:', "notes = str(q.note).split(\"; \")", 'if "unreliable" in note:',
                 "q.notes[-1].removeprefix(prefix)", 'ref.why.startswith("mech finds no finite value")'):
        assert FROM_WORDS.search(text) or "split(" in text, text


def test_the_grep_finds_a_hand_written_allowance(tmp_path):
    # the patterns must catch the forms the rule replaced (else the test above could not fail)
    for text in ("if abs(a - b) <= tol * abs(a) + err:", "ok = np.abs(y - ref) <= rtol * np.abs(ref) + ref_err",
                 "if diff <= own_tol + ref_err + ROUND_OFF * abs(v):", "moved = d > claim + 1",
                 "right = has_ref & (d <= tol)", "if not (drift <= allowed):"):
        assert DISTANCE.search(text) or TOLERANCE.search(text) or HELD.search(text), text


def test_the_allowance_adds_what_a_value_is_held_to():
    # by hand: 1e-3 * 200 + 0.5 + 0.25 + 1e-12 * 200 + 0.125
    got = J.allowance(-200.0, rel=1e-3, bars=(0.5, 0.25), round_off=1e-12, own=0.125)
    assert got == pytest.approx(0.2 + 0.5 + 0.25 + 2e-10 + 0.125, rel=1e-15)
    assert J.allowance(5.0) == 0.0
    # no relative part: an infinite scale adds nothing (not NaN)
    assert J.allowance(math.inf, bars=(1.0,)) == 1.0


def test_within_is_the_inequality_on_arrays_and_nan_is_never_within():
    d = np.array([0.0, 0.3, 0.31, np.nan])
    assert J.within(d, scale=10.0, rel=0.01, bars=(0.2,)).tolist() == [True, True, False, False]
    assert bool(J.within(1.0, bars=(1.0,)))  # the edge is within
    assert not bool(J.within(1.0 + 1e-15, bars=(1.0,)))


# -- "no verdict" means the same in solve, sweep and check: no failure ----------------------------------------

def test_no_verdict_is_no_failure_in_solve_and_check(capsys):
    from click.testing import CliRunner

    from mech.render import print_check
    from mech.cli.main import cli
    from mech.problems import registry
    from mech.studies import checking

    # solve with one method: nothing compared, exit 0
    r = CliRunner().invoke(cli, ["solve", "4.15", "--method", "analytic", "--json"])
    assert r.exit_code == 0 and '"agree": null' in r.stdout
    # a check case with one method registered: no verdict, counted neither passed nor failed, the run holds
    ex = registry.get("4.15")

    class OneMethod:
        methods = ("numeric",)

        def __getattr__(self, name):
            return getattr(ex, name)

    case = checking.run_case(checking.Case(OneMethod(), "defaults", {}))
    report = checking.Report(cases=[case])
    assert case.agree is None and case.ok and (report.passed, report.failed, report.ok) == (0, 0, True)
    print_check(report)
    out = capsys.readouterr().out
    assert "no verdict" in out and "0 passed, 1 no verdict, 0 failed" in out


def test_grade_and_solve_conclude_alike_on_no_verdict(tmp_path):
    """A cross-check with no verdict (one method: nothing compared) fails neither ``mech solve --expect`` nor a
    grade entry; a wrong answer fails both; an entry with nothing judged has no verdict, which is no failure."""
    import math

    from click.testing import CliRunner

    from mech.cli.main import cli
    from mech.problems import registry
    from mech.students import answers_files
    from mech.students import classrun
    from mech.students import expectations
    from mech.verification.crosscheck import cross_check

    ex = registry.get("4.15")

    class NumericOnly:  # 4.15 with its analytic solver taken away: the numeric value is all there is
        has_analytic = False
        methods = ("numeric",)

        def __getattr__(self, name):
            return getattr(ex, name)

    # by hand: the ladder leaves the wall at sin(theta_c) = (2/3) sin(theta0); theta0 = 60 deg gives asin(1/sqrt 3)
    right = math.degrees(math.asin(1 / math.sqrt(3)))
    assert f"{right:.6g}" == "35.2644"
    for answer, fails in (("35.2644deg", False), ("40deg", True)):
        r = CliRunner().invoke(cli, ["solve", "4.15", "--method", "numeric", "--theta0", "60deg",
                                     "--expect", f"theta_c={answer}", "--json"])
        assert r.exit_code == (1 if fails else 0), r.output
        assert '"agree": null' in r.stdout
        # the same answer in a grading file, graded against the numeric route alone
        path = tmp_path / "answers.toml"
        path.write_text(f'[[answer]]\nexercise = "4.15"\nparams = {{ theta0 = "60deg" }}\n'
                        f'expect = {{ theta_c = "{answer}", omega_c = "" }}\n', encoding="utf-8")
        entries = answers_files.load_answers(str(path))
        entries[0].exercise = NumericOnly()
        classrun.grade(entries, jobs=1)
        e = entries[0]
        assert e.result.agree is None  # the cross-check itself: no verdict
        sol = expectations.attach(cross_check(NumericOnly(), ex.resolve(e.given)), e.expectations)
        assert sol.agree is None and sol.expect_ok is (not fails)
        assert e.ok is (not fails) and e.conclusion is (False if fails else True)
        assert J.conclude([sol.agree, sol.expect_ok]) is e.conclusion
    # nothing judged (every answer left for the student): no verdict, as a solve with nothing compared
    path.write_text('[[answer]]\nexercise = "4.15"\nexpect = { theta_c = "" }\n', encoding="utf-8")
    entries = answers_files.load_answers(str(path))
    classrun.grade(entries, jobs=1)
    assert entries[0].judgements == [] and entries[0].conclusion is None and entries[0].ok
    # an unreadable entry fails, whatever its answers say
    path.write_text('[[answer]]\nexercise = "4.15"\nparams = { theta0 = "500deg" }\nexpect = { theta_c = "1" }\n',
                    encoding="utf-8")
    entries = answers_files.load_answers(str(path), strict=False)
    assert entries[0].invalid and entries[0].conclusion is False and not entries[0].ok


def test_a_judged_quantity_is_built_in_one_place():
    """``result.judged_quantity`` builds every judged output (a point's cross-check and a sweep's point):
    no other module calls ``Quantity(`` with the judge's fields; a refused point's unjudged output is the
    one other construction."""
    import ast

    found = []
    for path in sorted(ROOT.rglob("*.py")):
        rel = path.relative_to(ROOT).as_posix()
        if rel.startswith(("tests/", ".venv/", "scripts/")) or "/." in rel or rel == "verification/result.py":
            continue
        for node in ast.walk(parsed(path)):
            if isinstance(node, ast.Call) and getattr(node.func, "id", getattr(node.func, "attr", None)) == "Quantity":
                kws = {k.arg or "**" for k in node.keywords}
                found.append((rel, sorted(kws)))
    assert found == [("studies/sweep.py", ["notes", "theory"])], found


def test_a_batched_point_and_its_solve_read_alike():
    """The same point through the batched route and through the one-point cross-check: the same fields
    (the error bars, tolerances, verdicts, notes) where the values agree to their claims."""
    from mech.problems import registry
    from mech.studies.variants import cross_check_variants
    from mech.verification.crosscheck import cross_check

    ex = registry.get("5.13")
    params = [ex.resolve({}), ex.resolve({"Omega": 900.0})]
    for p, batched in zip(params, cross_check_variants(ex, params)):
        one = cross_check(ex, p)
        for q in one.quantities:
            b = batched[q.name]
            for field in ("analytic_err", "tol", "tol_abs", "verdict", "agree", "theory", "theory_valid",
                          "expected_err", "expected_err_abs", "notes", "reason"):
                assert getattr(b, field) == getattr(q, field), (q.name, field)
            assert abs(b.numeric - q.numeric) <= q.numeric_err + b.numeric_err

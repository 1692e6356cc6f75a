"""The one judge (verification/judge.py) and the verdicts every caller draws from it.

Hand values: each element below is built so its verdict follows from the rule in the judge's docstring,
|n - a| <= tol |a| + allowance + analytic_err, with tol = max(claim, neglect) for a leading-order value.
"""

import json
import math
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from mech.cli.main import cli
from mech.verification import judge as J

ROOT = Path(__file__).resolve().parent.parent


def test_the_rule_on_arrays():
    # 0: |1.000001 - 1| = 1e-6 <= 1e-5 * 1: agree;  1: 1e-4 > 1e-5: disagree;
    # 2: leading-order, neglect 1e-3 widens 1e-5: agree;  3: the same, but the theory outside its range:
    # nothing compared;  4: analytic round-off 2e-4 earns the 1e-4 miss;  5: the rerun moved 2e-5 > 1e-5
    a = np.array([1.0, 1.0, 1.0, 1.0, 1.0, 1.0])
    n = np.array([1.000001, 1.0001, 1.0001, 1.0001, 1.0001, 1.0])
    r = J.judge(analytic=a, numeric=n, rel_claim=1e-5, leading=[False, False, True, True, False, False],
                expected_rel=[np.nan, np.nan, 1e-3, 1e-3, np.nan, np.nan],
                analytic_err=[0, 0, 0, 0, 2e-4, 0], verify=n + [0, 0, 0, 0, 0, 2e-5],
                outside=[False, False, False, True, False, False],
                outside_why=["", "", "", "x = 2", "", ""])
    assert r.agree.tolist() == [1, 0, 1, -1, 1, 0]
    assert r.verdict.tolist() == [J.AGREE, J.DISAGREE, J.AGREE, J.OUTSIDE, J.AGREE, J.UNRELIABLE]
    assert r.tol.tolist() == [1e-5, 1e-5, 1e-3, 1e-5, 1e-5, 1e-5]
    assert r.numeric_err[1] == pytest.approx(1e-5 * 1.0001, rel=1e-12)
    assert J.notes(r, 3)[0] == "leading-order theory outside its range: x = 2"
    assert J.notes(r, 5)[0].startswith("unreliable")
    # the typed verdicts: what each concludes, and the words every renderer shows
    assert [J.Verdict(v).agree for v in r.verdict] == [True, False, True, None, True, False]
    assert [J.Verdict(v).cell for v in r.verdict] == ["yes", "NO", "yes", "outside range", "yes", "NO"]


def test_the_rerun_is_held_to_the_error_bar_printed_beside_the_value():
    """The rerun's claim is the numeric value's own error bar, rel |n| + abs: by hand, a numeric value 1 with
    a claim of 1e-8 moves by 5e-8 at rtol/10, more than its bar of 1e-8.  Beside a leading-order value of
    1000 outside its range (5.9's omega at mu/omega0 = 3e4 is 7700 times its numeric value) the claim was
    scaled by the analytic value, 1e-5, and the move passed; it is unreliable."""
    r = J.judge(analytic=[1000.0, 1.0], numeric=[1.0, 1.0], rel_claim=1e-8, leading=True, expected_rel=1e-3,
                verify=[1.0 + 5e-8, 1.0 + 5e-9], outside=[True, False], outside_why=["mu/omega0 = 3e4", ""])
    assert r.verify_claim.tolist() == pytest.approx([1e-8, 1e-8], rel=1e-12)
    assert r.verify_claim.tolist() == r.numeric_err.tolist()
    assert r.verdict.tolist() == [J.UNRELIABLE, J.AGREE]


def test_the_one_overall_rule():
    V = J.Verdict
    # outside its theory's range a verified numeric value holds; unverified it is no verdict
    assert J.holds(V.OUTSIDE, verified=True) is True and J.holds(V.OUTSIDE) is None
    assert J.holds(V.UNRELIABLE, verified=True) is False and J.holds(None, agree=False) is False
    assert J.conclude([True, None]) is True and J.conclude([None, None]) is None
    assert J.conclude([True, False, None]) is False and J.conclude([True], failed=True) is False
    assert J.conclude([]) is None
    got = J.conclude_arrays(np.array([1, 0, -1, -1, 1], np.int8), np.array([0, 0, 1, 0, 0], bool),
                            np.array([0, 0, 0, 0, 1], bool))
    assert got.tolist() == [1, 0, 1, -1, 0]


def test_undefined_missing_and_failed_values():
    nan = math.nan
    r = J.judge(analytic=[nan, nan, 2.0, 2.0, nan, 2.0], numeric=[nan, 3.0, nan, 2.0, 2.0, nan],
                a_undefined=[True, True, False, False, False, False],
                n_undefined=[True, False, False, False, False, False],
                n_failed=[False, False, False, False, False, True],
                has_analytic=[True, True, True, True, False, True], has_numeric=[True, True, False, True, True, True],
                rel_claim=[1e-8, 1e-8, 1e-8, math.inf, 1e-8, 1e-8])
    # both undefined agree; one undefined disagrees; analytic only; an infinite claim fails; numeric only;
    # a failed numeric solve: no verdict (the failure is the loud part)
    assert r.agree.tolist() == [1, 0, -1, 0, -1, -1]
    assert r.verdict.tolist() == [J.AGREE, J.ONE_UNDEFINED, J.ANALYTIC_ONLY, J.NO_CLAIM, J.NUMERIC_ONLY, J.FAILED]


def test_the_leading_order_theory_that_finds_no_value():
    # the theory finds none, what it neglects allows |n| up to 0.01: 0.005 agrees, 0.02 does not
    r = J.judge(analytic=[math.nan, math.nan], numeric=[0.005, 0.02], a_undefined=True, rel_claim=1e-8,
                leading=True, expected_rel=np.nan, expected_abs=0.01)
    assert r.agree.tolist() == [1, 0] and r.small.all()


def test_the_agreement_inequality_is_written_in_one_module():
    """No module but the judge compares an analytic with a numeric value, or a rerun with its claim."""
    patterns = [r"abs_err\s*<=", r"<=\s*tol\s*\*", r"verify_diff\s*>", r"abs\(n\s*-\s*a\)\s*<="]
    found = {}
    for path in list(ROOT.glob("**/*.py")):
        if ".venv" in path.parts or "tests" in path.parts or path.name == "judge.py":
            continue
        text = path.read_text(encoding="utf-8")
        for pat in patterns:
            if re.search(pat, text):
                found.setdefault(str(path.relative_to(ROOT)), []).append(pat)
    assert found == {}


# -- every caller, the same verdicts at the same points ------------------------------------------------------

def _fields(q: dict) -> tuple:
    return (q["agree"], q.get("theory_valid"), q["tol"], q.get("tol_abs"))


def _bars(q: dict) -> tuple:
    return tuple(q.get(k) for k in ("numeric_err", "abs_err"))


POINTS = [("5.11", {}, ()), ("5.11", {"delta": 0.001, "mu": 0.000404, "omega": 10.0}, ()),
          ("5.11", {"delta": 0.0}, ()), ("5.11", {"mu": 0.6, "omega": 9.5}, ()),
          ("5.11", {"mu": 0.9, "omega": 10.0}, ()), ("5.13", {}, ()),
          # just above the inverted pendulum's stability edge a_min = (2 g l)^(1/2)/Omega = 0.0440 m: the
          # averaging's beta0 -> 0 there, so omega_inv's theory is outside its range
          ("5.13", {"Omega": 45.0, "a": 0.045}, ("omega_inv",)),
          # mu/omega0 = 3.3: outside the reduced equation's range (5.9 has no batched route)
          ("5.9", {"mu": 10.0}, ("A", "omega", "lambda_lc"))]


@pytest.mark.parametrize("ex_id, given, outside", POINTS)
def test_solve_check_sweeps_and_grade_give_the_same_verdicts(ex_id, given, outside, tmp_path):
    from mech import api
    from mech.problems import registry
    from mech.studies.checking import Case, run_case
    from mech.students.answers_files import load_answers
    from mech.students.classrun import grade
    from mech.studies.sweep import Axis, run_sweep

    ex = registry.get(ex_id)
    params = ex.resolve(given)
    args = [a for k, v in given.items() for a in (f"--{k}", repr(v))]
    solved = json.loads(CliRunner().invoke(cli, ["solve", ex_id, *args, "--json"]).stdout)
    solve_q = {q["name"]: q for q in solved["quantities"]}
    for name, q in solve_q.items():
        if name in outside:
            assert q["theory_valid"] is False and q["agree"] is None, name
        elif q.get("theory") == "leading-order":
            assert q["theory_valid"] is True, name

    case = run_case(Case(ex, "here", dict(given)))
    check_q = {q.name: q.as_json() for q in case.result.quantities}
    assert case.ok == (solved["agree"] is True)

    name = next(iter(given), ex.params[0].name)
    axis = Axis(name, (float(params[name]),))
    fixed = {k: v for k, v in params.items() if k != name}
    swept = run_sweep(ex, [axis], fixed, [params], verify=True, jobs=1)
    pointwise = swept.point_list()[0]
    point_q = {q["name"]: q for q in pointwise["quantities"]}

    # --expect numbers: mech's own values, to 17 digits, as a student's answers; grade holds the same ones
    mine = {o: (q["numeric"] if q["numeric"] is not None and (q.get("theory") or q["analytic"] is None)
                else q["analytic"]) for o, q in solve_q.items()}
    mine = {o: v for o, v in mine.items() if v is not None}
    expects = [a for o, v in mine.items() for a in ("--expect", f"{o}={v!r}")]
    r = CliRunner().invoke(cli, ["solve", ex_id, *args, "--json", *expects])
    expected_solve = {q["name"]: q["expected"] for q in json.loads(r.stdout)["quantities"] if "expected" in q}

    answers = tmp_path / "a.toml"
    lines = ", ".join(f'{k} = {v!r}' for k, v in given.items())
    expect = ", ".join(f'{o} = "{v!r}"' for o, v in mine.items()) or f'{ex.outputs[0].name} = "1"'
    answers.write_text(f'[[answer]]\nexercise = "{ex_id}"\nparams = {{ {lines} }}\nexpect = {{ {expect} }}\n',
                       encoding="utf-8")
    entries = load_answers(str(answers))
    grade(entries)
    grade_q = {q.name: q.as_json() for q in entries[0].result.quantities}
    assert entries[0].result.agree == solved["agree"]
    # the same answers, the same verdicts: right exactly where mech has a trusted value (a failed output has
    # none), from solve --expect and from grade alike
    for j in entries[0].judgements:
        if j.name in mine:
            e = expected_solve[j.name]
            assert (j.match, j.verdict, j.reference) == (e["match"], e["verdict"], e["reference"]), j.name
            trusted = solve_q[j.name]["agree"] is not False and not solved.get("errors")
            assert j.match == trusted, (j.name, j.verdict)

    # baselines: the check case's record against the grade's and the point sweep's, value by value, held to
    # the judge's rule with both error bars: nothing moved, every value compared
    from mech.verification import baseline

    rec = baseline.record_case(ex_id, "here", params, case.ok, case.result.quantities)
    for other in (entries[0].result.quantities, swept.solutions()[0].quantities):
        now = baseline.record_case(ex_id, "here", params, True, other)
        cmp = baseline.compare(baseline.make([rec], hard=False), [now])
        assert cmp.ok and not cmp.moved and cmp.compared == sum(
            (o["analytic"] is not None) + (o["numeric"] is not None) for o in rec["outputs"].values())

    batch_q = {}
    if ex.batched_route is not None:
        batched = api.sweep(ex_id, ranges={name: [float(params[name])], **fixed})
        assert len(batched.points) == 1 and batched.points[0].agree == solved["agree"]
        batch_q = {q.name: q for q in batched.points[0].quantities}

    for out in solve_q:
        ref = solve_q[out]
        for other in (check_q[out], point_q[out], grade_q[out]):
            assert _fields(other) == _fields(ref) and _bars(other) == _bars(ref), out
        if out not in batch_q:
            continue
        b = batch_q[out]
        # the batched route integrates all points together, with its own claims: the same verdict, and a
        # numeric value within both error bars of the scalar route's
        assert (b.agree, b.theory_valid) == (ref["agree"], ref.get("theory_valid")), out
        if ref["numeric"] is not None:
            assert abs(b.numeric - ref["numeric"]) <= b.numeric_err + ref["numeric_err"], out


# -- answers: the verdicts a physicist would give (issue 23 item 6) -----------------------------------------

def run(*args):
    r = CliRunner().invoke(cli, ["solve", *args, "--json"])
    return r.exit_code, json.loads(r.stdout)


def _expected(d, name):
    return next(q for q in d["quantities"] if q["name"] == name)["expected"]


def test_an_axis_is_judged_modulo_pi():
    # 4.3 at a = b: the in-plane tensor is [[A, c], [c, A]] with A = M a^2/18, c = M a^2/36, whose smaller
    # eigenvalue's axis is (1, -1): theta1 = -45 deg.  135 deg is the same axis; 45 deg the perpendicular one
    code, d = run("4.3", "--expect", "theta1=135deg")
    assert code == 0 and _expected(d, "theta1")["match"] is True
    assert "same axis" in _expected(d, "theta1")["verdict"]
    code, d = run("4.3", "--expect", "theta1=45deg")
    assert code == 1 and _expected(d, "theta1")["hint"].startswith("another principal axis")


def test_a_sign_slip_is_named_only_within_half_a_unit_of_the_last_digit():
    # 4.8: the strike's angular impulse about the vertical is -b P, so omega_z = -b P / (2/5 M R^2)
    # = -0.625 P / (M R) = -0.625 * 0.34 / (0.17 * 0.028575) = -43.7445; 43.74 is the sign slip to its
    # digits; 43.75 is 0.0055 away from it, beyond half a unit (0.005): a hint is a claim, not named (issue 39)
    code, d = run("4.8", "--expect", "omega_z=43.74")
    e = _expected(d, "omega_z")
    assert code == 1 and e["match"] is False and e["hint"] == "wrong sign"
    code, d = run("4.8", "--expect", "omega_z=43.75")
    e = _expected(d, "omega_z")
    assert code == 1 and e["match"] is False and e["hint"] is None


def test_a_power_of_ten_is_named():
    # 4.8: slip 3 m/s, decelerating at 3.5 mu g: t = 3/6.867 = 0.436872 s, x = 2 t - mu g t^2/2 = 0.686513 m;
    # 68.65 is that length in cm given as m
    code, d = run("4.8", "--expect", "x_roll=68.65")
    assert code == 1 and _expected(d, "x_roll")["hint"] == "off by a power of ten (x100: cm given as m?)"


def test_an_expression_is_judged_to_its_least_precise_number():
    # 4.15 at 60 deg: omega_c = sqrt(9.81 sin 60 deg) = 2.914740; sqrt(9.81 * 0.866) = 2.914697 is 1.5e-5
    # away, inside 0.866's half unit (5.8e-4 relative); times 1.01 it is 1.0 % off, beyond 1.01's 0.5 %
    code, d = run("4.15", "--theta0", "60deg", "--expect", "omega_c=(9.81*0.866)^0.5")
    e = _expected(d, "omega_c")
    assert code == 0 and e["match"] is True and "0.866" in e["verdict"]
    assert e["tol"] == pytest.approx(0.0005 / 0.866 * math.sqrt(9.81 * 0.866), rel=1e-6)
    code, d = run("4.15", "--theta0", "60deg", "--expect", "omega_c=(9.81*0.866)^0.5*1.01")
    assert code == 1 and _expected(d, "omega_c")["match"] is False


def test_an_expression_of_exact_numbers_stays_exact():
    from mech.students.expectations import parse_expectation
    from mech.problems import registry

    ex = registry.get("4.15")
    e = parse_expectation(ex, "omega_c", "2*pi/921.5")  # 921.5: 4 digits, half unit 0.05 of 921.5
    assert e.digits == 4 and e.written_tol == pytest.approx(0.05 / 921.5 * 2 * math.pi / 921.5, rel=1e-12)
    e = parse_expectation(ex, "omega_c", "2*pi/3")
    assert e.digits is None and e.written_tol == 0


def test_degrees_given_as_radians_quotes_mechs_value_in_degrees():
    # theta_c = asin(1/sqrt 3) = 35.2644 deg = 0.615480 rad
    code, d = run("4.15", "--theta0", "60deg", "--expect", "theta_c=35.26")
    e = _expected(d, "theta_c")
    assert code == 1 and e["hint"] == "degrees given as radians" and "35.2644 deg" in e["verdict"]

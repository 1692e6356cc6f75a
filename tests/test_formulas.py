"""Formulas as answers (issue 24): the parser, dimensions, points, verdicts, the CLI, grade files, fuzz.

Expected values are worked by hand here (the dimension of sqrt(g*l) is m/s; asin(2/3) is 41.81 deg; the
4.15 ladder leaves the wall at sin(theta_c) = (2/3) sin(theta0), from energy conservation and the wall's
force vanishing), never read off mech's solvers.
"""

from __future__ import annotations

import dataclasses
import json
import math
import time
import tracemalloc
from fractions import Fraction

import numpy as np
import pytest
from conftest import mech_cli
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mech.students import expectations
from mech.problems import registry
from mech.problems.spec import BadInput
from mech.students import explain as X
from mech.students import formulas as F
from mech.students import points as P
from mech.students.formula_ast import (MAX_DEPTH, MAX_LENGTH, FormulaError, dim_text, parse_formula)

EX = registry.get("4.15")


def _mech(*args):
    return mech_cli(*args)  # in this process: what the command prints and exits with (conftest)


# -- the parser ----------------------------------------------------------------------------------------

def _value(text, ex=EX, **params):
    f = parse_formula(text, ex)
    env = {k: np.array([float(v)]) for k, v in params.items()}
    return float(f.evaluate(env)[0][0]) if env else float(f.evaluate({"_": np.zeros(1)})[0][0])


def test_arithmetic_functions_aliases_and_symbols():
    assert _value("asin(2/3*sin(theta0))", theta0=math.pi / 2) == pytest.approx(math.asin(2 / 3), rel=1e-15)
    assert _value("arcsin(2*sin(θ₀)/3)", theta0=math.pi / 2) == pytest.approx(math.asin(2 / 3), rel=1e-15)
    assert _value("2 l g", l=0.5, g=3.0) == 3.0  # a factor next to a name multiplies
    assert _value("l^2**1", l=3.0) == 9.0
    assert _value("-l^2", l=3.0) == -9.0  # the power binds tighter than the sign
    assert _value("2^3^2") == 512.0  # and to the right
    assert _value("ln(exp(1.5)) + log(1)") == pytest.approx(1.5, rel=1e-15)
    assert _value("atan2(1, -1)") == pytest.approx(3 * math.pi / 4, rel=1e-15)
    assert _value("abs(-2) + sqrt(16) + cosh(0) + tanh(0)") == 7.0
    assert _value("90deg") == pytest.approx(math.pi / 2, rel=1e-15)  # units convert to SI
    assert _value("0.4*M_prime", ex=registry.get("4.13"), M_prime=5.0) == 2.0
    assert _value("M'/2", ex=registry.get("4.13"), M_prime=5.0) == 2.5  # a symbol with a prime
    assert _value("5*(h/R)", ex=registry.get("4.8"), h_over_R=0.5) == 2.5  # a symbol with a slash


def test_parameters_win_over_units_of_the_same_name():
    # in 4.15 g is gravity, not the gram; in 4.7 m is the rod's mass, not the metre
    assert parse_formula("g", EX).dim == (Fraction(1), Fraction(0), Fraction(-2))
    assert parse_formula("m", registry.get("4.7")).dim == (Fraction(0), Fraction(1), Fraction(0))


@pytest.mark.parametrize("text, why", [
    ("asin(2/3*sin(foo))", "unknown name 'foo'"), ("sin", "is a function"), ("sin(1, 2)", "takes 1 argument"),
    ("atan2(1)", "takes 2 arguments"), ("(theta0", "missing ')'"), ("theta0 +", "ends too early"),
    ("2 3", "side by side"), ("theta0 $ 2", "unexpected character"), ("", "empty"), ("1e999*l", "not a finite"),
])
def test_unreadable_formulas_say_why(text, why):
    with pytest.raises(FormulaError, match=None) as info:
        parse_formula(text, EX)
    assert why in str(info.value)


def test_length_and_depth_are_bounded():
    with pytest.raises(FormulaError, match="too long"):
        parse_formula("theta0+" * 400 + "1", EX)
    with pytest.raises(FormulaError, match="nested too deeply"):
        parse_formula("sqrt(" * (MAX_DEPTH + 5) + "l" + ")" * (MAX_DEPTH + 5), EX)
    with pytest.raises(FormulaError, match="nested too deeply"):
        parse_formula("-" * (MAX_LENGTH - 10) + "l", EX)
    assert parse_formula("sqrt(" * 20 + "l" + ")" * 20, EX).dim is not None


def test_one_tokenizer_and_grammar_read_values_and_formulas():
    # formula_ast builds its tree with core.units' parser: it has no tokenizer or grammar of its own
    import inspect
    import re as re_module

    from mech.core import units
    from mech.students import formula_ast

    source = inspect.getsource(formula_ast)
    assert "re.compile" not in source and "class _Parser" not in source and "def _tokens" not in source
    assert formula_ast.parse is units.parse and formula_ast.tokens is units.tokens
    assert re_module.search(r"^import re$", source, re_module.M) is None
    # the same text read as a value and as a formula without parameters gives the same SI number:
    # 3 km/h = 3000 m / 3600 s; 2 pi rad per 4 s; (2 ft)^2 = (0.6096 m)^2
    for text, si in (("3 km/h", 3000 / 3600), ("2pi rad/(4 s)", math.pi / 2), ("(2 ft)^2", 0.6096**2),
                     ("-2^2", -4.0), ("1/(2 cm)", 50.0)):
        assert units.parse_quantity(text).value == pytest.approx(si, rel=1e-15)
        assert _value(text) == pytest.approx(si, rel=1e-15)
    # and the same grammar refuses the same slips, in the same words
    for text in ("2 3", "(1", "1 +", "1 $"):
        with pytest.raises(units.ValueError_) as as_value:
            units.parse_quantity(text)
        with pytest.raises(FormulaError) as as_formula:
            parse_formula(text, EX)
        assert str(as_value.value).replace("value", "formula") == str(as_formula.value)


def test_the_grammar_takes_any_meaning_for_its_parts():
    # core.units.parse with a builder that writes the expression back in prefix form: the precedence
    # and associativity are the grammar's, whatever the builder (worked by hand)
    from mech.core import units

    class Prefix:
        function = staticmethod(lambda name: 2 if name == "f" else None)
        number = staticmethod(lambda text: text)
        name = staticmethod(lambda text: text)
        neg = staticmethod(lambda a: f"(neg {a})")
        plus = staticmethod(lambda a: a)
        binary = staticmethod(lambda op, a, b: f"({op} {a} {b})")
        call = staticmethod(lambda fn, args: f"({fn} {' '.join(args)})")

    assert units.parse("a - b - c", Prefix) == "(- (- a b) c)"
    assert units.parse("-a^b^c", Prefix) == "(neg (^ a (^ b c)))"
    assert units.parse("2 a b / c", Prefix) == "(/ (* (* 2 a) b) c)"
    assert units.parse("f(a, b+1) x", Prefix) == "(* (f a (+ b 1)) x)"
    with pytest.raises(units.ValueError_, match="nested too deeply"):
        units.parse("(" * 30 + "a" + ")" * 30, Prefix, max_depth=20)


# -- dimensions -----------------------------------------------------------------------------------------

@pytest.mark.parametrize("text, dim", [
    ("sqrt(g*l)", "m/s"), ("sqrt(g/l)", "1/s"), ("l*theta0", "m"), ("g*l^2", "m^3/s^2"), ("sqrt(l)", "m^(1/2)"),
    ("asin(2/3)", "1"), ("abs(-g)", "m/s^2"), ("l^(3/2)", "m^(3/2)"),
])
def test_dimension_of_a_formula(text, dim):
    assert dim_text(parse_formula(text, EX).dim) == dim


@pytest.mark.parametrize("text, why", [
    ("l + g", "adds m and m/s^2"), ("sin(l)", "sin of m"), ("exp(g)", "exp of m/s^2"), ("l^theta0", "depends on"),
    ("2^l", "exponent has the dimension of m"), ("atan2(l, g)", "atan2 of m and m/s^2"),
])
def test_clashing_dimensions_are_named(text, why):
    f = parse_formula(text, EX)
    assert f.dim is None and why in f.dim_error


# -- points ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("ex_id", ["5.10", "5.8", "5.11", "5.12", "4.24", "4.20"])
def test_draws_stay_inside_joint_constraints_and_spread(ex_id):
    ex = registry.get(ex_id)
    pts = P.draw(ex, 24, F.DEFAULT_SEED)
    assert len(pts) == 24
    for p in pts:
        ex.resolve(dict(p))  # accepted by the exercise's own checks
    # spread: the draws are not all the defaults, every parameter takes several values
    for name in ex.param_map:
        assert len({p[name] for p in pts}) >= 6, name


def test_draws_repeat_with_the_seed_and_change_with_it():
    a = P.draw(EX, 8, 1)
    assert [dict(p) for p in a] == [dict(p) for p in P.draw(EX, 8, 1)]
    assert [dict(p) for p in a] != [dict(p) for p in P.draw(EX, 8, 2)]


def test_over_narrows_the_range():
    over = P.parse_over(EX, {"theta0": "10deg:60deg"})
    assert over["theta0"] == pytest.approx((math.radians(10), math.radians(60)))
    pts = P.draw(EX, 24, 3, over)
    assert all(math.radians(10) <= p.theta0 <= math.radians(60) for p in pts)
    with pytest.raises(BadInput, match="out of range"):
        P.parse_over(EX, {"theta0": "10deg:100deg"})
    with pytest.raises(BadInput, match="LO:HI"):
        P.parse_over(EX, {"theta0": "10deg"})


# -- verdicts through the command line (the done-when) --------------------------------------------

def test_done_when_right_formula():
    r = _mech("solve", "4.15", "--expect", "theta_c=asin(2/3*sin(theta0))", "--json")
    assert r.returncode == 0, r.stderr
    e = json.loads(r.stdout)["quantities"][0]["expected"]
    assert e["match"] and e["formula"] == "asin(2/3*sin(theta0))"
    assert e["dimension"] == {"ok": True, "yours": "1", "output": "rad"}
    assert e["points"]["checked"] == e["points"]["right"] >= 26  # 24 drawn, the given point, a hard case
    assert e["depends"] == []
    # the 90 deg default: mech's value is asin(2/3), 41.81 deg
    assert e["value"] == pytest.approx(math.asin(2 / 3), rel=1e-15)


def test_done_when_right_only_at_the_defaults():
    r = _mech("solve", "4.15", "--expect", "theta_c=asin(2/3)")
    assert r.returncode == 1
    assert "theta0" in r.stdout and "right when only l and g change" in " ".join(r.stdout.split())


def test_done_when_wrong_dimension():
    r = _mech("solve", "4.15", "--expect", "omega_c=sqrt(g*l)")
    assert r.returncode == 1
    assert "your formula has the dimension of m/s; omega_c is in rad/s" in " ".join(r.stdout.split())


def test_done_when_domain_error():
    r = _mech("solve", "4.15", "--expect", "theta_c=asin(1.2*sin(theta0))")
    assert r.returncode == 1
    assert "asin of 1.2" in r.stdout


def test_options_and_refusals():
    r = _mech("solve", "4.15", "--expect", "theta_c=asin(2/3*sin(theta0))", "--expect-points", "5",
              "--expect-seed", "7", "--json")
    assert r.returncode == 0
    assert json.loads(r.stdout)["quantities"][0]["expected"]["points"]["checked"] == 7  # 5 + given + hard case
    for args, word in ((["--expect-points", "0"], "--expect-points"), (["--expect-points", "x"], "--expect-points"),
                       (["--expect", "theta_c=sin(nope)"], "unknown name 'nope'")):
        extra = [] if "--expect" in args else ["--expect", "theta_c=asin(2/3*sin(theta0))"]
        r = _mech("solve", "4.15", *extra, *args)
        assert r.returncode == 2 and word in r.stderr and "Traceback" not in r.stderr
        assert len(r.stderr.strip().splitlines()) == 1


def test_a_number_stays_a_number():
    # '3 m' is a length even in 4.7, where m names the rod's mass: it reads as a value first
    e = expectations.parse_expectation(EX, "theta_c", "41.81deg")
    assert e.formula is None and e.digits == 4


# -- judging details ------------------------------------------------------------------------------------

def _judge(ex_id, out, text, **params):
    import mech

    sol = mech.solve(ex_id, **params, expect={out: text})
    expected = next(q for q in sol.quantities if q.name == out).expected
    return expected.as_json() if hasattr(expected, "as_json") else expected


def test_the_api_takes_the_number_of_points_and_their_seed():
    import mech

    def judged(**kw):
        sol = mech.solve("4.15", expect={"theta_c": "asin(2/3*sin(theta0))"}, **kw)
        return sol["theta_c"].expected

    few, more = judged(expect_points=3, expect_seed=1), judged(expect_points=9, expect_seed=1)
    assert few.match and more.match
    # six more drawn points, the given point, defaults and hard cases the same
    assert more.formula["points"]["checked"] - few.formula["points"]["checked"] == 6
    assert "3 drawn across the range" in few.verdict and "9 drawn across the range" in more.verdict
    # a wrong formula (the 4.15 slip: right at 90 deg only) fails at a drawn point that moves with the seed
    # and repeats with it
    def worst(seed):
        sol = mech.solve("4.15", expect={"theta_c": "asin(2/3)"}, expect_points=4, expect_seed=seed)
        e = sol["theta_c"].expected
        assert not e.match
        return e.formula["points"]["worst"]["params"]["theta0"]

    assert worst(7) == worst(7) != worst(8)
    # as the CLI's --expect-points/--expect-seed, validated, the error naming the argument and its range
    for kw, why in ((dict(expect_points=0), "expect_points: cannot use '0'"),
                    (dict(expect_points=2.5), "expect_points: cannot use '2.5'"),
                    (dict(expect_points=10_001), "[1, 10000]"),
                    (dict(expect_seed=-1), "expect_seed: cannot use '-1'"),
                    (dict(expect_seed="x"), "expect_seed: cannot use 'x'"),
                    (dict(expect_points=True), "expect_points: cannot use 'True'")):
        with pytest.raises(mech.BadInput) as info:
            judged(**kw)
        assert why in str(info.value)
    with pytest.raises(mech.BadInput, match="without any formula"):
        mech.solve("4.15", expect_points=5)


def test_cancellation_is_ill_conditioned_not_wrong():
    # zeta - sqrt(zeta^2 - 1) at zeta = 1e6 keeps ~6 of 16 digits; 1/(zeta + sqrt(zeta^2 - 1)) keeps all
    e = _judge("5.4", "lambda_slow", "omega0*(zeta - sqrt(zeta^2-1))", zeta="1e6")
    assert e["match"] and "ill-conditioned" in e["verdict"]
    assert not _judge("5.4", "lambda_slow", "omega0*(zeta - sqrt(zeta^2-1))*1.0001", zeta="1e6")["match"]


def test_exact_zero_and_round_off_at_90_degrees():
    # L_perp = M l^2 |omega| sin(beta) cos(beta) / 12 is 0 at beta = 90 deg; sin(2 beta) gives 1.2e-16 there
    assert _judge("4.4", "L_perp", "M*l^2*abs(omega)*sin(2*beta)/24", beta="90deg")["match"]


def test_over_restricts_a_formula_that_holds_only_in_part_of_the_range(tmp_path):
    # the underdamped Green's function is right for delta < omega0 only: its sqrt fails above
    text = "exp(-delta*tau)*sin(sqrt(omega0^2-delta^2)*tau)/(m*sqrt(omega0^2-delta^2))"
    e = _judge("5.1", "G", text)
    assert not e["match"] and "cannot be evaluated" in e["verdict"]
    f = tmp_path / "a.toml"
    f.write_text('[[answer]]\nexercise = "5.1"\nexpect = { G = "' + text + '" }\n'
                 'over = { delta = "0.01:0.5", omega0 = "1:10" }\npoints = 12\n')
    r = _mech("grade", str(f), "--json")
    assert r.returncode == 0, r.stdout
    q = next(q for q in json.loads(r.stdout)["entries"][0]["quantities"] if q["name"] == "G")
    assert q["expected"]["points"]["right"] == q["expected"]["points"]["checked"] >= 12


def test_grade_file_with_formulas_and_junit(tmp_path):
    f = tmp_path / "class.toml"
    f.write_text('[[answer]]\nexercise = "4.15"\nexpect = { theta_c = "asin(2/3*sin(theta0))" }\n'
                 'points = 10\nover = { theta0 = "10deg:60deg" }\n\n'
                 '[[answer]]\nexercise = "4.15"\nexpect = { theta_c = "asin(2/3)", omega_c = "sqrt(g/l)" }\n')
    junit = tmp_path / "j.xml"
    r = _mech("grade", str(f), "--json", "--junit", str(junit))
    assert r.returncode == 1
    d = json.loads(r.stdout)
    assert (d["passed"], d["failed"]) == (1, 2)
    assert junit.read_text().count("<testcase") == 3
    bad = tmp_path / "bad.toml"
    bad.write_text('[[answer]]\nexercise = "4.15"\nexpect = { theta_c = "0.7" }\npoints = 10\n')
    r = _mech("grade", str(bad), "--strict")  # without --strict: graded invalid, exit 1 (test_grade_invalid.py)
    assert r.returncode == 2 and "points: only for formulas" in r.stderr


def test_references_are_computed_once_per_exercise_and_point():
    ex = registry.get("4.10")
    p = ex.resolve({})
    P._CACHE.clear()
    P._SHARED.clear()
    a = P.point_set(ex, p)
    assert P.point_set(ex, p) is a


def test_each_point_is_solved_once_and_a_right_formula_asks_for_no_hints(monkeypatch):
    # 4.32 at R_E/r_S = 0.1, M_S/M_E = 1e-3: its analytic series is the costliest of the book (ms a point).
    # The solve's own values stand at the given point; the hints' lines come back to it without solving it again
    import mech

    ex = registry.get("4.32")
    calls = []
    real = type(ex).solve_analytic

    def counted(self, p):
        if self is ex:
            calls.append(dict(p))
        return real(self, p)

    P._CACHE.clear()
    P._SHARED.clear()
    r_s, m_s = 10 * ex.param_map["R_E"].default, 1e-3 * ex.param_map["M_E"].default
    sol = mech.solve("4.32", r_S=r_s, M_S=m_s, expect={"h_high": "M_S/M_E*R_E^4/r_S^3"}, expect_rtol=0.5)
    monkeypatch.setattr(type(ex), "solve_analytic", counted)
    P._CACHE.clear()
    P._SHARED.clear()
    given = sol.params
    ps = P.point_set(ex, given, known=F.known(sol))
    assert len(calls) == len(ps) - 1 and dict(given) not in calls  # every point but the given one, once
    # the leading-order tide, (M_S/M_E) R_E^4/r_S^3 at the sub-solar point, is within 50 % of the exact one
    # at every point (the multipole sum alone is 1/(1 - R_E/r_S) <= 1/0.7 of it): right, with no hint work
    q = sol["h_high"].expected
    assert q.match is True and not ps.lines and not ps.depends
    calls.clear()
    line = P.line_of(ps, "M_S")
    assert len(calls) == len(line) and all(c != dict(given) for c in calls)
    calls.clear()
    X._limits(parse_formula("M_S/M_E*R_E^4/r_S^3", ex), ps, "h_high")
    assert dict(given) not in calls  # each limit line starts at the given point, known already


def test_batched_references_agree_with_the_point_by_point_numeric_route():
    # 5.13's batched Floquet route against its scalar numeric solve (a different code path), point by point:
    # each verified value within the sum of the two claims; and a point the batch cannot verify gets none
    ex = registry.get("5.13")
    P._CACHE.clear()
    P._SHARED.clear()
    ps = P.point_set(ex, ex.resolve({}), 3, 5)
    idx = list(range(1, len(ps)))
    for name in ("omega_down", "omega_inv"):
        F._batched_numeric(ex, ps, idx, name)
        batched = {i: ps.numeric.pop((name, i)) for i in idx}
        for i in idx:
            scalar = F._verified_at(ex, ps, i, name)
            if batched[i] is None or scalar is None:
                assert batched[i] is None and (scalar is None or not np.isfinite(ps.analytic[name][i])), (name, i)
                continue
            (b, eb), (a, ea) = batched[i], scalar
            assert abs(b - a) <= eb + ea and 0 < eb < 1e-8 * abs(b), (name, i, b, a)


def test_a_formula_beyond_leading_order_is_held_against_the_batched_route(monkeypatch):
    # a "formula" that gives mech's scalar numeric value of 5.13's omega_down at every point (a student's
    # exact answer), not the leading-order one: right at every point, its references at the drawn points
    # from the batched route (the first point alone, then the rest at once), no point-by-point solve
    ex = registry.get("5.13")
    output = {o.name: o for o in ex.outputs}["omega_down"]
    P._CACHE.clear()
    P._SHARED.clear()
    ps = P.point_set(ex, ex.resolve({}), 3, 5)
    exact = np.array([F._verified_at(ex, ps, i, "omega_down")[0] for i in range(len(ps))])
    ps.numeric.clear()
    lead = ps.analytic["omega_down"]
    assert np.all(np.abs(exact - lead) > 1e-9 * np.abs(lead))  # the leading-order value misses them all

    class Exact:
        names = frozenset()

        def evaluate(self, env, dtype=np.float64):
            return exact.astype(dtype), np.zeros(len(exact), dtype), []

        def enclose(self, env, prec=None):  # the values taken as exact
            return exact.copy(), exact.copy(), []

    route = ex.batched_route
    calls = []
    real = route.numeric

    def counted(P, rtol, outputs, memo=None):
        calls.append(len(next(iter(P.values()))))
        return real(P, rtol, outputs, memo=memo)

    monkeypatch.setattr(ex, "batched_route", dataclasses.replace(route, numeric=counted))
    monkeypatch.setattr(type(ex), "solve_numeric", lambda *a, **k: pytest.fail("a point-by-point numeric solve"))
    pj = P.judge_points(Exact(), ps, lead.copy(), ps.analytic_err["omega_down"].copy(), F.FORMULA_RTOL)
    assert not pj.right.any()
    notes = []
    here = F._leading_order_numeric(Exact(), ex, output, ps, pj, F.FORMULA_RTOL, (exact[0], 1e-9 * exact[0]), notes)
    assert here.all() and pj.right.all()
    assert calls == [len(ps) - 1] * 2  # right at the given point: the others at once, at rtol and rtol/10
    assert f"at {len(ps)} points it matches mech's numeric value" in notes[0]
    # the given point outside the range the formula is meant for (not judged there): the first drawn point
    # is asked alone (a wrong formula stops there), then the others
    calls.clear()
    ps.numeric.clear()
    ps.batch_memo.clear()
    pj = P.judge_points(Exact(), ps, lead.copy(), ps.analytic_err["omega_down"].copy(), F.FORMULA_RTOL)
    pj.judged[0] = False
    here = F._leading_order_numeric(Exact(), ex, output, ps, pj, F.FORMULA_RTOL, None, [])
    assert here[1:].all() and not here[0]
    assert calls == [1, 1, len(ps) - 2, len(ps) - 2]


def test_a_batch_that_fails_leaves_its_points_to_the_point_by_point_route(monkeypatch):
    # 5.13's batched route raising: the exact answer (the scalar numeric values) is still right at every
    # point, verified one point at a time, never called wrong for want of a reference
    ex = registry.get("5.13")
    output = {o.name: o for o in ex.outputs}["omega_down"]
    P._CACHE.clear()
    P._SHARED.clear()
    ps = P.point_set(ex, ex.resolve({}), 3, 5)
    exact = np.array([F._verified_at(ex, ps, i, "omega_down")[0] for i in range(len(ps))])
    ps.numeric.clear()
    lead = ps.analytic["omega_down"]

    class Exact:
        names = frozenset()

        def evaluate(self, env, dtype=np.float64):
            return exact.astype(dtype), np.zeros(len(exact), dtype), []

        def enclose(self, env, prec=None):  # the values taken as exact
            return exact.copy(), exact.copy(), []

    real = ex.batched_route.numeric

    def broken(P, rtol, outputs, memo=None, tally=None):  # the batch fails; a point alone (its batch of one) runs
        if np.asarray(P["a"]).size > 1:
            raise FloatingPointError("the batch failed")
        return real(P, rtol, outputs, memo=memo, tally=tally)

    monkeypatch.setattr(ex, "batched_route", dataclasses.replace(ex.batched_route, numeric=broken))
    pj = P.judge_points(Exact(), ps, lead.copy(), ps.analytic_err["omega_down"].copy(), F.FORMULA_RTOL)
    here = F._leading_order_numeric(Exact(), ex, output, ps, pj, F.FORMULA_RTOL, (exact[0], 1e-9 * exact[0]), [])
    assert here.all() and pj.right.all()


# -- fuzz: any text, no traceback, no hang, bounded memory ----------------------------------------------

_ATOMS = ["theta0", "l", "g", "θ₀", "2", "0.5", "1e-300", "1e300", "pi", "deg", "m", "(", ")", "+", "-", "*", "/",
          "^", "**", ",", "sqrt(", "asin(", "log(", "exp(", "atan2(", "abs(", " ", "0", "tan(", "cosh("]


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.one_of(st.lists(st.sampled_from(_ATOMS), max_size=40).map("".join), st.text(max_size=60)))
def test_fuzz_formulas_never_crash(text):
    tracemalloc.start()
    t0 = time.perf_counter()
    try:
        f = parse_formula(text, EX)
    except FormulaError:
        pass
    else:
        pts = {k: np.array([0.3, 1.2, 1e-8]) for k in ("theta0", "l", "g")}
        y, err, problems = f.evaluate(pts)
        assert y.shape == (3,) and err.shape == (3,)
        if f.dim is not None:
            out = EX.outputs[0]
            ps = P.point_set(EX, EX.resolve({}), 6, 1)
            v = F.judge_formula(f, EX, out, ps, (float(ps.analytic["theta_c"][0]), 0.0), None)
            assert isinstance(v.verdict, str) and v.verdict
    assert time.perf_counter() - t0 < 5.0
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert peak < 50e6


def test_no_value_at_the_given_point_judges_the_others():
    # on the equator the Foucault plane does not turn (T_F infinite): the formula is held at the other points
    e = _judge("4.30", "T_F", "2*pi/(omega_E*abs(cos(theta)))", theta="90deg")
    assert e["match"] and "not at the given parameters" in e["verdict"]
    assert not _judge("4.30", "T_F", "2*pi/(omega_E*cos(theta))", theta="90deg")["match"]


def test_points_beyond_a_leading_order_theory_are_left_out(monkeypatch):
    # a declared range (here a made-up one: mu/omega0 <= 0.3) leaves those points out of the verdict
    ex = registry.get("5.9")
    monkeypatch.setattr(P, "theory_validity", lambda ex, p: {o: ("too strong" if p.mu / p.omega0 > 0.3 else None)
                                                              for o in ("A", "omega", "lambda_lc")})
    ps = P.point_set(ex, ex.resolve({}), 24, 11)
    out = next(o for o in ex.outputs if o.name == "A")
    n_out = int(ps.outside["A"].sum())
    assert 0 < n_out < len(ps)
    f = parse_formula("2/sqrt(beta)", ex)  # A = 2/sqrt(beta), the limit cycle's amplitude to leading order
    v = F.judge_formula(f, ex, out, ps, (float(ps.analytic["A"][0]), 0.0), None)
    assert v.match and v.points["checked"] == len(ps) - n_out and "not judged" in v.verdict
    P._CACHE.clear()
    P._SHARED.clear()

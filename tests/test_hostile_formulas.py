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
from conftest import mech_cli

from mech.problems import registry
from mech.students import points as P
from mech.students.formula_ast import FormulaError, parse_formula
from mech.students.formulas import judge_formula

HERE = pathlib.Path(__file__).parent


def _mech(*args, env=None, timeout=120, fresh=False):
    """``mech ARGS`` in this process (conftest's ``mech_cli``), or in a fresh Python where the command's own
    clock from its start, or what Python itself prints on standard error, is what a test is about."""
    if not fresh:
        return mech_cli(*args, env=env)
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


# -- the functions of the printed formulas --------------------------------------------------------------

# the printed formulas' functions that the formula language spells otherwise
_SPELLED = {"K": "ellipk", "E": "ellipe", "AGM": "agm", "ln": "ln"}
# printed functions that are not the language's, and why
_NOT_FUNCTIONS = {
    "cn": "Jacobi's elliptic function: 5.7's exact motion, not an answer's closed form",
    "P₂": "the Legendre polynomial (3x² - 1)/2: written out in an answer",
    "O": "order of the neglected terms",
    "max": "a maximum over the orbit (4.33)",
}


def _printed_functions():
    """{name: (exercise, formula)}: every ``name(`` of every exercise's printed formulas whose name is a run
    of two or more letters (a superscript dropped), or K/E before a parenthesis (the elliptic integrals),
    that is not one of the exercise's parameters, symbols or outputs (a product such as ``M (a² + b²)``)."""
    import re

    from mech.students.formula_ast import parameter_symbols

    found = {}
    for ex in registry.all_exercises().values():
        names = set(ex.param_map) | set(parameter_symbols(ex)) | {o.name for o in ex.outputs}
        for text in ex.formulas:
            for m in re.finditer(r"([^\W\d][\w₀-₉]*?)[²³⁴]?\s*\(", text):
                name = m.group(1)
                if name in names or name.split("_")[0] in names:
                    continue
                base = name.split("_")[0]
                if base in ("K", "E") and m.start() > 0 and not text[m.start() - 1].isalpha():
                    found.setdefault(base, (ex.id, text))
                elif re.fullmatch(r"[A-Za-z]{2,}\d*|[A-Za-z]₂|cn|O", base) \
                        and (base in ("ln", "cn") or not re.fullmatch(r"[a-z]_?[a-z]", base)):  # not ab(...)
                    found.setdefault(base, (ex.id, text))
    return found


def test_every_function_of_the_printed_formulas_is_accepted():
    from mech.students.formula_ast import FUNCTIONS

    found = _printed_functions()
    # the walk finds what the formulas print (checked by hand on mech show's formulas)
    assert {"sin", "cos", "atan2", "exp", "expm1", "sinh", "ln", "AGM", "K"} <= set(found), sorted(found)
    missing = {}
    for name, where in found.items():
        if name in _NOT_FUNCTIONS:
            continue
        if _SPELLED.get(name, name) not in FUNCTIONS:
            missing[name] = where
    assert not missing, missing
    ex = registry.get("4.20")
    # and they evaluate: K(1/2) = 1.854074677301372 (A&S table 17.1), E(1/2) = 1.350643881047676,
    # AGM(1, sqrt 2): Gauss's iteration, done here by hand
    a, b = 1.0, math.sqrt(2.0)
    for _ in range(8):
        a, b = (a + b) / 2, math.sqrt(a * b)
    one = {"_": np.zeros(1)}
    assert parse_formula("ellipk(0.5)", ex).evaluate(one)[0][0] == pytest.approx(1.854074677301372, rel=1e-14)
    assert parse_formula("ellipe(0.5)", ex).evaluate(one)[0][0] == pytest.approx(1.350643881047676, rel=1e-14)
    assert parse_formula("expm1(1e-10)", ex).evaluate(one)[0][0] == pytest.approx(1.00000000005e-10, rel=1e-15)
    ex = registry.get("5.6")
    f = parse_formula("AGM(l, sqrt(2)*l)", ex)
    assert f.dim == parse_formula("l", ex).dim
    assert f.evaluate({"l": np.array([1.0])})[0][0] == pytest.approx(a, rel=1e-15)
    assert parse_formula("agm(l, g)", ex).dim is None  # m and m/s^2: refused as mixing dimensions


def test_ellipe_against_scipy():
    import scipy.special as sc

    from mech.solvers.numerics.special import ellipe

    ms = np.concatenate([-np.logspace(-300, 308, 200), np.linspace(-5, 1, 601), 1 - np.logspace(-300, 0, 200),
                         [0.0, 1.0]])
    got = np.array([ellipe(m) for m in ms])
    assert np.allclose(got, sc.ellipe(ms), rtol=1e-13, atol=0)
    assert math.isnan(ellipe(1.5)) and math.isnan(ellipe(math.nan))


def test_the_5_6_frequency_shift_as_an_agm_formula_is_right():
    # 5.6: delta_omega = omega0 (AGM(1, cos(theta0/2)) - 1) (the exact pendulum period 2 pi / (omega0 AGM))
    # (omega0 = sqrt(g/l): 5.6 has l and g)
    v = _verdict("5.6", "domega", "sqrt(g/l)*(AGM(1, cos(theta0/2)) - 1)")
    assert v.match, v.verdict
    v = _verdict("5.6", "T", "4*ellipk(sin(theta0/2)^2)*sqrt(l/g)")
    assert v.match, v.verdict
    v = _verdict("5.6", "domega", "-sqrt(g/l)*theta0^2/16")
    assert not v.match


# -- the API: every user-caused failure is BadInput or NumericFailure, its message cut and escaped ------

_BAD = [10**400, -10**400, 10**5000, float("nan"), float("inf"), "a\x00b", "\x1f\x85\u200b1", "x" * 100000, [],
        {}, ["theta_c"], object(), b"bytes", True, -1, 1e308, (1, 2), {"a": 1}]


def _api_calls(b, tmp):
    import mech

    yield "exercise", lambda: mech.exercise(b)
    yield "exercises", lambda: mech.exercises(b)
    yield "solve id", lambda: mech.solve(b)
    yield "solve param", lambda: mech.solve("4.15", theta0=b, method="analytic")
    for kw in ("method", "rtol", "verify", "raise_on_failure", "expect", "expect_rtol"):
        yield f"solve {kw}", lambda kw=kw: mech.solve("4.15", method="analytic", **{kw: b}) if kw != "method" \
            else mech.solve("4.15", method=b)
    yield "solve expect value", lambda: mech.solve("4.15", method="analytic", expect={"theta_c": b})
    try:
        hash(b)
        yield "solve expect key", lambda: mech.solve("4.15", method="analytic", expect={b: "1"})
    except TypeError:
        pass
    f = {"theta_c": "asin(2/3*sin(theta0))"}
    yield "solve expect_points", lambda: mech.solve("4.15", method="analytic", expect=f, expect_points=b)
    yield "solve expect_seed", lambda: mech.solve("4.15", method="analytic", expect=f, expect_seed=b)
    yield "sweep param", lambda: mech.sweep("4.1", M=b)
    yield "sweep tuple", lambda: mech.sweep("4.1", M=(1, 2, b))
    for kw in ("only", "jobs", "budget", "method", "rtol", "verify"):
        yield f"sweep {kw}", lambda kw=kw: mech.sweep("4.1", M=(1, 2, 2), **{kw: b})
    yield "check ids", lambda: mech.check(b)
    yield "check hard", lambda: mech.check("4.1", hard=b)
    yield "grade path", lambda: mech.grade(b)
    yield "grade budget", lambda: mech.grade(str(tmp / "none.toml"), budget=b)
    # (a bench that runs is cut at 0.2 s: the test is about the arguments it refuses)
    for kw in ("methods", "tols", "max_seconds"):
        yield f"bench {kw}", lambda kw=kw: mech.bench("4.15", **{kw: b, "max_seconds": 0.2, "repeats": 1}) \
            if kw != "max_seconds" else mech.bench("4.15", max_seconds=b, repeats=1)
    yield "bench param", lambda: mech.bench("4.15", l=b, max_seconds=0.2, repeats=1)
    yield "plot id", lambda: mech.plot(b)
    yield "plot path", lambda: mech.plot("4.1", b if not isinstance(b, str) else str(tmp / b[:50]))
    yield "plot vary", lambda: mech.plot("4.1", str(tmp / "p.png"), vary=b)


def test_api_raises_bad_input_for_every_bad_argument(tmp_path):
    import warnings

    from mech import BadInput, NumericFailure

    wrong = []
    for b in _BAD:
        for label, call in _api_calls(b, tmp_path):
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("error")
                    call()
            except (BadInput, NumericFailure) as exc:
                text = str(exc)
                if len(text) > 400 or not text.isprintable():
                    wrong.append((label, repr(b)[:30], "message", text[:100]))
            except Exception as exc:  # noqa: BLE001  what the test is for
                wrong.append((label, repr(b)[:30], type(exc).__name__, str(exc)[:100]))
    assert not wrong, wrong[:10]


def test_a_flat_sum_is_bounded_by_length_not_depth():
    import mech

    text = "asin(2/3*sin(theta0))" + "+0" * 988  # 1997 characters, one level: exactly mech's theta_c
    sol = mech.solve("4.15", method="analytic", expect={"theta_c": text})
    assert sol["theta_c"].expected.verdict.startswith("right"), sol["theta_c"].expected.verdict
    text = "0*theta0" + "+1" * 995  # 995 rad: wrong, not "nested too deeply"
    sol = mech.solve("4.15", method="analytic", expect={"theta_c": text})
    assert sol["theta_c"].expected.verdict.startswith("wrong"), sol["theta_c"].expected.verdict


# -- budgets and memory -----------------------------------------------------------------------------------

def test_solve_budget_covers_the_formula_check():
    import time

    t0 = time.monotonic()
    r = _mech("solve", "4.32", "--expect", "h_high=M_S/M_E*R_E^4/r_S^3", "--expect-points", "10000",
              env={"MECH_BUDGET_S": "1"}, fresh=True)
    assert time.monotonic() - t0 < 10, r.stdout  # was 35 s
    assert r.returncode == 1, r.stdout + r.stderr
    assert "not graded (budget)" in r.stdout and "Traceback" not in r.stderr


def test_grade_budget_covers_the_formula_checks(tmp_path):
    import time

    hw = tmp_path / "hw.toml"
    hw.write_text("".join('[[answer]]\nexercise = "4.32"\npoints = 10000\n'
                          'expect = { h_high = "M_S/M_E*R_E^4/r_S^3" }\n\n' for _ in range(6)))
    t0 = time.monotonic()
    r = _mech("grade", str(hw), "--budget", "2", fresh=True)
    assert time.monotonic() - t0 < 15, r.stdout  # was 37 s, every entry graded
    assert r.returncode == 1 and "not graded" in r.stdout, r.stdout + r.stderr


def test_a_wrong_dimension_draws_no_point(monkeypatch):
    calls = []
    monkeypatch.setattr(P, "draw", lambda *a, **k: calls.append(a) or [])
    ex = registry.get("4.15")
    out = ex.outputs[0]
    from mech.students import answers

    # m^3/s^2 for an angle: no square, square root or parameter left out explains it, so no point is drawn
    f = parse_formula("l^2*g", ex)
    v = judge_formula(f, ex, out, lambda: P.point_set(ex, ex.resolve({}), 10000, 5), (0.7, 0.0), None)
    assert v.verdict.startswith("wrong dimension") and not calls
    assert answers  # the answers judge hands the point set over the same way (a callable)


def test_a_wrong_dimension_names_its_slip_at_no_more_than_the_default_points():
    """l*theta0 for an angle could be an l too many: that slip is tried at the default number of points,
    never the 10000 the entry asked for."""
    asked = []
    ex = registry.get("4.15")

    def ps(at_most=None):
        asked.append(at_most)
        return P.point_set(ex, ex.resolve({}), 10000 if at_most is None else min(10000, at_most), 5)

    v = judge_formula(parse_formula("l*theta0", ex), ex, ex.outputs[0], ps, (0.7, 0.0), None)
    assert v.verdict.startswith("wrong dimension")
    assert asked == [P.DEFAULT_POINTS]


def test_cache_is_bounded_in_bytes(monkeypatch):
    """The bound is in bytes: with it set to 8 MB, point sets of 2000 points are dropped oldest first.  By
    hand, 2000 points of 4.15's 3 parameters and 2 outputs at 400 + 250 x 5 bytes each are 3.3 MB, so at
    most 2 of the shared parts stay under 8 MB (64 MB and 40 sets test the same rule at 5 times the cost)."""
    monkeypatch.setattr(P, "CACHE_BYTES", 8 * 2**20)
    ex = registry.get("4.15")
    P._CACHE.clear()
    P._SHARED.clear()
    for seed in range(8):
        P.point_set(ex, ex.resolve({}), 2000, 1000 + seed)
    assert sum(P.size_of(v) for v in P._CACHE.values()) <= P.CACHE_BYTES
    assert 0 < len(P._CACHE) < 8
    assert sum(v["bytes"] for v in P._SHARED.values()) <= P.CACHE_BYTES
    assert 0 < len(P._SHARED) <= 2
    P._CACHE.clear()
    P._SHARED.clear()


def test_class_file_of_10000_points_under_500_mb(tmp_path):
    """100 entries of 10000 points each under a 500 MB address-space limit: the entries graded before the
    budget stops (about one a second) stay within it, and the rest are "not graded (budget)" verdicts in a
    report that is written whole.  (The bound on what is kept across entries is test_cache_is_bounded_in_bytes.)"""
    hw = tmp_path / "hw.toml"
    hw.write_text("".join(f'[[answer]]\nexercise = "4.15"\npoints = 10000\nseed = {k}\n'
                          'expect = { theta_c = "asin(2/3*sin(theta0))" }\n\n' for k in range(100)))
    code = ("import resource, sys; resource.setrlimit(resource.RLIMIT_AS, (500 * 2**20, 500 * 2**20)); "
            "from mech.cli.main import main; sys.argv = ['mech', 'grade', sys.argv[1], '--budget', '2.5']; main()")
    r = subprocess.run([sys.executable, "-c", code, str(hw)], capture_output=True, text=True, timeout=120,
                       env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
    assert "Traceback" not in r.stderr and "MemoryError" not in r.stderr, r.stderr[-2000:]
    assert r.returncode == 1, r.stderr[-500:]
    assert "answers right" in r.stdout and "(100 entries)" in r.stdout, r.stdout[-500:]


def test_memory_error_is_one_line(tmp_path):
    code = ("import sys; import mech.cli.main as m; from mech import api; "
            "api.solve_resolved = lambda *a, **k: (_ for _ in ()).throw(MemoryError()); "
            "sys.argv = ['mech', 'solve', '4.15']; m.main()")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    lines = r.stderr.strip().splitlines()
    assert r.returncode in (2, 3) and len(lines) == 1 and "out of memory" in lines[0], r.stderr


# -- one entry never decides the class ----------------------------------------------------------------------

def test_the_two_internal_errors_are_verdicts_inside_a_class_file(tmp_path):
    nested = "(" * 15 + "l" + "^1e300)" * 15 + "/l"
    hw = tmp_path / "hw.toml"
    hw.write_text(f'''
[[answer]]
exercise = "4.15"
expect = {{ theta_c = "asin(2/3*sin(theta0))*1e307" }}

[[answer]]
exercise = "4.15"
expect = {{ theta_c = "{nested}" }}

[[answer]]
exercise = "4.15"
expect = {{ theta_c = "asin(2/3*sin(theta0))" }}
''')
    junit = tmp_path / "out.xml"
    r = _mech("grade", str(hw), "--junit", str(junit))
    assert r.returncode == 1 and "internal error" not in r.stdout + r.stderr, r.stdout + r.stderr
    assert "1 of 3 answers right" in r.stdout, r.stdout
    assert "off by a constant factor" in r.stdout and "wrong dimension" in r.stdout
    assert junit.exists()


def test_junit_onto_the_answers_file_is_refused(tmp_path):
    hw = tmp_path / "hw.toml"
    text = '[[answer]]\nexercise = "4.15"\nexpect = { theta_c = "41.81deg" }\n'
    hw.write_text(text)
    r = _mech("grade", str(hw), "--junit", str(hw))
    assert r.returncode == 2 and "the same file" in r.stderr, r.stderr
    assert hw.read_text() == text
    os.link(hw, tmp_path / "link.toml")
    r = _mech("grade", str(hw), "--junit", str(tmp_path / "link.toml"))
    assert r.returncode == 2 and hw.read_text() == text
    base = tmp_path / "b.json"
    base.write_text("{}")
    r = _mech("check", "4.1", "--baseline", str(base), "--save-baseline", str(tmp_path / "." / "b.json"))
    assert r.returncode == 2 and "the same file" in r.stderr and base.read_text() == "{}"
    r = _mech("check", "4.1", "--junit", str(tmp_path / "j.xml"), "--save-baseline", str(tmp_path / "j.xml"))
    assert r.returncode == 2 and "the same file" in r.stderr


# -- edges ------------------------------------------------------------------------------------------------

def test_over_with_no_admissible_point_is_a_bad_file(tmp_path):
    hw = tmp_path / "hw.toml"
    hw.write_text('[[answer]]\nexercise = "4.13"\nover = { R = "1:2", R_prime = "0.01:0.5" }\n'
                  'expect = { omega = "sqrt(g/R)" }\n')  # R' > R cannot hold there
    r = _mech("grade", str(hw), "--strict")
    assert r.returncode == 2 and "over" in r.stderr and "R_prime = 0.01:0.5" in r.stderr, r.stderr
    r = _mech("grade", str(hw))  # the class's tolerant grading: that entry invalid, naming it
    assert r.returncode == 1 and "invalid" in r.stdout and "R_prime = 0.01:0.5" in r.stdout, r.stdout


def test_reference_overflow_points_are_left_out_and_counted():
    ex = registry.get("4.15")
    over = P.parse_over(ex, {"l": "1e-300:1e300", "g": "1e-300:1e300"})
    ps = P.point_set(ex, ex.resolve({}), 60, 3, over)
    gone = sum(w == "not finite" for w in ps.undefined["omega_c"][1:])
    f = parse_formula("sqrt(g*sin(theta0)/l)", ex)
    given = (float(ps.analytic["omega_c"][0]), float(ps.analytic_err["omega_c"][0]))
    v = judge_formula(f, ex, ex.outputs[1], ps, given, None)
    assert v.match, v.verdict  # l^2-like overflow in the formula: judged in exact arithmetic
    if gone:
        assert "overflows left out" in v.verdict


def test_juxtaposed_pi_and_root_read_as_a_product():
    ex = registry.get("5.6")
    f = parse_formula("2π√(l/g)", ex)
    assert f.evaluate({"l": np.array([1.0]), "g": np.array([9.81])})[0][0] == pytest.approx(
        2 * math.pi * math.sqrt(1 / 9.81), rel=1e-15)
    with pytest.raises(FormulaError, match="side by side"):
        parse_formula("pisqrt(l/g)", ex)


def test_formula_followed_by_its_own_unit_is_never_squared():
    ex = registry.get("5.6")
    f = parse_formula("2*pi*sqrt(l/g) s", ex)
    assert f.dim == parse_formula("sqrt(l/g)", ex).dim  # s, not s^2
    with pytest.raises(FormulaError, match="unit 'ms'"):
        parse_formula("2*pi*sqrt(l/g) ms", ex)


def test_control_characters_never_reach_the_yours_column():
    for ch in ("\x1f", "\x85", "\u200b"):
        r = _mech("solve", "4.15", "--expect", f"theta_c=asin(2/3*sin(theta0)){ch}")
        assert r.returncode == 2, r.stdout
        assert ch not in r.stdout + r.stderr and ascii(ch)[1:-1] in r.stderr, r.stderr


def test_runtime_warnings_never_reach_stderr():
    r = _mech("solve", "5.11", "--expect", "mu_th=4*delta/omega0", "--expect-seed", "5", fresh=True)
    assert "Warning" not in r.stderr and r.returncode in (0, 1), r.stderr
    r = _mech("solve", "4.15", "--expect", "theta_c=asin(2/3*sin(theta0))*1e308*10", fresh=True)
    assert "Warning" not in r.stderr and r.returncode == 1 and "internal error" not in r.stderr, r.stderr

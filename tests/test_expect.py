"""mech solve --expect: your own answers judged to the digits written, with slip hints.

Hand values used throughout (4.15, the sliding ladder): sin(theta_c) = (2/3) sin(theta0) and
omega_c^2 = g sin(theta0) / l.  At theta0 = 60 deg, l = 1 m, g = 9.81 m/s^2:
  theta_c = asin((2/3)(sqrt(3)/2)) = asin(1/sqrt(3)) = 0.6154797 rad = 35.2644 deg,
  omega_c = sqrt(9.81 * 0.8660254) = sqrt(8.4957) = 2.91474 rad/s,
and with g left out (g = 1): sqrt(0.8660254) = 0.930605 rad/s.
"""

import json
import math
from types import SimpleNamespace

import pytest
from click.testing import CliRunner

from mech.students.expectations import _literal_precision, parse_expectation
from mech.cli.main import cli
from mech.problems.spec import BadInput, Output, Undefined
from mech.students.answers import judge
from mech.verification.judge import Verdict
from mech.verification.result import Quantity

THETA_C = math.asin(1 / math.sqrt(3))
THETA_C_DEG = math.degrees(THETA_C)  # 35.2644
OMEGA_C = math.sqrt(9.81 * math.sqrt(3) / 2)


def run(*args):
    result = CliRunner().invoke(cli, list(args))
    return result.exit_code, result.stdout, result.stderr


def solve_4_15(*expects, extra=()):
    return run("solve", "4.15", "--theta0", "60deg", *[a for e in expects for a in ("--expect", e)], *extra)


# -- the acceptance cases ---------------------------------------------------------------------------

def test_right_to_the_digits_written_exits_0():
    code, out, err = solve_4_15("theta_c=35.26deg")
    assert code == 0, err
    assert "right to 4 digits" in out and "yours" in out and "35.26deg" in out


def test_a_factor_2_slip_is_named_and_exits_1():
    code, out, _ = solve_4_15("theta_c=70.53deg")  # 2 * 35.2644 = 70.529
    assert code == 1
    assert "off by a factor 2" in out


def test_degrees_given_as_radians_is_named():
    code, out, _ = solve_4_15("theta_c=35.26")  # a plain number is radians: 35.26 rad
    assert code == 1
    assert "degrees given as radians" in out


def test_json_carries_expected_and_expect_ok():
    code, out, _ = solve_4_15("theta_c=35.26deg", "omega_c=5.83", extra=("--json",))
    assert code == 1
    d = json.loads(out)
    assert d["expect_ok"] is False and d["agree"] is True
    theta, omega = d["quantities"]
    assert theta["expected"]["match"] is True and theta["expected"]["hint"] is None
    assert theta["expected"]["value"] == pytest.approx(math.radians(35.26), rel=1e-15)
    assert theta["expected"]["rel_err"] == pytest.approx(abs(35.26 - THETA_C_DEG) / THETA_C_DEG, rel=1e-6)
    assert theta["expected"]["reference"] == "analytic"
    assert omega["expected"]["match"] is False
    assert omega["expected"]["hint"] == "off by a factor 2"  # 2 * 2.91474 = 5.8295 -> 5.83 to 3 digits
    assert omega["expected"]["rel_err"] == pytest.approx(5.83 / OMEGA_C - 1, rel=1e-6)


def test_quantities_not_named_carry_no_expected():
    code, out, _ = solve_4_15("omega_c=2.91 rad/s", extra=("--json",))
    assert code == 0
    theta, omega = json.loads(out)["quantities"]
    assert "expected" not in theta and omega["expected"]["match"] is True


def test_one_digit_more_than_is_right_fails():
    # 35.27 is 0.0056 deg from 35.2644, more than half a unit (0.005) in its last digit
    code, out, _ = solve_4_15("theta_c=35.27deg")
    assert code == 1 and "off by 0.016 %" in out


def test_expect_rtol_replaces_the_written_digits():
    # 0.62 rad is 0.73 % above 0.61548: right within 1 %, wrong within 0.1 %
    assert solve_4_15("theta_c=0.62", extra=("--expect-rtol", "0.01"))[0] == 0
    assert solve_4_15("theta_c=0.62", extra=("--expect-rtol", "1e-3"))[0] == 1


def test_g_left_out_is_found_through_the_exercises_own_solver():
    code, out, _ = solve_4_15("omega_c=0.9306", extra=("--json",))
    assert code == 1
    assert json.loads(out)["quantities"][1]["expected"]["hint"] == "g left out (taken as 1)"


def test_analytic_only_says_it_is_not_cross_checked():
    code, out, _ = solve_4_15("theta_c=35.26deg", extra=("--method", "analytic", "--json"))
    assert code == 0
    assert json.loads(out)["quantities"][0]["expected"]["reference"] == "analytic (not cross-checked)"


@pytest.mark.parametrize("args, words", [
    (["--expect", "theta_x=1"], "theta_x"),
    (["--expect", "theta_c=2m"], "length"),
    (["--expect", "theta_c=abc"], "abc"),
    (["--expect", "theta_c"], "NAME=VALUE"),
    (["--expect", "theta_c=1", "--expect", "theta-c=2"], "more than once"),
    (["--expect-rtol", "0.01"], "without any --expect"),
    (["--expect", "theta_c=1", "--expect-rtol", "2"], "out of range"),
])
def test_a_bad_expect_exits_2_in_one_line(args, words):
    code, out, err = run("solve", "4.15", *args)
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and words in err and "Traceback" not in err


# -- reading the digits written ------------------------------------------------------------------------------

@pytest.mark.parametrize("literal, half_unit, digits", [
    ("35.26", 0.005, 4), ("0.6155", 0.00005, 4), ("1e-3", 0.0005, 1), ("2.50e3", 5.0, 3),
    ("3500", 0.5, 4), (".5", 0.05, 1), ("7.", 0.5, 1), ("0.000", 0.0, None), ("0e300", 0.0, None),
])
def test_literal_precision(literal, half_unit, digits):
    # as written (min_digits 0): a zero in any form is exactly zero
    h, d = _literal_precision(literal)
    assert h == pytest.approx(half_unit, rel=1e-12) and d == digits


def _fake_ex(*outputs):
    return SimpleNamespace(id="9.9", outputs=[Output(n, u) for n, u in outputs])


def test_parse_expectation_units_and_exponents():
    ex = _fake_ex(("a", "m/s^2"), ("phi", "rad"))
    e = parse_expectation(ex, "a", "981 cm/s^2")  # the 2 of s^2 is not a digit of the value
    assert e.value == pytest.approx(9.81) and e.digits == 3
    assert e.written_tol == pytest.approx(0.005)  # half of 1 cm/s^2, in m/s^2
    e = parse_expectation(ex, "phi", "-35.26 deg")
    assert e.value == pytest.approx(-math.radians(35.26)) and e.unit_text == "deg"
    assert e.written_tol == pytest.approx(math.radians(0.005))
    e = parse_expectation(ex, "phi", "pi/3")  # an expression is exact: no written tolerance
    assert e.digits is None and e.written_tol == 0 and e.value == pytest.approx(math.pi / 3)
    with pytest.raises(BadInput, match="not an output"):
        parse_expectation(ex, "b", "1")
    with pytest.raises(BadInput, match="a length"):
        parse_expectation(ex, "phi", "1 m")


# -- judging, on hand-made cross-check results ------------------------------------------------------------

def _result(*quantities, errors=()):
    ex = SimpleNamespace(id="9.9", _analytic=None)
    return SimpleNamespace(exercise=ex, params={}, quantities=list(quantities), errors=list(errors))


def _q(name, unit, a, n=None, agree=True, theory="exact", expected_err=None, numeric_err=None, theory_valid=None,
       notes=(), verdict=None, reason=""):
    n = a if n is None else n
    if isinstance(n, float):
        numeric_err = 1e-8 * abs(n) if numeric_err is None else numeric_err
    return Quantity(name, unit, analytic=a, numeric=n, agree=agree, theory=theory, tol=1e-8, verify_diff=0.0,
                    expected_err=expected_err, numeric_err=numeric_err, theory_valid=theory_valid,
                    notes=tuple(notes), verdict=verdict, reason=reason)


def _judge(q, *texts, others=()):
    ex = _fake_ex(*[(x.name, x.unit) for x in (q, *others)])
    exps = [parse_expectation(ex, name, text) for name, text in texts]
    return judge(_result(q, *others), exps)


@pytest.mark.parametrize("text, hint", [
    ("2.000", "off by a factor 2"), ("0.5000", "off by a factor 1/2"), ("-1.000", "wrong sign"),
    ("3.142", "off by a factor pi"), ("6.283", "off by a factor 2 pi"), ("0.1592", "off by a factor 1/(2 pi)"),
    ("1.414", "off by a factor sqrt(2)"), ("57.30", "degrees given as radians"),
    ("1.000deg", "radians given as degrees"),
])
def test_each_slip_is_named_against_a_reference_of_1(text, hint):
    # reference 1 rad: 2, 1/2, -1, pi = 3.1416, 2 pi = 6.2832, 1/(2 pi) = 0.15915, sqrt 2 = 1.4142,
    # 180/pi = 57.296 (degrees written as radians), 1 deg = pi/180 rad
    (j,) = _judge(_q("x", "rad", 1.0), ("x", text))
    assert not j.match and j.hint == hint


def test_a_slip_is_named_only_when_it_explains_the_value():
    # 2.02 is 0.02 from 2 * 1.0: beyond half a unit (0.005) of its last digit
    (j,) = _judge(_q("x", "m", 1.0), ("x", "2.02"))
    assert not j.match and j.hint is None and j.verdict.startswith("wrong: off by 102 %")


def test_angle_slips_only_for_angles():
    (j,) = _judge(_q("x", "m", 1.0), ("x", "57.30"))
    assert j.hint is None


def test_a_swapped_pair_is_named():
    a, b = _q("x", "m", 1.0), _q("y", "m", 3.0)
    ja, jb = _judge(a, ("x", "3.000"), ("y", "1.000"), others=(b,))
    assert ja.hint == "swapped with y" and jb.hint == "swapped with x"


def test_no_judgement_without_a_trusted_reference():
    (j,) = _judge(_q("x", "m", 1.0, 1.1, agree=False), ("x", "1.000"))
    assert not j.match and j.reference is None and "disagree" in j.verdict
    (j,) = _judge(_q("x", "m", Undefined("infinite"), Undefined("infinite")), ("x", "1.000"))
    assert not j.match and "infinite" in j.verdict


def test_leading_order_answer_is_right_to_its_digits_against_either_value_or_closer():
    # theory 1.000, exact (numeric) 1.010, the theory neglects 2 %: 1.000 and 1.010 are right to their
    # digits (half a unit: 0.0005); never by the 2 % band the theory neglects
    q = _q("x", "m", 1.000, 1.010, theory="leading-order", expected_err=0.02, theory_valid=True)
    (j,) = _judge(q, ("x", "1.000"))
    assert j.match and j.matches == "leading-order" and j.reference_value == 1.010
    # |1.010 - 1.000| / 1.010 = 0.0099
    assert "right to leading order; the exact value is 0.99 % away here" in j.verdict
    assert j.as_json()["matches"] == "leading-order"
    (j,) = _judge(q, ("x", "1.010"))
    assert j.match and j.matches == "exact" and j.verdict == "right: the exact value"
    # monotone (issue 39): an answer at least as close to the exact value as one judged right is right:
    # 1.005 and 1.020 are within 0.010 + 0.0005 of 1.010, as 1.000 is; 1.021 and 0.999 are not
    for text in ("1.005", "1.020"):
        (j,) = _judge(q, ("x", text))
        assert j.match and "at least as close to the exact value" in j.verdict
    for text in ("1.021", "0.999"):
        (j,) = _judge(q, ("x", text))
        assert not j.match and j.matches is None and j.as_json()["matches"] is None


def test_outside_its_range_only_the_exact_value_is_right():
    q = _q("x", "m", 1.000, 1.300, agree=None, theory="leading-order", expected_err=0.5, theory_valid=False,
           notes=["leading-order theory outside its range: mu/omega0 = 3.3"], verdict=Verdict.OUTSIDE,
           reason="mu/omega0 = 3.3")
    (j,) = _judge(q, ("x", "1.000"))
    assert not j.match and j.matches is None
    assert "does not apply here (mu/omega0 = 3.3)" in j.verdict and "1.3" in j.verdict
    assert j.hint.startswith("that is the leading-order value")
    (j,) = _judge(q, ("x", "1.300"))
    assert j.match and j.matches == "exact"


def test_an_exact_output_has_no_matches_field():
    (j,) = _judge(_q("x", "m", 1.0), ("x", "1.000"))
    assert j.match and "matches" not in j.as_json()


def test_mechs_error_bar_widens_the_tolerance():
    # reference 1.0 with a numeric error bar of 1e-3 (numeric only): 1.0008 written to 5 digits is right
    q = _q("x", "m", None, 1.0, agree=None, numeric_err=1e-3)
    (j,) = _judge(q, ("x", "1.0008"))
    assert j.match and "error bar" in j.verdict


def test_judging_imports_no_scipy(tmp_path):
    """--expect and mech grade add no scipy import to a solve that needs none."""
    import subprocess
    import sys

    answers = tmp_path / "a.toml"
    answers.write_text('[[answer]]\nexercise = "4.15"\nexpect = { theta_c = "0.7297" }\n', encoding="utf-8")
    code = (
        "import sys\n"
        "from mech.cli.main import cli\n"
        f"for argv in (['solve', '4.15', '--expect', 'theta_c=35.26deg'], ['grade', {str(answers)!r}]):\n"
        "    try:\n"
        "        cli.main(argv, standalone_mode=False)\n"
        "    except SystemExit:\n"
        "        pass\n"
        "bad = sorted(m for m in sys.modules if m.split('.')[0] == 'scipy')\n"
        "print(bad[:5], file=sys.stderr)\n"
        "sys.exit(1 if bad else 0)\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr


from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

_PIECES = ["theta_c", "omega_c", "=", "35.26", "deg", "rad", "/s", "pi", "-", "1e", "999", "0", ".", " ", "Hz",
           "m", "(", "^2", "e-3", "x"]


@settings(max_examples=150, deadline=None)
@given(pieces=st.lists(st.one_of(st.sampled_from(_PIECES), st.text(max_size=4)), min_size=1, max_size=6),
       rtol=st.one_of(st.none(), st.sampled_from(["1e-3", "0", "2", "abc", "0.5"])))
def test_fuzz_expect_never_crashes(pieces, rtol):
    args = ["solve", "4.15", "--method", "analytic", "--expect", "".join(pieces)]
    if rtol is not None:
        args += ["--expect-rtol", rtol]
    code, out, err = run(*args)
    assert code in (0, 1, 2), err
    assert "Traceback" not in err and "internal error" not in err
    if code == 2:
        assert out == "" and len(err.strip().splitlines()) == 1

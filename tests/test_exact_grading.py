"""Exact means exact (issue 39, items 2, 3, 6, 7): held-out cheats, the interval enclosures, zeros,
--min-digits, none, the monotone leading-order rule and proven hints.

The cheats were written after the judge, as a student trying to game it would: each is wrong in exact
arithmetic by far more than the tolerance (1e-9 relative), and each hides it from double precision
(a function of zero slope at a cancelled argument, a cancellation, a huge oscillation, a rational that
rounds to 1).  The expected verdicts come from the algebra written beside each, not from the program.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mech.problems import registry
from mech.solvers.numerics import interval as iv
from mech.students import expectations as expecting
from mech.students.answers import judge
from mech.students.cells import State
from mech.verification.crosscheck import cross_check

EX = registry.get("4.15")
RIGHT = "asin(2/3*sin(theta0))"  # theta_c of 4.15 (its statement)


@pytest.fixture(scope="module")
def result():
    return cross_check(EX, EX.resolve({"theta0": math.pi / 3}))


def _cell(result, text, out="theta_c", **kw):
    e = expecting.parse_expectation(result.exercise, out, text, **kw)
    return judge(result, [e])[0]


# -- held-out cheats: wrong in exact arithmetic, every one -------------------------------------------------

CHEATS = [
    f"{RIGHT}*cos((theta0+1e17)-1e17)",  # = theta_c cos(theta0): zero slope of cos at 0 in double
    f"{RIGHT}*cosh((theta0+1e17)-1e17)",  # = theta_c cosh(theta0)
    f"{RIGHT}*sqrt(1+((theta0+1e17)-1e17)^2)",  # = theta_c sqrt(1 + theta0^2)
    f"{RIGHT}+((theta0+1e16)-1e16)^2",  # + theta0^2
    f"{RIGHT}+1-cos((theta0+1e17)-1e17)",  # + 1 - cos(theta0)
    f"{RIGHT}+(theta0+1e17)-1e17-0.99*theta0",  # + theta0/100
    "1e30*sin(1e300*theta0)",  # a huge oscillation: its own round-off once widened its tolerance
    f"{RIGHT}+1e-3*sin(1e20*theta0)",  # a small fast oscillation
    f"{RIGHT}*(1+1e-17)^1000000000",  # (1 + 1e-17)^1e9 = 1 + 1e-8 exactly-ish: a rational that rounds to 1
    f"{RIGHT}*(1+2^-60)^(2^40)",  # (1 + 2^-60)^(2^40) = 1 + 2^-20 (to first order)
    f"{RIGHT}+1e-300*g",  # a tiny added term of another dimension: wrong by dimension
    f"{RIGHT}+1e-7",  # a tiny term above the tolerance
    f"{RIGHT}+1e-9*exp(30*(theta0+1e17)-30e17)",  # exp(30 theta0) 1e-9: large at the top of the range
]


@pytest.mark.parametrize("text", CHEATS)
def test_heldout_cheats_are_wrong(result, text):
    j = _cell(result, text)
    assert not j.match and j.cell is State.WRONG, j.verdict


NUMBER_CHEATS = ["0e300", "-0.0e9", "0", "0.0", "1e300", "-1e-300"]


@pytest.mark.parametrize("text", NUMBER_CHEATS)
def test_zeros_and_huge_exponents_are_what_they_say(result, text):
    # theta_c is 0.6155 rad at theta0 = 60 deg: no zero, however written, and no 1e+-300 is near it
    j = _cell(result, text)
    assert not j.match and j.cell is State.WRONG, j.verdict


RIGHT_FORMS = [
    "asin(2/3*sin((theta0+1e17)-1e17))",  # the cancellation is exact in rational arithmetic
    "asin(sin(theta0)/1.5)",  # 1.5 is 3/2 as written
    "asin(0.4/0.6*sin(theta0))",  # 0.4/0.6 = 2/3 exactly, though neither is a double
    "atan2(2*sin(theta0), sqrt(9-4*sin(theta0)^2))",
    f"{RIGHT}*cosh((theta0+1e17)-1e17-theta0)",  # cosh(0) = 1 exactly
    f"{RIGHT}+0*sin(1e300*theta0)",  # zero times anything real
    f"{RIGHT}+((theta0+1e17)-1e17-theta0)^2",  # + 0
    f"({RIGHT})^1",
]


@pytest.mark.parametrize("text", RIGHT_FORMS)
def test_right_formulas_in_unusual_exact_forms_stay_right(result, text):
    j = _cell(result, text)
    assert j.match and j.cell is State.RIGHT, j.verdict


_HIDERS = {
    "cos": "{F}*cos({c}*((theta0+1e{k})-1e{k}))",  # = F cos(c theta0)
    "cosh": "{F}*cosh({c}*((theta0+1e{k})-1e{k}))",
    "square": "{F}+{c}*((theta0+1e{k})-1e{k})^2",
    "sqrt": "{F}*sqrt(1+{c}*((theta0+1e{k})-1e{k})^2)",
    "cancel": "{F}+{c}*((theta0+1e{k})-1e{k})",
    "oscillate": "{F}+{c}*sin(1e{m}*theta0)",
}


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(kind=st.sampled_from(sorted(_HIDERS)), c=st.floats(1e-3, 1.0), k=st.integers(16, 22),
       m=st.integers(10, 300))
def test_planted_errors_behind_zero_slope_cancellation_and_oscillation_are_wrong(result, kind, c, k, m):
    # each planted term is, in exact arithmetic, at least ~1e-4 of theta_c at most points of the range
    text = _HIDERS[kind].format(F=RIGHT, c=f"{c:.6g}", k=k, m=m)
    j = _cell(result, text)
    assert not j.match and j.cell is State.WRONG, (text, j.verdict)


# -- the zero reference, the next order, the monotone rule ------------------------------------------------

def test_a_zero_reference_is_judged_on_the_outputs_scale():
    # 4.8 at h/R = 1.4: 7 - 5*1.4 is 0 in double (mech's value is exactly 0) but 4.4e-16 for the exact
    # double 1.4 = 1.399999999999999911...: the formula gives 6.5e-17 s on a scale P/(M mu g) ~ 1 s
    ex = registry.get("4.8")
    res = cross_check(ex, ex.resolve({"h_over_R": 1.4}))
    e = expecting.parse_expectation(ex, "t_roll", "P*abs(7-5*h_over_R)/(7*M*mu*g)")
    assert judge(res, [e])[0].match
    # and a formula off by 1e-6 of that scale there is wrong
    e = expecting.parse_expectation(ex, "t_roll", "P*abs(7-5*h_over_R)/(7*M*mu*g) + 1e-6*P/(M*mu*g)")
    assert not judge(res, [e])[0].match


def test_next_order_formula_of_5_9_is_right():
    ex = registry.get("5.9")
    res = cross_check(ex, ex.resolve({}))
    e = expecting.parse_expectation(ex, "omega", "omega0 - mu^2/(16*omega0)")
    j = judge(res, [e])[0]
    assert j.match, j.verdict


@pytest.fixture(scope="module")
def res58():
    ex = registry.get("5.8")
    return cross_check(ex, ex.resolve({"omega0": 45.1, "delta": 0.0198, "alpha": 82.7, "f0": 0.797}))


def test_5_8_a_closer_answer_is_right(res58):
    q = res58["A_max"]
    assert abs(q.numeric - 0.445029) < 5e-7 and abs(q.analytic - 0.446259) < 5e-7  # the figures
    assert _cell(res58, "0.4463 m", "A_max").match  # the leading-order value to 4 digits
    assert _cell(res58, "0.4457 m", "A_max").match  # closer to the exact value
    assert not _cell(res58, "0.4470 m", "A_max").match  # farther than the leading-order value


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(t=st.floats(0.0, 1.0), digits=st.integers(2, 9))
def test_monotone_between_exact_and_leading_order(res58, t, digits):
    q = res58["A_max"]
    exact, lead = q.numeric, q.analytic
    x = exact + t * (lead - exact)

    def written(v):
        return f"{v:.{digits - 1}e} m"

    if _cell(res58, written(lead), "A_max").match:
        assert _cell(res58, written(x), "A_max").match, written(x)


# -- numbers: --min-digits, none, proven hints ------------------------------------------------------------

def test_min_digits_and_the_power_of_ten_that_is_not_proven():
    ex = registry.get("4.15")
    res = cross_check(ex, ex.resolve({}))  # theta_c = 0.7297 rad
    j = _cell(res, "9")  # one digit: judged as 9.0 (min 2 digits); 10 x 0.73 = 7.3 is not 9.0
    assert not j.match and "power of ten" not in (j.hint or "") and "power of ten" not in j.verdict
    assert not _cell(res, "0.7").match  # as 0.70: off by 0.03
    assert _cell(res, "0.7", min_digits=1).match  # as written, one digit: 0.7 +- 0.05
    assert _cell(res, "0.73").match


def test_none_is_an_answer():
    res = cross_check(EX, EX.resolve({}))
    j = _cell(res, "none")
    assert not j.match and j.cell is State.WRONG and "there is a value here" in j.verdict


def test_a_swap_outside_the_declared_range_is_never_named(res58):
    from mech.students.explain import _OutOfRange, _in_bounds

    ex = registry.get("5.8")
    base = {p.name: p.default for p in ex.params}
    with pytest.raises(_OutOfRange):
        _in_bounds(ex, {**base, "omega0": base["delta"] - base["omega0"]})  # a negative omega0
    j = _cell(res58, f"{-res58['xi_peak'].analytic:.6g} rad/s", "xi_peak")
    assert "swapped" not in (j.hint or ""), j.verdict


# -- the interval arithmetic against mpmath ---------------------------------------------------------------

_FNS = ["sqrt", "exp", "expm1", "log", "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh", "abs",
        "ellipk", "ellipe"]


@settings(max_examples=200, deadline=None)
@given(name=st.sampled_from(_FNS), a=st.floats(-50, 50), w=st.floats(0, 10), f=st.floats(0, 1))
@np.errstate(all="ignore")
def test_function_enclosures_hold_the_exact_values(name, a, w, f):
    lo, hi = np.array([a]), np.array([a + w])
    for B in (iv.DOUBLE, iv.precise(200)):
        args = (lo, hi) if B is iv.DOUBLE else (B.asarray([mpmath.mpf(a)]), B.asarray([mpmath.mpf(a + w)]))
        (ylo, yhi), bad = iv.function(B, name, args)
        with mpmath.workprec(300):  # a point of [a, a + w], exactly
            x = mpmath.mpf(a) + mpmath.mpf(f) * (mpmath.mpf(a + w) - mpmath.mpf(a))
            try:
                y = {"abs": abs}.get(name, getattr(mpmath, name, None))(x)
            except (ValueError, ZeroDivisionError):
                continue
        if bad[0]:
            assert not isinstance(y, mpmath.mpf) or not mpmath.isfinite(y)
            continue
        if isinstance(y, mpmath.mpf) and mpmath.isfinite(y):
            exact = (lambda v: v if isinstance(v, mpmath.mpf) else mpmath.mpf(float(v)))
            assert exact(ylo[0]) <= y <= exact(yhi[0]), (name, a, w, f, ylo, yhi, y)


@settings(max_examples=200, deadline=None)
@given(a=st.floats(-1e3, 1e3), b=st.floats(-1e3, 1e3), n=st.integers(-5, 7), op=st.sampled_from("+-*/^"))
@np.errstate(all="ignore")
def test_arithmetic_enclosures_hold_the_exact_values(a, b, n, op):
    exact = {"+": lambda: mpmath.mpf(a) + mpmath.mpf(b), "-": lambda: mpmath.mpf(a) - mpmath.mpf(b),
             "*": lambda: mpmath.mpf(a) * mpmath.mpf(b),
             "/": lambda: mpmath.mpf(a) / mpmath.mpf(b) if b else None,
             "^": lambda: mpmath.mpf(a) ** n if (a or n >= 0) else None}
    with mpmath.workprec(400):
        y = exact[op]()
    if y is None:
        return
    bv = float(n) if op == "^" else b
    for D in (iv.DOUBLE, iv.precise(60)):  # 60 bits: the products of doubles are rounded there too
        A = (D.asarray([a]), D.asarray([a])) if D is iv.DOUBLE else (D.asarray([mpmath.mpf(a)]),) * 2
        Bv = (D.asarray([bv]), D.asarray([bv])) if D is iv.DOUBLE else (D.asarray([mpmath.mpf(bv)]),) * 2
        out = {"+": lambda: iv.add(D, A, Bv), "-": lambda: iv.sub(D, A, Bv), "*": lambda: iv.mul(D, A, Bv),
               "/": lambda: iv.div(D, A, Bv)[0], "^": lambda: iv.power(D, A, Bv)[0]}[op]()
        lo, hi = (mpmath.mpf(float(v[0])) if D is iv.DOUBLE else v[0] for v in out)
        assert lo <= y <= hi, (op, a, b, n, lo, hi, y)


def test_min_digits_on_the_command_line_and_in_the_api():
    from click.testing import CliRunner

    import mech
    from mech.cli.main import cli

    def run(*args):  # in this process (click's runner): the exit codes and messages are the command's own
        return CliRunner().invoke(cli, ["solve", "4.15", *args])

    assert run("--expect", "theta_c=0.7").exit_code == 1  # as 0.70: wrong (theta_c = 0.7297)
    assert run("--expect", "theta_c=0.7", "--min-digits", "1").exit_code == 0  # as written: 0.7 +- 0.05
    bad = run("--expect", "theta_c=0.7", "--min-digits", "0")
    assert bad.exit_code == 2 and "--min-digits" in bad.stderr and "Traceback" not in bad.stderr
    assert bad.exception is None or isinstance(bad.exception, SystemExit)
    assert run("--min-digits", "3").exit_code == 2  # without any --expect
    assert mech.solve("4.15", expect={"theta_c": "0.7"}, expect_min_digits=1)["theta_c"].expected.match
    assert not mech.solve("4.15", expect={"theta_c": "0.7"})["theta_c"].expected.match

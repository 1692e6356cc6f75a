"""4.17 against values worked out by hand.

Hand derivation: for a box of mass M = rho a1 a2 a3 the moments about the edge
directions are I1 = M (a2^2 + a3^2)/12 and cyclic; a constant omega fixed in
the body needs tau = omega x (I omega).  With omega = w (a1, a2, a3)/d:
tau1 = (w^2/d^2) a2 a3 (I3 - I2) = K a2 a3 (a2^2 - a3^2), K = M w^2/(12 d^2),
and cyclic.  Numbers by hand:
 * defaults (0.1, 0.2, 0.3), rho 2700, w 20: M = 16.2, d^2 = 0.14,
   K = 16.2*400/1.68 = 3857.142857...; tau1 = K*0.06*(-0.05) = -0.003 K,
   tau2 = K*0.03*0.08 = 0.0024 K, tau3 = K*0.02*(-0.03) = -0.0006 K.
 * (1, 1, 2), rho 1, w 1: K = 2/(12*6) = 1/36; tau1 = 2*(1-4)/36 = -1/6,
   tau2 = +1/6, tau3 = 0.
"""

import math

import pytest

from conftest import solve_both

K0 = 16.2 * 400.0 / 1.68


@pytest.mark.parametrize(
    "given, t1, t2, t3",
    [
        ({}, -0.003 * K0, 0.0024 * K0, -0.0006 * K0),
        (dict(a1=1.0, a2=1.0, a3=2.0, rho=1.0, omega=1.0), -1 / 6, 1 / 6, 0.0),
        # cube: every axis is principal
        (dict(a1=0.1, a2=0.1, a3=0.1), 0.0, 0.0, 0.0),
    ],
)
def test_against_hand_values(given, t1, t2, t3):
    an, nu, run = solve_both("4.17", **given)
    scale = 1e-13 * max(abs(t1), abs(t2), abs(t3), 1e-3)
    for v in (an, nu):
        assert v["tau1"] == pytest.approx(t1, rel=1e-12, abs=scale)
        assert v["tau2"] == pytest.approx(t2, rel=1e-12, abs=scale)
        assert v["tau3"] == pytest.approx(t3, rel=1e-12, abs=scale)
        assert v["tau"] == pytest.approx(math.sqrt(t1**2 + t2**2 + t3**2), rel=1e-12, abs=scale)


def test_near_cube_first_order():
    # a2 = a (1 + e): to first order in e, tau1 = K a^2 (2 e a^2), tau3 = -K a^2 (2 e a^2),
    # K = rho a^3 w^2 / (36 a^2); tau2 = 0 exactly
    a, e, rho, w = 0.1, 1e-6, 2700.0, 20.0
    first = rho * a**3 * w**2 / 36.0 * 2.0 * e * a**2
    an, nu, _ = solve_both("4.17", a1=a, a2=a * (1 + e), a3=a)
    assert an["tau2"] == 0.0
    assert an["tau1"] == pytest.approx(first, rel=3e-6)
    assert an["tau3"] == pytest.approx(-first, rel=3e-6)
    # the numeric sum cancels terms of size rho a^5 w^2: absolute accuracy ~1e-15 of that
    assert nu["tau1"] == pytest.approx(first, rel=3e-6, abs=1e-15 * rho * a**5 * w**2)
    assert abs(nu["tau2"]) < 1e-15 * rho * a**5 * w**2


def test_swapping_two_edges_reverses_the_torque_pattern():
    a, nu, _ = solve_both("4.17", a1=0.3, a2=0.2, a3=0.1)
    b, _, _ = solve_both("4.17", a1=0.1, a2=0.2, a3=0.3)
    # mirror relabelling 1 <-> 3 with the diagonal kept: components swap and change sign
    assert a["tau1"] == pytest.approx(-b["tau3"], rel=1e-13)
    assert a["tau3"] == pytest.approx(-b["tau1"], rel=1e-13)
    assert a["tau2"] == pytest.approx(-b["tau2"], rel=1e-13)
    assert nu["tau"] == pytest.approx(b["tau"], rel=1e-12)


def test_huge_box_scales_without_overflow():
    """Edges (1, 1, 2) x 1e100 m, rho 1e-250, w 20: the (1, 1, 2) box above with lengths times 1e100
    (tau ~ rho w^2 L^5: 1e500 times the unit box's -1/6 at rho 1e-250, w^2 400) gives
    tau1 = -(1/6) * 1e-250 * 400 * 1e500 = -(2/3) 1e252 N m, tau2 = +(2/3) 1e252, tau3 = 0.
    Every SI intermediate (a^5 = 1e500) would overflow."""
    a, n, _ = solve_both("4.17", a1=1e100, a2=1e100, a3=2e100, rho=1e-250, omega=20.0)
    for values in (a, n):
        assert values["tau1"] == pytest.approx(-2 / 3 * 1e252, rel=1e-12)
        assert values["tau2"] == pytest.approx(2 / 3 * 1e252, rel=1e-12)
        assert abs(values["tau3"]) <= 1e-13 * 1e252


def test_torque_beyond_the_float_range_is_refused():
    """Issue 14: a1 = 2^1000, a2 = pi ended in 'internal error: ... inf'; the torque scale
    rho a1 a2 a3 d^2 w^2 ~ 2700 * 2^3000 * ... is 1e909 N m: refused with the reason."""
    from mech.problems import registry
    from mech.problems.spec import BadInput

    with pytest.raises(BadInput, match="floating-point range"):
        registry.get("4.17").resolve(dict(a1=2.0**1000, a2=math.pi))

"""4.4 against values worked out by hand.

rho(s) = d + s sin(beta), z(s) = s cos(beta), s uniform on [-l/2, l/2] with <s> = 0,
<s^2> = l^2/12.  I = M <rho^2> = M (d^2 + l^2 sin^2 beta/12); L_z = I omega;
T = I omega^2/2; |L_perp| = M |omega| |<rho z>| = M |omega| l^2 sin beta cos beta/12.
  defaults M = 1, l = 1, d = 0.5, beta = 30 deg, omega = 10:
    I = 0.25 + 0.25/12 = 0.2708333..., L_z = 2.708333..., T = 13.541666...,
    L_perp = 10 (1/2)(sqrt3/2)/12 = 0.3608439182435161
  M = 2, l = 0.6, d = 0.1, beta = 60 deg, omega = -3:
    I = 2 (0.01 + 0.36 (3/4)/12) = 0.065, L_z = -0.195, T = 0.2925,
    L_perp = 2 * 3 * 0.36 (sqrt3/4)/12 = 0.0779422863405995
  d = 0, beta = 90 deg (a principal axis): I = M l^2/12, L_perp = 0.
"""

import math

import pytest

from conftest import solve_both


@pytest.mark.parametrize(
    "M, l, d, beta, omega, I, Lz, T, Lp",
    [
        (1.0, 1.0, 0.5, math.pi / 6, 10.0, 0.25 + 0.25 / 12, 2.5 + 2.5 / 12, 12.5 + 12.5 / 12, 0.3608439182435161),
        (2.0, 0.6, 0.1, math.pi / 3, -3.0, 0.065, -0.195, 0.2925, 0.0779422863405995),
        (1.0, 1.0, 0.0, math.pi / 2, 10.0, 1 / 12, 10 / 12, 100 / 24, 0.0),
        (1.0, 1.0, 0.0, 0.0, 10.0, 0.0, 0.0, 0.0, 0.0),
    ],
)
def test_against_hand_values(M, l, d, beta, omega, I, Lz, T, Lp):
    an, nu, _ = solve_both("4.4", M=M, l=l, d=d, beta=beta, omega=omega)
    for v in (an, nu):
        assert v["I_axis"] == pytest.approx(I, rel=1e-12, abs=1e-15)
        assert v["Lz"] == pytest.approx(Lz, rel=1e-12, abs=1e-14)
        assert v["T"] == pytest.approx(T, rel=1e-12, abs=1e-13)
        assert v["L_perp"] == pytest.approx(Lp, rel=1e-12, abs=1e-14)


def test_Lz_is_the_same_about_any_axis_point():
    _, n, run = solve_both("4.4", M=1.5, l=0.8, d=0.3, beta=1.0, omega=4.0)
    assert run.info["Lz_about_another_axis_point"] == pytest.approx(n["Lz"], rel=1e-12)
    assert n["L_perp"] > 0.01 * abs(n["Lz"])  # L is not parallel to the axis

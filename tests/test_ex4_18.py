"""4.18 against values worked out by hand.

Hand derivation: differentiate the no-slip condition v - R w x z = Omega z x r
and use M v' = f, (2/5) M R^2 w' = -R z x f; (z x f) x z = f for a horizontal
f, so v' + (5/2) v' = Omega z x v: v turns counterclockwise at 2 Omega/7 with
constant speed.  The center then circles at radius |v0|/omega about
r0 + (z x v0)/omega = (x0 - vy0/omega, y0 + vx0/omega).
 * Omega = 3.5: omega = 1; r0 = (1, 2), v0 = (3, 4): radius 5, center (-3, 5).
 * released at rest on the table, v0 = Omega z x r0: center r0 - (7/2) r0 =
   -(5/2) r0, radius (7/2)|r0|.
 * at rest in the lab: it stays, radius 0, center r0.
"""

import math

import pytest

from conftest import solve_both


def _check(values, omega, r, xc, yc, length):
    assert values["omega_orbit"] == pytest.approx(omega, rel=1e-8)
    assert values["r_orbit"] == pytest.approx(r, rel=1e-8, abs=1e-8 * length)
    assert values["xc"] == pytest.approx(xc, rel=1e-8, abs=1e-8 * length)
    assert values["yc"] == pytest.approx(yc, rel=1e-8, abs=1e-8 * length)


def test_nice_numbers():
    an, nu, run = solve_both("4.18", Omega=3.5, R=0.7, x0=1.0, y0=2.0, vx0=3.0, vy0=4.0)
    for v in (an, nu):
        _check(v, 1.0, 5.0, -3.0, 5.0, 5.0)
    assert run.invariants["no-slip residual"] < 1e-10
    assert run.invariants["speed"] < 1e-8


@pytest.mark.parametrize("Omega, x0, y0", [(3.490658503988659, 0.1, 0.05), (0.01, -2.0, 0.3)])
def test_released_at_rest_on_the_table(Omega, x0, y0):
    vx0, vy0 = -Omega * y0, Omega * x0
    an, nu, _ = solve_both("4.18", Omega=Omega, x0=x0, y0=y0, vx0=vx0, vy0=vy0)
    for v in (an, nu):
        _check(v, 2 * Omega / 7, 3.5 * math.hypot(x0, y0), -2.5 * x0, -2.5 * y0, math.hypot(x0, y0))


def test_at_rest_in_the_lab():
    an, nu, _ = solve_both("4.18", Omega=7.0, x0=0.3, y0=-0.4, vx0=0.0, vy0=0.0)
    for v in (an, nu):
        assert v["omega_orbit"] == pytest.approx(2.0, rel=1e-8)
        assert v["r_orbit"] == 0.0
        assert (v["xc"], v["yc"]) == (0.3, -0.4)


def test_tiny_orbit_far_from_the_axis():
    # orbit radius 1e-9 * 7/(2 Omega); center shifted by vx0/omega along y only
    Omega = 3.490658503988659
    w = 2 * Omega / 7
    an, nu, _ = solve_both("4.18", x0=0.1, y0=0.05, vx0=1e-9, vy0=0.0)
    for v in (an, nu):
        assert v["r_orbit"] == pytest.approx(1e-9 / w, rel=1e-8)
        assert v["xc"] - 0.1 == pytest.approx(0.0, abs=1e-18)
        assert v["yc"] - 0.05 == pytest.approx(1e-9 / w, rel=1e-6)

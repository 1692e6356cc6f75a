"""4.19 against values worked out by hand.

Hand derivation: a thin disk has I3 = M R^2/2 and I1 = I2 = M R^2/4.  With
I1 = I2, Euler gives omega3 = const and d(omega1 + i omega2)/dt =
i (I3 - I1)/I1 omega3 (omega1 + i omega2): Omega_body = omega3 = omega cos(alpha).
In the lab n3, omega and L stay coplanar and the plane turns about L at
|L|/I1: L = (I1 omega sin(alpha), 0, 2 I1 omega cos(alpha)) so
omega_lab = omega (sin^2 + 4 cos^2)^(1/2); tan(theta_L) = sin/(2 cos).
 * alpha = pi/3: cos = 1/2 -> Omega_body = omega/2, omega_lab = omega sqrt(7)/2,
   tan(theta_L) = sqrt(3)/2.
 * alpha = pi/4, omega = 2: Omega_body = sqrt(2), omega_lab = 2 sqrt(5/2),
   theta_L = atan(1/2).
 * alpha -> 0: omega, 2 omega, 0.  alpha = pi/2: 0 (to round-off), omega, pi/2.
"""

import math

import numpy as np
import pytest

from conftest import solve_both


@pytest.mark.parametrize(
    "omega, alpha, Ob, ol, th",
    [
        (10.0, math.pi / 3, 5.0, 10.0 * math.sqrt(7) / 2, math.atan(math.sqrt(3) / 2)),
        (2.0, math.pi / 4, math.sqrt(2), 2 * math.sqrt(2.5), math.atan(0.5)),
        (3.0, 0.0, 3.0, 6.0, 0.0),
    ],
)
def test_against_hand_values(omega, alpha, Ob, ol, th):
    an, nu, run = solve_both("4.19", omega=omega, alpha=alpha)
    for v in (an, nu):
        assert v["Omega_body"] == pytest.approx(Ob, rel=1e-8)
        assert v["omega_lab"] == pytest.approx(ol, rel=1e-8)
        assert v["theta_L"] == pytest.approx(th, rel=1e-8, abs=1e-15)
    assert run.invariants["energy"] < 1e-9
    assert run.invariants["L (lab vector)"] < 1e-8


def test_spin_in_the_plane():
    an, nu, _ = solve_both("4.19", omega=10.0, alpha=math.pi / 2)
    for v in (an, nu):
        assert abs(v["Omega_body"]) < 1e-12
        assert v["omega_lab"] == pytest.approx(10.0, rel=1e-8)
        assert v["theta_L"] == pytest.approx(math.pi / 2, rel=1e-12)


def test_small_tilt_approaches_the_limit():
    # second order in alpha: omega_lab = 2 omega (1 - 3 alpha^2/8), Omega_body = omega (1 - alpha^2/2),
    # theta_L = alpha/2 (1 + O(alpha^2))
    a = 1e-3
    _, nu, _ = solve_both("4.19", omega=1.0, alpha=a)
    assert nu["omega_lab"] == pytest.approx(2.0 * (1 - 3 * a * a / 8), rel=1e-10)
    assert nu["Omega_body"] == pytest.approx(1 - a * a / 2, rel=1e-10)
    assert nu["theta_L"] == pytest.approx(a / 2, rel=1e-6)


def test_fast_free_rhs_matches_rigid():
    from mech.solvers.mechanics.freebody import free_rhs
    from mech.solvers.mechanics.rigid import euler_rhs

    rng = np.random.default_rng(0)
    I = np.array([1.0, 1.7, 2.3])
    for _ in range(5):
        s = rng.normal(size=7)
        assert np.allclose(free_rhs(I)(0.0, s), euler_rhs(I)(0.0, s), rtol=1e-14, atol=1e-14)

"""4.5 against values worked out by a different route (Koenig's theorem).

The cone's center of mass is on the axis at 3H/4 from the apex; the axis is at the
half-angle alpha (tan alpha = R/H) above the table, so the center moves on a
horizontal circle of radius (3H/4) cos alpha at Omega = 2 pi f.  The angular velocity
lies along the contact line (the instantaneous axis, through the apex at rest)
with |omega| = Omega cot alpha, for the axis turns at Omega about the vertical while
the contact line stays on the table.  Its components: omega cos alpha along the symmetry
axis, omega sin alpha transverse.  Moments about the center: I3 = (3/10) M R^2,
I_t = (3/20) M (R^2 + H^2/4).  Then
  T = M ((3H/4) cos alpha Omega)^2/2 + (I3 cos^2 alpha + I_t sin^2 alpha) omega^2/2,
  M = pi rho R^2 H/3.
"""

import math

import pytest

from conftest import solve_both


def koenig(rho, H, R, f):
    Om = 2 * math.pi * f
    M = math.pi * rho * R**2 * H / 3
    al = math.atan2(R, H)
    w = Om / math.tan(al)
    v_cm = 0.75 * H * math.cos(al) * Om
    I3 = 0.3 * M * R**2
    It = 0.15 * M * (R**2 + H**2 / 4)
    T = 0.5 * M * v_cm**2 + 0.5 * (I3 * math.cos(al) ** 2 + It * math.sin(al) ** 2) * w**2
    return T, w, M


@pytest.mark.parametrize(
    "rho, H, R, f",
    [
        (700.0, 0.2, 0.05, 1.0),
        (2700.0, 0.1, 0.1, 3.0),  # 45 degrees: |omega| = Omega
        (7800.0, 0.3, 3.0e-4, 0.5),
        (1000.0, 2.0e-4, 0.2, 2.0),
    ],
)
def test_against_koenig(rho, H, R, f):
    T, w, M = koenig(rho, H, R, f)
    an, nu, _ = solve_both("4.5", rho=rho, H=H, R=R, f=f)
    for v in (an, nu):
        assert v["T"] == pytest.approx(T, rel=1e-10)
        assert v["omega"] == pytest.approx(w, rel=1e-12)
        assert v["M"] == pytest.approx(M, rel=1e-13)


def test_defaults_by_calculator():
    # M = pi 700 0.05^2 0.2/3 = 0.3665191429188092; omega = 2 pi * 4 = 25.132741228718345
    an, nu, _ = solve_both("4.5")
    for v in (an, nu):
        assert v["M"] == pytest.approx(0.3665191429188092, rel=1e-13)
        assert v["omega"] == pytest.approx(25.132741228718345, rel=1e-13)


def test_needle_and_flat_limits():
    # needle: alpha -> 0, T -> (3/40) 6 M Omega^2 H^2; flat: alpha -> 90 deg, T -> (3/40) M Omega^2 H^2
    for H, R, factor in ((1.0, 1e-6, 6.0), (1e-6, 1.0, 1.0)):
        _, n, _ = solve_both("4.5", rho=1000.0, H=H, R=R, f=1.0)
        assert n["T"] == pytest.approx(0.075 * factor * n["M"] * (2 * math.pi) ** 2 * H**2, rel=1e-10)

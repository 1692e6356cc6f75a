"""4.33 against values worked out by hand.

Hand derivation.  Closing needs the body's period = the satellite's, i.e. its
semi-major axis a = R.  Started at R + x0 with a tangential velocity it is at
an apse, so its eccentricity is e = |x0|/R and vis-viva gives the inertial
speed (GM (2/(R + x0) - 1/R))^(1/2); relative to the rotating frame
v0 = that - Omega (R + x0).  Evaluated below in 50-digit decimal arithmetic,
straight from vis-viva (the module uses a rearranged, cancellation-free form).
Shape: the body is at angle nu - M from the satellite, at distance
r = R (1 - e cos E); the radial extremes are the apses, x = +-R e, so
a_radial = |x0|.  Along track, y/R = r sin(nu - M)/R expanded in e:
  y/R = 2 e sin E - (3/4) e^2 sin 2E - (7/6) e^3 sin^3 E + O(e^4),
maximal at E = pi/2 + 3e/4 where it is 2e - (29/48) e^3; so
a_along = 2 |x0| (1 - 29 e^2/96) (relative error ~ e^3).  T_rel = 2 pi/Omega.
(Hill's linear theory is the e -> 0 limit: v0 = -2 Omega x0, axes x0 and 2 x0.)
"""

import math
from decimal import Decimal, getcontext

import pytest

from conftest import solve_both

GM = 3.986004418e14


def v0_visviva(R, x0, gm=GM):
    getcontext().prec = 50
    R_, x_, gm_ = Decimal(R), Decimal(x0), Decimal(gm)
    v_in = (gm_ * (2 / (R_ + x_) - 1 / R_)).sqrt()
    omega = (gm_ / R_**3).sqrt()
    return float(v_in - omega * (R_ + x_))


@pytest.mark.parametrize(
    "R, x0, rel_shape",
    [
        (6.778e6, 100.0, 1e-10),
        (6.778e6, -100.0, 1e-10),
        (6.778e6, 0.01, 1e-10),
        (1.0e7, 1.0e4, 1e-8),  # e = 1e-3: the e^3 term left out is 1e-9
        (1.0e7, 1.0e5, 2e-6),  # e = 1e-2: e^3 = 1e-6
    ],
)
def test_hand_values(R, x0, rel_shape):
    e = abs(x0) / R
    Omega = math.sqrt(GM / R**3)
    a_along = 2 * abs(x0) * (1 - 29 * e * e / 96)
    ratio = abs(x0) / a_along
    a, n, run = solve_both("4.33", R=R, x0=x0, GM=GM)
    for values in (a, n):
        assert values["v0"] == pytest.approx(v0_visviva(R, x0), rel=1e-8)
        assert values["a_radial"] == pytest.approx(abs(x0), rel=1e-8)
        assert values["a_along"] == pytest.approx(a_along, rel=max(rel_shape, 1e-8))
        assert values["ecc"] == pytest.approx(math.sqrt(1 - ratio**2), rel=max(rel_shape, 1e-8))
        assert values["T_rel"] == pytest.approx(2 * math.pi / Omega, rel=1e-9)
    assert run.invariants["Jacobi integral"] < 1e-9


def test_hill_limit_numbers():
    # default orbit: R^3 = 3.1138e20, Omega = 1.13141e-3 rad/s; v0 -> -2 Omega x0 = -0.226281 m/s (1 - xi/4)
    a, n, _ = solve_both("4.33")
    for values in (a, n):
        assert values["v0"] == pytest.approx(-0.226281, rel=1e-5)
        assert values["ecc"] == pytest.approx(math.sqrt(3) / 2, rel=1e-9)
        assert values["T_rel"] == pytest.approx(5553.46, rel=1e-6)


def test_one_percent_offset_departs_from_hill_by_a_quarter_percent():
    # v0 = -2 Omega x0 (1 - xi/4 + ...): xi = 0.01 -> 0.25 %
    R, x0 = 1.0e7, 1.0e5
    Omega = math.sqrt(GM / R**3)
    _, n, _ = solve_both("4.33", R=R, x0=x0)
    assert n["v0"] / (-2 * Omega * x0) - 1 == pytest.approx(-0.0025, rel=0.02)


def test_zero_offset_is_refused():
    from mech.problems import registry
    from mech.problems.spec import BadInput

    with pytest.raises(BadInput):
        registry.get("4.33").resolve({"x0": 0.0})


def test_a_tiny_gm_keeps_the_orbit_rate():
    """Issue 26: GM = 1e-300 m^3/s^2.  GM/R^3 = 3.2e-321 is a subnormal double (10 significant bits), and
    Omega formed from it was 3.1e-6 off in both solvers (the natural units of the analytic one avoided it,
    so they disagreed).  Reference in 60-digit Decimal: Omega = (GM/R^3)^(1/2), T_rel = 2 pi/Omega and
    the vis-viva start v0 = Omega R ((1 - xi)/(1 + xi))^(1/2) - Omega (R + x0), xi = x0/R."""
    from decimal import Decimal, localcontext

    import hiprec

    R, x0, GM = 6.778e6, 100.0, 1e-300
    with localcontext() as ctx:
        ctx.prec = 60
        W = (Decimal(GM) / Decimal(R) ** 3).sqrt()
        xi = Decimal(x0) / Decimal(R)
        v0 = float(W * Decimal(R) * ((1 - xi) / (1 + xi)).sqrt() - W * (Decimal(R) + Decimal(x0)))
        T = float(2 * hiprec.PI / W)
    a, n, _ = solve_both("4.33", GM=GM)
    assert a["v0"] == pytest.approx(v0, rel=1e-13, abs=0.0)
    assert a["T_rel"] == pytest.approx(T, rel=1e-14, abs=0.0)
    assert n["v0"] == pytest.approx(v0, rel=1e-8, abs=0.0)
    assert n["T_rel"] == pytest.approx(T, rel=1e-8, abs=0.0)

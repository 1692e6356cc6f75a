"""4.31 against values worked out by hand.

Series derivation (independent of the module's closed form): with phi = w t,
to second order in phi the drop is h = (g t^2/2)(1 - sin^2 th phi^2/3), so
t = T0 (1 + sin^2 th eps^2/6), T0 = (2h/g)^(1/2), eps = w T0.  Integrating the
east equation x'' = 2 w (cos th v_north - sin th v_up) twice with the first-order
velocities gives d = (g w t^3 sin th / 3)(1 - w^2 t^2/5) and
v = g w t^2 sin th (1 - w^2 t^2/3); both are off by O(eps^4).

Equator (cos th = 0): the motion stays in the east-up plane, a circle in velocity
space: v_up = -(g/2w) sin 2wt, v_east = (g/w) sin^2 wt, so z = h - g sin^2(wt)/(2w^2);
it lands at sin(wt) = eps exactly, where v_east = g eps^2 / w and
d = g (2 phi - sin 2 phi)/(4 w^2), phi = arcsin(eps).
"""

import math

import pytest

from conftest import solve_both

W = 7.2921159e-5


def series(h, theta, g, w):
    T0 = math.sqrt(2 * h / g)
    s = math.sin(theta)
    t = T0 * (1 + s * s * (w * T0) ** 2 / 6)
    d = g * w * t**3 * s / 3 * (1 - (w * t) ** 2 / 5)
    v = g * w * t**2 * s * (1 - (w * t) ** 2 / 3)
    return t, d, v


@pytest.mark.parametrize(
    "h, theta, g, rel",
    [
        (381.0, 0.8595746566072073, 9.81, 1e-11),  # defaults: Empire State Building
        (1.0, math.pi / 2, 9.81, 1e-12),  # hard case 1: 22 micrometres
        (4.0e4, 0.5235987755982988, 9.81, 3e-8),  # hard case 2: eps^4 = 2e-9
        (100.0, 2.5, 1.62, 1e-11),  # southern hemisphere, the Moon's g: still eastward
    ],
)
def test_against_second_order_series(h, theta, g, rel):
    t, d, v = series(h, theta, g, W)
    a, n, run = solve_both("4.31", h=h, theta=theta, g=g)
    for values in (a, n):
        assert values["t_fall"] == pytest.approx(t, rel=rel)
        assert values["d_east"] == pytest.approx(d, rel=rel)
        assert values["v_east"] == pytest.approx(v, rel=rel)
    assert run.invariants["energy"] < 1e-9


def test_defaults_order_of_magnitude():
    # the leading-order number by a calculator: (1/3) w g t^3 sin th = 12.4 cm
    a, n, _ = solve_both("4.31")
    assert a["d_east"] == pytest.approx(0.12367, rel=1e-4)
    assert n["d_east"] == pytest.approx(0.12367, rel=1e-4)


def test_equator_exact_closed_form_at_large_eps():
    # a fast planet: eps = 0.4, far outside the series; cos th = 0 is needed exactly, so
    # check the solvers against the closed form at the float pi/2 (cos = 6e-17: negligible)
    g, w, eps = 9.81, 1e-3, 0.4
    h = g * (eps / w) ** 2 / 2
    phi = math.asin(eps)
    t = phi / w
    d = g * (2 * phi - math.sin(2 * phi)) / (4 * w * w)
    v = g * eps**2 / w
    a, n, _ = solve_both("4.31", h=h, theta=math.pi / 2, g=g, omega_E=w)
    for values in (a, n):
        assert values["t_fall"] == pytest.approx(t, rel=1e-9)
        assert values["d_east"] == pytest.approx(d, rel=1e-9)
        assert values["v_east"] == pytest.approx(v, rel=1e-9)


@pytest.mark.parametrize("theta, w", [(0.0, W), (math.pi, W), (1.0, 0.0)])
def test_no_deflection_at_poles_or_without_rotation(theta, w):
    a, n, _ = solve_both("4.31", h=381.0, theta=theta, omega_E=w)
    T0 = math.sqrt(2 * 381.0 / 9.81)
    for values in (a, n):
        assert values["t_fall"] == pytest.approx(T0, rel=1e-12)
        assert abs(values["d_east"]) < 1e-15
        assert abs(values["v_east"]) < 1e-15


def test_symmetric_between_hemispheres():
    a1, n1, _ = solve_both("4.31", theta=0.7)
    a2, n2, _ = solve_both("4.31", theta=math.pi - 0.7)
    assert a1["d_east"] == pytest.approx(a2["d_east"], rel=1e-13)
    assert n1["d_east"] == pytest.approx(n2["d_east"], rel=1e-8)


def test_fall_lasting_a_large_part_of_a_turn_is_refused():
    from mech.problems import registry
    from mech.problems.spec import BadInput

    with pytest.raises(BadInput):
        registry.get("4.31").resolve({"h": 1e9})


def test_a_short_fall_where_the_rotation_is_below_rounding():
    """Draw of /work/shared/tools/draws.py (seed 4711): h = 320.533 m, g = 1.03343e6 m/s^2, omega_E = 1.8093e-6
    rad/s, theta = 0.03211 (drawn: 0.0321744...).  omega_E T0 = 4.5e-8, so the fall time is T0 = (2h/g)^(1/2) to 1 + s^2 eps^2/6 ~
    1 + 4e-19, and the deflection and speed are their leading orders (1/3) g w t^3 sin th and g w t^2 sin th
    to O((w t)^2) ~ 2e-15.  The analytic fall-time equation formed c^2 + s^2 - 1 = +2.2e-16 at tau = 1 and
    its root was not bracketed (loud)."""
    h, g, w, th = 320.533, 1.03343e6, 1.8093e-6, 0.03211  # theta as drawn (0.0321744) happens to round well
    t = math.sqrt(2 * h / g)
    a, n, _ = solve_both("4.31", h=h, g=g, omega_E=w, theta=th)
    for got in (a, n):
        assert got["t_fall"] == pytest.approx(t, rel=1e-13, abs=0.0)
        assert got["d_east"] == pytest.approx(g * w * t**3 * math.sin(th) / 3, rel=1e-9, abs=0.0)
        assert got["v_east"] == pytest.approx(g * w * t**2 * math.sin(th), rel=1e-9, abs=0.0)

"""4.15 against values worked out by hand.

Hand derivation: energy, (M l^2/3) w^2 / 2 = M g (l/2)(sin t0 - sin t), gives
w^2 = (3g/l)(sin t0 - sin t).  The wall's force is M d^2/dt^2 (l/2 cos t) =
(3 M g/2) cos t (3/2 sin t - sin t0), zero at sin tc = 2/3 sin t0, and there
w^2 = (g/l) sin t0.  Numbers below by a calculator from those two lines.
"""

import math

import pytest

from conftest import solve_both

import mech
from mech.problems import registry
from mech.problems.scene import make_scene


@pytest.mark.parametrize(
    "theta0, l, g, theta_c, omega_c",
    [
        # sin tc = 2/3 -> tc = 0.7297276562269663; w = sqrt(9.81) = 3.132091952673165
        (math.pi / 2, 1.0, 9.81, 0.7297276562269663, 3.132091952673165),
        # t0 = 30 deg: sin tc = 1/3 -> 0.3398369094541219; w = sqrt(9.81 * 0.5 / 3)
        (math.pi / 6, 3.0, 9.81, 0.3398369094541219, math.sqrt(9.81 * 0.5 / 3.0)),
        # t0 = 1 deg on the Moon: sin tc = 2/3 sin(1 deg) = 0.011635463...
        (math.radians(1.0), 2.0, 1.62, math.asin(2 / 3 * math.sin(math.radians(1.0))),
         math.sqrt(1.62 * math.sin(math.radians(1.0)) / 2.0)),
    ],
)
def test_against_hand_values(theta0, l, g, theta_c, omega_c):
    a, n, run = solve_both("4.15", theta0=theta0, l=l, g=g)
    for values in (a, n):
        assert values["theta_c"] == pytest.approx(theta_c, rel=1e-8)
        assert values["omega_c"] == pytest.approx(omega_c, rel=1e-8)
    assert run.invariants["energy"] < 1e-8


def test_nearly_upright_start_at_rest_matches_upright_limit():
    # 1e-9 rad below vertical, started at rest: leaves the unstable equilibrium by itself
    a, n, _ = solve_both("4.15", theta0=math.pi / 2 - 1e-9)
    assert n["theta_c"] == pytest.approx(0.7297276562269663, rel=1e-8)


# Issue 14: `mech solve 4.15 --l 1e-15` (down to 1e-300) printed numpy warnings and spun forever.
# The run is now in units l = g = 1 and theta/theta0, so only theta0 shapes it.  Hand values:
# sin tc = (2/3) sin t0, omega_c = (g sin t0 / l)^(1/2), written out with math here.
@pytest.mark.parametrize("given", [
    dict(l=1e-15), dict(l=1e-300), dict(l=1e300), dict(g=1e-300),
    # theta0 = 1e-280 (theta_c = 2/3 of it; at 1e-300 it falls below 1e-290 and is refused, see scales.py)
    dict(theta0=1e-280), dict(theta0=1e-9, l=1e300),
])
def test_extreme_scales_answer_quickly(given):
    from mech.core import budget

    p = dict(theta0=math.pi / 2, l=1.0, g=9.81) | given
    with budget.limit(5.0):
        _, n, _ = solve_both("4.15", **given)
    s0 = math.sin(p["theta0"])
    assert n["theta_c"] == pytest.approx(math.asin(2 * s0 / 3), rel=1e-8)
    assert n["omega_c"] == pytest.approx(math.sqrt(s0) * math.sqrt(p["g"]) / math.sqrt(p["l"]), rel=1e-8)


def test_subnormal_start_angle_is_refused():
    from mech.problems import registry
    from mech.problems.spec import BadInput

    ex = registry.get("4.15")
    with pytest.raises(BadInput, match=r"theta0 = .* is outside \[1e-300, inf\]"):
        ex.resolve(dict(theta0=5e-324))


def test_the_declared_motion_starts_on_the_energy_path_below_upright():
    """The start is declared once (``@exercise.motion``); the numeric solve, the trajectory and the
    Hamiltonian for bench all take it from there.  By hand: with both ends in contact
    θ'² = (3g/l)(sin θ₀ - sin θ), so UPRIGHT_NUDGE below upright θ' = -(3g/l (1 - cos 1e-6))^(1/2)."""
    from mech.problems.ch4.ex4_15_sliding_ladder import UPRIGHT_NUDGE

    ex = registry.get("4.15")
    l, g = 2.0, 9.81
    p = ex.resolve({"theta0": math.pi / 2, "l": l, "g": g})
    theta, omega = ex.motion_at(p).start
    assert theta == pytest.approx(math.pi / 2 - UPRIGHT_NUDGE, rel=1e-15)
    # the program forms sin θ₀ - sin θ as a difference of two numbers near 1 (about 5e-13 apart): up to
    # 2 ulp / 5e-13 ~ 1e-3 of it is round-off, half that in the square root
    assert omega == pytest.approx(-math.sqrt(3 * g / l * 2 * math.sin(UPRIGHT_NUDGE / 2) ** 2), rel=1e-3)
    tr = mech.solve("4.15", theta0=math.pi / 2, l=l, g=g).trajectory
    assert tr.y[:, 0] == pytest.approx([theta, omega], rel=1e-12)
    H = ex.separable_hamiltonian(p)
    assert (H.q0, 3.0 * H.p0 * math.sqrt(g / l)) == pytest.approx((theta, omega), rel=1e-12)


def test_the_scene_draws_the_declared_motion_to_the_wall_letting_go():
    """The scene integrates nothing of its own: its curve ends where the numeric solve's event is, and the
    wall's force there is zero (N ∝ cos θ ((3/2) sin θ - sin θ₀) from energy, by hand)."""
    ex = registry.get("4.15")
    p = ex.resolve({"theta0": 1.2})
    scene, _ = make_scene(ex, p, points=0)
    curve = scene.panels[0].items[0]
    theta_c = math.asin(2.0 / 3.0 * math.sin(1.2))
    assert math.radians(curve.x[-1]) == pytest.approx(theta_c, rel=1e-8)
    assert abs(curve.y[-1]) < 1e-8 and curve.y[0] > 0.0

"""4.8 against values worked out by hand.

Hand derivation (angular momentum about the contact point, not the slip rate):
during the strike the impulse P x at height h has moment P h about the
horizontal axis y through the contact point; afterwards friction acts at that
point and gravity/normal force pass through it, so L_y about the contact point,
L = I w_y + M R V, stays P h.  Rolling (w_y = V/R) with I = 2 M R^2/5 gives
(7/5) M R V_f = P h: V_f = 5 P h/(7 M R), whatever the sideways offset b (the
offset's moment is about the vertical axis and only spins the ball about z:
I w_z = -b P, w_z = -5 b P/(2 M R^2)).  The center's velocity changes at the
constant rate -+mu g, from P/M to V_f, so t_roll = |P/M - V_f|/(mu g) and
x_roll = (P/M + V_f) t_roll / 2.  Defaults: V0 = 2 m/s, V_f = 10/7 * 0.8 =
8/7 m/s, t_roll = (6/7)/1.962 s.
"""

import pytest

from conftest import solve_both


def hand(M, R, P, h_over_R, b_over_R, mu, g):
    V0 = P / M
    V_f = 5 * P * h_over_R / (7 * M)
    t = abs(V0 - V_f) / (mu * g)
    return V_f, t, 0.5 * (V0 + V_f) * t, -2.5 * b_over_R * P / (M * R)


CASES = [
    (0.17, 0.028575, 0.34, 0.8, 0.25, 0.2, 9.81),
    (0.17, 0.028575, 0.34, 0.02, 0.1, 0.2, 9.81),
    (0.17, 0.028575, 0.34, 1.0, 0.99, 0.2, 9.81),
    (0.17, 0.028575, 0.34, 1.9, -0.3, 0.2, 9.81),  # above 7R/5: friction speeds it up
    (1.0, 0.5, 2.0, 0.5, -0.5, 0.05, 1.62),
]


@pytest.mark.parametrize("M, R, P, h_over_R, b_over_R, mu, g", CASES)
def test_against_hand_values(M, R, P, h_over_R, b_over_R, mu, g):
    V_f, t, x, wz = hand(M, R, P, h_over_R, b_over_R, mu, g)
    a, n, run = solve_both("4.8", M=M, R=R, P=P, h_over_R=h_over_R, b_over_R=b_over_R, mu=mu, g=g)
    for values in (a, n):
        assert values["V_f"] == pytest.approx(V_f, rel=1e-9)
        assert values["t_roll"] == pytest.approx(t, rel=1e-9)
        assert values["x_roll"] == pytest.approx(x, rel=1e-9)
        assert values["omega_z"] == pytest.approx(wz, rel=1e-9)
    # the impulse-momentum result comes out of the pulse integration
    assert abs(run.info["pulse_momentum_error"]) < 1e-10
    assert run.invariants.get("L_contact", 0.0) < 1e-12


def test_defaults_by_hand():
    a, n, _ = solve_both("4.8")
    for values in (a, n):
        assert values["V_f"] == pytest.approx(8 / 7, rel=1e-10)
        assert values["t_roll"] == pytest.approx((6 / 7) / 1.962, rel=1e-9)
        assert values["omega_z"] == pytest.approx(-2.5 * 0.25 * 2 / 0.028575, rel=1e-9)


def test_final_velocity_does_not_depend_on_the_side_offset():
    finals = [solve_both("4.8", h_over_R=1.2, b_over_R=b)[1]["V_f"] for b in (0.0, 0.5, -0.9)]
    assert finals[1] == pytest.approx(finals[0], rel=1e-10)
    assert finals[2] == pytest.approx(finals[0], rel=1e-10)


def test_hit_at_seven_fifths_rolls_at_once():
    a, n, run = solve_both("4.8", h_over_R=1.4, b_over_R=0.0)
    assert n["t_roll"] == pytest.approx(0.0, abs=1e-12)
    assert n["x_roll"] == pytest.approx(0.0, abs=1e-12)
    assert n["V_f"] == pytest.approx(2.0, rel=1e-10)  # P/M, unchanged
    assert n["omega_z"] == pytest.approx(0.0, abs=1e-12)


def test_hit_point_must_be_on_the_ball():
    from mech.problems import registry
    from mech.problems.spec import BadInput

    with pytest.raises(BadInput):
        registry.get("4.8").resolve({"h_over_R": 0.2, "b_over_R": 0.7})


@pytest.mark.parametrize("scale", [1e-200, 1e200])
def test_ball_radius_at_extreme_scales(scale):
    """R = 0.028575 * 1e+-200 m: V_f, t_roll and x_roll do not contain R (the hand values above:
    V_f = 8/7 m/s, t_roll = (6/7)/1.962 s), and w_z = -5 b P/(2 M R^2) = -2.5 (b/R) V0 / R with
    V0 = 2 m/s: -1.25/R, 1e+-200 times its default.  (M R^2 itself would leave the range.)"""
    R = 0.028575 * scale
    a, n, _ = solve_both("4.8", R=R)
    for values in (a, n):
        assert values["V_f"] == pytest.approx(8 / 7, rel=1e-8)
        assert values["t_roll"] == pytest.approx((6 / 7) / 1.962, rel=1e-8)
        assert values["x_roll"] == pytest.approx(0.5 * (2 + 8 / 7) * (6 / 7) / 1.962, rel=1e-8)
        assert values["omega_z"] == pytest.approx(-1.25 / R, rel=1e-8)

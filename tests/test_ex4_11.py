"""4.11 against values worked out by hand (Newton-Euler, not the Lagrangian).

Hand derivation: let F be the friction force of the block on the cylinder (along
+x).  Cylinder: M x'' = F and (M R^2/2) phi'' = R F (the force acts at (0, -R)
from the axis, torque z = R F).  Block: M' X'' = -kappa X - F.  No slip:
R phi'' = X'' - x''.  Then X'' - x'' = 2F/M and x'' = F/M give X'' = 3F/M, so
F = M X''/3 and (M' + M/3) X'' = -kappa X: omega^2 = kappa/(M' + M/3).  Started
from rest, x'' = X''/3 at all times, so x = X/3 (relative to the rest values)
and phi = (X - x)/R = 2X/(3R).
"""

import math

import pytest

from conftest import solve_both


@pytest.mark.parametrize(
    "M, R, M_prime, kappa",
    [
        (1.0, 0.05, 2.0, 100.0),  # omega = sqrt(100/(7/3)) = sqrt(300/7)
        (1.0, 0.05, 0.0, 100.0),  # massless block: sqrt(300)
        (0.001, 0.05, 1000.0, 100.0),
        (3.0, 1.5, 0.5, 2.0),
        (1e4, 0.001, 1e-3, 1e6),
    ],
)
def test_against_hand_values(M, R, M_prime, kappa):
    a, n, _ = solve_both("4.11", M=M, R=R, M_prime=M_prime, kappa=kappa)
    for values in (a, n):
        assert values["omega"] == pytest.approx(math.sqrt(kappa / (M_prime + M / 3)), rel=1e-10)
        assert values["x_over_X"] == pytest.approx(1 / 3, rel=1e-10)
        assert values["phi_over_X"] == pytest.approx(2 / (3 * R), rel=1e-10)


def test_default_numbers():
    a, n, _ = solve_both("4.11")
    assert n["omega"] == pytest.approx(math.sqrt(300 / 7), rel=1e-12)
    assert n["phi_over_X"] == pytest.approx(40 / 3, rel=1e-12)  # 2/(3 * 0.05)


def test_heavy_block_shift_is_tiny_but_resolved():
    # M/M' = 1e-6: omega = sqrt(kappa/M') (1 - M/(6 M') + ...): shift -1.6667e-7
    a, n, _ = solve_both("4.11", M=0.001, M_prime=1000.0)
    bare = math.sqrt(100.0 / 1000.0)
    assert (n["omega"] / bare - 1) == pytest.approx(-1e-6 / 6, rel=1e-5)


def test_pair_shapes_keep_a_light_body_beside_a_heavy_one():
    """Block M' = 1e200 kg, cylinder M = 1 kg.  In units M = R = 1: T = mu X'^2/2 + x'^2/2 + (X' - x')^2/4,
    so the mass matrix is [[mu + 1/2, -1/2], [-1/2, 3/2]] and K = [[1, 0], [0, 0]].  The second row of
    (K - w^2 M) a = 0 reads w^2 (X/2 - 3x/2) = 0 for the nonzero root: x/X = 1/3 whatever mu, and the zero
    root's shape is X = 0 (first row: X = 0).  By hand, not from the solver."""
    import numpy as np

    from mech.solvers.mechanics.rolling import balanced_modes

    mu = 1e200
    modes = balanced_modes(np.array([[mu + 0.5, -0.5], [-0.5, 1.5]]), np.array([[1.0, 0.0], [0.0, 0.0]]))
    assert modes.omega2[1] == pytest.approx(1.0 / (mu + 1.0 / 3.0), rel=1e-14)
    assert modes.shapes[1, 1] / modes.shapes[0, 1] == pytest.approx(1.0 / 3.0, rel=1e-14)
    assert abs(modes.shapes[0, 0]) <= 1e-15 * abs(modes.shapes[1, 0])


@pytest.mark.parametrize("given", [{"M_prime": 2e200}, {"R": 5e-202}, {"R": 5e198}, {"kappa": 1e-198}])
def test_extreme_ratios_answer(given):
    """x/X = 1/3 and phi/X = 2/(3R) (the no-slip spin of the p_x = 0 mode) hold for every M', R, kappa."""
    a, n, _ = solve_both("4.11", **given)
    R = given.get("R", 0.05)
    assert n["x_over_X"] == pytest.approx(1.0 / 3.0, rel=1e-11)
    assert n["phi_over_X"] == pytest.approx(2.0 / (3.0 * R), rel=1e-11)

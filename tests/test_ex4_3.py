"""4.3 against values worked out by hand.

About the centroid (a/3, b/3), per unit mass: <x^2> = a^2/18, <y^2> = b^2/18,
<xy> = -ab/36 (the textbook b h^3/36 moments of a triangle divided by its area ab/2).
The in-plane inertia block is then (1/36)[[2 b^2, ab], [ab, 2 a^2]] (times M).
  a = b = 0.2: (0.04/36)[[2, 1], [1, 2]]: eigenvalues 0.04/36 (vector (1, -1), theta1 = -45 deg)
               and 3 * 0.04/36; I3 = 4 * 0.04/36.
  a = 2, b = 1: (1/18)[[1, 1], [1, 4]]: eigenvalues (5 -+ sqrt 13)/36; the I1 vector solves
               (1 - lam) x + y = 0 with lam = (5 - sqrt 13)/2, so theta1 = -atan((sqrt 13 - 3)/2).
  sliver a = 1, b = 1e-6: I1 = b^2/24 (1 + O(b^2)), I2 = 1/18 (1 + O(b^2)),
               theta1 = -b/(2a) (1 + O(b^2)); mirrored: theta1 = -pi/2 + b/(2a).
"""

import math

import pytest

from conftest import solve_both

S13 = math.sqrt(13.0)


@pytest.mark.parametrize(
    "M, a, b, I1, I2, I3, theta1, rel",
    [
        (1.0, 0.2, 0.2, 0.04 / 36, 0.04 / 12, 0.04 / 9, -math.pi / 4, 1e-12),
        (1.0, 2.0, 1.0, (5 - S13) / 36, (5 + S13) / 36, 5 / 18, -math.atan((S13 - 3) / 2), 1e-12),
        # the same plate mirrored in y = x and three times heavier: theta1 -> -pi/2 - theta1
        (3.0, 1.0, 2.0, (5 - S13) / 12, (5 + S13) / 12, 5 / 6, -math.pi / 2 + math.atan((S13 - 3) / 2), 1e-12),
        (1.0, 1.0, 1e-6, 1e-12 / 24, 1 / 18, 1 / 18, -5e-7, 1e-10),
        (1.0, 1e-6, 1.0, 1e-12 / 24, 1 / 18, 1 / 18, -math.pi / 2 + 5e-7, 1e-10),
    ],
)
def test_against_hand_values(M, a, b, I1, I2, I3, theta1, rel):
    an, nu, _ = solve_both("4.3", M=M, a=a, b=b)
    for v in (an, nu):
        assert v["I1"] == pytest.approx(I1, rel=rel)
        assert v["I2"] == pytest.approx(I2, rel=rel)
        assert v["I3"] == pytest.approx(I3, rel=rel)
        assert v["theta1"] == pytest.approx(theta1, rel=rel)
        assert -math.pi / 2 < v["theta1"] <= math.pi / 2


def test_perpendicular_axis_rule_and_order():
    _, n, _ = solve_both("4.3", M=1.3, a=0.7, b=0.4)
    assert n["I1"] <= n["I2"] <= n["I3"]
    assert n["I3"] == pytest.approx(n["I1"] + n["I2"], rel=1e-13)

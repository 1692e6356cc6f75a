"""4.2 against values worked out by hand.

Rod triangle: rod of mass M/3, length a, midpoint at the inradius r = a/(2 sqrt 3)
from the center; normal moment per rod (M/3)(a^2/12 + r^2) = (M/3)(a^2/6), so
I3 = M a^2/6; planar body: I1 + I2 = I3 and threefold symmetry gives I1 = I2.
Plate: polar moment of a triangle about its centroid is M (a^2+b^2+c^2)/36 = M a^2/12.
Tetrahedron: vertices (1,1,1), (1,-1,-1), (-1,1,-1), (-1,-1,1) times s have edge
a = 2 sqrt2 s; the second moments of a tetrahedron about its centroid are
(M/20) sum v v^T = (M/20)(4 s^2) 1, so I = 2 * (M/20) 4 s^2 = (2/5) M s^2 = M a^2/20.
"""

import pytest

from conftest import solve_both


def hand(M, a):
    return {
        "I_rods_inplane": M * a**2 / 12,
        "I_rods_normal": M * a**2 / 6,
        "I_plate_inplane": M * a**2 / 24,
        "I_plate_normal": M * a**2 / 12,
        "I_tetra": M * a**2 / 20,
    }


@pytest.mark.parametrize(
    "M, a, expected",
    [
        # defaults: M a^2 = 0.04
        (1.0, 0.2, {"I_rods_inplane": 0.04 / 12, "I_rods_normal": 0.04 / 6, "I_plate_inplane": 0.04 / 24,
                    "I_plate_normal": 0.04 / 12, "I_tetra": 0.002}),
        # M a^2 = 0.75
        (3.0, 0.5, {"I_rods_inplane": 0.0625, "I_rods_normal": 0.125, "I_plate_inplane": 0.03125,
                    "I_plate_normal": 0.0625, "I_tetra": 0.0375}),
        (2.06e-25, 2.21e-10, hand(2.06e-25, 2.21e-10)),
        (1.0e13, 1.0e4, hand(1.0e13, 1.0e4)),
    ],
)
def test_against_hand_values(M, a, expected):
    an, nu, _ = solve_both("4.2", M=M, a=a)
    for values in (an, nu):
        for k, v in expected.items():
            assert values[k] == pytest.approx(v, rel=1e-12)


def test_ordering_explained():
    # mass drawn toward the center lowers every moment: rods > plate; the planar rule I3 = 2 I1
    _, n, _ = solve_both("4.2", M=1.0, a=1.0)
    assert n["I_rods_normal"] == pytest.approx(2 * n["I_rods_inplane"], rel=1e-13)
    assert n["I_plate_normal"] == pytest.approx(2 * n["I_plate_inplane"], rel=1e-13)
    assert n["I_rods_inplane"] > n["I_plate_inplane"]
    assert n["I_tetra"] > n["I_plate_inplane"]

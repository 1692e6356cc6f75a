"""4.1 against the textbook ratios, worked out by hand.

Hoop: every element at R from the axis, I_axis = M R^2; perpendicular axes:
I_x + I_y = I_z, so I_diam = M R^2 / 2.  Disk: I_axis = int_0^R r^2 (2 M r dr / R^2)
= M R^2 / 2, I_diam = M R^2 / 4.  Shell: 3 I = 2 M R^2.  Ball: 3 I = 2 int r^2 dm
= 2 (3/5) M R^2.
"""

import pytest

from conftest import solve_both

RATIOS = {"I_hoop_diam": 0.5, "I_hoop_axis": 1.0, "I_disk_diam": 0.25, "I_disk_axis": 0.5,
          "I_shell": 2 / 3, "I_ball": 0.4}


@pytest.mark.parametrize("M, R", [(1.0, 0.1), (7.5, 2.0), (5.972e24, 6.371e6), (3.95e-25, 7.4e-15)])
def test_ratios(M, R):
    a, n, _ = solve_both("4.1", M=M, R=R)
    for name, ratio in RATIOS.items():
        assert a[name] == pytest.approx(ratio * M * R**2, rel=1e-14)
        assert n[name] == pytest.approx(ratio * M * R**2, rel=1e-12)


def test_ordering_the_comparison_is_about():
    _, n, _ = solve_both("4.1")
    # the mass farther from the center turns harder: hoop > shell > disk axis > ball
    assert n["I_hoop_axis"] > n["I_shell"] > n["I_disk_axis"] > n["I_ball"] > n["I_disk_diam"]

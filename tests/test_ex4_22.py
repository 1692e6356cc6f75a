"""4.22 against values worked out by hand.

Hand derivation (torques about the joint, shaft along e_r, horizontal):
rolling at distance l from the axis: R omega_spin = Omega l.  The spin's
angular momentum (M R^2/2) omega_spin lies along the shaft and turns with it,
so dL/dt = (M R^2/2)(Omega l/R) Omega, along the horizontal direction normal to
the shaft; the only torques with that direction are the weight's, M g l, and the
floor's, -N l.  Hence N - M g = M R Omega^2/2.  Numbers by a calculator.
"""

import math

import pytest

from conftest import solve_both


@pytest.mark.parametrize(
    "M, R, l, Omega, g, N, dN, spin",
    [
        # defaults: dN = 2 * 0.1 * 9 / 2 = 0.9; N = 19.62 + 0.9; spin = 3 * 0.5 / 0.1
        (2.0, 0.1, 0.5, 3.0, 9.81, 20.52, 0.9, 15.0),
        # the catalogue's large-disk case: dN = 0.5 * 0.3 * 400 / 2 = 30; N = 4.905 + 30; spin = 20 * 0.4 / 0.3
        (0.5, 0.3, 0.4, 20.0, 9.81, 34.905, 30.0, 80.0 / 3.0),
        # slow turning: dN = 2 * 0.1 * 1e-6 / 2 = 1e-7 exactly, no subtraction
        (2.0, 0.1, 0.5, 1e-3, 9.81, 19.6200001, 1e-7, 5e-3),
        # disk much larger than the shaft, on the Moon: dN = 3 * 2 * 25 / 2 = 75
        (3.0, 2.0, 0.01, 5.0, 1.62, 4.86 + 75.0, 75.0, 0.025),
    ],
)
def test_against_hand_values(M, R, l, Omega, g, N, dN, spin):
    a, n, _ = solve_both("4.22", M=M, R=R, l=l, Omega=Omega, g=g)
    for values in (a, n):
        assert values["N"] == pytest.approx(N, rel=1e-12)
        assert values["delta_N"] == pytest.approx(dN, rel=1e-11)
        assert values["omega_spin"] == pytest.approx(spin, rel=1e-12)


def test_excess_is_independent_of_shaft_length_and_even_in_omega():
    # dN = M R Omega^2 / 2 has no l in it: the numeric torque sums must not depend on l either
    base = solve_both("4.22", l=0.5)[1]["delta_N"]
    for l in (1e-4, 0.05, 5.0, 1e4):
        assert solve_both("4.22", l=l)[1]["delta_N"] == pytest.approx(base, rel=1e-11)
    assert base == pytest.approx(0.5 * 2.0 * 0.1 * 9.0, rel=1e-12)


def test_extreme_aspect_ratio_keeps_the_small_excess():
    # l/R = 1e12: the elements' Coriolis and spin terms are 1e12 times the answer, dN = 1e-6 * 9 / 2 * 1
    a, n, _ = solve_both("4.22", M=1.0, R=1e-6, l=1e6, Omega=3.0)
    assert n["delta_N"] == pytest.approx(4.5e-6, rel=1e-10)
    assert n["omega_spin"] == pytest.approx(3e12, rel=1e-12)

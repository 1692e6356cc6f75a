"""4.14 against values worked out by hand.

Hand derivation: for the solid hemisphere (z <= 0 below the flat face's center O)
the first moment is int z dV = -pi R^4 / 4 over the volume 2 pi R^3 / 3, so
d = 3R/8.  A full ball has 2 M' R^2/5 about a diameter, so the half has
I_O = 2 M R^2/5 about an axis in its flat face; I_c = I_O - M d^2 = 83 M R^2/320.
U = M g (R - d cos t) has stiffness M g d.  Frictionless: no horizontal force,
so the center of mass moves vertically only, to second order: omega^2 =
M g d / I_c = (3/8)(320/83) g/R = 120 g/(83 R).  Rolling: the center of mass
is R - d = 5R/8 above the contact, I_P = I_c + 25 M R^2/64 = 13 M R^2/20,
omega^2 = (3/8)(20/13) g/R = 15 g/(26 R).
"""

import math

import pytest

from conftest import solve_both


@pytest.mark.parametrize(
    "R, g",
    [(0.1, 9.81), (0.001, 9.81), (50.0, 9.81), (0.37, 1.62), (2.0, 274.0),
     # far from 1 m the SI polarization lost the cross terms: 4e-4 off at R = 1e-13, 4e-6 at 1e11
     # down to 1e-280 m (the answers stay inside 1e+-290, the range mech answers in; R = 1e-300 m is refused)
     (1e-13, 9.81), (1e-7, 9.81), (1e11, 9.81), (1e-280, 9.81)],
)
def test_against_hand_values(R, g):
    a, n, _ = solve_both("4.14", R=R, g=g)
    for values in (a, n):
        assert values["d_cm"] == pytest.approx(0.375 * R, rel=1e-12)
        assert values["omega_frictionless"] == pytest.approx(math.sqrt(120 * g / (83 * R)), rel=1e-9)
        assert values["omega_rolling"] == pytest.approx(math.sqrt(15 * g / (26 * R)), rel=1e-9)


def test_an_answer_below_the_floating_point_range_is_refused():
    # d_cm = 3 R / 8 = 3.75e-301 m at R = 1e-300 m: below 1e-290, refused in one line naming the answer
    from mech.problems import registry
    from mech.problems.spec import BadInput

    with pytest.raises(BadInput, match="d_cm .*floating-point range"):
        registry.get("4.14").resolve({"R": 1e-300})


def test_defaults_numbers_and_catalogue_orders_of_magnitude():
    # the catalogue quotes 75 and 119 rad/s for R = 1 mm
    a, n, _ = solve_both("4.14", R=0.001)
    assert n["omega_rolling"] == pytest.approx(75.2, abs=0.1)
    assert n["omega_frictionless"] == pytest.approx(119.1, abs=0.1)
    # defaults: sqrt(120*9.81/8.3) = 11.90929575..., sqrt(15*9.81/2.6) = 7.52304152...
    a, n, _ = solve_both("4.14")
    assert n["omega_frictionless"] == pytest.approx(11.909295751, rel=1e-9)
    assert n["omega_rolling"] == pytest.approx(7.523041529, rel=1e-9)


def test_rolling_is_slower_and_free_mode_pivots_about_center_of_mass():
    a, n, run = solve_both("4.14", R=0.2)
    assert n["omega_rolling"] < n["omega_frictionless"]
    # free sliding: the zero-momentum mode keeps the center of mass fixed horizontally,
    # x_O + d theta = 0 (the center of mass is d below O; theta z x (0, -d) = (d theta, 0))
    assert run.info["free_mode_xO_per_theta"] == pytest.approx(-0.375 * 0.2, rel=1e-9)

"""4.13 against values worked out by hand.

Hand derivation: rho = R' - R.  The cylinder's axis moves with velocity
(X' + rho theta' cos theta, rho theta' sin theta); its contact point with the
hollow is at rho + R = R' from the hollow's axis, and no slip there asks the axis
velocity relative to the block plus R phi' along the tangent to vanish:
rho theta' + R phi' = 0.  At theta = 0 the linearized T is
(M + M') X'^2/2 + M rho X' theta' + (M rho^2/2 + (M R^2/2)(rho/R)^2/2) theta'^2,
so the mass matrix is [[M + M', M rho], [M rho, 3 M rho^2/2]] and U = M g rho theta^2/2.
Zero total momentum: (M + M') X + M rho theta = 0; eliminating X leaves
(3/2 - M/(M + M')) M rho^2 theta'' = -M g rho theta.  The test evaluates these
two lines numerically for each parameter set.  M' = M, R' = 2R gives
omega^2 = g/R (rho = R, 3/2 - 1/2 = 1).
"""

import math

import pytest

from conftest import solve_both


def hand(M, R, Mb, Rp, g):
    rho = Rp - R
    m_eff = (1.5 - M / (M + Mb)) * M * rho**2
    X_over_theta = -M * rho / (M + Mb)
    return math.sqrt(M * g * rho / m_eff), X_over_theta, (X_over_theta + rho) / X_over_theta, -rho / R


@pytest.mark.parametrize(
    "M, R, M_prime, R_prime, g",
    [
        (1.0, 0.1, 1.0, 0.2, 9.81),
        (1.0, 0.1, 0.0, 0.2, 9.81),
        (1.0, 0.1, 1e6, 0.2, 9.81),
        (2.0, 0.03, 0.5, 1.0, 1.62),
        (1.0, 0.1, 1.0, 0.1000001, 9.81),
    ],
)
def test_against_hand_values(M, R, M_prime, R_prime, g):
    omega, X_t, xc_X, phi_t = hand(M, R, M_prime, R_prime, g)
    a, n, _ = solve_both("4.13", M=M, R=R, M_prime=M_prime, R_prime=R_prime, g=g)
    for values in (a, n):
        assert values["omega"] == pytest.approx(omega, rel=1e-9)
        assert values["X_over_theta"] == pytest.approx(X_t, rel=1e-9)
        assert values["xc_over_X"] == pytest.approx(xc_X, rel=1e-9, abs=1e-11)
        assert values["phi_over_theta"] == pytest.approx(phi_t, rel=1e-9)


def test_book_case_and_massless_block():
    a, n, _ = solve_both("4.13")  # M' = M, R' = 2R
    for values in (a, n):
        assert values["omega"] == pytest.approx(math.sqrt(9.81 / 0.1), rel=1e-10)
        assert values["X_over_theta"] == pytest.approx(-0.05, rel=1e-10)  # -M rho/(2M)
        assert values["xc_over_X"] == pytest.approx(-1.0, rel=1e-10)  # the axis moves against the block
    a, n, _ = solve_both("4.13", M_prime=0.0)
    for values in (a, n):
        # no block inertia: the axis stays put horizontally, omega^2 = 2 g / rho
        assert values["xc_over_X"] == pytest.approx(0.0, abs=1e-12)
        assert values["omega"] == pytest.approx(math.sqrt(2 * 9.81 / 0.1), rel=1e-10)


def test_cylinder_must_fit():
    from mech.problems import registry
    from mech.problems.spec import BadInput

    with pytest.raises(BadInput):
        registry.get("4.13").resolve({"R_prime": 0.05})


@pytest.mark.parametrize("scale", [1e-200, 1e200])
def test_extreme_scales(scale):
    """Every parameter times 1e+-200 (M' = M, R' = 2R): rho = R, (M + M')/(M + 3M') = 1/2, so
    omega^2 = g/rho = 9.81/0.1 whatever the scale (g/R is a ratio of scaled values), X/theta = -rho/2,
    x_c/X = -1, phi/theta = -1.  And R' alone 1e200 times its default: rho = 2e199 m to the last bit
    (R = 0.1 is below its ulp), omega^2 = g/rho, X/theta = -rho/2, phi/theta = -rho/R = -2e200."""
    a, n, _ = solve_both("4.13", M=scale, R=0.1 * scale, M_prime=scale, R_prime=0.2 * scale, g=9.81 * scale)
    for values in (a, n):
        assert values["omega"] == pytest.approx(math.sqrt(98.1), rel=1e-9)
        assert values["X_over_theta"] == pytest.approx(-0.05 * scale, rel=1e-9)
        assert values["xc_over_X"] == pytest.approx(-1.0, rel=1e-9)
        assert values["phi_over_theta"] == pytest.approx(-1.0, rel=1e-9)
    a, n, _ = solve_both("4.13", R_prime=0.2e200)
    for values in (a, n):
        assert values["omega"] == pytest.approx(math.sqrt(9.81 / 0.2e200), rel=1e-9)
        assert values["X_over_theta"] == pytest.approx(-0.1e200, rel=1e-9)
        assert values["phi_over_theta"] == pytest.approx(-2e200, rel=1e-9)

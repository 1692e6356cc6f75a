"""4.9 against values worked out by hand and a different quadrature.

Hand derivation: the contact line is the instantaneous axis; the center of mass
is at distance d from it, d^2 = l^2 + R^2 - 2 R l cos phi (law of cosines in the
triangle axis / center of mass / contact).  T = (I + M d^2) phi'^2/2,
U = -M g l cos phi; at phi = 0, d = R - l, so Omega^2 = M g l / (I + M (R - l)^2).
Defaults: I + M (R - l)^2 = 0.004 + 0.0049 = 0.0089, Omega^2 = 0.2943/0.0089.
The period is checked against the energy integral taken directly in phi,
4 int_0^phi0 (J / (2 M g l (cos phi - cos phi0)))^(1/2) dphi, by scipy's quad with
the (phi0 - phi)^(-1/2) endpoint weight (a different route from the module's
elliptic split in the variable u).
"""

import math

import pytest
from scipy.integrate import quad

from conftest import solve_both


def period_direct(M, R, l, I, phi0, g):
    def f(phi):
        J = I + M * ((R - l) ** 2 + 4 * R * l * math.sin(phi / 2) ** 2)  # law of cosines, cancellation-free
        # (cos phi - cos phi0)/(phi0 - phi), finite at phi = phi0
        ratio = 2 * math.sin((phi0 + phi) / 2) * math.sin((phi0 - phi) / 2) / (phi0 - phi) if phi < phi0 else math.sin(phi0)
        return math.sqrt(J / (2 * M * g * l * ratio))

    val, _ = quad(f, 0.0, phi0, weight="alg", wvar=(0.0, -0.5), epsabs=0, epsrel=1e-12, limit=200)
    return 4 * val


@pytest.mark.parametrize(
    "M, R, l, I, phi0, g",
    [
        (1.0, 0.1, 0.03, 0.004, math.pi / 6, 9.81),
        (2.0, 0.5, 0.2, 0.1, 1.5, 9.81),
        (1.0, 0.1, 0.0999, 1e-8, math.pi / 6, 9.81),
        (0.3, 0.02, 0.001, 5e-5, 2.5, 1.62),
        (1.0, 0.1, 0.05, 0.0, 0.01, 9.81),
        (1.0, 0.1, 0.0999999, 0.0, math.pi / 6, 9.81),  # all mass on the rim line: Omega ~ 1e7
    ],
)
def test_against_hand_values(M, R, l, I, phi0, g):
    a, n, run = solve_both("4.9", M=M, R=R, l=l, I=I, phi0=phi0, g=g)
    Omega = math.sqrt(M * g * l / (I + M * (R - l) ** 2))
    T = period_direct(M, R, l, I, phi0, g)
    for values in (a, n):
        assert values["Omega"] == pytest.approx(Omega, rel=1e-10)
        assert values["period"] == pytest.approx(T, rel=1e-8)
    assert run.invariants["energy"] < 1e-8


def test_defaults_by_hand():
    a, n, _ = solve_both("4.9")
    for values in (a, n):
        assert values["Omega"] == pytest.approx(math.sqrt(0.2943 / 0.0089), rel=1e-12)


def test_small_amplitude_period_tends_to_two_pi_over_Omega():
    phi0 = 1e-3
    a, n, _ = solve_both("4.9", phi0=phi0)
    # the relative correction is of order phi0^2 (here below 1e-6)
    for values in (a, n):
        assert values["period"] == pytest.approx(2 * math.pi / values["Omega"], rel=1e-6)


def test_near_top_period_grows_logarithmically():
    # near the unstable top the quarter period grows as ln(1/gap)/lambda: each factor 10
    # closer adds ln(10)/lambda per quarter, lambda^2 = M g l / (I + M (R + l)^2)
    lam = math.sqrt(9.81 * 0.03 / (0.004 + 0.13**2))
    T5 = solve_both("4.9", phi0=math.pi - 1e-5)[1]["period"]
    T6 = solve_both("4.9", phi0=math.pi - 1e-6)[1]["period"]
    assert T6 - T5 == pytest.approx(4 * math.log(10) / lam, rel=1e-6)


def test_release_a_nanoradian_below_the_top():
    # both solvers hold their digits 1e-9 rad below the top (the module keeps phi - phi0 as state)
    a, n, _ = solve_both("4.9", phi0=math.pi - 1e-9)
    assert n["period"] == pytest.approx(a["period"], rel=1e-9)
    T6 = solve_both("4.9", phi0=math.pi - 1e-6)[0]["period"]
    lam = math.sqrt(9.81 * 0.03 / (0.004 + 0.13**2))
    assert a["period"] - T6 == pytest.approx(4 * math.log(1000) / lam, rel=1e-6)


def test_a_center_of_mass_1e300_from_the_axis_keeps_omega():
    """Issue 26: l = 1e-300 m, g = 2.05e-4 m/s^2.  Omega^2 = M g l / (I + M (R - l)^2) = 2.05e-304/0.014
    is representable in SI but not in every set of units (1e-379 in the natural units the analytic
    solution works in), and Omega came out 0 for 1.2e-151 rad/s.  With l -> 0 the contact-line inertia
    I + M d^2 is I + M R^2 at every angle (the R l terms are 1e-301 of it), so the swing is a plain
    pendulum's: period = 4 K(sin(phi0/2))/Omega, K = pi/(2 agm(1, cos(phi0/2)))."""
    M, R, l, I, phi0, g = 1.0, 0.1, 1e-300, 0.004, 0.5236, 2.05e-4
    omega = math.sqrt(M * g * l / (I + M * R * R))
    a_, b_ = 1.0, math.cos(phi0 / 2)
    for _ in range(40):
        a_, b_ = (a_ + b_) / 2, math.sqrt(a_ * b_)
    period = 4 * (math.pi / (2 * a_)) / omega
    a, n, _ = solve_both("4.9", l=l, phi0=phi0, g=g)
    assert a["Omega"] == pytest.approx(omega, rel=1e-14, abs=0.0)
    assert n["Omega"] == pytest.approx(omega, rel=1e-11, abs=0.0)
    assert a["period"] == pytest.approx(period, rel=1e-12)
    assert n["period"] == pytest.approx(period, rel=1e-8)


def test_a_release_at_1e_184_rad_keeps_its_energy_check():
    """phi0 = 2.4e-184 rad squares to 0 in doubles; the energy check divides by the amplitude first, so the
    drift is a number and the cross-check stands (it failed on a NaN drift before).  By hand, small
    oscillations: Omega^2 = M g l / (I + M (R - l)^2)."""
    import math

    import mech

    M, R, l, I, g = 1.2e95, 0.1, 5.6e-38, 0.004, 9.81
    sol = mech.solve("4.9", M=M, l=l, phi0=2.4e-184)
    assert sol.agree is True
    drift = sol.to_dict()["numeric_info"]["invariants"]["energy"]
    assert math.isfinite(drift) and drift < 1e-8
    assert sol["Omega"].numeric == pytest.approx(math.sqrt(M * g * l / (I + M * (R - l) ** 2)), rel=1e-9)


@pytest.mark.parametrize("M, R, l, I, phi0, g", [
    (1.17199e95, 1.26867e28, 5.61857e-38, 6.19556e-90, 2.42484e-184, 3.71034e-125),
    (9.07183e-288, 1.03238e117, 2.1478e-46, 2.80894e-191, 9.71968e-66, 8.6113e77),
])
def test_far_apart_si_values_are_solved_in_the_routes_own_units(M, R, l, I, phi0, g):
    """In-bounds inputs 300 decades from the defaults (hostile2's budget probe): in SI the swing's products
    (M l sin phi, Omega^2 phi0) underflow and the solve ran until its budget.  In units of M, R and
    sqrt(R/g) they do not.  By hand, small oscillations: Omega^2 = M g l / (I + M (R - l)^2) = (g/R) (l/R) /
    (I/(M R^2) + (1 - l/R)^2), each factor representable."""
    import math

    import mech

    sol = mech.solve("4.9", M=M, R=R, l=l, I=I, phi0=phi0, g=g)
    assert sol.agree is True
    omega = math.sqrt(g / R) * math.sqrt((l / R) / (I / M / R / R + (1 - l / R) ** 2))
    assert sol["Omega"].numeric == pytest.approx(omega, rel=1e-9)

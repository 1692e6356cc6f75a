"""4.34 against values worked out by hand.

Hand derivation (orbital frame, Hill's field): two masses m at +-l n have
U = m Omega^2 l^2 (-3 n_x^2 + n_z^2): lowest with n along the vertical
(|cos psi| = 1).  Pitch: 2 m l^2 theta'' = -3 m l^2 Omega^2 sin 2 theta, so
phi = 2 theta is a pendulum of frequency 3^(1/2) Omega; roll: the tilt alpha
out of the plane is pulled back by 3 Omega^2 (vertical) + Omega^2 (normal),
frequency 2 Omega.  Period of amplitude theta_amp: T = 4 K(k)/(3^(1/2) Omega),
k = sin theta_amp.  K is computed here by the arithmetic-geometric mean,
K = pi/(2 AGM(1, cos theta_amp)), a different route from the module's
elliptic-integral call.
"""

import math

import pytest

from conftest import solve_both

GM = 3.986004418e14


def agm(a, b):
    for _ in range(60):
        a, b = 0.5 * (a + b), math.sqrt(a * b)
    return a


def T_hand(theta_amp, Omega):
    return 4 * (math.pi / (2 * agm(1.0, math.cos(theta_amp)))) / (math.sqrt(3) * Omega)


@pytest.mark.parametrize(
    "R, theta_amp",
    [(7.0e6, math.radians(10.0)), (7.0e6, 1.5706217938696971), (7.0e6, 0.0), (4.2164e7, math.radians(45.0)),
     (6.6e6, 1e-9),
     # a swing of 1e-200 rad: integrated with a 1e-150 floor on the tolerances it came out 6e-5 off
     (7.0e6, 1.74533e-201), (7.0e6, 1e-12)],
)
def test_hand_values(R, theta_amp):
    Omega = math.sqrt(GM / R**3)
    a, n, run = solve_both("4.34", R=R, GM=GM, theta_amp=theta_amp)
    for values in (a, n):
        assert values["cos_psi_eq"] == pytest.approx(1.0, rel=1e-12)
        assert values["omega_pitch"] == pytest.approx(math.sqrt(3) * Omega, rel=1e-9)
        assert values["omega_roll"] == pytest.approx(2 * Omega, rel=1e-9)
        assert values["T_pitch"] == pytest.approx(T_hand(theta_amp, Omega), rel=1e-8)
    for drift in run.invariants.values():
        assert drift < 1e-9


def test_default_orbit_numbers():
    # Omega^2 = 3.986004418e14 / 3.43e20 = 1.16210e-6, Omega = 1.07801e-3 rad/s (1.07801^2 = 1.162106)
    a, n, _ = solve_both("4.34")
    for values in (a, n):
        assert values["omega_pitch"] == pytest.approx(1.73205 * 1.07801e-3, rel=1e-5)
        assert values["omega_roll"] == pytest.approx(2.15602e-3, rel=1e-5)


def test_near_the_separatrix_the_period_is_6_4_times_the_small_one():
    # K(k) ~ ln(4/k') for k' = cos(89.99 deg) = 1.745e-4: ln(22918) = 10.04; 10.04/(pi/2) = 6.39
    a, n, _ = solve_both("4.34", theta_amp=1.5706217938696971)
    _, n0, _ = solve_both("4.34", theta_amp=0.0)
    assert n["T_pitch"] / n0["T_pitch"] == pytest.approx(6.39, abs=0.01)


@pytest.mark.parametrize("scale", [1e-200, 1e200])
def test_orbit_at_extreme_scales(scale):
    """R and GM both 1e+-200 times their defaults: Omega^2 = GM/R^3 becomes 1e-+400 times the default's,
    so Omega = 1e-+200 Omega_0 with Omega_0 = (3.986004418e14/7e6^3)^(1/2) s^-1 (R^3 alone would leave the
    range), and T = 4 K(sin theta)/(3^(1/2) Omega) as above."""
    Omega = math.sqrt(GM / 7.0e6**3) / scale
    theta = math.radians(10.0)
    a, n, _ = solve_both("4.34", R=7.0e6 * scale, GM=GM * scale, theta_amp=theta)
    for values in (a, n):
        assert values["omega_pitch"] == pytest.approx(math.sqrt(3) * Omega, rel=1e-9)
        assert values["omega_roll"] == pytest.approx(2 * Omega, rel=1e-9)
        assert values["T_pitch"] == pytest.approx(T_hand(theta, Omega), rel=1e-8)

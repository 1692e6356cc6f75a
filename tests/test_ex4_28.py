"""4.28 against values worked out by hand.

Hand derivation: with the origin at the center of mass, grad U_eff =
G M1 (r1^-3 - d^-3) d1 + G M2 (r2^-3 - d^-3) d2, zero off the line only for
r1 = r2 = d: x = d/2 - mu d, y = (sqrt 3/2) d.  At that point U_xx = -(3/4) W^2,
U_yy = -(9/4) W^2, U_xy = -(3 sqrt3/4)(1 - 2 mu) W^2, and the determinant of
[[l^2 + U_xx, -2 W l + U_xy], [2 W l + U_xy, l^2 + U_yy]] is
l^4 + W^2 l^2 + (27/4) mu (1 - mu) W^4.  Vieta: omega_slow^2 + omega_fast^2 = W^2 and
omega_slow^2 omega_fast^2 = (27/4) mu (1-mu) W^4 where stable.  Numbers by a calculator.
"""

import math

import pytest

from conftest import solve_both

G = 6.67430e-11


def hand(M1, M2, d):
    mu = M2 / (M1 + M2)
    W = math.sqrt(G * (M1 + M2) / d**3)
    q = 27 * mu * (1 - mu)
    if q <= 1:
        s = math.sqrt(1 - q)
        slow, fast, growth = W * math.sqrt((1 - s) / 2), W * math.sqrt((1 + s) / 2), 0.0
    else:
        growth = W / 2 * math.sqrt(math.sqrt(q) - 1)
        slow = fast = W / 2 * math.sqrt(math.sqrt(q) + 1)
    return {"x_L4": d * (0.5 - mu), "y_L4": d * math.sqrt(3) / 2, "growth_rate": growth,
            "omega_slow": slow, "omega_fast": fast}, W, mu


@pytest.mark.parametrize(
    "M1, M2, d",
    [
        (5.9722e24, 7.342e22, 3.844e8),  # defaults: Earth-Moon, stable
        (1.98847e30, 1.898e27, 7.785e11),  # Sun-Jupiter: the Trojans
        (1.922e30, 7.8e28, 1.0e11),  # hard case 3: just unstable
        (5e24, 5e24, 1e9),  # equal masses: strongly unstable, x_L4 = 0
        (1e20, 3e22, 1e8),  # labels swapped: M2 the heavier, mu = 0.9967
    ],
)
def test_against_hand_formulas(M1, M2, d):
    expect, W, mu = hand(M1, M2, d)
    a, n, _ = solve_both("4.28", M1=M1, M2=M2, d=d)
    for values in (a, n):
        for k, v in expect.items():
            assert values[k] == pytest.approx(v, rel=1e-7, abs=1e-12 * d if k == "x_L4" else 1e-9 * W), k


def test_sun_earth_slow_libration():
    # mu = 3.0035e-6: omega_slow = W sqrt(27 mu/4) (1 + O(mu)) = 0.0045 W
    M1, M2, d = 1.98847e30, 5.9722e24, 1.495978707e11
    mu = M2 / (M1 + M2)
    W = math.sqrt(G * (M1 + M2) / d**3)
    a, n, _ = solve_both("4.28", M1=M1, M2=M2, d=d)
    for values in (a, n):
        assert values["omega_slow"] == pytest.approx(W * math.sqrt(27 * mu / 4), rel=3e-5)
        assert values["omega_slow"] ** 2 + values["omega_fast"] ** 2 == pytest.approx(W * W, rel=1e-12)
        assert values["omega_slow"] ** 2 * values["omega_fast"] ** 2 == pytest.approx(
            27 / 4 * mu * (1 - mu) * W**4, rel=1e-9)
        assert values["growth_rate"] < 1e-12 * W


def test_routh_limit_merges_the_frequencies():
    # mu_c = (1 - sqrt(23/27))/2: both frequencies W/sqrt 2, no growth (to sqrt(eps) W)
    M1, M2, d = 1.9229582069908973e30, 7.704179300910274e28, 1.0e11
    W = math.sqrt(G * (M1 + M2) / d**3)
    a, n, _ = solve_both("4.28", M1=M1, M2=M2, d=d)
    for values in (a, n):
        assert values["omega_slow"] == pytest.approx(W / math.sqrt(2), abs=3e-7 * W)
        assert values["omega_fast"] == pytest.approx(W / math.sqrt(2), abs=3e-7 * W)
        assert values["growth_rate"] < 3e-7 * W


def test_newton_finds_l4_for_every_mass_ratio():
    """L4 is at r1 = r2 = d for any mu: (1/2 - mu, sqrt3/2) in units of d (M2/M1 from 1e-290 to 1e290:
    the flat circle is about the heavier body, either one).  Cartesian Newton stopped
    short of it for mu < 1e-25 (at x = 0.198) and cycled at mu = 4.4e-5 (issue 14 draw)."""
    import numpy as np

    from mech.solvers.mechanics.frames import mass_fractions, newton_equilibrium

    for ratio in np.concatenate([np.geomspace(1e-290, 1.0, 120), np.geomspace(1.0, 1e290, 60)]):
        nu, mu = mass_fractions(1.0, float(ratio))
        r, iters = newton_equilibrium([0.0, 1.0], mu, nu)
        assert r[0] == pytest.approx(0.5 - mu, abs=1e-14), ratio
        assert r[1] == pytest.approx(math.sqrt(3) / 2, rel=1e-14), ratio
        assert iters <= 20


@pytest.mark.parametrize(
    "M1, M2, d",
    [
        (4.99008e28, 2.19363e24, 1.22544e8),  # issue 14 draw: Newton cycled, a loud failure
        (5.9722e24, 5.9722e12, 3.844e8),  # mu = 1e-12: the 4x4 eigen-solve could not resolve the slow pair
        (5.9722e24, 5.9722e4, 3.844e8),  # mu = 1e-20
    ],
)
def test_small_mass_ratios(M1, M2, d):
    """Stable: Vieta on l^4 + W^2 l^2 + (27/4) mu nu W^4 with q = 27 mu nu, s = (1 - q)^(1/2):
    fast^2 = W^2 (1 + s)/2 and slow^2 = (27/4) mu nu W^4 / fast^2 = W^2 q / (2 (1 + s)),
    the product over the larger root (no 1 - s cancellation)."""
    mu = M2 / (M1 + M2)
    W = math.sqrt(G * (M1 + M2) / d**3)
    q = 27 * mu * (1 - mu)
    s = math.sqrt(1 - q)
    a, n, _ = solve_both("4.28", M1=M1, M2=M2, d=d)
    for values in (a, n):
        assert values["omega_slow"] == pytest.approx(W * math.sqrt(q / (2 * (1 + s))), rel=1e-12)
        assert values["omega_fast"] == pytest.approx(W * math.sqrt((1 + s) / 2), rel=1e-12)
        assert values["x_L4"] == pytest.approx(d * (0.5 - mu), rel=1e-13)

"""5.6 against values worked out by hand.

Hand derivation: energy gives dt = dtheta / (omega0 sqrt(2 (cos theta - cos theta0))),
and sin(theta/2) = k sin(psi), k = sin(theta0/2), turns the quarter period into
K(k^2)/omega0.  Independent values used below:
  * theta0 = 90 deg: K(1/2) = Gamma(1/4)^2 / (4 sqrt(pi)) (lemniscate constant);
  * theta0 = 60 deg: K(1/4) = 1.6857503548125960 (tables);
  * small theta0: 2K/pi = 1 + m/4 + 9 m^2/64 + O(m^3), so
    2 pi/T - omega0 = omega0 (-m/4 - 5 m^2/64 + O(m^3)), m = sin^2(theta0/2);
  * near the top: K ~ ln(4/k') with k' = cos(theta0/2) ~ phi0/2, T ~ (4/omega0) ln(8/phi0)
    with a relative correction O(phi0^2).
"""

import math

import numpy as np
import pytest

from conftest import solve_both
from mech.problems.scene import make_scene


def test_ninety_degrees_lemniscate():
    K = math.gamma(0.25) ** 2 / (4 * math.sqrt(math.pi))
    w0 = math.sqrt(9.81 / 2.0)
    a, n, run = solve_both("5.6", theta0=math.pi / 2, l=2.0)
    for v in (a, n):
        assert v["T"] == pytest.approx(4 * K / w0, rel=1e-8)
        assert v["T_ratio"] == pytest.approx(2 * K / math.pi, rel=1e-8)
        assert v["domega"] == pytest.approx(w0 * (math.pi / (2 * K) - 1), rel=1e-7)
    assert run.invariants["energy"] < 1e-8


def test_sixty_degrees_defaults():
    K = 1.6857503548125960
    a, n, _ = solve_both("5.6")
    for v in (a, n):
        assert v["T"] == pytest.approx(4 * K / math.sqrt(9.81), rel=1e-8)
        assert v["T_ratio"] == pytest.approx(2 * K / math.pi, rel=1e-8)


@pytest.mark.parametrize("theta0", [0.01, 1e-4])
def test_small_amplitude_series(theta0):
    m = math.sin(theta0 / 2) ** 2
    w0 = math.sqrt(1.62 / 0.5)
    a, n, _ = solve_both("5.6", theta0=theta0, l=0.5, g=1.62)
    for v in (a, n):
        assert v["T_ratio"] == pytest.approx(1 + m / 4 + 9 * m * m / 64, rel=1e-10)
        assert v["domega"] == pytest.approx(w0 * (-m / 4 - 5 * m * m / 64), rel=1e-8)


def test_logarithmic_divergence_near_the_top():
    phi0 = 1e-7
    w0 = math.sqrt(9.81)
    a, n, _ = solve_both("5.6", theta0=math.pi - phi0)
    for v in (a, n):
        # (math.pi - phi0) is phi0 below the true pi to ~1e-9 relative in phi0
        assert v["T"] == pytest.approx(4 / w0 * math.log(8 / phi0), rel=1e-8)


def test_the_scene_draws_the_declared_quarter_swing_and_its_mirror_images_on_one_energy_level():
    """The phase portrait's swing is the numeric solve's declared motion (a quarter swing, here above 90
    degrees where it is integrated from upright) mirrored by time reversal and parity: a closed curve on
    θ'²/(2 ω0²) - cos θ = -cos θ0, written here, through (±θ0, 0) and (0, ±2 sin(θ0/2))."""
    from mech.problems import registry

    ex = registry.get("5.6")
    theta0 = 2.5
    scene, _ = make_scene(ex, ex.resolve({"theta0": theta0}), points=0)
    swing = next(i for i in scene.panels[0].items if getattr(i, "kind", "") == "trajectory")
    q, v = np.radians(swing.x), np.asarray(swing.y)
    assert np.max(np.abs(0.5 * v**2 - np.cos(q) + math.cos(theta0))) < 1e-8
    assert np.max(q) == pytest.approx(theta0, rel=1e-12) and np.min(q) == pytest.approx(-theta0, rel=1e-12)
    assert np.max(np.abs(v)) == pytest.approx(2.0 * math.sin(theta0 / 2.0), rel=1e-6)


def test_domega_next_to_the_top_against_a_100_digit_agm():
    """Issue 26: theta0 = pi - 3.1e-12.  2 pi/T = omega0 AGM(1, cos(theta0/2)) (K = pi/(2 AGM)), so
    domega = omega0 (AGM - 1); here cos(theta0/2) = sin((pi - theta0)/2) ~ 1.6e-12, with pi and the AGM
    taken in 100-digit Decimal (tests/hiprec.py).  The analytic value came out 6.5e-8 off (its claim
    5.8e-10): 1 - a b formed from the deviations from 1 held the small mean only to 1e-16 absolute."""
    from decimal import localcontext

    import hiprec

    g, theta0, l = 254219.77, 3.1415926535866516, 27.165
    with localcontext() as ctx:
        ctx.prec = hiprec.PREC
        a, b = hiprec.D(1), hiprec.sin((hiprec.PI - hiprec.D(theta0)) / 2)
        for _ in range(60):
            a, b = (a + b) / 2, (a * b).sqrt()
        w0 = (hiprec.D(g) / hiprec.D(l)).sqrt()
        want = float(w0 * (a - 1))
    an, num, _ = solve_both("5.6", g=g, theta0=theta0, l=l)
    assert an["domega"] == pytest.approx(want, rel=1e-13, abs=0.0)
    assert num["domega"] == pytest.approx(want, rel=1e-9, abs=0.0)

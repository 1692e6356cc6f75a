"""4.21 against values worked out by hand and by a different method.

Hand derivation: for the axis at fixed theta turning at Omega about z,
L = I_A Omega (z - cos th n3) + I3 w3 n3 (I_A = I1 + M l^2); a rigidly turning L
changes at Omega z x L = Omega (I3 w3 - I_A Omega cos th) z x n3, which must equal
the weight's torque M g l z x n3:  I_A cos th Omega^2 - I3 w3 Omega + M g l = 0.
The slow root is the one that tends to M g l/(I3 w3) for fast spin; it is real
when (I3 w3)^2 >= 4 I_A M g l cos th.  Threshold of the upright top (Eq. 4.85):
w_th = 2 sqrt(I_A M g l)/I3.  The quadratic is solved below by numpy.roots
(companion-matrix eigenvalues), not by the closed form of the module.

Defaults: I_A = 1.5625e-5 + 0.1*0.03^2 = 1.05625e-4, M g l = 0.02943,
w_th = 2 sqrt(1.05625e-4 * 0.02943)/3.125e-5 = 112.838801836...
"""

import math

import numpy as np
import pytest

from conftest import solve_both
from mech.problems.spec import Undefined

IA, MGL, I3 = 1.05625e-4, 0.1 * 9.81 * 0.03, 3.125e-5
W_TH = 2 * math.sqrt(IA * MGL) / I3


def slow_root_by_numpy(IA, I3, w3, Mgl, th):
    roots = np.roots([IA * math.cos(th), -I3 * w3, Mgl])
    pos = sorted(r.real for r in roots if abs(r.imag) < 1e-12 * abs(r) and r.real > 0)
    return pos[0]


def test_threshold_by_hand():
    assert W_TH == pytest.approx(112.83880183695, rel=1e-12)
    a, n, _ = solve_both("4.21")
    for v in (a, n):
        assert v["omega_th"] == pytest.approx(W_TH, rel=1e-12)


@pytest.mark.parametrize(
    "theta0, omega3",
    [(math.pi / 6, 400.0), (1.0, 150.0), (0.3, 2000.0), (2.0, 50.0), (3.0, 1.0)],
)
def test_rate_against_numpy_roots(theta0, omega3):
    a, n, run = solve_both("4.21", theta0=theta0, omega3=omega3)
    Om = slow_root_by_numpy(IA, I3, omega3, MGL, theta0)
    for v in (a, n):
        assert v["omega_pre"] == pytest.approx(Om, rel=1e-9)
        assert v["pre_ratio"] == pytest.approx(Om * I3 * omega3 / MGL, rel=1e-9)
        wmin = W_TH * math.sqrt(math.cos(theta0)) if math.cos(theta0) > 0 else 0.0
        assert v["omega_min"] == pytest.approx(wmin, rel=1e-9, abs=1e-9)
    # the integrated steady state holds: tilt constant, energy and L3 conserved
    assert run.invariants["tilt theta - theta0 (rad)"] < 1e-6
    assert run.invariants["energy less the spin's"] < 1e-8
    assert run.invariants["L3"] < 1e-8


def test_thin_fast_rotor_on_a_long_arm_keeps_its_energy():
    """Draw of scripts/draws.py (seed 1124): I3 = 1.2e-8 kg m^2 spun at 5632 rad/s on a 470 m arm.  By hand:
    L3 = I3 omega3 = 6.6e-5, the precession's |L| ~ (I1 + M l^2) Omega sin(theta0) ~ 1e2 kg m^2/s, so the whole
    energy's derivative in L (the angular velocity, ~omega3) times an error 1e-10 |L| moves the energy by
    ~6e-5 J of 0.25 J: the whole energy cannot be monitored to rtol.  Less its spin part (constant with L3,
    monitored on its own) it can: the motion is steady, so it must hold to rtol."""
    given = dict(M=0.0146227, l=470.246, I1=0.0898032, I3=1.17569e-08, omega3=5632.44, theta0=2.10357,
                 g=0.00858414)
    a, n, run = solve_both("4.21", **given)
    assert run.invariants["energy less the spin's"] < 1e-8
    assert run.invariants["tilt theta - theta0 (rad)"] < 1e-8


def test_horizontal_axis_is_the_fast_top_value():
    # cos th = 0: the quadratic is linear, Omega = M g l/(I3 w3) = 0.02943/0.0125 = 2.3544, ratio 1
    a, n, _ = solve_both("4.21", theta0=math.pi / 2)
    for v in (a, n):
        assert v["omega_pre"] == pytest.approx(2.3544, rel=1e-12)
        assert v["pre_ratio"] == pytest.approx(1.0, rel=1e-12)
        # cos(float pi/2) = 6.1e-17: omega_min = w_th * 7.8e-9, essentially zero
        assert v["omega_min"] < 1e-6


def test_hanging_gyroscope_exists_at_any_spin():
    # th = 120 deg, cos = -1/2: (I_A/2) Om^2 + I3 w3 Om - M g l = 0, positive root
    w3 = 5.0
    b, c = I3 * w3, IA / 2
    Om = (-b + math.sqrt(b * b + 4 * c * MGL)) / (2 * c)
    a, n, _ = solve_both("4.21", theta0=2 * math.pi / 3, omega3=w3)
    for v in (a, n):
        assert v["omega_min"] == 0.0 or v["omega_min"] < 1e-9 * W_TH
        assert v["omega_pre"] == pytest.approx(Om, rel=1e-9)


def test_just_above_omega_min_roots_nearly_merge():
    # w3 = w_min (1 + 1e-8) at th = 0.1: ratio = 2/(1 + sqrt(1 - (w_min/w3)^2)), sqrt(...) ~ 1.414e-4
    w3 = 112.55658804431975
    wmin = W_TH * math.sqrt(math.cos(0.1))
    ratio = 2 / (1 + math.sqrt(1 - (wmin / w3) ** 2))
    assert 2 - ratio == pytest.approx(2.828e-4, rel=1e-3)
    a, n, _ = solve_both("4.21", theta0=0.1, omega3=w3)
    for v in (a, n):
        assert v["pre_ratio"] == pytest.approx(ratio, rel=1e-10)
        assert v["omega_min"] == pytest.approx(wmin, rel=1e-12)


def test_below_omega_min_no_steady_precession():
    a, n, _ = solve_both("4.21", theta0=0.1, omega3=100.0)
    for v in (a, n):
        assert isinstance(v["omega_pre"], Undefined)
        assert isinstance(v["pre_ratio"], Undefined)
        assert v["omega_th"] == pytest.approx(W_TH, rel=1e-12)


def test_sweep_point_with_a_slow_steady_state_holds_its_tilt():
    """mech sweep 4.21 --omega3 200:2000:200 failed at omega3 = 453.266 (issue 14): unbounded
    steps grew to radians of the nutation, a round-off nutation grew to a 1.3e-6 rad tilt
    drift at any rtol.  The steady state is exact, so the integrated tilt must stay at
    theta0 to round-off, and the rate is the numpy root of the hand quadratic."""
    w3 = 453.266
    a, n, run = solve_both("4.21", omega3=w3)
    Om = slow_root_by_numpy(IA, I3, w3, MGL, math.pi / 6)
    assert n["omega_pre"] == pytest.approx(Om, rel=1e-9)
    assert run.invariants["tilt theta - theta0 (rad)"] < 1e-11


@pytest.mark.parametrize(
    "M, l, I1, I3_, w3, th, g",
    [
        # seeded draws (draws.py --seed 101) where omega_min missed by 0.3 % and 3 %: I_A/I3 ~ 1e10..1e14
        (24132.1, 2406.95, 0.0249653, 0.00139018, 27.517, 0.103769, 0.0643615),
        (4535.96, 1997.06, 1.00106, 4.36196e-05, 2.26233e07, 0.00310503, 517999.0),
        (969.172, 17317.7, 1.88843e-08, 7.64458, 1138.95, 0.00451451, 140.086),
    ],
)
def test_omega_min_at_extreme_inertias(M, l, I1, I3_, w3, th, g):
    """omega_min = 2 sqrt(I_A M g l cos th)/I3 (the discriminant of the hand quadratic
    vanishes); rotating the inertia tensor into lab axes lost its digits to a part in I_A/I3."""
    IA_, Mgl = I1 + M * l * l, M * g * l
    wmin = 2 * math.sqrt(IA_ * Mgl * math.cos(th)) / I3_
    a, n, _ = solve_both("4.21", M=M, l=l, I1=I1, I3=I3_, omega3=w3, theta0=th, g=g)
    assert n["omega_min"] == pytest.approx(wmin, rel=1e-9)
    if w3 > wmin:
        assert n["omega_pre"] == pytest.approx(slow_root_by_numpy(IA_, I3_, w3, Mgl, th), rel=1e-8)


def test_spin_carrying_nearly_all_of_l_keeps_its_energy():
    """Draw of scripts/draws.py (seed 20261125): L3 = I3 omega3 = 0.0104 kg m^2/s, while the precession
    Omega ~ M g l/(I3 omega3) ~ 1.3e-16 rad/s gives L_perp ~ 3e-17 and M g l ~ 1.4e-18 J.  |L|^2 - L3^2 loses
    everything to round-off (eps L3^2/I_A ~ 2e-20 J, a drift of ~1e-2 of the energy); the rejection
    L - (n.L) n does not, and the steady motion must then hold the energy to rtol."""
    given = dict(M=1.24915e-07, l=4.72373e-08, I1=0.499719, I3=0.0357475, omega3=0.292039, theta0=0.480073,
                 g=0.000229291)
    a, n, run = solve_both("4.21", **given)
    assert run.invariants["energy less the spin's"] < 1e-8

"""4.24 against values worked out by hand and by a different integration method.

Hand derivation (fast-top approximation, L = L3 n3): dn3/dt = (l/L3) n3 x (-M g z + F(t)).
In the frame turning with F at w = M g l/L3 the weight's precession is removed and
F = F x' is fixed: dn3/dt = (l F/L3) n3 x x', a uniform turn about -x' at l F/L3
from z, so n3 = cos(l F t/L3) z + sin(l F t/L3) y'.  Horizontal at
t_down = pi L3/(2 l F), straight down at 2 t_down, horizontal again at 3 t_down;
the axis is along y', 90 degrees ahead of F.  Defaults: L3 = 6.25e-4 * 600 = 0.375,
l F = 0.1: t_down = 0.375 pi/0.2 = 5.890486225480862 s.

The exact motion (nutation included) is integrated independently below with
scipy's adaptive DOP853 on the vector equations dn/dt = L x n/I_A,
dL/dt = l n x (-M g z + F(t)), at rtol 1e-10.
"""

import math

import numpy as np
import pytest

from conftest import solve_both


def test_leading_order_by_hand():
    a, n, _ = solve_both("4.24")
    assert a["t_down"] == pytest.approx(0.375 * math.pi / 0.2, rel=1e-14)
    assert a["t_up"] == pytest.approx(3 * 0.375 * math.pi / 0.2, rel=1e-14)
    assert a["phi_lead"] == pytest.approx(math.pi / 2, rel=1e-15)
    assert a["cos_min"] == -1.0
    # the exact motion is close to it: eps_g = I_A M g l/L3^2 = 1.5625e-3*0.24525/0.140625 = 2.7e-3
    assert abs(n["t_down"] / a["t_down"] - 1) < 3 * 2.725e-3
    assert abs(n["t_up"] / a["t_up"] - 1) < 3 * 2.725e-3
    assert abs(n["phi_lead"] - math.pi / 2) < 0.02
    assert n["cos_min"] == pytest.approx(-1.0, abs=1e-6)


def _dop853(M=0.5, l=0.05, I1=3.125e-4, I3=6.25e-4, w3=600.0, F=2.0, g=9.81):
    from scipy.integrate import solve_ivp

    IA = I1 + M * l * l
    L3 = I3 * w3
    w = M * g * l / L3

    def rhs(t, y):
        nv, L = y[:3], y[3:]
        f = np.array([F * math.cos(w * t), F * math.sin(w * t), -M * g])
        return np.concatenate([np.cross(L, nv) / IA, l * np.cross(nv, f)])

    def down(t, y):
        return y[2]

    down.direction = -1

    def up(t, y):
        return y[2]

    up.direction = 1
    up.terminal = True
    sol = solve_ivp(rhs, (0, 30.0), [0, 0, 1, 0, 0, L3], method="DOP853", rtol=1e-10, atol=1e-13, events=[down, up])
    td, tu = sol.t_events[0][0], sol.t_events[1][0]
    yd = sol.y_events[0][0]
    lead = math.atan2(yd[1], yd[0]) - w * td
    lead = math.pi - (math.pi - lead) % (2 * math.pi)
    return td, tu, lead


def test_against_adaptive_runge_kutta_at_defaults():
    td, tu, lead = _dop853()
    _, n, run = solve_both("4.24", rtol=1e-7)
    assert n["t_down"] == pytest.approx(td, rel=1e-6)
    assert n["t_up"] == pytest.approx(tu, rel=1e-6)
    assert n["phi_lead"] == pytest.approx(lead, rel=1e-5)
    assert run.invariants["L3 = L . n3"] < 1e-12


def test_faster_spin_approaches_the_gyroscopic_answer():
    # omega_rot = 3000: eps_g = 1.5625e-3*0.24525/1.875^2 = 1.09e-4; deviations shrink with it
    a, n, _ = solve_both("4.24", omega_rot=3000.0)
    assert a["t_down"] == pytest.approx(1.875 * math.pi / 0.2, rel=1e-14)
    assert abs(n["t_down"] / a["t_down"] - 1) < 3 * 1.09e-4
    assert abs(n["phi_lead"] - math.pi / 2) < 3 * 1.09e-4 * 4.9
    a6, n6, _ = solve_both("4.24")
    assert abs(n["t_down"] / a["t_down"] - 1) < abs(n6["t_down"] / a6["t_down"] - 1) / 10


def test_weak_force_slips_ahead():
    # F = 0.2: t_down = 0.375 pi/0.02 = 58.9 s; the exact precession outruns the drive by
    # about eps_g M g/F = 2.7e-3 * 24.5 = 0.067 rad at most: the lead grows above pi/2
    a, n, _ = solve_both("4.24", F=0.2)
    assert a["t_down"] == pytest.approx(0.375 * math.pi / 0.02, rel=1e-14)
    assert 0.005 < n["phi_lead"] - math.pi / 2 < 0.067

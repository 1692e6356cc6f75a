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
dL/dt = l n x (-M g z + F(t)), at rtol 1e-10, at a stronger force (a shorter run);
the solver's coarse Strang steps of a very fast top are checked against its own
fine splitting, itself checked against DOP853 (and for its order, below).
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

    from ref_top424 import exact_rhs, horizontal_events

    rhs, w, _k, L3 = exact_rhs(M, l, I1, I3, w3, F, g)
    down, up = horizontal_events()
    t_end = 6 * math.pi * L3 / (2 * l * F)  # twice the leading-order t_up
    sol = solve_ivp(rhs, (0, t_end), [0, 0, 1, 0, 0, 1], method="DOP853", rtol=1e-10, atol=1e-13, events=[down, up])
    td, tu = sol.t_events[0][0], sol.t_events[1][0]
    yd = sol.y_events[0][0]
    lead = math.atan2(yd[1], yd[0]) - w * td
    lead = math.pi - (math.pi - lead) % (2 * math.pi)
    return td, tu, lead


def test_against_adaptive_runge_kutta():
    # F = 6 N: t_up = 5.9 s, about 230 nutation periods (k = 240 rad/s), eps_F = I_A l F/L3^2 = 3.3e-3, so the
    # exact motion differs from the leading order by ~1e-2 and the 1e-6 agreement checks the nutation's effect
    # (at this eps the fine splitting is the 8th-order one)
    td, tu, lead = _dop853(F=6.0)
    a, n, run = solve_both("4.24", rtol=1e-7, F=6.0)
    assert abs(td / a["t_down"] - 1) > 1e-3  # the comparison is not with the leading order
    assert n["t_down"] == pytest.approx(td, rel=1e-6)
    assert n["t_up"] == pytest.approx(tu, rel=1e-6)
    assert n["phi_lead"] == pytest.approx(lead, rel=1e-5)
    assert run.invariants["L3 = L . n3"] < 1e-12


def _fine_only(monkeypatch):
    """Force the solver onto its fine splitting at every step (validated above against DOP853)."""
    import mech.problems.ch4.ex4_24_driven_fast_top as mod
    import mech.solvers.mechanics.top_splitting as splitting

    monkeypatch.setattr(splitting, "tan_root", lambda j: math.inf)
    monkeypatch.setattr(mod, "MAX_STEPS", 10**7)


def test_coarse_strang_steps_against_fine_splitting(monkeypatch):
    # omega_rot = 4000, F = 6: eps = I_A l F/L3^2 = 7.5e-5; at rtol 1e-6 the solver takes Strang steps of ~1.6
    # nutation periods between the events.  Their error ~ (H Om)^2 = rtol; the fine run is an independent
    # 6th-order integration resolving every nutation period.  The leading order is off by ~1e-4: the
    # agreement to 1e-5 shows the coarse steps keep the nutation's effect (their forced-nutation factor is 1)
    a, c, run = solve_both("4.24", rtol=1e-6, omega_rot=4000.0, F=6.0)
    assert run.info["coarse_steps"] > 1000
    _fine_only(monkeypatch)
    _, f, run_f = solve_both("4.24", rtol=1e-7, omega_rot=4000.0, F=6.0)
    assert "coarse_steps" not in run_f.info
    for q in ("t_down", "t_up", "phi_lead"):
        assert c[q] == pytest.approx(f[q], rel=1e-5)
    assert abs(f["t_down"] / a["t_down"] - 1) > 3e-5
    assert c["cos_min"] == pytest.approx(f["cos_min"], abs=1e-8)


def test_very_fast_top_across_the_bounds():
    # the draw of tests/test_bounds.py that once exceeded the step budget: eps_F = I_A l F/L3^2 = 3.3e-6,
    # 2.4e5 nutation periods to t_up.  Leading order: t_down = pi L3/(2 l F) = 540.81 s
    given = dict(M=0.11133548615087796, l=0.0016932264139467971, I1=0.0039053861223051554,
                 I3=0.017314891933817397, omega_rot=195.93337946538765, F=5.819498232502652, g=0.32923686169570554)
    L3 = given["I3"] * given["omega_rot"]
    IA = given["I1"] + given["M"] * given["l"] ** 2
    eps_F = IA * given["l"] * given["F"] / L3**2
    a, n, run = solve_both("4.24", **given)
    assert a["t_down"] == pytest.approx(math.pi * L3 / (2 * given["l"] * given["F"]), rel=1e-14)
    assert run.info["steps"] < 20_000
    for q in ("t_down", "t_up"):
        assert abs(n[q] / a[q] - 1) < 3 * eps_F
    assert abs(n["phi_lead"] - math.pi / 2) < 3 * eps_F * math.pi / 2
    assert n["cos_min"] == pytest.approx(-1.0, abs=1e-8)


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


def test_fine_splittings_have_their_orders():
    """The two compositions of Strang steps the fine splitting uses, checked for their order on one step
    from a tilted, nutating state (eps ~ 0.04, where the kicks matter): against 16 substeps of the same
    scheme, a step's error is O(H^(p+1)), so halving H divides it by 2^7 = 128 for Yoshida's 6th-order
    composition and by 2^9 = 512 for Kahan and Li's 8th-order one.  A wrong weight drops the order."""
    from mech.solvers.mechanics.top_splitting import fine_stepper
    from mech.solvers.numerics.splitting import KAHAN_LI8, YOSHIDA6

    k, a, b, w = 60.0, 2.6, 2.7, 2.6
    n0 = (math.sin(0.7) * math.cos(0.3), math.sin(0.7) * math.sin(0.3), math.cos(0.7))
    L0 = (n0[0] + 0.02, n0[1] - 0.01, n0[2] - (0.02 * n0[0] - 0.01 * n0[1]) / n0[2])  # L . n = 1
    for weights, ratio in ((YOSHIDA6, 128.0), (KAHAN_LI8, 512.0)):
        assert sum(weights) == pytest.approx(1.0, abs=1e-15)
        errs = []
        for H in (1.6 / k, 0.8 / k, 0.4 / k):
            one = fine_stepper(k, a, b, w, H, weights)(n0, L0, 0.3, H)
            sub = fine_stepper(k, a, b, w, H / 16, weights)
            s = (n0, L0, 0.3)
            for _ in range(16):
                s = sub(*s, H / 16)
            errs.append(max(abs(x - y) for x, y in zip(one[0] + one[1], s[0] + s[1])))
        for e0, e1 in zip(errs, errs[1:]):
            assert e0 / e1 == pytest.approx(ratio, rel=0.3)

"""4.24's stroboscopic-averaging route (solvers/mechanics/top_strobe.py) against the fine splitting.

The fine splitting resolving every nutation period is checked against scipy's DOP853 in test_ex4_24.py
(test_against_adaptive_runge_kutta); here it is the reference, at rtol/100, for tops on which the solver
chooses stroboscopic averaging.  The route claims what the resolved one does (10 rtol); measured, it stays
within 0.32 rtol, and the tests ask for 1 rtol.  The slow field at the sleeping top is checked against the
fast-top velocity worked out by hand.
"""

import math

import numpy as np
import pytest

from conftest import solve_both

QS = ("t_down", "t_up", "phi_lead", "cos_min")


def _fine_only(monkeypatch):
    """The solver on its fine splitting at every step: no coarse Strang steps, no stroboscopic averaging."""
    import mech.problems.ch4.ex4_24_driven_fast_top as mod
    import mech.solvers.mechanics.top_splitting as splitting

    monkeypatch.setattr(splitting, "tan_root", lambda j: math.inf)
    monkeypatch.setattr(mod, "strobe_cost", lambda *args: math.inf)
    monkeypatch.setattr(mod, "MAX_STEPS", 10**7)


def _against_fine(monkeypatch, rtol, **given):
    """The route at rtol against the fine splitting at rtol/100 (its error there: 0.02-2 of that rtol)."""
    a, s, run = solve_both("4.24", rtol=rtol, **given)
    assert "macro_steps" in run.info and "stroboscopic averaging" in run.method
    assert run.info["macro_steps"] < 60
    _fine_only(monkeypatch)
    _, f, run_f = solve_both("4.24", rtol=rtol / 100, **given)
    assert "macro_steps" not in run_f.info and "coarse_steps" not in run_f.info
    for q in ("t_down", "t_up"):
        assert s[q] == pytest.approx(f[q], rel=rtol)
    assert s["phi_lead"] == pytest.approx(f["phi_lead"], abs=rtol)
    assert s["cos_min"] == pytest.approx(f["cos_min"], abs=rtol)
    return a, s, f, run


def test_fast_spin_against_the_fine_splitting(monkeypatch):
    # omega_rot = 3000 (a hard case): k/b = L3^2/(I_A l F) = 1.875^2/(1.5625e-3 * 0.1) = 22500 nutation rates
    # per overturn rate, about 17000 nutation periods to t_up; the weight 2.45 times the force (a/b = M g/F).
    # The leading order is off by ~eps_g = 1.1e-4: the agreement to 1e-7 is with the nutation's effect in it
    a, _, f, run = _against_fine(monkeypatch, 1e-7, omega_rot=3000.0)
    assert abs(f["t_down"] / a["t_down"] - 1) > 1e-5
    assert run.invariants["Jacobi integral (frame turning with F)"] < 1e-6


def test_weight_dominated_top_against_the_fine_splitting(monkeypatch):
    # F = 0.08 N: the weight is M g/F = 61 times the force (the fields take 2.5 m fine steps a period above 50),
    # omega_rot = 640: k/b = 0.0625 * 640^2 = 25600; the precession slips eps_g M g/F = 0.147 rad by t_down
    _, _, f, _ = _against_fine(monkeypatch, 1e-6, F=0.08, omega_rot=640.0)
    assert f["phi_lead"] - math.pi / 2 > 0.02  # the slip's lead, far beyond the tolerance


def test_the_slow_field_at_the_sleeping_top():
    # at n = L = z (scaled) the guiding center moves at n x g = z x (-a z + b x') = b y' (the fast-top velocity,
    # by hand), and L with it (dL/dt = n x g); the sampled nutation adds nothing to the average, to O(b/k)
    from mech.solvers.mechanics.top_splitting import fine_steps
    from mech.solvers.mechanics.top_strobe import Strobe

    a, b, k = 2.0, 1.0, 2.0e4
    weights, _, m = fine_steps(a / k, 1e-8)
    strobe = Strobe(k, a, b, a, weights, math.ceil(2 * m))
    Y = np.array([0.0, 0.0, 1.0, 0.0, 0.0, 1.0])
    strobe.use(strobe.period(Y))
    F = strobe.field(0.0, Y)
    assert F == pytest.approx([0.0, b, 0.0, 0.0, b, 0.0], abs=5 * b * (a + b) / k)
    # the period is 2 pi over the sleeping top's fast nutation rate in the turning frame, k - a - w = k - 2a
    assert strobe.T == pytest.approx(2 * math.pi / (k - 2 * a), rel=1e-15)


def test_dop853_steps_whole_quanta():
    from mech.solvers.numerics import dop853

    pair = dop853.stepper(lambda t, y: -y, 1, rtol=1e-10, atol=1e-12)
    q = 0.0123
    t, y = 0.0, np.array([1.0])
    f = -y
    for _ in range(5):
        got = pair.attempt(t, y, f, 0.3, 1.0, math.inf, quantum=q)
        t_new, h, y, f, _ = got
        assert h / q == pytest.approx(round(h / q), abs=1e-9) and round(h / q) >= 1
        assert y[0] == pytest.approx(math.exp(-t_new), rel=1e-9)
        t = t_new
    # a try of four quanta too long for the tolerance falls back to one quantum, which passes
    tight = dop853.stepper(lambda t, y: -y, 1, rtol=1e-12, atol=1e-12)
    got = tight.attempt(0.0, np.array([1.0]), np.array([-1.0]), 0.8, 1.0, math.inf, quantum=0.2)
    assert got is not None and got[1] == pytest.approx(0.2, rel=1e-15)
    assert got[2][0] == pytest.approx(math.exp(-0.2), rel=1e-12)
    # one quantum too long for the tolerance: no step, rather than a step off the grid
    assert dop853.stepper(lambda t, y: -y, 1, rtol=1e-14, atol=1e-16).attempt(0.0, np.array([1.0]), np.array([-1.0]),
                                                                            5.0, 1.0, math.inf, quantum=5.0) is None

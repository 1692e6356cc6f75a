"""4.6 against values worked out by hand.

No slip at the two meshes of a satellite with identical side gears (radius r):
omega1 r = omega_c r + s rho and omega2 r = omega_c r - s rho, so omega_c is the mean
of omega1 and omega2.  Satellite free on its pin: its two tangential mesh forces are
equal; carrier (massless) torque balance: tau = 2 f r, so each shaft gets f r = tau/2.
Power delivered to shaft i: (tau/2) omega_i.
  defaults tau = 100, omega = 50, 40:  omega_c = 45, tau_i = 50, P = 2500, 2000
  tau = -40, omega = 10, -4:            omega_c = 3, tau_i = -20, P = -200, 80
  tau = 100, omega = 30, -30:           omega_c = 0, tau_i = 50, P = 1500, -1500
  tau = 250, omega = 0, 0 (stall):      omega_c = 0, tau_i = 125, P = 0, 0
"""

import pytest

from conftest import solve_both


@pytest.mark.parametrize(
    "tau, w1, w2, wc, t1, P1, P2",
    [
        (100.0, 50.0, 40.0, 45.0, 50.0, 2500.0, 2000.0),
        (-40.0, 10.0, -4.0, 3.0, -20.0, -200.0, 80.0),
        (100.0, 30.0, -30.0, 0.0, 50.0, 1500.0, -1500.0),
        (250.0, 0.0, 0.0, 0.0, 125.0, 0.0, 0.0),
    ],
)
def test_against_hand_values(tau, w1, w2, wc, t1, P1, P2):
    an, nu, run = solve_both("4.6", tau=tau, omega1=w1, omega2=w2)
    for v in (an, nu):
        assert v["omega_c"] == pytest.approx(wc, rel=1e-12, abs=1e-12)
        assert v["tau1"] == pytest.approx(t1, rel=1e-12)
        assert v["tau2"] == pytest.approx(t1, rel=1e-12)
        assert v["P1"] == pytest.approx(P1, rel=1e-12, abs=1e-10)
        assert v["P2"] == pytest.approx(P2, rel=1e-12, abs=1e-10)
    assert run.invariants["power balance P1 + P2 - tau omega_c"] < 1e-12


def test_no_torque_no_load():
    _, n, _ = solve_both("4.6", tau=0.0, omega1=7.0, omega2=3.0)
    assert n["tau1"] == pytest.approx(0.0, abs=1e-13)
    assert n["P2"] == pytest.approx(0.0, abs=1e-12)

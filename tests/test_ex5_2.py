"""5.2 against values worked out by hand.

Hand derivation: q_st = F0/(m w0^2).  From rest under a constant force,
q = q_st (1 - cos w0 t) (a harmonic swing about the shifted equilibrium q_st).
After switch-off the motion is the step response minus the same response
delayed by T: q = q_st [cos w0(t - T) - cos w0 t], amplitude
2 |q_st| |sin(w0 T/2)|.  The largest |q| during the pulse is 2 |q_st| once
w0 T >= pi.  Independent check: in the impulse limit the oscillator gets the
momentum F0 T at q ~ 0, so A_after -> F0 T/(m w0).
"""

import math

import pytest

from conftest import solve_both


def test_defaults():
    # q_st = 0.3/(0.2*25) = 0.06; w0 T = 2, sin 1 = 0.8414709848078965
    # t1 = 2 s: q = 0.12 sin(1) sin(5*(2 - 0.2)) = 0.12 * 0.8414709848078965 * sin(9)
    a, n, run = solve_both("5.2")
    amp = 0.12 * 0.8414709848078965
    for v in (a, n):
        assert v["A_after"] == pytest.approx(amp, rel=1e-8)
        assert v["q_max"] == pytest.approx(amp, rel=1e-8)           # w0 T = 2 < pi
        assert v["q_t"] == pytest.approx(amp * 0.4121184852417566, rel=1e-8)
    assert run.invariants["energy (pulse)"] < 1e-8


def test_long_pulse_reading_during_it_and_negative_force():
    # F0 = -0.3: q_st = -0.06; T = 1 s, w0 T = 5 > pi so q_max = 0.12
    # t1 = 0.5 s inside the pulse: q = -0.06 (1 - cos 2.5) = -0.06 * 1.8011436155469337
    a, n, _ = solve_both("5.2", F0=-0.3, T=1.0, t1=0.5)
    for v in (a, n):
        assert v["q_max"] == pytest.approx(0.12, rel=1e-8)
        assert v["A_after"] == pytest.approx(0.12 * 0.5984721441039564, rel=1e-8)   # |sin 2.5|
        assert v["q_t"] == pytest.approx(-0.06 * 1.8011436155469337, rel=1e-8)


def test_heavier_slower_oscillator_after_pulse():
    # m = 2, w0 = 0.5, F0 = 1: q_st = 1/(2*0.25) = 2; T = 3 s: w0 T = 1.5, sin 0.75 = 0.6816387600233341
    # t1 = 10 s: q = 4 sin(0.75) sin(0.5*(10 - 1.5)) = 4 * 0.6816387600233341 * sin(4.25)
    a, n, _ = solve_both("5.2", m=2.0, omega0=0.5, F0=1.0, T=3.0, t1=10.0)
    for v in (a, n):
        assert v["A_after"] == pytest.approx(4 * 0.6816387600233341, rel=1e-8)
        assert v["q_t"] == pytest.approx(4 * 0.6816387600233341 * -0.8949893582285835, rel=1e-8)


def test_impulse_limit_by_momentum():
    # momentum F0 T, speed F0 T/m at q ~ 0: amplitude (F0 T/m)/w0, error O((w0 T)^2)
    a, n, _ = solve_both("5.2", T=1e-6, t1=3.0)
    for v in (a, n):
        assert v["A_after"] == pytest.approx(0.3e-6 / (0.2 * 5.0), rel=1e-10)
        # after the kick, q = A sin(w0 (t - T/2))
        assert v["q_t"] == pytest.approx(3e-7 * math.sin(15.0), rel=1e-8)


def test_whole_period_pulse_leaves_oscillator_at_rest():
    a, n, _ = solve_both("5.2", T=2 * math.pi / 5.0, t1=3.0)
    for v in (a, n):
        assert abs(v["A_after"]) < 1e-10
        assert abs(v["q_t"]) < 1e-10
        assert v["q_max"] == pytest.approx(0.12, rel=1e-8)

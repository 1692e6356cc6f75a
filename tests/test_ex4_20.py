"""4.20 against values worked out by hand and by a separate integration.

Hand derivation of the rates: about omega0 n1, Euler's equations linearized in
the small omega2, omega3 give omega2'' = (I3 - I1)(I1 - I2)/(I2 I3) omega0^2 omega2,
so Omega_1^2 = (I2 - I1)(I3 - I1) omega0^2/(I2 I3); cyclically about n2 the sign
flips (lambda_2^2 = (I2 - I1)(I3 - I2) omega0^2/(I1 I3)) and about n3
Omega_3^2 = (I3 - I1)(I3 - I2) omega0^2/(I1 I2).  For I = (1, 2, 3), omega0 = 1:
Omega_1 = sqrt(1*2/6) = sqrt(1/3), lambda_2 = sqrt(1*1/3) = sqrt(1/3),
Omega_3 = sqrt(2*1/2) = 1.

The period: for delta -> pi/2 it is the small-oscillation period 2 pi/Omega_1
(amplitude cos(delta) corrections are of relative order cos^2(delta)); near the
separatrix the motion spends its time at the saddle, where omega3 grows as
e^(lambda_2 t) from a start of order k', and T -> (4/lambda_2) ln(4/k'), with
k'^2 = I1 (I3 - I1) sin^2(delta) / [I2 (I3 - I2)] to leading order.  At a
moderate delta the period is checked against a separate integration here,
which times the first sign change of omega2 (at T/4), an event the code under
test does not use.
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from conftest import solve_both
from mech.problems import registry
from mech.problems.spec import BadInput


def test_rates_hand_values():
    # (1, 2, 3) is also the flat-plate edge I3 = I1 + I2 of the allowed range
    an, nu, _ = solve_both("4.20", I1=1.0, I2=2.0, I3=3.0, omega0=1.0, delta=0.3)
    for v in (an, nu):
        assert v["Omega_1"] == pytest.approx(math.sqrt(1 / 3), rel=1e-12)
        assert v["lambda_2"] == pytest.approx(math.sqrt(1 / 3), rel=1e-12)
        assert v["Omega_3"] == pytest.approx(1.0, rel=1e-12)


def test_near_symmetric_rates():
    # I3 - I2 = 5e-9: lambda_2 = 10 sqrt(2.5e-3 * 5e-9 / (2.8e-3 * 5.300005e-3)), by a calculator
    lam = 10.0 * math.sqrt(2.5e-3 * 5e-9 / (2.8e-3 * 5.300005e-3))
    om3 = 10.0 * math.sqrt(2.500005e-3 * 5e-9 / (2.8e-3 * 5.3e-3))
    an, nu, _ = solve_both("4.20", I3=5.300005e-3)
    for v in (an, nu):
        assert v["lambda_2"] == pytest.approx(lam, rel=1e-9)
        assert v["Omega_3"] == pytest.approx(om3, rel=1e-9)


def _quarter_period_by_omega2(I, delta):
    I1, I2, I3 = I

    def rhs(t, w):
        return [(I2 - I3) * w[1] * w[2] / I1, (I3 - I1) * w[2] * w[0] / I2, (I1 - I2) * w[0] * w[1] / I3]

    def w2(t, w):
        return w[1]

    w2.terminal = True
    sol = solve_ivp(rhs, (0, 1e4), [math.sin(delta), math.cos(delta), 0.0], method="DOP853",
                    rtol=1e-13, atol=1e-16, events=w2, max_step=0.05)
    return sol.t_events[0][0]


@pytest.mark.parametrize("I, delta, omega0", [((1.0, 2.0, 3.0), 0.3, 1.0), ((2.8e-3, 5.3e-3, 7.9e-3), 0.01, 10.0)])
def test_period_against_a_separate_integration(I, delta, omega0):
    T = 4.0 * _quarter_period_by_omega2(I, delta) / omega0
    an, nu, _ = solve_both("4.20", I1=I[0], I2=I[1], I3=I[2], omega0=omega0, delta=delta)
    for v in (an, nu):
        assert v["T_period"] == pytest.approx(T, rel=1e-9)


def test_period_small_oscillation_limit():
    c = 1e-5  # cos(delta)
    an, nu, _ = solve_both("4.20", I1=1.0, I2=2.0, I3=3.0, omega0=2.0, delta=math.acos(c))
    for v in (an, nu):
        assert v["T_period"] == pytest.approx(2 * math.pi / (2.0 * math.sqrt(1 / 3)), rel=1e-8)


def test_period_at_the_separatrix():
    I1, I2, I3, w0, d = 2.8e-3, 5.3e-3, 7.9e-3, 10.0, 1e-12
    lam = w0 * math.sqrt((I2 - I1) * (I3 - I2) / (I1 * I3))
    kp = math.sqrt(I1 * (I3 - I1) / (I2 * (I3 - I2))) * math.sin(d)
    T = 4.0 / lam * math.log(4.0 / kp)
    an, nu, run = solve_both("4.20", delta=d)
    for v in (an, nu):
        assert v["T_period"] == pytest.approx(T, rel=1e-10)
    assert "quadrature" in run.info["T_route"]


@pytest.mark.parametrize("d", [1e-300, 5e-324])
def test_period_for_tilts_that_underflow_when_squared(d):
    I1, I2, I3, w0 = 2.8e-3, 5.3e-3, 7.9e-3, 10.0
    lam = w0 * math.sqrt((I2 - I1) * (I3 - I2) / (I1 * I3))
    log_kp = 0.5 * math.log(I1 * (I3 - I1) / (I2 * (I3 - I2))) + math.log(d)
    T = 4.0 / lam * (math.log(4.0) - log_kp)
    an, nu, _ = solve_both("4.20", delta=d)
    for v in (an, nu):
        assert v["T_period"] == pytest.approx(T, rel=1e-12)


def test_default_uses_integration_and_monitors_invariants():
    _, _, run = solve_both("4.20")
    assert "integration" in run.info["T_route"]
    assert run.invariants["energy"] < 1e-9
    assert run.invariants["separatrix distance 2EI2 - L^2"] < 1e-9


@pytest.mark.parametrize(
    "given",
    [dict(I1=3.0, I2=2.0, I3=4.0), dict(I1=1.0, I2=2.0, I3=2.0), dict(I1=1.0, I2=2.0, I3=3.5)],
)
def test_unphysical_moments_are_refused(given):
    with pytest.raises(BadInput):
        registry.get("4.20").resolve(given)


"""solvers/mechanics/harmonic_balance.py against the linear oscillator's closed form and its own finite differences.

Linear (gamma = 0): q'' + 2 delta q' + omega0^2 q = f0 cos(omega t) has the response q = R Q cos(omega t - phi)
with tan phi = 2 delta omega/(omega0^2 - omega^2) and R Q = f0/sqrt((omega0^2 - omega^2)^2 + 4 delta^2 omega^2)
(by hand: put q = Re(Z e^{i omega t}) in the equation).  In the module's units (Q = f0/(2 omega0 delta),
omega = omega0 + delta w, d = delta/omega0) that is R = 2 omega0 delta/sqrt(...) and, solving tan phi for w,
the detuning at a phase: (omega0^2 - omega^2) = 2 delta omega cot phi, a quadratic in omega.
"""

import math

import numpy as np
import pytest

from mech.solvers.mechanics.harmonic_balance import DuffingBalance


def linear_at_phase(phi, omega0, delta):
    """The detuning omega - omega0 with omega0^2 - omega^2 = 2 delta omega cot(phi) (the positive root, written
    without cancellation) and the amplitude over Q."""
    c = 2.0 * delta / math.tan(phi)
    xi = 0.5 * (-c + c * c / (math.sqrt(c * c + 4.0 * omega0**2) + 2.0 * omega0))
    amp = 2.0 * omega0 * delta / ((omega0 + xi) * math.sqrt(c * c + 4 * delta**2))  # omega0^2 - omega^2 = c omega
    return xi, amp


@pytest.mark.parametrize("omega0, delta", [(10.0, 0.02), (3.0, 0.1), (1e4, 1e-3)])
def test_linear_response_is_the_closed_form(omega0, delta):
    phis = np.array([0.05, 0.4, 1.2, math.pi / 2, 2.0, 3.0])
    hb = DuffingBalance(np.full(phis.size, delta / omega0), np.zeros(phis.size))
    v = hb.evaluate(phis, np.arange(phis.size))
    assert v.ok.all()
    for k, phi in enumerate(phis):
        xi, amp = linear_at_phase(phi, omega0, delta)
        assert delta * v.w[k] == pytest.approx(xi, rel=1e-13)
        assert v.A[k] == pytest.approx(amp, rel=1e-12)
        # the tangent: central differences of the closed form
        h = 1e-5
        (om_p, a_p), (om_m, a_m) = linear_at_phase(phi + h, omega0, delta), linear_at_phase(phi - h, omega0, delta)
        assert v.dw[k] == pytest.approx((om_p - om_m) / (2 * h * delta), rel=1e-6)
        assert v.dA[k] == pytest.approx((a_p - a_m) / (2 * h), rel=1e-6, abs=1e-9)
    assert np.all(np.abs(hb.c[:, 2:]) < 1e-14)  # no harmonics without the cubic


def test_tangent_matches_finite_differences_with_the_cubic():
    """dw/dphi and dA/dphi from -J^-1 dF/dphi against central differences of solved points (gamma = 8: the
    defaults of 5.8, bistable), and the solution does not depend on where Newton started."""
    d, gamma = 0.002, 8.0
    phis = np.array([0.7, 1.6, 2.0, 2.6])
    n = phis.size
    hb = DuffingBalance(np.full(n, d), np.full(n, gamma))
    v = hb.evaluate(phis, np.arange(n))
    h = 1e-5
    up = DuffingBalance(np.full(n, d), np.full(n, gamma)).evaluate(phis + h, np.arange(n))
    dn = DuffingBalance(np.full(n, d), np.full(n, gamma)).evaluate(phis - h, np.arange(n))
    assert v.dw == pytest.approx((up.w - dn.w) / (2 * h), rel=1e-7, abs=1e-7)
    assert v.dA == pytest.approx((up.A - dn.A) / (2 * h), rel=1e-7, abs=1e-9)
    # solved again from the neighbours' solutions (the predictor along the tangent): the same point
    again = hb.evaluate(phis + 1e-3, np.arange(n))
    fresh = DuffingBalance(np.full(n, d), np.full(n, gamma)).evaluate(phis + 1e-3, np.arange(n))
    assert again.w == pytest.approx(fresh.w, rel=1e-13, abs=1e-13)
    assert again.A == pytest.approx(fresh.A, rel=1e-13)
    assert np.all(v.tail < 1e-15)

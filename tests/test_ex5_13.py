"""5.13 against hand values and a stroboscopic simulation of the full nonlinear equation.

Hand derivation: the fast torque per unit m l^2 is f = (a Omega^2/l) cos(Omega t) sin theta;
the jitter -f/Omega^2 feeds back on average <f d f/d theta>/Omega^2, so
U_eff = -omega0^2 cos theta + (a Omega/2l)^2 sin^2 theta and
omega_down^2 = omega0^2 + (a Omega/l)^2/2, omega_inv^2 = (a Omega/l)^2/2 - omega0^2,
a_min = sqrt(2 g l)/Omega.  Defaults (l = 0.2, g = 9.81, a = 0.01, Omega = 200 pi):
omega0^2 = 49.05, (a Omega/l)^2/2 = (10 pi)^2/2 = 493.4802; omega_down = sqrt(542.5302)
= 23.29228, omega_inv = sqrt(444.4302) = 21.08151, a_min = sqrt(3.924)/(200 pi) = 3.152714e-3.

The different method: simulate the full equation theta'' = -(g + z'')/l sin theta from
a 1e-5 rad offset, sample theta at t = k 2 pi/Omega and fit the recurrence
x_{k+1} + x_{k-1} = 2 cos(nu 2 pi/Omega) x_k by least squares.
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from conftest import solve_both
from mech.problems.spec import Undefined


def test_defaults_by_hand():
    a, n, run = solve_both("5.13")
    assert a["a_min"] == pytest.approx(math.sqrt(3.924) / (200 * math.pi), rel=1e-12)
    assert a["omega_down"] == pytest.approx(math.sqrt(49.05 + 50 * math.pi**2), rel=1e-12)
    assert a["omega_inv"] == pytest.approx(math.sqrt(50 * math.pi**2 - 49.05), rel=1e-12)
    # exact differs by O((2 omega0/Omega)^2 + (2a/l)^2) ~ 1e-2 at most
    for k in a:
        assert n[k] == pytest.approx(a[k], rel=1e-2)
    assert run.invariants["Wronskian"] < 1e-10


def _stroboscopic_nu(l, g, a, Omega, around, periods):
    """Slow frequency from the full nonlinear equation, sampled once per fast period."""
    T = 2 * math.pi / Omega

    def rhs(t, y):
        return [y[1], -(g - a * Omega**2 * math.cos(Omega * t)) / l * math.sin(y[0])]

    ts = T * np.arange(periods + 1)
    sol = solve_ivp(rhs, (0, ts[-1]), [around + 1e-5, 0.0], method="DOP853", rtol=1e-12, atol=1e-16, t_eval=ts)
    x = sol.y[0] - around
    c = np.dot(x[2:] + x[:-2], x[1:-1]) / np.dot(x[1:-1], x[1:-1])  # = 2 cos(nu T)
    return math.acos(c / 2) / T


@pytest.mark.parametrize(
    "l, g, a, Omega, periods",
    [(0.2, 9.81, 0.01, 200 * math.pi, 120), (0.2, 9.81, 0.065, 45.0, 40), (0.5, 1.62, 0.05, 30.0, 40)],
)
def test_slow_frequencies_against_stroboscopic_simulation(l, g, a, Omega, periods):
    an, n, _ = solve_both("5.13", l=l, g=g, a=a, Omega=Omega)
    nu_down = _stroboscopic_nu(l, g, a, Omega, 0.0, periods)
    nu_inv = _stroboscopic_nu(l, g, a, Omega, math.pi, periods)
    assert n["omega_down"] == pytest.approx(nu_down, rel=1e-5)
    assert n["omega_inv"] == pytest.approx(nu_inv, rel=1e-5)


def test_a_min_separates_stable_from_unstable_in_simulation():
    _, n, _ = solve_both("5.13", Omega=45.0, a=0.05)
    a_min = n["a_min"]
    T = 2 * math.pi / 45.0

    def final_offset(a, periods=150):
        def rhs(t, y):
            return [y[1], -(9.81 - a * 45.0**2 * math.cos(45.0 * t)) / 0.2 * math.sin(y[0])]

        sol = solve_ivp(rhs, (0, periods * T), [math.pi + 1e-6, 0.0], method="DOP853", rtol=1e-11, atol=1e-15,
                        t_eval=T * np.arange(periods + 1))
        return np.max(np.abs(sol.y[0] - math.pi))

    assert final_offset(1.03 * a_min) < 1e-5  # bounded slow oscillation
    assert final_offset(0.97 * a_min) > 1e-4  # runs away


def test_below_a_min_inverted_is_undefined_in_both():
    a, n, _ = solve_both("5.13", a=0.002)
    assert isinstance(a["omega_inv"], Undefined) and isinstance(n["omega_inv"], Undefined)
    # no vibration: the lower frequency is omega0 exactly
    a, n, _ = solve_both("5.13", a=0.0)
    assert n["omega_down"] == pytest.approx(math.sqrt(9.81 / 0.2), rel=1e-10)


def test_leading_order_error_falls_as_the_square_of_omega0_over_Omega():
    # at fixed a Omega/l (fixed leading-order answers), the error ~ (2 omega0/Omega)^2 + (2a/l)^2
    errs = []
    for Omega in (200.0, 400.0, 800.0):
        a = 0.2 * 12.0 / Omega
        an, n, _ = solve_both("5.13", a=a, Omega=Omega)
        errs.append(abs(n["omega_down"] / an["omega_down"] - 1))
    slope = math.log(errs[0] / errs[2]) / math.log(4.0)
    assert 1.8 < slope < 2.2


@pytest.mark.parametrize(
    "l, g, Omega",
    [(118038.0, 129.932, 119466.0), (12359.0, 526.458, 12187.7), (52.6563, 329169.0, 2.17765e7)],
)
def test_a_min_at_extreme_scales_keeps_its_accuracy(l, g, Omega):
    """Draws that failed their rerun (the fast jitter of y', of size a/l, swamped the slow drift of
    order (a/l)^2).  Here omega0/Omega <= 4e-3 and a_min/l <= 3e-5, so the leading-order
    a_min = sqrt(2 g l)/Omega is off by relative O(4 omega0^2/Omega^2 + (2 a_min/l)^2) <= 7e-5, the
    first case 1e-12; and the numeric value must not move at rtol/10 by more than its claim."""
    lead = math.sqrt(2.0 * g * l) / Omega
    eta = 4.0 * g / (l * Omega**2) + (2.0 * lead / l) ** 2
    _, n, _ = solve_both("5.13", l=l, g=g, a=0.01 * l, Omega=Omega)
    _, n10, _ = solve_both("5.13", rtol=1e-13, l=l, g=g, a=0.01 * l, Omega=Omega)
    assert n["a_min"] == pytest.approx(lead, rel=max(eta, 1e-11))
    assert n10["a_min"] == pytest.approx(n["a_min"], rel=1e-10)


def test_omega_1e200_times_its_default_answers():
    """Omega = 200 pi * 1e200: kappa = omega0^2/Omega^2 ~ 1e-403 underflows, yet a_min ~ 1e-202 m is due.
    By hand, a_min = sqrt(2 g l)/Omega = sqrt(3.924)/(200 pi 1e200) = 3.152714e-203 m, off the exact
    value by relative O(12 omega0^2/Omega^2) ~ 1e-403: the numeric root must equal it to its rtol.
    The slow frequencies: with kappa beneath round-off both linearized equations are y'' = -+ eps cos(tau) y
    (eps = a/l = 0.05, tau = Omega t), whose monodromy over 2 pi (scipy's solve_ivp, a different
    integrator and the raw second-order form) gives cos(2 pi nu/Omega) = tr M/2, the same for both signs
    (a shift of tau by pi).  With a = 0 instead, omega_down is omega0 = sqrt(49.05) exactly."""
    Omega = 200 * math.pi * 1e200
    a, n, _ = solve_both("5.13", Omega=Omega)
    assert n["a_min"] == pytest.approx(math.sqrt(3.924) / Omega, rel=1e-10)

    def mono(eps):
        rhs = lambda t, y: [y[1], eps * math.cos(t) * y[0], y[3], eps * math.cos(t) * y[2]]  # noqa: E731
        y = solve_ivp(rhs, (0.0, 2 * math.pi), [1.0, 0.0, 0.0, 1.0], method="Radau", rtol=1e-12,
                      atol=1e-14).y[:, -1]
        return y[0] + y[3]

    nu = Omega * math.acos(mono(0.05) / 2.0) / (2 * math.pi)
    assert n["omega_down"] == pytest.approx(nu, rel=1e-8)
    assert n["omega_inv"] == pytest.approx(nu, rel=1e-8)
    _, n0, _ = solve_both("5.13", Omega=Omega, a=0.0)
    assert n0["omega_down"] == pytest.approx(math.sqrt(49.05), rel=1e-10)


def test_a_drive_1e200_times_faster_than_the_pendulum():
    """Omega = 1e200 rad/s, a = 1e-199 m (l = 0.2 m): a Omega/l = 50 rad/s, so by hand omega_inv^2 =
    50^2/2 - 49.05 = 1200.95, omega_down^2 = 1299.05 and a_min = sqrt(2 g l)/Omega = 1.9809e-200 m.  The
    analytic side forms neither (h - sk)(h + sk) nor e^4 (both below the doubles' range, ~1e-397): it gave
    omega_inv = 0, and e^4/beta0^2 a division by zero."""
    import mech

    p = dict(l=0.2, g=9.81, a=1e-199, Omega=1e200)
    an, n, _ = solve_both("5.13", **p)
    for v in (an, n):
        assert v["omega_inv"] == pytest.approx(math.sqrt(1200.95), rel=1e-9)
        assert v["omega_down"] == pytest.approx(math.sqrt(1299.05), rel=1e-9)
        assert v["a_min"] == pytest.approx(math.sqrt(2 * 9.81 * 0.2) / 1e200, rel=1e-9)
    sol = mech.solve("5.13", **p)
    assert sol.agree, sol.errors

"""5.12 against hand values and direct simulation of the full pendulum.

Hand derivation (reduced equations): the pivot turns omega0^2 into
omega0^2 (1 - mu cos Omega t), mu = a Omega^2/g; the coupling of the slow
amplitude to its conjugate is mu omega0^2/(2 Omega) = a Omega/(2l) = eps; with
xi = Omega/2 - omega0: growth = -delta + sqrt(eps^2 - xi^2), a_th = (2l/Omega)
sqrt(delta^2 + xi^2); a swing's frequency is omega0 (1 - A^2/16), so it settles
where xi + omega0 A^2/16 = sqrt(eps^2 - delta^2).
Defaults (l = 0.5, g = 9.81, delta = 0.05, a = 0.008, Omega = 8.9):
omega0 = sqrt(19.62) = 4.429447, xi = 0.020553, eps = 0.0712,
growth = -0.05 + sqrt(0.0712^2 - xi^2) = 0.018169, a_th = sqrt(0.05^2 + xi^2)/8.9
= 0.0060741, theta_st^2 = 16 (sqrt(0.0712^2 - 0.0025) - xi)/omega0 -> 0.32994.

Different methods: simulate theta'' + 2 delta theta' + (g - a Omega^2 cos Omega t)/l sin theta = 0
from a small swing until it settles and read its amplitude; the growth rate from
the growth of a tiny swing (linear regime) over many pivot periods.
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from conftest import solve_both


def test_defaults_by_hand():
    a, n, _ = solve_both("5.12")
    w0 = math.sqrt(19.62)
    xi, eps = 4.45 - w0, 0.0712
    assert a["growth"] == pytest.approx(-0.05 + math.sqrt(eps**2 - xi**2), rel=1e-12)
    assert a["a_th"] == pytest.approx(math.hypot(0.05, xi) / 8.9, rel=1e-12)
    assert a["theta_st"] == pytest.approx(math.sqrt(16 * (math.sqrt(eps**2 - 0.0025) - xi) / w0), rel=1e-12)
    assert a["growth"] == pytest.approx(0.018169, rel=1e-4)
    for k in a:
        assert n[k] == pytest.approx(a[k], rel=3e-2)


def _rhs(l, g, delta, a, Omega):
    def f(t, y):
        return [y[1], -2 * delta * y[1] - (g - a * Omega**2 * math.cos(Omega * t)) / l * math.sin(y[0])]
    return f


@pytest.mark.parametrize("given", [{}, {"Omega": 8.7, "a": 0.0125}])
def test_stationary_swing_against_long_simulation(given):
    _, n, _ = solve_both("5.12", **given)
    p = {"l": 0.5, "g": 9.81, "delta": 0.05, "a": 0.008, "Omega": 8.9, **given}
    T = 2 * math.pi / p["Omega"]
    t_end = 2 * T * round(900 / (2 * T))
    sol = solve_ivp(_rhs(**p), (0, t_end), [1e-3, 0.0], method="DOP853", rtol=1e-10, atol=1e-13, dense_output=True)
    t = np.linspace(t_end - 4 * T, t_end, 4001)
    amp = np.max(np.abs(sol.sol(t)[0]))
    assert n["theta_st"] == pytest.approx(amp, rel=2e-4)


@pytest.mark.parametrize("given", [{}, {"delta": 0.005, "a": 0.004}])
def test_growth_against_simulated_small_swing(given):
    _, n, _ = solve_both("5.12", **given)
    p = {"l": 0.5, "g": 9.81, "delta": 0.05, "a": 0.008, "Omega": 8.9, **given}
    T = 2 * math.pi / p["Omega"]

    # the linearized equation (sin theta -> theta), sampled once per pivot period
    def lin(t, y):
        return [y[1], -2 * p["delta"] * y[1] - (p["g"] - p["a"] * p["Omega"] ** 2 * math.cos(p["Omega"] * t)) / p["l"] * y[0]]

    ks = np.arange(0, 601)
    sol = solve_ivp(lin, (0, ks[-1] * T), [1.0, 0.0], method="DOP853", rtol=1e-11, atol=1e-14, t_eval=ks * T)
    w0 = math.sqrt(p["g"] / p["l"])
    norm = np.hypot(sol.y[0], sol.y[1] / w0)
    g_sim = math.log(norm[-1] / norm[-201]) / (200 * T)  # after the other solution has died out
    assert n["growth"] == pytest.approx(g_sim, rel=1e-3)


def test_below_threshold_no_swing_and_growth_sign():
    a, n, _ = solve_both("5.12", a=0.005)
    assert a["theta_st"] == 0.0 and n["theta_st"] == 0.0
    assert n["growth"] < 0 and a["growth"] < 0
    # a_th does not depend on a
    a2, n2, _ = solve_both("5.12")
    assert n["a_th"] == pytest.approx(n2["a_th"], rel=1e-9)

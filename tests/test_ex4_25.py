"""4.25 against values worked out by hand.

Hand derivation (fast top, L = I3 w n3, spherical unit vectors n3, e_th, e_ph of
the axis): the contact point is P - C = -l n3 + R e_th, the rim slides along
e_ph, so the friction is -mu M g e_ph.  Torque about C:
    M g (l sin th - R cos th) e_ph - mu M g l e_th - mu M g R n3
(n3 x z = -sin th e_ph, e_th x z = -cos th e_ph, n3 x e_ph = -e_th, e_th x e_ph = n3).
The n3 part: I3 dw/dt = -mu M g R; the e_th part: I3 w dth/dt = -mu M g l.
Dividing: dth = (l/R) dw/w, so w1 = w0 exp(-(th0 - th1) R/l) and
t = (w0 - w1) I3/(mu M g R).  Numbers below by a calculator from these lines.
"""

import math

import pytest

from conftest import solve_both


def test_defaults_by_hand():
    # a = 0.05*0.1*9.81*1e-3/3.125e-5 = 1.5696; thdot = 0.05*0.1*9.81*0.03/(3.125e-5*300) = 0.15696
    # w1 = 300 exp(-0.4/30) = 296.02654854...; t = (300 - w1)/1.5696
    a, n, run = solve_both("4.25")
    w1 = 300.0 * math.exp(-0.4 / 30.0)
    for v in (a, n):
        assert v["omega_dot"] == pytest.approx(1.5696, rel=1e-12)
        assert v["theta_dot0"] == pytest.approx(0.15696, rel=1e-12)
        assert v["omega_rise"] == pytest.approx(w1, rel=1e-9)
        assert v["t_rise"] == pytest.approx((300.0 - w1) / 1.5696, rel=1e-8)
    assert run.invariants["|L| + mu M g R t"] < 1e-9


def test_spin_halves():
    # R/l * (th0 - th1) = ln 2 with th0 - th1 = 1: the spin halves, t = w0/(2a)
    # a = 0.2*0.5*9.81*R/1e-4 with R = 0.05 ln 2; w0 = 500
    R = 0.05 * math.log(2.0)
    acc = 0.2 * 0.5 * 9.81 * R / 1e-4
    a, n, _ = solve_both("4.25", M=0.5, I3=1e-4, l=0.05, R=R, mu=0.2, omega0=500.0, theta0=1.3, theta1=0.3)
    for v in (a, n):
        assert v["omega_rise"] == pytest.approx(250.0, rel=1e-9)
        assert v["t_rise"] == pytest.approx(250.0 / acc, rel=1e-8)
        assert v["omega_dot"] == pytest.approx(acc, rel=1e-12)
        # thdot0 = 0.2*0.5*9.81*0.05/(1e-4*500)
        assert v["theta_dot0"] == pytest.approx(0.981, rel=1e-12)


def test_sharp_tip_limit_constant_tilt_rate():
    # R -> 0: the spin barely changes, the tilt falls at the constant rate 0.15696 rad/s:
    # t = (w0 - w1)/a with w1 = w0 exp(-x), x = 0.4 R/l: t = 0.4/0.15696 (1 - x/2 + ...), x/2 = 6.7e-7
    a, n, _ = solve_both("4.25", R=1e-7)
    t0 = 0.4 / 0.15696
    for v in (a, n):
        assert v["t_rise"] == pytest.approx(t0 * (1 - 0.4 * 1e-7 / 0.06), rel=1e-9)
        # spin change: w0 (th0 - th1) R / l = 300 * 0.4 / 3e5 = 4e-4 rad/s
        assert 300.0 - v["omega_rise"] == pytest.approx(4e-4, rel=1e-5)
        assert v["omega_dot"] == pytest.approx(1.5696e-4, rel=1e-10)


def test_small_friction_long_rise():
    # mu = 1e-4: 500 times slower, t = 500 * default t_rise; hundreds of precession turns
    a, n, run = solve_both("4.25", mu=1e-4)
    w1 = 300.0 * math.exp(-0.4 / 30.0)
    for v in (a, n):
        assert v["t_rise"] == pytest.approx(500.0 * (300.0 - w1) / 1.5696, rel=1e-8)
    assert run.info["precession_turns"] > 100


def test_theta1_must_be_below_theta0():
    from mech.problems import registry
    from mech.problems.spec import BadInput

    with pytest.raises(BadInput):
        registry.get("4.25").resolve({"theta0": 0.3, "theta1": 0.4})


@pytest.mark.parametrize("draw", [
    # issue-14 draws (draws.py --seed 201): a near-vertical axis (theta ~ 1e-5..1e-4) with R/l up to 5e3;
    # theta_dot0 missed its 1e-12 claim by up to 2e-11, three timed out (a noisy rim direction)
    dict(M=1562.57, I3=0.208068, l=0.000243859, R=1.33597, mu=3.23226, omega0=1.31497, theta0=4.92365e-05,
         theta1=1.79872e-06, g=17275.7),
    dict(M=6479.19, I3=0.591768, l=3.96829e-05, R=0.0080112, mu=57.2271, omega0=1.09973e+07, theta0=0.000551392,
         theta1=1.17496e-07, g=0.456999),
    dict(M=0.00149573, I3=5.29885e-07, l=0.00149831, R=1.36382, mu=21995.7, omega0=971767.0, theta0=0.00269603,
         theta1=1.50993e-05, g=24.1108),
])
def test_near_vertical_draws_by_hand(draw):
    """theta_dot0 = mu M g l/(I3 omega0) and omega_dot = mu M g R/I3 (the e_theta and n3 parts of the
    torque about C, by hand in the module docstring), within the 1e-12 claimed; the rise at the spin's
    log-rate: omega_rise = omega0 exp(-(theta0 - theta1) R/l), t_rise = (omega0 - omega_rise)/omega_dot."""
    d = draw
    _, n, run = solve_both("4.25", **d)
    assert n["theta_dot0"] == pytest.approx(d["mu"] * d["M"] * d["g"] * d["l"] / (d["I3"] * d["omega0"]), rel=1e-12)
    wdot = d["mu"] * d["M"] * d["g"] * d["R"] / d["I3"]
    assert n["omega_dot"] == pytest.approx(wdot, rel=1e-12)
    w_rise = d["omega0"] * math.exp(-(d["theta0"] - d["theta1"]) * d["R"] / d["l"])
    assert n["omega_rise"] == pytest.approx(w_rise, rel=1e-8, abs=1e-12 * d["omega0"])
    assert n["t_rise"] == pytest.approx((d["omega0"] - w_rise) / wdot, rel=1e-8)
    assert run.nfev < 5000


@pytest.mark.parametrize("draw", [
    # issue 14: mu = 1e4, R/l = 3873, the spin falls by e^12.1 during the rise; integrated in t,
    # omega_rise moved by 4e-4 between rtol 1e-10 and 1e-11 (a log singularity just past the event)
    dict(M=7.98662, I3=0.274206, l=0.000677744, R=2.62522, mu=10146, omega0=5.45532e+06, theta0=0.00313117,
         theta1=4.70024e-06, g=0.189171),
    # the constraint's edge: a fall by e^24.9 (x = 0.498 * 50), near a full stop
    dict(M=0.1, I3=3.125e-5, l=0.02, R=1.0, mu=0.05, omega0=300.0, theta0=0.5, theta1=0.002, g=9.81),
])
def test_strong_spin_down_converges(draw):
    """By hand (module docstring): dtheta = (l/R) dln(omega3), so omega_rise = omega0 exp(-x) with
    x = (theta0 - theta1) R/l, and the spin falls linearly: t_rise = (omega0 - omega_rise)/omega_dot,
    omega_dot = mu M g R/I3.  The numeric value must hold its 1e-8 claim at rtol 1e-10 and 1e-11
    and pass the cross-check with its rerun."""
    from mech.studies.checking import Case, run_case
    from mech.problems import registry

    d = draw
    x = (d["theta0"] - d["theta1"]) * d["R"] / d["l"]
    w_rise = d["omega0"] * math.exp(-x)
    wdot = d["mu"] * d["M"] * d["g"] * d["R"] / d["I3"]
    for rtol in (1e-10, 1e-11):
        _, n, _ = solve_both("4.25", rtol=rtol, **d)
        assert n["omega_rise"] == pytest.approx(w_rise, rel=1e-8)
        assert n["t_rise"] == pytest.approx((d["omega0"] - w_rise) / wdot, rel=1e-8)
    case = run_case(Case(registry.all_exercises()["4.25"], "draw", d))
    assert case.ok, case.detail

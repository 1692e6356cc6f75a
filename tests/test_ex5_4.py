"""5.4 against values worked out by hand.

Hand derivation: q = C1 e^{-l1 t} + C2 e^{-l2 t} with l1,2 = w0 (z -+ sqrt(z^2-1));
q(0) = q0, q'(0) = 0 give q = q0 (l2 e^{-l1 t} - l1 e^{-l2 t})/(l2 - l1) and
q' = q0 l1 l2 (e^{-l2 t} - e^{-l1 t})/(l2 - l1) (one sign: no crossing).  The
speed peaks at q'' = 0: t* = ln(l2/l1)/(l2 - l1).  Critical: q = q0 (1 + w0 t) e^{-w0 t},
q' = -q0 w0^2 t e^{-w0 t}, peak at t = 1/w0, v_max = q0 w0/e.  t_eps is found here by
plain bisection on these textbook forms (not the module's log form).
"""

import math

import pytest

from conftest import solve_both


def bisect(f, lo, hi):
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if f(mid) > 0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def textbook(omega0, zeta, q0, t1, eps):
    s = math.sqrt(zeta**2 - 1)
    l1, l2 = omega0 * (zeta - s), omega0 * (zeta + s)
    q = lambda t: q0 * (l2 * math.exp(-l1 * t) - l1 * math.exp(-l2 * t)) / (l2 - l1)
    v = lambda t: q0 * l1 * l2 * (math.exp(-l2 * t) - math.exp(-l1 * t)) / (l2 - l1)
    ts = math.log(l2 / l1) / (l2 - l1)
    t_eps = bisect(lambda t: q(t) - eps * q0, 0.0, 100.0 / l1)
    return l1, q(t1), t_eps, abs(v(ts))


@pytest.mark.parametrize(
    "params",
    [
        {},                                                    # defaults: zeta = 2
        {"omega0": 0.3, "zeta": 1.5, "q0": 2.0, "t1": 7.0, "eps": 0.2},
        {"omega0": 40.0, "zeta": 8.0, "q0": 0.01, "t1": 0.05, "eps": 1e-4},   # Radau
    ],
)
def test_against_textbook_form(params):
    full = {"omega0": 5.0, "zeta": 2.0, "q0": 0.1, "t1": 1.0, "eps": 0.01, **params}
    lam, q, t_eps, v_max = textbook(**full)
    a, n, _ = solve_both("5.4", **params)
    for vals in (a, n):
        assert vals["lambda_slow"] == pytest.approx(lam, rel=1e-10)
        assert vals["q_t"] == pytest.approx(q, rel=1e-7)
        assert vals["t_eps"] == pytest.approx(t_eps, rel=1e-7)
        assert vals["v_max"] == pytest.approx(v_max, rel=1e-7)


def test_critical_damping():
    # q(1) = 0.1 * 6 e^{-5}; v_max = 0.1 * 5/e; (1 + x) e^{-x} = 0.01 at x = 5 t_eps
    a, n, run = solve_both("5.4", zeta=1.0)
    x = bisect(lambda x: (1 + x) * math.exp(-x) - 0.01, 0.0, 50.0)
    for vals in (a, n):
        assert vals["lambda_slow"] == pytest.approx(5.0, rel=1e-7)
        assert vals["q_t"] == pytest.approx(0.6 * math.exp(-5.0), rel=1e-7)
        assert vals["v_max"] == pytest.approx(0.5 / math.e, rel=1e-7)
        assert vals["t_eps"] == pytest.approx(x / 5.0, rel=1e-7)
    assert run.invariants["E + dissipated work"] < 1e-6


def test_strong_damping_asymptotics():
    # zeta = 1e6: l1 = w0/(z + s) = 2.5e-6 (1 + 1/(4 z^2) + ...), fast part negligible:
    # q ~ q0 (1 + l1/l2) e^{-l1 t}, so t_eps ~ ln(1/eps)/l1 and v_max ~ q0 l1
    a, n, _ = solve_both("5.4", zeta=1e6, t1=3e5)
    l1 = 2.5e-6
    for vals in (a, n):
        assert vals["lambda_slow"] == pytest.approx(l1, rel=1e-11)
        assert vals["t_eps"] == pytest.approx(math.log(100.0) / l1, rel=1e-9)
        assert vals["q_t"] == pytest.approx(0.1 * math.exp(-l1 * 3e5), rel=1e-9)
        assert vals["v_max"] == pytest.approx(0.1 * l1, rel=1e-9)


def test_critical_damping_relaxes_fastest():
    rates = [solve_both("5.4", zeta=z)[0]["lambda_slow"] for z in (1.0, 1.01, 1.5, 3.0)]
    assert rates == sorted(rates, reverse=True)


def test_a_reading_after_1e5_decay_times_is_zero_within_its_claim_and_fast():
    """Issue 14 draw: omega0 0.484781, zeta 3.69078, t1 = 521341 s: the slow rate is
    omega0/(zeta + (zeta^2 - 1)^(1/2)) = 0.0664 1/s, so q(t1)/q0 ~ e^-34600, zero in doubles; the leg
    once took 6e5 steps (and divided by zero in the step control).  t_eps: the root of
    q/q0 = eps = 1.74208e-5 is about ln(1/eps)/lambda_s (within the prefactor's log)."""
    a, n, run = solve_both("5.4", omega0=0.484781, zeta=3.69078, q0=5095.95, t1=521341.0, eps=1.74208e-05)
    # cost that does not grow with the phase or the decay: stepping through these spans would take
    # 1e6-1e10 evaluations; a count, not a wall time, so a loaded machine cannot fail it
    assert run.nfev < 20_000
    rel, ab = run.claims["q_t"]
    assert abs(n["q_t"]) <= ab and 0.0 < ab < 1e-12 * 5095.95
    lam = 0.484781 / (3.69078 + math.sqrt(3.69078**2 - 1.0))
    assert n["t_eps"] == pytest.approx(math.log(1 / 1.74208e-05) / lam, rel=0.1)


def _decimal_textbook(omega0, zeta, q0, t1, eps):
    """The textbook forms above in 100-digit Decimal (tests/hiprec.py); t_eps by bisection on them."""
    from decimal import localcontext

    import hiprec

    with localcontext() as ctx:
        ctx.prec = hiprec.PREC
        D = hiprec.D
        s = (D(zeta) ** 2 - 1).sqrt()
        l1, l2 = D(omega0) * (D(zeta) - s), D(omega0) * (D(zeta) + s)
        q = lambda t: D(q0) * (l2 * hiprec.exp(-l1 * t) - l1 * hiprec.exp(-l2 * t)) / (l2 - l1)
        ts = (l2 / l1).ln() / (l2 - l1)
        v_max = D(q0) * l1 * l2 * (hiprec.exp(-l1 * ts) - hiprec.exp(-l2 * ts)) / (l2 - l1)
        lo, hi = D(0), 100 / l1
        for _ in range(120):
            mid = (lo + hi) / 2
            lo, hi = (mid, hi) if q(mid) > D(eps) * D(q0) else (lo, mid)
        return float(l1), float(q(D(t1))), float(lo), float(v_max)


@pytest.mark.parametrize("given", [
    {"zeta": 1000.0, "eps": 0.001, "t1": 500.0},               # hard 2
    {"zeta": 1e6, "t1": 3e5},                                  # hard 3
    {"zeta": 7.0, "omega0": 0.02, "q0": 3.0, "t1": 900.0, "eps": 0.3},
])
def test_stiff_cases_by_the_exact_flow_against_100_digits(given):
    """zeta > 5: the numeric route propagates exp(A tau) (no integrator, no scipy) and finds the events by
    Brent's method; within a small fraction of its claim (10 rtol) of the Decimal values."""
    full = {"omega0": 5.0, "zeta": 2.0, "q0": 0.1, "t1": 1.0, "eps": 0.01, **given}
    want = dict(zip(("lambda_slow", "q_t", "t_eps", "v_max"), _decimal_textbook(**full)))
    _, n, run = solve_both("5.4", **given)
    assert run.method.startswith("exact flow") and run.nfev == 0
    for name, value in want.items():
        assert n[name] == pytest.approx(value, rel=1e-9), name
    assert run.invariants["semigroup Phi(a) Phi(b) = Phi(a + b)"] < 1e-12


def test_long_decay_keeps_its_relative_accuracy():
    """Released from rest at q0, an overdamped oscillator follows
    q(t) = q0 (lf e^(-ls t) - ls e^(-lf t)) / (lf - ls), ls, lf = omega0 (zeta -+ (zeta^2 - 1)^(1/2)).
    Draw of scripts/draws.py (seed 20261125): omega0 = 3048.71, zeta = 599.958, t1 = 29230.6 s, where
    ls t1 = 7.4e4 and q(t1) = 0 in double precision; exp(A tau1) taken in one piece gave 2.5e-21 m
    (1e-16 of q0).  At t1 = 236 s, ls t1 = 600: q(t1) = q0 lf/(lf - ls) e^-600 ~ 2e-266 m, representable,
    and the numeric value must keep its relative accuracy there."""
    base = dict(omega0=3048.7064204236535, zeta=599.9583194078805, q0=2.2267010862732086e-05,
                eps=1.1000462045078789e-07)
    a, n, _ = solve_both("5.4", t1=29230.562507718536, **base)
    assert n["q_t"] == 0.0 and a["q_t"] == 0.0
    w0, z, q0 = base["omega0"], base["zeta"], base["q0"]
    ls = w0 / (z + math.sqrt(z * z - 1.0))  # = w0 (z - sqrt(z^2 - 1)) without the cancellation
    lf = w0 * (z + math.sqrt(z * z - 1.0))
    t1 = 600.0 / ls
    a, n, _ = solve_both("5.4", t1=t1, **base)
    expected = q0 * lf / (lf - ls) * math.exp(-600.0)
    assert n["q_t"] == pytest.approx(expected, rel=1e-9)
    assert a["q_t"] == pytest.approx(expected, rel=1e-9)


def test_a_small_eps_keeps_t_eps_to_its_claim():
    """Issue 26: zeta 1e4, eps 1e-12.  exp(A tau) in one piece holds x only to ~1e-16 of q0, so x = 1e-12
    came out 1.3e-4 off and t_eps 1.3e-6 off (claim 1e-7); the chain of hops keeps x relative to itself.
    Reference: the textbook forms in 100-digit Decimal, t_eps by bisection on them."""
    given = {"zeta": 1e4, "eps": 1e-12}
    want = dict(zip(("lambda_slow", "q_t", "t_eps", "v_max"),
                    _decimal_textbook(omega0=5.0, zeta=1e4, q0=0.1, t1=1.0, eps=1e-12)))
    _, n, run = solve_both("5.4", **given)
    for name, value in want.items():
        assert n[name] == pytest.approx(value, rel=1e-9), name
    assert run.invariants["semigroup Phi(a) Phi(b) = Phi(a + b)"] < 1e-12


@pytest.mark.parametrize("t1", [74208.0, 0.0018, 0.003])
def test_a_reading_past_the_chains_last_node(t1):
    # A draw of ../shared/tools/draws.py (seed 31337, 5.4#2): the event chain stops at t_eps (tau = 14.3)
    # while its grid of short hops runs on to tau ~ 21; a t1 beyond the last computed node indexed past
    # the chain (IndexError).  Held to the textbook closed form (q(t1) underflows to 0 at t1 = 74208 s).
    given = {"omega0": 10468.0, "zeta": 5.41725, "q0": 9.80394, "t1": t1, "eps": 0.266483}
    lam, q, t_eps, v_max = textbook(**given)
    a, n, _ = solve_both("5.4", **given)
    for vals in (a, n):
        assert vals["q_t"] == pytest.approx(q, rel=1e-7, abs=1e-300)
        assert vals["t_eps"] == pytest.approx(t_eps, rel=1e-7)
        assert vals["v_max"] == pytest.approx(v_max, rel=1e-7)


def test_the_declared_motion_alone_ends_at_q_eps():
    """``motion`` followed alone at zeta = 2, t1 = 0.2 s (before q = eps q0): a leg to t1, then one on to
    q = eps q0, which the two exponentials put at t_eps (a root of q0 (l+ e^(-l- t) - l- e^(-l+ t))/(l+ - l-))."""
    import numpy as np

    from mech.problems.registry import get
    from mech.problems.spec import Run
    from mech.solvers.numerics.roots import brentq

    w0, z, q0, eps = 5.0, 2.0, 0.1, 0.01
    ex = get("5.4")
    p = ex.resolve({"omega0": w0, "zeta": z, "q0": q0, "t1": 0.2, "eps": eps})
    run = Run(rtol=1e-10, keep_trajectories=True)
    path = run.follow(ex.motion_at(p))
    assert len(path.legs) == 2 and path.legs[0].t_end == pytest.approx(w0 * 0.2, rel=1e-15)  # tau1 = omega0 t1
    lp, lm = w0 * (z + math.sqrt(z * z - 1)), w0 * (z - math.sqrt(z * z - 1))
    q = lambda t: q0 * (lp * np.exp(-lm * t) - lm * np.exp(-lp * t)) / (lp - lm)  # noqa: E731
    t_eps = brentq(lambda t: q(t) - eps * q0, 0.0, 10.0, xtol=1e-15)
    t, y = run.trajectory(2)
    assert t[-1] == pytest.approx(t_eps, rel=1e-8) and np.allclose(y[0], q(t), rtol=1e-8, atol=0)
    assert run.invariants["E + dissipated work"] < 1e-8

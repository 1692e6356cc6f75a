"""The routes of 5.2, 5.3, 5.4, 5.6 and 5.7 written once over arrays of variants (issue 41): at N variants each
variant equals its batch of one within its claims, agrees with values derived independently (mpmath, by
hand), and a variant whose integration fails fails alone.

5.6 by hand: energy gives the quarter period K(m)/omega0, m = sin^2(theta0/2) (mpmath's ellipk, 30 digits),
and 2 pi/T - omega0 = omega0 (pi/(2K) - 1).
"""

import math

import numpy as np
import pytest

from mech.problems import registry


def route_at(ex_id, points, rtol=None):
    """The exercise's batched route at the given points (dicts of every parameter): its Columns."""
    ex = registry.get(ex_id)
    full = [dict(ex.resolve(p)) for p in points]
    P = {k: np.array([q[k] for q in full]) for k in full[0]}
    route = ex.batched_route
    return route.numeric(P, rtol or ex.default_rtol, route.outputs), full


def agree_within_claims(cols, k, one, name):
    """Variant k of a batch against the batch of one ``one`` (same Columns), within both claims."""
    a, b = cols[name], one[name]
    va, vb = float(a.value[k]), float(b.value[0])
    rel = float(np.broadcast_to(a.rel, a.value.shape)[k])
    ab = float(np.broadcast_to(a.abs, a.value.shape)[k])
    assert abs(va - vb) <= 2 * (rel * abs(va) + ab) + 1e-300, (name, k, va, vb)


# ---------------------------------------------------------------- 5.6
THETAS = [1e-4, 0.01, 0.5, 1.0, math.pi / 2, 1.6, 2.5, 3.1, math.pi - 1e-6, 3.141592643589793]


def test_5_6_batch_matches_mpmath_and_its_batches_of_one():
    mp = pytest.importorskip("mpmath")
    mp.mp.dps = 30
    pts = [dict(theta0=t, l=0.7, g=9.81) for t in THETAS]
    cols, full = route_at("5.6", pts)
    w0 = math.sqrt(9.81 / 0.7)
    for k, th in enumerate(THETAS):
        assert not cols["T"].mask("failed")[k]
        m = mp.sin(mp.mpf(th) / 2) ** 2
        K = mp.ellipk(m)
        T = float(4 * K / w0)
        dw = float(w0 * (mp.pi / (2 * K) - 1))
        assert cols["T"].value[k] == pytest.approx(T, rel=1e-8)
        assert cols["T_ratio"].value[k] == pytest.approx(float(2 * K / mp.pi), rel=1e-8)
        assert cols["domega"].value[k] == pytest.approx(dw, rel=1e-8)
        one, _ = route_at("5.6", [pts[k]])
        for name in ("T", "T_ratio", "domega"):
            agree_within_claims(cols, k, one, name)


def test_5_6_a_failing_variant_fails_alone(monkeypatch):
    """A variant whose right-hand side turns non-finite midway (poisoned on its own energy level) fails with its
    reason; the others keep their values."""
    from mech.problems.ch5 import ex5_6_pendulum_period as mod

    real = mod._swing_rhs
    level = 2 * math.sin(0.75 / 2) ** 2  # the middle swing's energy, from the bottom

    def poisoned(high):
        rhs = real(high)

        def f(psi, y):
            out = rhs(psi, y)
            own = np.abs(0.5 * y[1] ** 2 + 2 * np.sin(y[0] / 2) ** 2 - level) < 1e-3
            return np.where(own & (psi > 0.3), np.nan, out)

        return f

    monkeypatch.setattr(mod, "_swing_rhs", poisoned)
    pts = [dict(theta0=t) for t in (0.3, 0.75, 1.2)]
    cols, _ = route_at("5.6", pts)
    assert cols["T"].mask("failed").tolist() == [False, True, False]
    assert cols["T"].reason("failed", 1)
    assert np.isfinite(cols["T"].value[[0, 2]]).all()


# ---------------------------------------------------------------- 5.7
# 5.7 by hand (the module's docstring): q = A cn(Omega t | m), Omega^2 = omega0^2 + alpha A^2,
# m = alpha A^2/(2 Omega^2), so omega = pi Omega/(2 K(m)) and c3 = (2/T) int_0^T q cos(3 omega t) dt; mpmath
# gives K (m < 0 too) and cn, and the Fourier integral by quadrature over a quarter period (half-wave symmetry:
# (8/T) int_0^{T/4}).
DUFFING = [dict(omega0=2.0, alpha=0.8, A=0.5), dict(omega0=2.0, alpha=0.8, A=20.0),
           dict(omega0=2.0, alpha=0.8, A=0.00223606797749979), dict(omega0=2.0, alpha=-1.0, A=1.9),
           dict(omega0=2.0, alpha=-1.0, A=1.99999998), dict(omega0=1.5, alpha=-0.3, A=1.0)]


def duffing_reference(omega0, alpha, A):
    mp = pytest.importorskip("mpmath")
    with mp.workdps(30):
        w0, al, a = mp.mpf(omega0), mp.mpf(alpha), mp.mpf(A)
        Om = mp.sqrt(w0**2 + al * a**2)
        m = al * a**2 / (2 * Om**2)
        K = mp.ellipk(m)
        omega = mp.pi * Om / (2 * K)
        quarter = K / Om
        c3 = 8 / (4 * quarter) * mp.quad(lambda t: a * mp.re(mp.ellipfun("cn", Om * t, m)) * mp.cos(3 * omega * t),
                                         [0, quarter / 2, quarter])
        return float(omega), float(omega - w0), float(c3)


def test_5_7_batch_matches_mpmath_and_its_batches_of_one():
    cols, _ = route_at("5.7", DUFFING)
    for k, p in enumerate(DUFFING):
        omega, domega, c3 = duffing_reference(**p)
        assert not cols["omega"].mask("failed")[k]
        assert cols["omega"].value[k] == pytest.approx(omega, rel=1e-8)
        assert cols["domega"].value[k] == pytest.approx(domega, rel=1e-8)
        # near the barrier the reference's own quadrature of cn is held to 1e-7
        assert cols["c3"].value[k] == pytest.approx(c3, rel=1e-8 if p["A"] != 1.99999998 else 1e-7)
        one, _ = route_at("5.7", [p])
        for name in ("omega", "domega", "c3"):
            agree_within_claims(cols, k, one, name)


def test_5_7_a_failing_variant_fails_alone(monkeypatch):
    """A variant whose force turns non-finite midway (poisoned on its own stiffness b) fails with its reason;
    the others keep their values."""
    from mech.problems.ch5 import ex5_7_duffing_free as mod

    real = mod.restoring_factor
    b_bad = 0.8 * 0.7**2 / 4.0  # eps = alpha A^2/omega0^2 of the middle variant (S = 1: b = eps)

    def poisoned(y, k, b):
        return np.where((np.abs(b - b_bad) < 1e-12) & (y > 0.3), np.nan, real(y, k, b))

    monkeypatch.setattr(mod, "restoring_factor", poisoned)
    cols, _ = route_at("5.7", [dict(A=0.5), dict(A=0.7), dict(A=0.9)])
    assert cols["omega"].mask("failed").tolist() == [False, True, False]
    assert cols["c3"].mask("failed").tolist() == [False, True, False]
    assert np.isfinite(cols["omega"].value[[0, 2]]).all()


# ---------------------------------------------------------------- 5.2
# 5.2 by hand: q = q_st (1 - cos omega0 t) during the pulse, q_st [cos omega0 (t - T) - cos omega0 t] after it
# (two step responses superposed), so A_after = 2 |q_st| |sin(omega0 T/2)|, q_max = 2 |q_st| once omega0 T >= pi.
PULSES = [dict(T=0.4, t1=2.0), dict(T=0.4, t1=0.1), dict(T=1.0, t1=0.9), dict(T=125.9778654089507, t1=377.1167821369188),
          dict(T=50.0, t1=20.0), dict(T=1e-6, t1=1e-6), dict(T=3.0, t1=0.0), dict(F0=-0.7, T=7.0, t1=9.0)]


def pulse_by_hand(m=0.2, omega0=5.0, F0=0.3, T=0.4, t1=2.0):
    qst = F0 / (m * omega0**2)

    def q(t):
        if t <= T:
            return 2 * qst * math.sin(omega0 * t / 2) ** 2  # q_st (1 - cos omega0 t), no cancellation
        return qst * (math.cos(omega0 * (t - T)) - math.cos(omega0 * t))

    a_after = 2 * abs(qst) * abs(math.sin(omega0 * T / 2))
    return {"A_after": a_after, "q_max": 2 * abs(qst) if omega0 * T >= math.pi else a_after, "q_t": q(t1)}


def test_5_2_batch_matches_hand_values_and_its_batches_of_one():
    cols, full = route_at("5.2", PULSES)
    for k, p in enumerate(full):
        want = pulse_by_hand(**{n: p[n] for n in ("m", "omega0", "F0", "T", "t1")})
        qst = abs(p["F0"] / (p["m"] * p["omega0"] ** 2))
        for name in ("A_after", "q_max", "q_t"):
            assert not cols[name].mask("failed")[k]
            # the reading after 1e4 rad carries its phase's round-off, ~u * phase in both
            slack = 1e-8 * abs(want[name]) + qst * (1e-9 + 1e-15 * p["omega0"] * max(p["T"], p["t1"]))
            assert abs(cols[name].value[k] - want[name]) <= slack, (name, p)
        one, _ = route_at("5.2", [PULSES[k]])
        for name in ("A_after", "q_max", "q_t"):
            agree_within_claims(cols, k, one, name)


def test_5_2_a_failing_variant_fails_alone(monkeypatch):
    from mech.problems.ch5 import ex5_2_force_pulse as mod

    real = mod._pulse_rhs

    def poisoned(L):
        rhs = real(L)
        bad = np.abs(np.asarray(L) - 5.0 * 0.7) < 1e-12  # the middle pulse, omega0 T = 3.5
        return lambda s, y: np.where(bad & (s > 0.5), np.nan, rhs(s, y))

    monkeypatch.setattr(mod, "_pulse_rhs", poisoned)
    cols, _ = route_at("5.2", [dict(T=0.4), dict(T=0.7), dict(T=1.0)])
    assert cols["A_after"].mask("failed").tolist() == [False, True, False]
    assert np.isfinite(cols["A_after"].value[[0, 2]]).all()


# ---------------------------------------------------------------- 5.3
# 5.3 by hand: undamped from rest, q = f (cos omega t - cos omega0 t)/(omega0^2 - omega^2) (mpmath, 30 digits, no
# cancellation left), at exact resonance f t sin(omega0 t)/(2 omega0); the stationary amplitude
# |f|/[(omega0^2 - omega^2)^2 + 4 delta^2 omega^2]^(1/2) for any damping.
DRIVES = [dict(delta=0.0, omega=4.0, t1=3.0), dict(delta=0.0, omega=6.00000000006, t1=100.0),
          dict(delta=0.0, omega=6.0, t1=7.0), dict(delta=0.0, omega=0.01, t1=50.0), dict(delta=0.0, omega=40.0, t1=1e4)]


def test_5_3_batch_matches_hand_values_and_its_batches_of_one():
    mp = pytest.importorskip("mpmath")
    cols, full = route_at("5.3", DRIVES)
    for k, p in enumerate(full):
        with mp.workdps(30):
            f, w0, w, t = (mp.mpf(p[n]) for n in ("F0", "omega0", "omega", "t1"))
            f = f / mp.mpf(p["m"])
            if w == w0:
                q, a_ss = f * t * mp.sin(w0 * t) / (2 * w0), None
            else:
                q, a_ss = f * (mp.cos(w * t) - mp.cos(w0 * t)) / (w0**2 - w**2), abs(f) / abs(w0**2 - w**2)
        assert not cols["q_t"].mask("failed")[k]
        bar = float(cols["q_t"].abs[k]) + 1e-8 * abs(float(q))
        assert abs(cols["q_t"].value[k] - float(q)) <= bar, p
        if a_ss is None:
            assert cols["A_ss"].mask("undefined")[k]
        else:
            assert cols["A_ss"].value[k] == pytest.approx(float(a_ss), rel=1e-8)
        one, _ = route_at("5.3", [DRIVES[k]])
        for name in ("q_t", "v_t") + (("A_ss",) if a_ss is not None else ()):
            agree_within_claims(cols, k, one, name)


def test_5_3_damped_stationary_amplitude_over_a_batch():
    omegas = np.linspace(1.0, 12.0, 23)
    cols, full = route_at("5.3", [dict(delta=0.3, omega=w) for w in omegas])
    for k, p in enumerate(full):
        f = abs(p["F0"] / p["m"])
        want = f / math.hypot((p["omega0"] - p["omega"]) * (p["omega0"] + p["omega"]), 2 * p["delta"] * p["omega"])
        assert cols["A_ss"].value[k] == pytest.approx(want, rel=1e-8)

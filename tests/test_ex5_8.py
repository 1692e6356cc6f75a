"""5.8 against hand values, an independent extremum search and harmonic balance.

Hand derivation (reduced equations): q = A cos(omega t - phi) with A, phi slow;
averaging gives A^2 [(xi - kappa A^2)^2 + delta^2] = (f0/(2 omega0))^2 with
kappa = 3 alpha/(8 omega0).  The largest A makes the bracket smallest, i.e.
xi = kappa A^2: A_max = f0/(2 omega0 delta), xi_peak = kappa A_max^2.
Defaults (omega0 = 10, delta = 0.02, alpha = 1000, f0 = 0.016):
A_max = 0.016/0.4 = 0.04 m, kappa = 37.5, xi_peak = 37.5 * 0.0016 = 0.06 rad/s.
The folds are the extreme detunings of the two halves of the curve,
xi(s) = delta (g s -+ sqrt(1/s - 1)) with s = (A/A_max)^2, g = xi_peak/delta:
found here by a bounded scalar minimisation (a different method from the
module's quartic in s).

The exact periodic orbits, for the numeric solver, by harmonic balance: q as
a sum of odd harmonics up to the 9th, the equation's residual projected on
them (collocation at 64 points) and solved by fsolve; A_max by maximising the
swing over omega, each fold as the extremum of omega along the branch, the
branch parametrised by the fundamental's amplitude.  No shooting, no
integration.  Since issue 41 the numeric solver is itself a harmonic balance
(parametrised by the fundamental's phase, its own Newton and root searches):
these are a second implementation of that method, and
tests/test_ex5_8_shooting.py holds it against shooting and long time
integration, methods of another kind.
"""

import math

import numpy as np
import pytest
from scipy.optimize import fsolve, minimize_scalar

from conftest import solve_both
from mech.problems.spec import Undefined

DEF = dict(omega0=10.0, delta=0.02, alpha=1000.0, f0=0.016)


def rwa_folds(omega0, delta, alpha, f0):
    am = f0 / (2 * omega0 * delta)
    g = 3 * alpha / (8 * omega0) * am**2 / delta
    sg = math.copysign(1.0, g)
    # the half of the curve that leans (the + root for alpha > 0) has both folds; the minimum/maximum
    # of xi(s) over s in (0, 1) on the side where the square root adds to the lean
    def xi(s):
        return delta * (g * s + sg * math.sqrt(1 / s - 1))
    lo = minimize_scalar(lambda s: sg * xi(s), bounds=(1e-6, 0.75), method="bounded", options={"xatol": 1e-14})
    hi = minimize_scalar(lambda s: -sg * xi(s), bounds=(0.75, 1 - 1e-12), method="bounded", options={"xatol": 1e-14})
    return sorted([xi(lo.x), xi(hi.x)])


def test_defaults_by_hand():
    a, n, run = solve_both("5.8")
    assert a["A_max"] == pytest.approx(0.04, rel=1e-14)
    assert a["xi_peak"] == pytest.approx(0.06, rel=1e-14)
    lo, hi = rwa_folds(**DEF)
    assert a["xi_lo"] == pytest.approx(lo, rel=1e-9)
    assert a["xi_hi"] == pytest.approx(hi, rel=1e-9)
    assert lo < a["xi_peak"] < hi  # hardening: the peak lies inside the window
    assert run.info["harmonic_tail"] < 1e-15  # the 13th harmonic, against the fundamental


@pytest.mark.parametrize("given", [dict(f0=0.012), dict(alpha=-1000.0), dict(omega0=3.0, delta=0.01, alpha=-150.0, f0=0.0024)])
def test_analytic_folds_other_parameters(given):
    p = {**DEF, **given}
    a, _, _ = solve_both("5.8", **given)
    lo, hi = rwa_folds(**p)
    assert a["xi_lo"] == pytest.approx(lo, rel=1e-9)
    assert a["xi_hi"] == pytest.approx(hi, rel=1e-9)


def test_softening_mirrors_hardening():
    a1, _, _ = solve_both("5.8")
    a2, _, _ = solve_both("5.8", alpha=-1000.0)
    assert a2["xi_peak"] == pytest.approx(-a1["xi_peak"], rel=1e-14)
    assert a2["xi_lo"] == pytest.approx(-a1["xi_hi"], rel=1e-13)
    assert a2["xi_hi"] == pytest.approx(-a1["xi_lo"], rel=1e-13)


def test_below_critical_force_no_window():
    # g = 37.5 * 0.0009 * ... : f0 = 0.01 gives A_max = 0.025, g = 37.5 * 6.25e-4 / 0.02 = 1.17 < 1.54
    a, n, _ = solve_both("5.8", f0=0.01)
    for v in (a, n):
        assert isinstance(v["xi_lo"], Undefined) and isinstance(v["xi_hi"], Undefined)
    assert a["A_max"] == pytest.approx(0.025, rel=1e-14)
    assert a["xi_peak"] == pytest.approx(37.5 * 0.025**2, rel=1e-14)


# --- harmonic balance: the exact periodic orbits by a different method ---------------------------------
K = np.arange(1, 10, 2)  # odd harmonics
TAU = 2 * np.pi * np.arange(64) / 64
C, S = np.cos(np.outer(TAU, K)), np.sin(np.outer(TAU, K))


def hb_residual(c, omega, p):
    a, b = c[: len(K)], c[len(K):]
    q = C @ a + S @ b
    dq = (-S * K) @ a + (C * K) @ b
    d2q = (-C * K**2) @ a + (-S * K**2) @ b
    r = omega**2 * d2q + 2 * p["delta"] * omega * dq + p["omega0"] ** 2 * q + p["alpha"] * q**3 - p["f0"] * np.cos(TAU)
    return np.concatenate([C.T @ r, S.T @ r]) * (2 / 64) / p["f0"]


def hb_jac(c, omega, p):
    a, b = c[: len(K)], c[len(K):]
    q = C @ a + S @ b
    lin = lambda B, dB, d2B: omega**2 * d2B + 2 * p["delta"] * omega * dB + p["omega0"] ** 2 * B + 3 * p["alpha"] * (q**2)[:, None] * B  # noqa: E731
    Ja = lin(C, -S * K, -C * K**2)
    Jb = lin(S, C * K, -S * K**2)
    J = np.hstack([Ja, Jb])
    return np.vstack([C.T @ J, S.T @ J]) * (2 / 64) / p["f0"]


def hb_swing(c):
    t = np.linspace(0, 2 * np.pi, 20001)
    q = np.cos(np.outer(t, K)) @ c[: len(K)] + np.sin(np.outer(t, K)) @ c[len(K):]
    i, j = np.argmax(q), np.argmin(q)

    def ext(k, sign):  # refine the extremum of the trigonometric polynomial
        f = lambda x: -sign * (np.cos(x * K) @ c[: len(K)] + np.sin(x * K) @ c[len(K):])  # noqa: E731
        r = minimize_scalar(f, bounds=(t[k] - 1e-3, t[k] + 1e-3), method="bounded", options={"xatol": 1e-12})
        return -r.fun * sign

    return 0.5 * (ext(i, 1) - ext(j, -1))


def hb_orbit(omega, p, guess):
    c, info, ier, msg = fsolve(hb_residual, guess, args=(omega, p), fprime=hb_jac, full_output=True, xtol=1e-13)
    assert np.max(np.abs(hb_residual(c, omega, p))) < 1e-11, msg  # converged (ier 3 only says xtol is below eps)
    return c


def hb_peak(p):
    am = p["f0"] / (2 * p["omega0"] * p["delta"])
    w0 = p["omega0"] + 3 * p["alpha"] / (8 * p["omega0"]) * am**2  # a start near the top of the curve
    guess = np.zeros(2 * len(K))
    guess[len(K)] = am  # q ~ A sin(tau): the response lags the drive by 90 degrees at the peak
    state = {"c": hb_orbit(w0, p, guess)}

    def neg_swing(omega):
        state["c"] = hb_orbit(omega, p, state["c"])
        return -hb_swing(state["c"])

    # the exact peak lies a little below the leading-order one (by ~0.05 delta at these parameters), and the
    # resonant branch ends at a fold just beyond it: search a short interval around it
    d = p["delta"]
    r = minimize_scalar(neg_swing, bounds=(w0 - 0.1 * d, w0 + 0.02 * d), method="bounded", options={"xatol": 1e-13})
    assert w0 - 0.099 * d < r.x < w0 + 0.019 * d  # an interior maximum
    return -r.fun, r.x - p["omega0"]


def hb_omega_at_amplitude(R, p, guess):
    """The branch point whose fundamental has amplitude R: unknowns the coefficients and omega."""

    def eqs(x):
        c, om = x[:-1], x[-1]
        return np.concatenate([hb_residual(c, om, p), [(c[0] ** 2 + c[len(K)] ** 2 - R**2) / R**2]])

    def jac(x):
        c, om = x[:-1], x[-1]
        a, b = c[: len(K)], c[len(K):]
        dq = (-S * K) @ a + (C * K) @ b
        d2q = (-C * K**2) @ a + (-S * K**2) @ b
        dr = 2 * om * d2q + 2 * p["delta"] * dq
        col = np.concatenate([C.T @ dr, S.T @ dr]) * (2 / 64) / p["f0"]
        last = np.zeros(len(x))
        last[0], last[len(K)] = 2 * c[0] / R**2, 2 * c[len(K)] / R**2
        return np.vstack([np.hstack([hb_jac(c, om, p), col[:, None]]), last])

    x, info, ier, msg = fsolve(eqs, guess, fprime=jac, full_output=True, xtol=1e-13)
    assert np.max(np.abs(eqs(x))) < 1e-11, msg
    guess[:] = x
    return x[-1]


def hb_fold(p, xi_guess, s_guess):
    """A fold is where omega is extreme along the branch: extremum of omega(R) (a different route from
    the module's det(M - I) = 0 on shot orbits)."""
    am = p["f0"] / (2 * p["omega0"] * p["delta"])
    om = p["omega0"] + xi_guess
    y = xi_guess - 3 * p["alpha"] / (8 * p["omega0"]) * am**2 * s_guess  # leading-order guess of the phase
    D, E = -2 * p["omega0"] * y, 2 * p["delta"] * p["omega0"]
    guess = np.zeros(2 * len(K) + 1)
    guess[0], guess[len(K)], guess[-1] = p["f0"] * D / (D * D + E * E), p["f0"] * E / (D * D + E * E), om
    R0 = am * math.sqrt(s_guess)
    # on the hardening side the lower fold is a minimum of omega, the upper one a maximum (mirrored for alpha < 0)
    upper = s_guess > 0.75
    sign = (1.0 if upper else -1.0) * math.copysign(1.0, p["alpha"])
    lo, hi = R0 - 0.05 * am, min(R0 + 0.05 * am, 0.995 * hb_peak(p)[0])  # no branch above the peak's amplitude
    r = minimize_scalar(lambda R: -sign * hb_omega_at_amplitude(R, p, guess), bounds=(lo, hi),
                        method="bounded", options={"xatol": 1e-12})
    assert lo + 1e-3 * am < r.x < hi - 1e-3 * am  # an interior extremum
    return -sign * r.fun - p["omega0"]


@pytest.mark.parametrize("given", [{}, dict(alpha=-1000.0), dict(f0=0.012), dict(omega0=3.0, delta=0.01, alpha=-150.0, f0=0.0024)])
def test_numeric_peak_against_harmonic_balance(given):
    p = {**DEF, **given}
    _, n, _ = solve_both("5.8", **given)
    A, xi = hb_peak(p)
    assert n["A_max"] == pytest.approx(A, rel=1e-8)
    assert n["xi_peak"] == pytest.approx(xi, rel=1e-5)  # the HB maximum is flat: located to ~sqrt(eps)


@pytest.mark.parametrize("given", [{}, dict(alpha=-1000.0), dict(omega0=3.0, delta=0.01, alpha=-150.0, f0=0.0024)])
def test_numeric_folds_against_harmonic_balance(given):
    p = {**DEF, **given}
    a, n, _ = solve_both("5.8", **given)
    # start the augmented Newton from the leading-order fold (s near each root)
    am = p["f0"] / (2 * p["omega0"] * p["delta"])
    g = 3 * p["alpha"] / (8 * p["omega0"]) * am**2 / p["delta"]
    for name in ("xi_lo", "xi_hi"):
        xi0 = a[name]
        # the leading-order s of this fold (roots of s^3 (1 - s) = 1/(4 g^2)), as the start only
        ss = [r.real for r in np.roots([1, -1, 0, 0, 1 / (4 * g * g)]) if abs(r.imag) < 1e-9 and 0 < r.real < 1]
        s0 = min(ss, key=lambda s: abs(p["delta"] * (g * s + 1 / (2 * g * s * s)) - xi0))
        assert n[name] == pytest.approx(hb_fold(p, xi0, s0), rel=1e-7)


def test_leading_order_error_scales_linearly():
    """Shrinking delta/omega0 and |alpha| A^2/omega0^2 together (g = 3 fixed) shrinks every error by the same factor."""
    errs = []
    for eps in (0.016, 0.004):
        om0, am, g = 10.0, 0.04, 3.0
        alpha = eps * om0**2 / am**2
        delta = 3 * alpha / (8 * om0) * am**2 / g
        a, n, _ = solve_both("5.8", omega0=om0, alpha=alpha, delta=delta, f0=2 * om0 * delta * am)
        errs.append({k: abs(n[k] / a[k] - 1) for k in a})
    for k in errs[0]:
        assert errs[0][k] / errs[1][k] == pytest.approx(4.0, rel=0.1)


def test_very_weak_damping_draw_agrees_with_the_reduced_equations():
    """A draw at delta/omega0 = 4e-9 where the plain one-period map (fixed point resolved to rtol/damp)
    stalled.  Its small parameters are delta/omega0 = 4e-9 and |alpha| A_max^2/omega0^2 = 5e-7, so the
    reduced equations hold to ~1e-6 relative: the hand formulas and the folds of rwa_folds."""
    p = dict(omega0=865531.0, delta=0.00342526, alpha=-3.91372e8, f0=183.589)
    _, n, run = solve_both("5.8", **p)
    am = p["f0"] / (2 * p["omega0"] * p["delta"])
    assert n["A_max"] == pytest.approx(am, rel=3e-6)
    assert n["xi_peak"] == pytest.approx(3 * p["alpha"] / (8 * p["omega0"]) * am**2, rel=3e-6)
    lo, hi = rwa_folds(**p)
    assert n["xi_lo"] == pytest.approx(lo, rel=1e-5)
    assert n["xi_hi"] == pytest.approx(hi, rel=1e-5)


def test_half_period_fixed_point_closes_the_full_period():
    """(continuation.OrbitMap's odd mode, which 5.8 used before its harmonic balance.)  At a fixed point of G = -phi_{T/2} (the symmetric orbit), the one-period map closes too, and its
    monodromy matrix is dG^2 (the chain rule through G o G: what OrbitMap.monodromy returns)."""
    from mech.solvers.mechanics.continuation import OrbitMap, solve_on_plane

    def _force(omega0, delta, alpha):
        def force(q, v):
            return -2 * delta * v - omega0**2 * q - alpha * q**3, -omega0**2 - 3 * alpha * q * q, -2 * delta

        return force

    p = DEF
    Q, W = p["f0"] / (2 * p["omega0"] * p["delta"]), p["delta"]
    half = OrbitMap(_force(p["omega0"], p["delta"], p["alpha"]), p["f0"], Q, p["omega0"], W, odd=True)
    whole = OrbitMap(_force(p["omega0"], p["delta"], p["alpha"]), p["f0"], Q, p["omega0"], W)
    bp = solve_on_plane(half, [0.0, 0.0, 2.5], [0.0, 0.0, 1.0], 2.5, rtol=1e-12, tol=1e-12, max_iter=40,
                        monotone=False)
    assert bp is not None and bp.residual < 1e-11
    ev = whole.evaluate(bp.z, 1e-12)
    assert ev.residual < 1e-9
    assert np.allclose(half.monodromy(bp), ev.M, rtol=0, atol=1e-9)
    assert ev.A == pytest.approx(bp.A, rel=1e-9)


# --- issue 41: the batched route, the scalar solve its batch of one ----------------------------------------
def _arrays(rows):
    return {k: np.array([r[k] for r in rows], dtype=float) for k in DEF}


def test_batch_of_many_is_each_variant_alone():
    """numeric_batch over several variants gives each the values of its own scalar solve (the batch of one),
    its own claims and its own undefined folds; a variant that fails (a NaN force: Newton fails) fails alone."""
    from mech.problems import registry

    ex = registry.get("5.8")
    rows = [DEF, {**DEF, "f0": 0.01}, {**DEF, "alpha": -1000.0}, {**DEF, "f0": float("nan")},
            {**DEF, "delta": 0.001, "f0": 0.0008}]
    cols = ex.batched_route.numeric(_arrays(rows), 1e-10, ("A_max", "xi_peak", "xi_lo", "xi_hi"))
    for k, row in enumerate(rows):
        failed = any(np.asarray(m)[k] for m, _ in cols["A_max"].failed)
        if row["f0"] != row["f0"]:
            assert failed and cols["A_max"].reason("failed", k) == "harmonic balance did not converge on the branch"
            continue
        assert not failed
        _, n, run = solve_both("5.8", **{q: v for q, v in row.items() if v != DEF[q]})
        for name, col in cols.items():
            if isinstance(n[name], Undefined):
                assert col.mask("undefined")[k]
            else:
                assert col.value[k] == pytest.approx(n[name], rel=1e-13, abs=1e-15 * row["delta"])
                assert np.broadcast_to(col.rel, (len(rows),))[k] == pytest.approx(run.claims[name][0])


def test_sweep_near_the_old_symmetry_failure_agrees_at_every_point():
    """Issue 41, item 5: 4 of these 120 points failed ('near losing its q -> -q symmetry')."""
    import mech

    res = mech.sweep("5.8", f0=(0.013, 0.025, 120))
    assert res.agree is True
    assert res.batched is not None  # the batched route


def test_a_sweep_across_the_critical_force_marks_the_undecided_point():
    """Issue 41, item 2: `mech sweep 5.8 --f0 0.004:0.025:12` exited 2 for the whole sweep, its point f0 =
    0.0116364 m/s^2 lying within 3 (eps + delta/omega0) of the leading-order critical force 0.0114621 m/s^2
    (g_c = 8/3^1.5 at f0_c = 0.016 sqrt(g_c/3)).  Now that point's folds are outside the theory's range
    (marked, not compared), its A_max and xi_peak judged, and every other point swept as before."""
    import mech
    from mech.verification.judge import Verdict

    f0_c = 0.016 * math.sqrt(8 / 3**1.5 / 3.0)
    assert round(f0_c, 7) == 0.0114621
    res = mech.sweep("5.8", f0=(0.004, 0.025, 12))
    assert res.agree is True
    k = 4
    pt = res.points[k]
    assert pt.params["f0"] == pytest.approx(0.004 + 4 * 0.021 / 11)
    assert pt["xi_lo"].verdict is Verdict.OUTSIDE and pt["xi_hi"].verdict is Verdict.OUTSIDE
    assert pt["A_max"].verdict is Verdict.AGREE and pt["xi_peak"].verdict is Verdict.AGREE
    marked = [i for i, q in enumerate(res.points) if q["xi_lo"].verdict is Verdict.OUTSIDE]
    assert marked == [k]

"""5.8's reported outputs are those of shot periodic orbits: checked on orbits integrated here by scipy.

The numeric solve reports, for the peak and each fold, the orbit it shot: its state (q, dq/dt) at t = 0 and
the drive's omega (``run.info["orbits"]``).  Here each is integrated over one drive period 2 pi/omega of
q'' + 2 delta q' + omega0^2 q + alpha q^3 = f0 cos(omega t) by scipy's DOP853 (rtol 1e-12) with its own
variational equations (the monodromy matrix M), in SI units, without the solver's scaling or code:

* every orbit closes: Phi_T(y) = y;
* at a fold, det(M - I) = 0: small against the size it has on the branch a little away from the fold,
  where M - I is of order 4 pi delta/omega (measured here on the orbit closed by Newton at omega -+ 1e-3
  of the window's width inside it);
* at the peak, A_max is half the peak-to-peak swing of the orbit (its extremes from the dense output,
  refined by a bounded search), and the reported omega is the swing's maximum along the branch: orbits
  closed by Newton at omega -+ h (h 1e-3 of the curve's smallest scale) have smaller swings, and the
  parabola through the three peaks within xi_peak's claimed error of omega;
* Liouville: det M = exp(-2 delta T).
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

from conftest import claimed_error, solve_both
from mech.problems import registry

CASES = {
    "defaults": dict(omega0=10.0, delta=0.02, alpha=1000.0, f0=0.016),
    "softening": dict(omega0=10.0, delta=0.02, alpha=-1000.0, f0=0.016),
    "Q5000": dict(omega0=10.0, delta=0.001, alpha=1000.0, f0=0.0008),
}


def _period(p, omega, y0, dense=False):
    o2, d2, al, f0 = p["omega0"] ** 2, 2.0 * p["delta"], p["alpha"], p["f0"]

    def rhs(t, y):
        q, v = y[0], y[1]
        k = -o2 - 3.0 * al * q * q
        return [v, -d2 * v - o2 * q - al * q ** 3 + f0 * math.cos(omega * t),
                y[4], y[5], k * y[2] - d2 * y[4], k * y[3] - d2 * y[5]]

    s = solve_ivp(rhs, (0.0, 2.0 * math.pi / omega), [y0[0], y0[1], 1.0, 0.0, 0.0, 1.0], method="DOP853",
                  rtol=1e-12, atol=1e-16, dense_output=dense)
    end = s.y[:, -1]
    return end[:2], np.array([[end[2], end[3]], [end[4], end[5]]]), s


def _closed(p, omega, y0):
    y = np.array(y0, dtype=float)
    for _ in range(20):
        end, M, _ = _period(p, omega, y)
        dy = np.linalg.solve(M - np.eye(2), y - end)
        y = y + dy
        size = abs(y[0]) + abs(y[1]) / omega  # q and q'/omega: both of the swing's size
        if abs(dy[0]) <= 1e-10 * size and abs(dy[1]) <= 1e-10 * omega * size:
            return y
    raise AssertionError("Newton did not close the orbit")


def _swing(p, omega, y0):
    *_, s = _period(p, omega, y0, dense=True)
    T = 2.0 * math.pi / omega
    t = np.linspace(0.0, T, 2001)
    q = s.sol(t)[0]
    ext = []
    for i, sign in ((int(np.argmax(q)), -1.0), (int(np.argmin(q)), 1.0)):
        lo, hi = t[max(i - 1, 0)], t[min(i + 1, t.size - 1)]
        r = minimize_scalar(lambda x: sign * s.sol(x)[0], bounds=(lo, hi), method="bounded",
                            options={"xatol": 1e-12 * T})
        ext.append(s.sol(r.x)[0])
    return 0.5 * (ext[0] - ext[1])


@pytest.fixture(scope="module", params=sorted(CASES))
def solved(request):
    p = CASES[request.param]
    _, num, run = solve_both("5.8", **p)
    return p, num, run


def test_every_reported_output_has_its_orbit(solved):
    p, num, run = solved
    orbits = run.info["orbits"]
    assert orbits["A_max"][2] == pytest.approx(p["omega0"] + num["xi_peak"], rel=1e-15)
    for name in ("xi_lo", "xi_hi"):
        assert orbits[name][2] == pytest.approx(p["omega0"] + num[name], rel=1e-15)


def test_the_orbits_close_and_keep_liouville(solved):
    p, num, run = solved
    for name, (q0, v0, omega) in run.info["orbits"].items():
        end, M, _ = _period(p, omega, (q0, v0))
        scale = num["A_max"]
        assert abs(end[0] - q0) <= 1e-8 * scale and abs(end[1] - v0) <= 1e-8 * scale * omega, name
        assert np.linalg.det(M) == pytest.approx(math.exp(-2.0 * p["delta"] * 2.0 * math.pi / omega), rel=1e-10)
    assert run.info["liouville"] < 1e-10


def test_folds_are_where_det_M_minus_I_vanishes(solved):
    p, num, run = solved
    width = num["xi_hi"] - num["xi_lo"]
    for name, inward in (("xi_lo", 1.0), ("xi_hi", -1.0)):
        q0, v0, omega = run.info["orbits"][name]
        _, M, _ = _period(p, omega, (q0, v0))
        at = abs(np.linalg.det(M - np.eye(2)))
        # the same branch a little inside the window: Newton from the fold's orbit
        w_in = omega + inward * 1e-3 * width
        _, M_in, _ = _period(p, w_in, _closed(p, w_in, (q0, v0)))
        away = abs(np.linalg.det(M_in - np.eye(2)))
        assert away > 0.0
        assert at <= 1e-4 * away, (name, at, away)


def test_peak_is_half_the_swing_and_the_swing_is_largest_there(solved):
    p, num, run = solved
    q0, v0, omega = run.info["orbits"]["A_max"]
    A = _swing(p, omega, (q0, v0))
    assert num["A_max"] == pytest.approx(A, rel=1e-9)
    # h well inside the curve's smallest scale (at Q = 5000 the upper fold lies 4e-6 rad/s beyond the peak): the
    # parabola's own bias, about h^2 A3/(6 A2) with A2, A3 the swing's 2nd and 3rd derivatives, stays below 1e-3 h
    h = 1e-3 * min(p["delta"], abs(num["xi_hi"] - num["xi_peak"]), abs(num["xi_peak"] - num["xi_lo"]))
    A_dn = _swing(p, omega - h, _closed(p, omega - h, (q0, v0)))
    A_up = _swing(p, omega + h, _closed(p, omega + h, (q0, v0)))
    assert A_dn < A and A_up < A
    vertex = 0.5 * h * (A_dn - A_up) / (A_dn - 2.0 * A + A_up)  # the parabola's vertex from omega
    assert abs(vertex) <= claimed_error(registry.get("5.8"), run, "xi_peak", num["xi_peak"]), vertex


def test_a_variant_whose_shooting_does_not_converge_fails_alone(monkeypatch):
    """Shooting's Newton reported unconverged for the first variant's folds (the others' untouched): that variant
    fails, saying so, and the other keeps its values; the scalar solve raises with the same reason."""
    import mech.solvers.mechanics.duffing_shooting as shooting
    from mech.problems.spec import NumericFailure

    real = shooting.shoot_folds

    def first_fails(*args, idx, **kw):
        w, y, ok = real(*args, idx=idx, **kw)
        return w, y, ok & (idx != 0)

    monkeypatch.setattr(shooting, "shoot_folds", first_fails)
    ex = registry.get("5.8")
    rows = [CASES["defaults"], CASES["softening"]]
    P = {k: np.array([r[k] for r in rows]) for k in rows[0]}
    cols = ex.batched_route.numeric(P, 1e-10, ("A_max", "xi_peak", "xi_lo", "xi_hi"))
    for name, col in cols.items():
        assert list(col.mask("failed")) == [True, False], name
        assert "shooting's Newton did not converge" in col.reason("failed", 0)
    monkeypatch.setattr(shooting, "shoot_folds", real)
    _, alone, _ = solve_both("5.8", **CASES["softening"])
    assert cols["xi_lo"].value[1] == pytest.approx(alone["xi_lo"], rel=1e-8)
    monkeypatch.setattr(shooting, "shoot_folds", first_fails)
    with pytest.raises(NumericFailure, match="shooting's Newton did not converge"):
        solve_both("5.8", **CASES["defaults"])


def test_second_order_variational_equations_against_differences():
    """dM/dx0, dM/dv0 and dM/dw integrated by duffing_shooting (for the folds' Newton) equal central differences
    of its M, and its M and y_w equal central differences of the end state (steps 1e-5: errors ~1e-9)."""
    from mech.solvers.mechanics import duffing_shooting as S

    d, g, w, y0 = np.array([0.01]), np.array([3.0]), np.array([2.5]), np.array([[0.3], [0.9]])
    shots = S.Shots(1)

    def run(y, ww):
        Y = S._flow(d, g, ww, S._start(y, True), 0.0, 2.0 * math.pi, np.array([1e-13]), shots, True)
        return Y, *S._monodromy(Y)

    Y, M, yw, end = run(y0, w)
    h = 1e-5
    for j, (dy, dw) in enumerate((([h, 0.0], 0.0), ([0.0, h], 0.0), ([0.0, 0.0], h))):
        step = np.array(dy)[:, None]
        _, Mp, _, ep = run(y0 + step, w + dw)
        _, Mm, _, em = run(y0 - step, w - dw)
        dM = np.array([[Y[4 + 2 * j], Y[5 + 2 * j]], [Y[14 + 2 * j], Y[15 + 2 * j]]])
        assert np.allclose(dM, (Mp - Mm) / (2 * h), rtol=1e-6, atol=1e-7), j
        first = M[:, j] if j < 2 else yw
        assert np.allclose(first, (ep - em) / (2 * h), rtol=1e-6, atol=1e-7), j

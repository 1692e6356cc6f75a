"""5.4's numeric route written once over arrays of variants (issue 41).

References by hand, evaluated in mpmath at 40 digits (not the module's log form): from rest at x = q/q0 = 1,
tau = omega0 t, x = (l2 e^{-l1 tau} - l1 e^{-l2 tau})/(l2 - l1), l1,2 = zeta -+ (zeta^2 - 1)^(1/2)
((1 + tau) e^{-tau} at zeta = 1); x' = l1 l2 (e^{-l2 tau} - e^{-l1 tau})/(l2 - l1) (-tau e^{-tau}), largest
in size at tau* = ln(l2/l1)/(l2 - l1) (1); t_eps the root of x = eps found by mpmath's bisection.
"""


import mpmath
import numpy as np

from mech.problems import registry

OUTS = ("lambda_slow", "q_t", "t_eps", "v_max")

# zeta <= 5 by DOP853 together, beyond by the exact flow: critical, mild, near the switch on both sides, stiff;
# t1 = 0 (no first leg), t1 past t_eps (one leg), t1 of 1e5 decay times (the first leg settles), eps near 1
POINTS = [
    dict(zeta=1.0),
    dict(zeta=1.5, omega0=0.3, q0=2.0, t1=7.0, eps=0.2),
    dict(zeta=2.0, t1=0.0),
    dict(zeta=3.0, t1=20.0, eps=0.05),
    dict(zeta=4.9, eps=1e-6),
    dict(zeta=2.0, eps=0.999999999999),
    dict(omega0=0.484781, zeta=3.69078, q0=5095.95, t1=521341.0, eps=1.74208e-05),
    dict(zeta=5.5, t1=0.0),
    dict(zeta=40.0, t1=3.0, eps=1e-3),
    dict(zeta=1e4, eps=1e-12),
]


def route_at(points, rtol=None, tally=None):
    ex = registry.get("5.4")
    full = [dict(ex.resolve(p)) for p in points]
    P = {k: np.array([q[k] for q in full]) for k in full[0]}
    return ex.batched_route.numeric(P, rtol or ex.default_rtol, OUTS, tally=tally), full


def reference(omega0, zeta, q0, t1, eps):
    """(lambda_slow, q(t1), t_eps, v_max) from the two exponentials in mpmath."""
    mp = mpmath.mp
    mp.dps = 40
    w0, z, q0, eps = (mpmath.mpf(v) for v in (omega0, zeta, q0, eps))
    if z == 1:
        x = lambda tau: (1 + tau) * mpmath.exp(-tau)  # noqa: E731
        l1, tau_star, v = mpmath.mpf(1), mpmath.mpf(1), lambda tau: -tau * mpmath.exp(-tau)  # noqa: E731
    else:
        s = mpmath.sqrt(z * z - 1)
        l1, l2 = z - s, z + s
        x = lambda tau: (l2 * mpmath.exp(-l1 * tau) - l1 * mpmath.exp(-l2 * tau)) / (l2 - l1)  # noqa: E731
        v = lambda tau: l1 * l2 * (mpmath.exp(-l2 * tau) - mpmath.exp(-l1 * tau)) / (l2 - l1)  # noqa: E731
        tau_star = mpmath.log(l2 / l1) / (l2 - l1)
    hi = 1 / l1
    while x(hi) > eps:
        hi *= 2
    tau_eps = mpmath.findroot(lambda tau: x(tau) - eps, (mpmath.mpf(0), hi), solver="bisect")
    return (float(w0 * l1), float(q0 * x(w0 * mpmath.mpf(t1))), float(tau_eps / w0),
            float(q0 * w0 * abs(v(tau_star))))


def within_claim(col, k, value, want):
    rel = float(np.broadcast_to(col.rel, col.value.shape)[k])
    ab = float(np.broadcast_to(col.abs, col.value.shape)[k])
    return abs(value - want) <= rel * abs(want) + ab


def test_batch_against_the_two_exponentials_in_mpmath():
    cols, full = route_at(POINTS)
    for k, p in enumerate(full):
        want = reference(p["omega0"], p["zeta"], p["q0"], p["t1"], p["eps"])
        for name, w in zip(OUTS, want):
            col = cols[name]
            assert not col.mask("failed")[k], (k, name, col.reason("failed", k))
            assert within_claim(col, k, float(col.value[k]), w), (k, name, float(col.value[k]), w)


def test_each_variant_equals_its_batch_of_one_within_the_claims():
    cols, full = route_at(POINTS)
    for k, p in enumerate(POINTS):
        one, _ = route_at([p])
        for name in OUTS:
            a, b = float(cols[name].value[k]), float(one[name].value[0])
            assert within_claim(cols[name], k, a, b) and within_claim(one[name], 0, b, a), (k, name, a, b)


def test_a_variant_whose_integration_fails_fails_alone(monkeypatch):
    """The middle variant's right-hand side turns non-finite midway (poisoned on its own zeta): it fails with
    its reason, the others keep the values of their batch of one."""
    from mech.problems.ch5 import ex5_4_overdamped_relaxation as mod

    real = mod._equations

    def poisoned(z, y):
        out = real(z, y)
        bad = np.abs(np.asarray(z) - 2.5) < 1e-12
        return np.where(bad & (np.abs(y[0]) < 0.5), np.nan, out)

    monkeypatch.setattr(mod, "_equations", poisoned)
    pts = [dict(zeta=1.5), dict(zeta=2.5), dict(zeta=3.5), dict(zeta=8.0)]
    cols, _ = route_at(pts)
    for name in OUTS:
        assert cols[name].mask("failed").tolist() == [False, True, False, False], name
    assert cols["t_eps"].reason("failed", 1)
    monkeypatch.setattr(mod, "_equations", real)
    for k in (0, 2, 3):
        one, _ = route_at([pts[k]])
        for name in OUTS:
            assert within_claim(one[name], 0, float(cols[name].value[k]), float(one[name].value[0])), (k, name)


def test_a_flow_variant_that_fails_fails_alone(monkeypatch):
    from mech.core.errors import NumericFailure
    from mech.problems.ch5 import ex5_4_overdamped_relaxation as mod

    real = mod._flow_chain

    def failing(A, z, *args):
        if z == 9.0:
            raise NumericFailure("the flow's state vanished along the chain")
        return real(A, z, *args)

    monkeypatch.setattr(mod, "_flow_chain", failing)
    cols, _ = route_at([dict(zeta=6.0), dict(zeta=9.0), dict(zeta=2.0)])
    assert cols["q_t"].mask("failed").tolist() == [False, True, False]
    assert cols["q_t"].reason("failed", 1) == "the flow's state vanished along the chain"
    assert np.all(np.isfinite(cols["t_eps"].value[[0, 2]]))


def test_the_one_point_solve_reports_the_batch_of_one():
    """A one-point solve is the route over arrays of one: the same values, its method and invariant."""
    from mech.problems.spec import Run

    ex = registry.get("5.4")
    for given, method, inv in (({"zeta": 2.0}, "DOP853", "E + dissipated work"),
                               ({"zeta": 40.0}, "exact flow", "semigroup Phi(a) Phi(b) = Phi(a + b)")):
        p = ex.resolve(given)
        run = Run(rtol=ex.default_rtol)
        vals = ex.numeric_solver(p, run)
        cols, _ = route_at([given])
        assert all(vals[n] == float(cols[n].value[0]) for n in OUTS)
        assert run.method.startswith(method) and run.invariants[inv] < 1e-9

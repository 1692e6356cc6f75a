"""``ensemble_search.brent_minimum``: Brent's bounded minimizer on arrays of N functions.

Each point takes the same steps as a one-point Brent search would (``roots.minimize_bounded``, the
same rules written for one float), so both land on the same x; the minima themselves are checked against
where they are known by hand (a shifted cosine's, a quartic's)."""

import math

import numpy as np
import pytest

from mech.solvers.numerics.ensemble_search import brent_minimum
from mech.solvers.numerics.roots import minimize_bounded


def _funcs():
    # (function of x and a shift c, where its minimum on [a, b] lies by hand)
    return [
        (lambda x, c: (x - c) ** 2 * (1 + 0.3 * (x - c)), lambda c, a, b: c),  # a cubic term: not a parabola
        (lambda x, c: -np.cos(x - c), lambda c, a, b: c),
        (lambda x, c: (x - c) ** 4 + 0.1 * x, lambda c, a, b: c - (0.1 / 4) ** (1 / 3)),
        (lambda x, c: x + 0 * c, lambda c, a, b: a),  # the minimum at the bracket's end
    ]


@pytest.mark.parametrize("k", range(4))
def test_every_point_lands_where_its_one_point_search_does(k):
    fn, where = _funcs()[k]
    c = np.array([0.1, -0.4, 0.77, 0.0, 0.3])
    a = np.array([-1.0, -2.0, 0.0, -0.5, -1.0])
    b = np.array([1.0, 1.0, 2.0, 0.5, 0.35])
    calls = []

    def f(x, idx):
        calls.append(idx.size)
        return fn(x, c[idx])

    x, fx, ok = brent_minimum(f, a, b, xatol=1e-9)
    assert ok.all()
    for j in range(c.size):
        xs, fs, _ = minimize_bounded(lambda t: float(fn(np.float64(t), c[j])), a[j], b[j], xatol=1e-9)
        assert x[j] == xs and fx[j] == fs
        assert x[j] == pytest.approx(min(max(where(c[j], a[j], b[j]), a[j]), b[j]), abs=1e-7)
    assert max(calls) == c.size and min(calls) < c.size  # points that are done are no longer evaluated


def test_a_start_inside_the_bracket_and_a_point_not_converged():
    c = np.array([0.25, 2.0])
    x, fx, ok = brent_minimum(lambda x, idx: (x - c[idx]) ** 2, np.zeros(2), np.full(2, 4.0), xatol=1e-10,
                              x0=c + 0.01)
    assert ok.all() and x == pytest.approx(c, abs=1e-9)
    x, fx, ok = brent_minimum(lambda x, idx: (x - c[idx]) ** 2, np.zeros(2), np.full(2, 4.0), xatol=1e-12,
                              max_iter=2)
    assert not ok.any()


def test_integrate_variants_fails_a_variant_alone():
    """y' = c y^2 from y = 1: y = 1/(1 - c t), which blows up at t = 1/c.  Over [0, 2] the variant c = 1 cannot
    be integrated (its step underflows before t = 1); the others keep their values, in one chunk or in chunks
    by work, and every integration is recorded."""
    from mech.solvers.numerics.ensemble_search import integrate_variants

    def system(c):
        return lambda t, y: c * y * y

    c = np.array([0.1, 1.0, -0.5, 0.3])
    for work in (None, 1.0 / (2.0 - np.minimum(c, 1.0))):
        seen = []
        y, why, t_stop = integrate_variants(system, (c,), (0.0, 2.0), np.ones((1, 4)), rtol=1e-10, atol=1e-13,
                                            work=work, record=seen.append)
        ok = np.array([True, False, True, True])
        assert np.allclose(y[0, ok], 1.0 / (1.0 - 2.0 * c[ok]), rtol=1e-8, atol=0)
        assert np.isnan(y[0, 1]) and why[1] and all(w == "" for w in why[ok])
        assert seen


@pytest.mark.parametrize("integrator", [None, "DOP853"])
def test_integrate_variants_stops_each_variant_at_its_event(integrator):
    """x'' = -k^2 x from (1, 0): x' = -k sin(k t) first crosses zero upward at t = pi/k (a minimum, x = -1);
    a variant whose minimum lies beyond the span has no stop time and its state at the span's end."""
    from mech.solvers.numerics.ensemble_search import integrate_variants

    def system(k):
        return lambda t, y: np.array([y[1], -k * k * y[0]])

    k = np.array([1.0, 2.0, 0.5, 3.0])
    y0 = np.array([[1.0] * 4, [0.0] * 4])
    y, why, t_stop = integrate_variants(system, (k,), (0.0, 5.0), y0, rtol=1e-11, atol=1e-14,
                                        event=(lambda t, y: y[1], 1.0), integrator=integrator)
    assert all(w == "" for w in why)
    hit = np.pi / k < 5.0
    assert t_stop[hit] == pytest.approx(np.pi / k[hit], rel=1e-10)
    assert y[0, hit] == pytest.approx(-1.0, abs=1e-10)
    assert np.isnan(t_stop[~hit]).all() and y[0, ~hit] == pytest.approx(np.cos(5.0 * k[~hit]), abs=1e-9)


def test_integrate_variants_a_spent_work_budget_stops_the_call():
    """The work budget is the call's, never one variant's verdict: variants integrated alone (y' = -y: e^-1)
    run within four times one variant's work, and a budget of 2.5 variants' stops the call (OutOfWork)
    rather than failing the two it did not reach."""
    from mech.core import budget
    from mech.solvers.numerics.ensemble_search import integrate_variants

    def system(k):
        return lambda t, y: -k * y

    k = np.ones(4)
    with budget.limit(work=1e12):
        start = budget.used()
        integrate_variants(system, (k[:1],), (0.0, 1.0), np.ones((1, 1)), rtol=1e-12, atol=1e-15,
                           options=lambda k: {})
        one = budget.used() - start
    with budget.limit(work=4.5 * one):
        y, why, _ = integrate_variants(system, (k,), (0.0, 1.0), np.ones((1, 4)), rtol=1e-12, atol=1e-15,
                                       options=lambda k: {})
    assert y[0] == pytest.approx(np.exp(-1.0), rel=1e-10) and not any(why)
    with budget.limit(work=2.5 * one), pytest.raises(budget.OutOfWork):
        integrate_variants(system, (k,), (0.0, 1.0), np.ones((1, 4)), rtol=1e-12, atol=1e-15,
                           options=lambda k: {})


def _roots():
    # (function of x and a parameter c, its root by hand, bracket)
    return [
        (lambda x, c: x**3 - c, lambda c: c ** (1 / 3), (0.0, 5.0)),
        (lambda x, c: np.exp(x) - c, lambda c: math.log(c), (-3.0, 4.0)),
        (lambda x, c: c * np.cos(x) - x, None, (0.0, 1.5)),  # c = 1: the Dottie number 0.7390851332151607
        (lambda x, c: np.arctan(200.0 * (x - c / 10)), lambda c: c / 10, (-1.0, 2.0)),  # a step: the safeguard
    ]


@pytest.mark.parametrize("k", range(4))
@pytest.mark.parametrize("interior", [False, True])
def test_interpolated_root_lands_on_the_root_at_a_point_it_evaluated(k, interior):
    from mech.solvers.numerics.ensemble_search import interpolated_root

    fn, root, (lo, hi) = _roots()[k]
    c = np.array([1.5, 2.0, 7.0, 3.0, 0.5]) if root is not None else np.ones(5)  # roots away from 0 (rtol |x|)
    seen = [set() for _ in c]
    rounds = []

    def f(x, idx):
        rounds.append(idx.size)
        for j, xj in zip(idx, x):
            seen[j].add(float(xj))
        return fn(x, c[idx])

    a, b = np.full(c.size, lo), np.full(c.size, hi)
    x0 = 0.5 * (a + b) if interior else None
    x, ok = interpolated_root(f, a, b, fn(a, c), fn(b, c), x0, None if x0 is None else fn(x0, c), rtol=1e-12)
    want = np.array([root(cj) for cj in c]) if root is not None else np.full(c.size, 0.7390851332151607)
    assert ok.all()
    assert x == pytest.approx(want, rel=1e-11, abs=1e-13)
    for j in range(c.size):  # the root is a point evaluated (or a bracket end or x0 given), never extrapolated
        assert float(x[j]) in seen[j] | {lo, hi} | ({float(x0[j])} if interior else set())
    assert len(rounds) <= (40 if k == 3 else 12)


def test_interpolated_root_stops_at_an_exact_zero_and_refuses_no_bracket():
    from mech.solvers.numerics.ensemble_search import interpolated_root

    x, ok = interpolated_root(lambda x, idx: x - 0.25, np.zeros(1), np.ones(1), np.array([-0.25]), np.array([0.75]),
                              np.array([0.25]), np.array([0.0]), rtol=1e-12)
    assert ok.all() and x[0] == 0.25
    with pytest.raises(ValueError):
        interpolated_root(lambda x, idx: x, np.ones(1), np.full(1, 2.0), np.ones(1), np.full(1, 2.0), rtol=1e-12)
    # a point not converged in max_iter rounds is left so
    x, ok = interpolated_root(lambda x, idx: np.arctan(200.0 * (x - 0.3)), np.full(1, -1.0), np.full(1, 2.0),
                              np.arctan(200.0 * np.array([-1.3])), np.arctan(200.0 * np.array([1.7])), rtol=1e-14,
                              max_iter=2)
    assert not ok.any()


def test_integrate_variants_alone_with_a_stiff_method_to_an_event():
    """Variants each alone with ``options`` (LSODA and its Jacobian) up to a terminal event: each variant's end
    state and event time are solve_ivp's with that event, bit for bit; a variant whose right-hand side fails
    fails alone with its reason.  y' = -c (y - cos t): y follows cos t, crossing y = 0.5 downward near t = pi/3."""
    from scipy.integrate import solve_ivp

    from mech.core.errors import NumericFailure
    from mech.solvers.numerics.ensemble_search import integrate_variants

    c = np.array([10.0, 1e4, -1.0, 300.0])

    def system(k):
        def rhs(t, y):
            if k < 0:
                raise NumericFailure("no such variant")
            return [-k * (y[0] - math.cos(t))]

        return rhs

    opts = lambda k: {"method": "LSODA", "jac": lambda t, y: [[-k]]}  # noqa: E731
    g = lambda t, y: y[0] - 0.5  # noqa: E731
    y, why, t_stop = integrate_variants(system, (c,), (0.0, 3.0), np.ones((1, c.size)), rtol=1e-10, atol=1e-13,
                                        event=(g, -1.0), options=opts)
    assert why[2] == "no such variant" and np.isnan(y[0, 2]) and np.isnan(t_stop[2])
    for j in (0, 1, 3):
        ev = lambda t, y: g(t, y)  # noqa: E731
        ev.terminal, ev.direction = True, -1.0
        ref = solve_ivp(system(c[j]), (0.0, 3.0), [1.0], method="LSODA", jac=opts(c[j])["jac"], rtol=1e-10,
                        atol=1e-13, events=[ev])
        assert why[j] == "" and t_stop[j] == ref.t_events[0][0] and y[0, j] == ref.y[0, -1]
        assert t_stop[j] == pytest.approx(math.pi / 3, abs=2.0 / c[j])  # y lags cos t by ~sin t / c

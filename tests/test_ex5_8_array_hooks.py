"""5.8's array hooks (``analytic``, ``expected_error``, ``theory_range``) over N variants at once equal the
scalar functions they replaced (frozen in tests/ex5_8_scalar_ref.py) to 1e-12 relative, variant by variant:
at ~200 drawn points, the defaults, the hard cases and a few edge points (alpha = 0, softening, near the cusp,
no bistability)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import ex5_8_scalar_ref as ref
from mech.problems import registry
from mech.problems.params import Params

NAMES = ("A_max", "xi_peak", "xi_lo", "xi_hi")


def _points():
    from mech.students.assign import ranges_for
    from mech.students.points import draw

    ex = registry.get("5.8")
    pts = [dict(p) for p in draw(ex, 200, 20261207, ranges_for(ex, {}))]
    pts.append(dict(ex.resolve({})))
    pts += [dict(ex.resolve(h["params"])) for h in ex.hard_cases]
    base = dict(ex.resolve({}))
    g = ref._g(Params(base))
    for extra in ({"alpha": 0.0}, {"alpha": -base["alpha"]}, {"f0": base["f0"] * math.sqrt(1.001 * ref.G_CRIT / abs(g))},
                  {"f0": base["f0"] * math.sqrt(0.5 * ref.G_CRIT / abs(g))},
                  {"f0": base["f0"] * math.sqrt(1.05 * ref.G_CRIT / abs(g))}):
        pts.append({**base, **extra})
    return ex, pts


def _close(a, b):
    return abs(a - b) <= 1e-12 * abs(b)


@pytest.fixture(scope="module")
def case():
    ex, pts = _points()
    P = {k: np.array([p[k] for p in pts]) for k in pts[0]}
    return ex, pts, P


def test_analytic_over_arrays_equals_the_scalar_one(case):
    ex, pts, P = case
    mod = ex.module if hasattr(ex, "module") else None
    from mech.problems.ch5 import ex5_8_duffing_resonance as m

    cols = m.analytic(P)
    undefined = 0
    for k, p in enumerate(pts):
        want = ref._analytic_at(Params(p))
        for name in NAMES:
            col = cols[name]
            masks = [(mask[k], why) for mask, why in col.undefined if mask[k]]
            if isinstance(want[name], ref.Undefined):
                undefined += 1
                assert len(masks) == 1 and masks[0][1] == want[name].why, (k, name)
            else:
                assert not masks, (k, name)
                assert _close(float(col.value[k]), want[name]), (k, name, float(col.value[k]), want[name])
    assert 0 < undefined < 2 * len(pts)  # both kinds of variant are among the points


def test_expected_error_over_arrays_equals_the_scalar_one(case):
    ex, pts, P = case
    from mech.problems.ch5 import ex5_8_duffing_resonance as m

    got = m.expected_error(P)
    kinds = set()
    for k, p in enumerate(pts):
        want = ref._expected_at(Params(p))
        for name in NAMES:
            rel, ab = (float(got[name][0][k]), float(got[name][1][k]))
            if name not in want:
                assert math.isnan(rel) and math.isnan(ab), (k, name)
                continue
            w = want[name]
            w_rel, w_abs = w if isinstance(w, tuple) else (w, None)
            kinds.add((w_rel is None, w_abs is None))
            # 2 |b/a - 1| + floor carries the old folds' rounding (the old t-root's 3/4 + t cancels: up to 2.2e-14
            # of a, against mpmath; test_folds_against_mpmath): 1e-13 relative of a allowed there
            lead, nx = ref._analytic_at(Params(p))[name], ref._harmonic_balance(Params(p))[name]
            slack = 2e-13 * abs(nx / lead) if name in ("xi_lo", "xi_hi") and nx is not None else 0.0
            assert math.isnan(rel) if w_rel is None else abs(rel - w_rel) <= 1e-12 * w_rel + slack, (k, name, rel, w_rel)
            assert math.isnan(ab) if w_abs is None else _close(ab, w_abs), (k, name, ab, w_abs)
    assert kinds == {(False, True), (True, False)}  # relative allowances and alpha = 0's absolute one


def test_theory_range_over_arrays_equals_the_scalar_one(case):
    ex, pts, P = case
    from mech.problems.ch5 import ex5_8_duffing_resonance as m

    got = m.theory_range(P)
    cusp = 0
    for k, p in enumerate(pts):
        want = ref._range_at(Params(p))
        for name in NAMES:
            label, value = got[name][0][k], float(got[name][1][k])
            assert label == want[name][0], (k, name)
            assert value == want[name][1] or _close(value, want[name][1]), (k, name)
            cusp += label.startswith("3 (eps")
    assert cusp > 0


@pytest.mark.parametrize("g", [1.0001 * ref.G_CRIT, -1.01 * ref.G_CRIT, 1.6, 1.99, 2.0, -2.01, 3.0, 10.0, 28.2847, -37.5, 100.0])
def test_folds_against_mpmath(g):
    """The quartic's roots s^3 (1 - s) = 1/(4 g^2) and the folds' detunings g s + 1/(2 g s^2) (over delta)
    against mpmath at 50 digits: to a few ulps (the old t-root left up to 2e-14 in the lower fold)."""
    import mpmath as mp

    from mech.problems.ch5 import ex5_8_duffing_resonance as m

    mp.mp.dps = 50
    s = m._folds(np.array([g]))[:, 0]
    c = 1 / (4 * mp.mpf(g) ** 2)
    for got, (lo, hi) in zip(s, ((mp.mpf(0), mp.mpf("0.75")), (mp.mpf("0.75"), mp.mpf(1)))):
        up = lo**3 * (1 - lo) < c  # bisection at 50 digits
        for _ in range(180):
            mid = (lo + hi) / 2
            lo, hi = (mid, hi) if (mid**3 * (1 - mid) < c) == up else (lo, mid)
        exact = (lo + hi) / 2
        # within 1e-4 of the cusp, 27/256 - 1/(4 g^2)'s rounding moves the nearly double roots by ~1e-15
        assert abs(got - exact) <= (4e-16 if abs(g) > 1.6 else 4e-15) * exact
        xi, xi_exact = g * got + 1 / (2 * g * got * got), mp.mpf(g) * exact + 1 / (2 * mp.mpf(g) * exact**2)
        assert abs(xi - xi_exact) <= 1e-15 * abs(xi_exact)


def test_no_folds_below_the_critical_g():
    from mech.problems.ch5 import ex5_8_duffing_resonance as m

    assert np.isnan(m._folds(np.array([0.999 * ref.G_CRIT, -1.5, 0.0]))).all()

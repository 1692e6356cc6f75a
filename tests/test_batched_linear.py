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

"""5.5 against values worked out independently of the module.

Hand derivation:
  * Free motion from rest at q = 1: q = Re[C e^{lam t}], lam = -delta + i w_d,
    w_d = sqrt(w0^2 - delta^2), C = 1 - i delta/w_d (so q(0) = 1, q'(0) = Re(C lam) = 0).
    E(t)/E(0) = q^2 + (q'/w0)^2, evaluated below with complex arithmetic (the module
    uses the expanded real form).  The loss per cycle is 1 - E(T')/E(0), T' = 2 pi/w_d.
  * Q = w0/(2 delta) by definition.
  * |a|^2 ~ 1/f(x), f(x) = (w0^2 - x)^2 + 4 delta^2 x, x = w^2.  f' = 0 at
    x* = w0^2 - 2 delta^2, f(x*) = 4 delta^2 (w0^2 - delta^2).  The half-power points
    solve f(x) = 2 f(x*); below they are found by bisection in 50-digit Decimal
    arithmetic on that equation (not from the module's closed form); the lower one
    is absent when f(0) = w0^4 <= 2 f(x*).
"""

import cmath
import functools
import math
from decimal import Decimal, getcontext

import pytest

from conftest import solve_both
from mech.problems.spec import Undefined


def free_energy_ratio(w0, d, t):
    wd = math.sqrt(w0 * w0 - d * d)
    lam = complex(-d, wd)
    C = complex(1.0, -d / wd)
    q = (C * cmath.exp(lam * t)).real
    v = (C * lam * cmath.exp(lam * t)).real
    return q * q + (v / w0) ** 2


def half_power_width(w0, d):
    getcontext().prec = 50
    W0, D = Decimal(repr(w0)), Decimal(repr(d))

    def f(x):
        return (W0 * W0 - x) ** 2 + 4 * D * D * x

    xs = W0 * W0 - 2 * D * D
    target = 2 * f(xs)
    if f(Decimal(0)) <= target:
        return None

    def bisect(lo, hi):  # f - target changes sign between lo and hi
        s_lo = f(lo) > target
        for _ in range(200):
            mid = (lo + hi) / 2
            if (f(mid) > target) == s_lo:
                lo = mid
            else:
                hi = mid
        return (lo + hi) / 2

    x_lo = bisect(Decimal(0), xs)
    hi = xs + 1
    while f(hi) <= target:
        hi = 2 * hi
    x_hi = bisect(xs, hi)
    return float(x_hi.sqrt() - x_lo.sqrt())


CASES = [
    # defaults: 440 Hz fork, delta = 1.5/s, t1 = 0.25 s
    (2764.601535159018, 1.5, 0.25),
    # catalogue hard cases: Q = 5e4 read 2000 periods in; Q = 1.43
    (10.0, 1e-4, 1256.637061435917),
    (10.0, 3.5, 0.9),
    # other parameters
    (1.0, 0.2, 7.3),
    (50.0, 0.01, 2.0),
]


@functools.lru_cache(maxsize=None)
def _solved(w0, d, t1):
    """``solve_both`` at one of CASES, once: the batched test reads the same one-point solve."""
    return solve_both("5.5", omega0=w0, delta=d, t1=t1)


@pytest.mark.parametrize("w0, d, t1", CASES)
def test_against_independent_values(w0, d, t1):
    a, n, run = _solved(w0, d, t1)
    wd = math.sqrt(w0 * w0 - d * d)
    loss = 1.0 - free_energy_ratio(w0, d, 2 * math.pi / wd)
    e1 = free_energy_ratio(w0, d, t1)
    width = half_power_width(w0, d)
    for v in (a, n):
        assert v["Q"] == pytest.approx(w0 / (2 * d), rel=1e-9)
        assert v["loss_per_cycle"] == pytest.approx(loss, rel=1e-9)
        # cmath's exp at w_d t ~ 1e4 carries a phase error of ~1e-12
        assert v["E_ratio"] == pytest.approx(e1, rel=1e-9)
        assert v["bandwidth"] == pytest.approx(width, rel=1e-9)
    assert run.invariants["E + dissipated work"] < 1e-9


def test_no_lower_half_power_point_above_sin_pi_over_8():
    # delta = 0.5 w0: f(0) = w0^4 = 1, 2 f(x*) = 8 * 0.25 * 0.75 = 1.5 > 1: no lower point
    assert half_power_width(1.0, 0.5) is None
    a, n, _ = solve_both("5.5", omega0=1.0, delta=0.5, t1=1.0)
    assert isinstance(a["bandwidth"], Undefined) and isinstance(n["bandwidth"], Undefined)
    # the ringdown quantities still exist: loss = 1 - exp(-4 pi (0.5)/sqrt(0.75))
    for v in (a, n):
        assert v["loss_per_cycle"] == pytest.approx(1 - math.exp(-4 * math.pi * 0.5 / math.sqrt(0.75)), rel=1e-9)
        assert v["Q"] == pytest.approx(1.0, rel=1e-9)


def test_high_q_limit_width_is_omega0_over_q():
    # width = 2 delta (1 + O(delta^2/w0^2)) and loss = 2 pi/Q (1 + O(1/Q)) as Q -> infinity
    a, n, _ = solve_both("5.5", omega0=3.0, delta=3e-9, t1=0.0)
    for v in (a, n):
        assert v["bandwidth"] == pytest.approx(6e-9, rel=1e-9)
        assert v["loss_per_cycle"] == pytest.approx(4 * math.pi * 1e-9, rel=1e-8)
        assert v["E_ratio"] == pytest.approx(1.0, rel=1e-12)


def test_the_declared_ringdown_alone_is_a_damped_cosine_over_five_quarter_cycles():
    """``motion`` asked for alone measures its own cycle: 1.25 periods 2 pi/w_d of
    q/q0 = e^(-d t) (cos w_d t + (d/w_d) sin w_d t), from rest at q0; none past delta = 0.9 omega0."""
    import numpy as np

    from mech.problems.registry import get
    from mech.problems.spec import Run

    w0, d = 10.0, 1.5
    ex = get("5.5")
    assert ex.motion_at(ex.resolve({"omega0": w0, "delta": 9.5})) is None
    run = Run(rtol=1e-10, keep_trajectories=True)
    run.follow(ex.motion_at(ex.resolve({"omega0": w0, "delta": d})))
    t, (x, v) = run.trajectory(2)
    wd = math.sqrt(w0 * w0 - d * d)
    assert t[-1] == pytest.approx(1.25 * 2 * math.pi / wd, rel=1e-8)
    assert np.allclose(x, np.exp(-d * t) * (np.cos(wd * t) + d / wd * np.sin(wd * t)), rtol=0, atol=1e-8)
    assert run.invariants["E + dissipated work"] < 1e-8


def test_batched_route_equals_each_variant_alone_and_the_references():
    """The route over N variants (a sweep's, a class's) gives each variant what its one-point solve (the batch
    of one) gives, within the claims, and both the independent values above; the undefined width where the
    lower half-power point is absent (delta = 0.5 omega0)."""
    import numpy as np

    from mech.problems.registry import get
    from mech.problems.spec import Run

    ex = get("5.5")
    cases = CASES + [(1.0, 0.5, 1.0), (3.0, 3e-9, 0.0)]
    P = {k: np.array([c[i] for c in cases]) for i, k in enumerate(("omega0", "delta", "t1"))}
    rtol = ex.default_rtol
    cols = ex.batched_route.numeric(P, rtol, tuple(o.name for o in ex.outputs))
    for j, (w0, d, t1) in enumerate(cases):
        if (w0, d, t1) in CASES:  # the one-point solve test_against_independent_values made
            one = _solved(w0, d, t1)[1]
        else:
            one = ex.numeric_solver(ex.resolve({"omega0": w0, "delta": d, "t1": t1}), Run(rtol=rtol))
        wd = math.sqrt(w0 * w0 - d * d)
        width = half_power_width(w0, d)
        want = {"Q": w0 / (2 * d), "loss_per_cycle": 1.0 - free_energy_ratio(w0, d, 2 * math.pi / wd),
                "E_ratio": free_energy_ratio(w0, d, t1), "bandwidth": width}
        for name, col in cols.items():
            assert col.reason("failed", j) is None, (j, name)
            if name == "bandwidth" and width is None:
                assert col.reason("undefined", j) and isinstance(one[name], Undefined)
                continue
            claim = float(np.broadcast_to(col.rel, col.value.shape)[j])
            assert col.value[j] == pytest.approx(one[name], rel=claim, abs=1e-300), (j, name)
            assert col.value[j] == pytest.approx(want[name], rel=max(claim, 1e-9)), (j, name)


def test_a_variant_that_fails_fails_alone():
    """delta = 0.3826 omega0, within 3e-4 of sin(pi/8) omega0: the lower half-power point lies below 0.02
    omega0 (x_- = 1 - 2 z^2 - 2 z sqrt(1 - z^2) = 2.6e-4, omega_- = 0.016), which the route does not shoot;
    that variant's width fails, saying so, and its other outputs and the other variants stand."""
    import numpy as np

    from mech.problems.registry import get

    ex = get("5.5")
    z = 0.3826
    assert math.sqrt(1 - 2 * z * z - 2 * z * math.sqrt(1 - z * z)) < 0.02
    P = {"omega0": np.array([10.0, 1.0, 10.0]), "delta": np.array([1.0, z, 3.5]), "t1": np.array([1.0, 1.0, 0.9])}
    cols = ex.batched_route.numeric(P, ex.default_rtol, tuple(o.name for o in ex.outputs))
    assert "below 0.02 omega0" in cols["bandwidth"].reason("failed", 1)
    assert [cols["bandwidth"].reason("failed", j) for j in (0, 2)] == [None, None]
    assert cols["bandwidth"].value[2] == pytest.approx(half_power_width(10.0, 3.5), rel=1e-9)
    assert cols["Q"].reason("failed", 1) is None and cols["Q"].value[1] == pytest.approx(0.5 / z, rel=1e-9)

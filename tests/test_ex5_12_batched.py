"""5.12's route over arrays of variants: the stationary swing followed for N variants at once gives each
variant what its batch of one gives (within the claims), the swing's zero below threshold exactly, and the
one-point solve has no scalar route of its own (issue 41)."""

import math

import numpy as np
import pytest

from mech.problems import registry
from mech.problems.ch5 import ex5_12_pumped_pendulum as m

VARIANTS = [  # defaults; a larger pump below 2 omega0; a weakly damped subcritical swing; below threshold
    dict(l=0.5, g=9.81, delta=0.05, a=0.008, Omega=8.9),
    dict(l=0.5, g=9.81, delta=0.05, a=0.0125, Omega=8.7),
    dict(l=0.4639332370415426, g=11.329059803811615, delta=0.0026624568187754304, a=0.00692992246207903,
         Omega=9.758636785679768),
    dict(l=0.5, g=9.81, delta=0.05, a=0.005, Omega=8.9),
]


def _P(rows):
    return {k: np.array([r[k] for r in rows]) for k in rows[0]}


def test_the_swings_together_are_each_alone():
    rtol = 1e-11
    together = m.small_swings(_P(VARIANTS), rtol, ("growth", "a_th", "theta_st"))
    for j, v in enumerate(VARIANTS):
        alone = m.small_swings(_P([v]), rtol, ("growth", "a_th", "theta_st"))
        for name in ("growth", "a_th", "theta_st"):
            col = together[name]
            assert not col.mask("failed")[j]
            one = alone[name]
            claim = sum(np.broadcast_to(c.rel, c.value.shape)[i] * abs(c.value[i])
                        + np.broadcast_to(c.abs, c.value.shape)[i] for c, i in ((col, j), (one, 0)))
            assert abs(col.value[j] - one.value[0]) <= claim, name
    th = together["theta_st"]
    assert th.value[3] == 0.0 and together["growth"].value[3] < 0  # below threshold: no swing, exactly
    # claimed to 100 rtol times the swing's conditioning (>= 1; 9 to 36 here, far from any threshold)
    assert np.all(th.value[:3] > 0.1) and np.all((100 * rtol <= th.rel[:3]) & (th.rel[:3] <= 1e5 * rtol))


def test_the_one_point_solve_is_the_batch_of_one():
    ex = registry.get("5.12")
    route = ex.batched_route
    assert set(route.outputs) == {o.name for o in ex.outputs}
    assert not hasattr(m, "numeric") and not hasattr(m, "_stationary_swing")


def test_the_swing_is_a_fixed_point_of_the_half_map():
    # independent of the route's Newton: the start it returns, carried over one pivot period by scipy,
    # comes back as its mirror (theta, theta') -> (-theta, -theta')
    from scipy.integrate import solve_ivp

    p = VARIANTS[0]
    z = m._start(registry.get("5.12").resolve(p))
    T = 2 * math.pi / p["Omega"]
    f = lambda t, y: [y[1], -2 * p["delta"] * y[1] - (p["g"] - p["a"] * p["Omega"] ** 2 * math.cos(p["Omega"] * t))
                      / p["l"] * math.sin(y[0])]  # noqa: E731
    y = solve_ivp(f, (0, T), list(z), method="DOP853", rtol=1e-12, atol=1e-14).y[:, -1]
    assert y[0] == pytest.approx(-z[0], rel=1e-8) and y[1] == pytest.approx(-z[1], rel=1e-7)

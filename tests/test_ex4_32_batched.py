"""4.32's route over arrays of variants: the same numbers as the batch of one, each variant alone, and the
far tides whose level the secant used to chase through the rounding of the volume condition.

Reference values are the hand first-order formulas of tests/test_ex4_32.py: with eps = R_E/r_S and
eta = (M_S/M_E) eps^3, h_high = R_E eta/(1 - eps) (1 + O(eta)), h_low = -R_E eta/2 (1 + O(eta))."""

import numpy as np
import pytest

from conftest import solve_both
from mech.problems import registry
from mech.problems.params import Params

SUN = dict(M_S=1.98847e30, r_S=1.495978707e11, M_E=5.9722e24, R_E=6.371e6)
NAMES = ("M_S", "r_S", "M_E", "R_E")


def first_order(M_S, r_S, M_E, R_E):
    eps = R_E / r_S
    eta = M_S / M_E * eps**3
    return R_E * eta / (1 - eps), -R_E * eta / 2


def _route(points, rtol=1e-10):
    ex = registry.get("4.32")
    route = ex.batched_route
    P = Params({k: np.array([float(p[k]) for p in points]) for k in NAMES})
    return route.numeric(P, rtol, route.outputs)


# points 41, 79 and 193 of `mech sweep 4.32 --r_S 1e8:1e13:200`: tides of 1e-10..1e-13 of the radius, where
# the level c (~eta^2) is below the rounding of the volume quadrature's terms (~eta): the secant's steps
# never fell below 1e-15 of c, and the solve failed with "the volume condition did not converge"
FAR = [1e8 + i * (1e13 - 1e8) / 199 for i in (40, 78, 192)]


@pytest.mark.parametrize("r_S", FAR)
def test_far_tide_converges_to_the_hand_values(r_S):
    given = dict(SUN, r_S=r_S)
    high, low = first_order(**given)
    a, n, _ = solve_both("4.32", **given)
    for values in (a, n):
        # eta <= 1.5e-10 here: the hand formula's O(eta) is below 1e-9
        assert values["h_high"] == pytest.approx(high, rel=1e-9)
        assert values["h_low"] == pytest.approx(low, rel=1e-9)
        assert values["h_range"] == pytest.approx(high - low, rel=1e-9)


def test_many_variants_are_each_their_batch_of_one():
    points = [SUN, dict(SUN, r_S=FAR[2]), dict(SUN, M_S=7.342e22, r_S=3.844e8),
              dict(M_S=1e13, r_S=1e6, M_E=1.0, R_E=1.0), dict(SUN, r_S=1.495978707e12)]
    together = _route(points)
    for i, p in enumerate(points):
        alone = _route([p])
        high, low = first_order(**p)
        for name, ref in (("h_high", high), ("h_low", low), ("h_range", high - low)):
            col = together[name]
            assert not col.mask("failed")[i]
            assert col.value[i] == pytest.approx(alone[name].value[0], rel=1e-12)
            assert col.value[i] == pytest.approx(ref, rel=3e-5)  # eta <= 1e-5: O(eta) of the hand formula


def test_a_failing_variant_fails_alone_and_says_why():
    # R_E = 1, r_S = 2, M_S/M_E = 1e20: a "tide" far beyond the radius (the bounds refuse it; the route
    # is called directly): its surface iteration cannot converge
    bad = dict(M_S=1e20, r_S=2.0, M_E=1.0, R_E=1.0)
    got = _route([SUN, bad, dict(SUN, r_S=FAR[0])])
    for name in ("h_high", "h_low", "h_range"):
        col = got[name]
        assert list(col.mask("failed")) == [False, True, False]
        assert col.reason("failed", 1) == "the surface iteration did not converge"
        assert np.isnan(col.value[1]) and np.all(np.isfinite(col.value[[0, 2]]))
    high, low = first_order(**SUN)
    assert got["h_high"].value[0] == pytest.approx(high, rel=1e-7)
    assert got["h_low"].value[0] == pytest.approx(low, rel=1e-7)

"""solvers.mechanics.floquet's half-period formulas against closed forms: for y'' - k^2 y = 0 (unstable) and
y'' + w^2 y = 0 (stable) the half-period solutions are cosh/sinh and cos/sin, tr M = 2 cosh(k T) or
2 cos(w T) over the period T, and det(M + I) exp(delta T) = 2 cosh(delta T) + tr M."""

import math

import numpy as np
import pytest

from mech.solvers.mechanics.floquet import half_period_growth, half_period_minus_one


def _hyperbolic(k, T):
    t = T / 2
    return (np.array([math.cosh(k * t)]), np.array([k * math.sinh(k * t)]), np.array([math.sinh(k * t) / k]),
            np.array([math.cosh(k * t)]))


def _circular(w, T):
    t = T / 2
    return (np.array([math.cos(w * t)]), np.array([-w * math.sin(w * t)]), np.array([math.sin(w * t) / w]),
            np.array([math.cos(w * t)]))


@pytest.mark.parametrize("k, delta", [(0.3, 0.1), (2e-6, 1e-6), (1.5, 0.0)])
def test_growth_of_an_unstable_solution_is_k_minus_delta(k, delta):
    T = 2.0
    g, err = half_period_growth(*_hyperbolic(k, T), 1e-15, 1.0, delta, T)
    assert float(g[0]) == pytest.approx(k - delta, rel=1e-9, abs=1e-14)
    assert 0 < float(err[0]) < 1e-6


def test_a_stable_solution_grows_at_minus_delta():
    g, _ = half_period_growth(*_circular(1.3, 2.0), 1e-15, 1.3, 0.05, 2.0)
    assert float(g[0]) == pytest.approx(-0.05, rel=1e-12)


@pytest.mark.parametrize("make, arg", [(_hyperbolic, 0.4), (_circular, 1.3), (_circular, math.pi / 2 * 0.999)])
def test_minus_one_function(make, arg):
    T, delta = 2.0, 0.07
    y = make(arg, T)
    tr = 2 * math.cosh(arg * T) if make is _hyperbolic else 2 * math.cos(arg * T)
    F, err = half_period_minus_one(*y, 1e-15, delta * T, 1.0)
    assert float(F[0]) == pytest.approx(2 * math.cosh(delta * T) + tr, rel=1e-12, abs=1e-14)
    assert float(err[0]) < 1e-13

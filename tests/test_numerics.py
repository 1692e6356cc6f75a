"""Conformance of the generic numerics (mech.solvers.numerics) against scipy and closed forms.

The exercises lean on these instead of importing scipy (0.4-1.5 s of import); each is held here to the
routine it replaces or to an answer known in closed form.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from mech.problems.spec import NumericFailure
from mech.solvers.numerics import modes, roots

FUNCTIONS = [
    (lambda x: x**3 - 2 * x - 5, 2.0, 3.0),  # Wallis's cubic
    (lambda x: math.cos(x) - x, 0.0, 1.0),  # the Dottie number
    (lambda x: math.exp(x) - 1e6, 0.0, 20.0),  # ln(1e6)
    (lambda x: math.tanh(50 * (x - 0.3)), -1.0, 1.0),  # a steep root at 0.3
]


@pytest.mark.parametrize("f, a, b", FUNCTIONS)
def test_brentq_matches_scipy(f, a, b):
    optimize = pytest.importorskip("scipy.optimize")
    ours = roots.brentq(f, a, b, xtol=1e-14, rtol=4 * np.finfo(float).eps)
    theirs = optimize.brentq(f, a, b, xtol=1e-14, rtol=4 * np.finfo(float).eps)
    assert ours == pytest.approx(theirs, rel=1e-13, abs=1e-14)


def test_brentq_closed_forms_and_a_missing_bracket():
    assert roots.brentq(lambda x: math.exp(x) - 1e6, 0.0, 20.0, xtol=1e-15) == pytest.approx(6 * math.log(10), rel=1e-14)
    assert roots.brentq(lambda x: math.cos(x), 0.0, 3.0, xtol=1e-15) == pytest.approx(math.pi / 2, rel=1e-14)
    with pytest.raises((NumericFailure, ValueError)):
        roots.brentq(lambda x: x * x + 1.0, -1.0, 1.0)


def test_bracketed_root_to_the_last_bit():
    """sqrt(2) as the root of x^2 - 2: within one ulp."""
    x = roots.bracketed_root(lambda x: x * x - 2.0, 1.0, 2.0)
    assert abs(x - math.sqrt(2.0)) <= math.ulp(math.sqrt(2.0))


@pytest.mark.parametrize("f, a, b, x_min", [
    (lambda x: (x - 0.7) ** 2 + 1.0, 0.0, 2.0, 0.7),
    (lambda x: -math.sin(x), 0.0, 3.0, math.pi / 2),
    (lambda x: x * math.log(x), 0.05, 1.0, math.exp(-1.0)),
])
def test_minimizers_against_closed_forms_and_scipy(f, a, b, x_min):
    x, fx, _ = roots.minimize_bounded(f, a, b, xatol=1e-10)
    assert x == pytest.approx(x_min, abs=1e-7)
    g, fg, stopped = roots.golden_min(f, a, b, xtol=1e-10)
    assert not stopped and g == pytest.approx(x_min, abs=1e-7) and fg == pytest.approx(f(x_min), abs=1e-13)
    optimize = pytest.importorskip("scipy.optimize")
    theirs = optimize.minimize_scalar(f, bounds=(a, b), method="bounded", options={"xatol": 1e-10}).x
    assert x == pytest.approx(theirs, abs=1e-7)


def test_golden_min_stops_at_the_first_accepted_value():
    """A parabola dipping to -1 at 0.7: asked only for a negative value, the search stops early."""
    calls = []

    def f(x):
        calls.append(x)
        return (x - 0.7) ** 2 - 1e-3

    x, fx, stopped = roots.golden_min(f, 0.0, 2.0, xtol=1e-12, stop=lambda v: v < 0)
    assert stopped and fx < 0 and abs(x - 0.7) < math.sqrt(1e-3)
    assert len(calls) < 15


def test_normal_modes_match_scipys_generalized_eigenproblem():
    """Two masses and three springs: omega^2 = k/m and 3k/m by hand; a random SPD pair against eigh."""
    m, k = 2.0, 5.0
    res = modes.normal_modes(np.diag([m, m]), np.array([[2 * k, -k], [-k, 2 * k]]))
    assert np.allclose(np.sort(res.omega2), [k / m, 3 * k / m], rtol=1e-13)
    linalg = pytest.importorskip("scipy.linalg")
    rng = np.random.default_rng(5)
    A = rng.normal(size=(4, 4))
    B = rng.normal(size=(4, 4))
    M = A @ A.T + 4 * np.eye(4)
    K = B @ B.T + np.eye(4)
    ours = np.sort(modes.normal_modes(M, K).omega2)
    theirs = np.sort(linalg.eigh(K, M, eigvals_only=True))
    assert np.allclose(ours, theirs, rtol=1e-12)


def test_gradient_and_hessian_of_a_known_potential():
    """U = x^2 y + cos(y): grad = (2xy, x^2 - sin y), Hessian [[2y, 2x], [2x, -cos y]]."""
    U = lambda q: q[0] ** 2 * q[1] + math.cos(q[1])  # noqa: E731
    q0 = np.array([0.8, 0.3])
    assert np.allclose(modes.gradient(U, q0), [2 * 0.8 * 0.3, 0.64 - math.sin(0.3)], rtol=1e-9)
    H = modes.hessian(U, q0)
    assert np.allclose(H, [[0.6, 1.6], [1.6, -math.cos(0.3)]], rtol=1e-7, atol=1e-9)

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


def test_pair_roots_against_closed_forms_and_eigh():
    """Two masses m, three springs k: omega^2 = k/m and 3k/m.  M = diag(1, 1), K = diag(1e200, 1): the roots
    are the diagonal, 1 and 1e200, exactly (an eigensolver returns the low one as 0 to within 1e184).  A mass
    matrix [[1, 1/2], [1/2, 1/3]] (det 1/12) with K = diag(1/a, 1/2): 4.12 in units of the bar, roots of
    w^4/12 - (1/(3a) + 1/2) w^2 + 1/(2a) = 0; at a = 1e-200 the product of the roots is 6/a and their sum
    12 (1/(3a) + 1/2) = 4/a + 6, so the low root is 6/a / (4/a + 6 - low) = 1.5 (1 - 1.5 a) + O(a^2):
    1.5 to round-off; at a = 1e200 the high root is 6 + O(1/a) and the low one (6/a)/6 = 1/a.
    A random SPD pair against scipy's eigh; a zero root exactly (K singular)."""
    m, k = 2.0, 5.0
    w2, err = modes.pair_roots(np.diag([m, m]), np.array([[2 * k, -k], [-k, 2 * k]]))
    assert np.allclose(w2, [k / m, 3 * k / m], rtol=1e-14)
    assert np.all(err < 1e-14 * w2)
    w2, err = modes.pair_roots(np.eye(2), np.diag([1e200, 1.0]))
    assert w2[0] == pytest.approx(1.0, rel=1e-15) and w2[1] == pytest.approx(1e200, rel=1e-15)
    Mb = np.array([[1.0, 0.5], [0.5, 1.0 / 3.0]])
    w2, _ = modes.pair_roots(Mb, np.diag([1e200, 0.5]))
    assert w2[0] == pytest.approx(1.5, rel=1e-14) and w2[1] == pytest.approx(4e200, rel=1e-14)
    w2, _ = modes.pair_roots(Mb, np.diag([1e-200, 0.5]))
    assert w2[0] == pytest.approx(1e-200, rel=1e-14) and w2[1] == pytest.approx(6.0, rel=1e-14)
    w2, err = modes.pair_roots(np.diag([1.0, 3.0]), np.array([[1.0, 1.0], [1.0, 1.0]]))
    assert w2[0] == 0.0 and w2[1] == pytest.approx(4.0 / 3.0, rel=1e-15)  # trace of M^-1 K, the other 0
    linalg = pytest.importorskip("scipy.linalg")
    rng = np.random.default_rng(7)
    for _ in range(20):
        A, B = rng.normal(size=(2, 2)), rng.normal(size=(2, 2))
        M, K = A @ A.T + 0.1 * np.eye(2), B @ B.T + 0.1 * np.eye(2)
        ours, err = modes.pair_roots(M, K)
        theirs = linalg.eigh(K, M, eigvals_only=True)
        assert np.all(np.abs(ours - theirs) <= err + 4e-16 * np.abs(theirs))
    with pytest.raises(NumericFailure):
        modes.pair_roots(np.eye(2), np.diag([1.0, -1.0]))


def test_gradient_and_hessian_of_a_known_potential():
    """U = x^2 y + cos(y): grad = (2xy, x^2 - sin y), Hessian [[2y, 2x], [2x, -cos y]]."""
    U = lambda q: q[0] ** 2 * q[1] + math.cos(q[1])  # noqa: E731
    q0 = np.array([0.8, 0.3])
    assert np.allclose(modes.gradient(U, q0), [2 * 0.8 * 0.3, 0.64 - math.sin(0.3)], rtol=1e-9)
    H = modes.hessian(U, q0)
    assert np.allclose(H, [[0.6, 1.6], [1.6, -math.cos(0.3)]], rtol=1e-7, atol=1e-9)

"""solvers.numerics.branch against closed forms: the pitchfork z0^2 = a - 1 (supercritical), a subcritical
branch with a fold, z0^2 = 1 - a + ... , and Newton at a fixed parameter; several variants at once, each as
it would be alone, and one that fails says why alone."""

import numpy as np
import pytest

from mech.solvers.numerics.branch import follow, newton, on_branch


def pitchfork(z, a, c=1.0):
    # F = ((a - c - |z|^2) z0, z1): the branch leaves (0, c) along e = (1, 0) with z0^2 = a - c
    z0, z1 = z
    F = np.array([(a - c - z0 * z0 - z1 * z1) * z0, z1])
    J = np.array([[a - c - 3 * z0 * z0 - z1 * z1, -2 * z1 * z0], [0 * z0, 1.0 + 0 * z0]])
    return F, J, np.array([z0, 0.0 * z0])


def _corrector(res, N):
    ones = np.ones((2, N))
    return lambda idx, z, a, s: on_branch(res, idx, z, a, s, ones, 1e-12, np.ones(N), np.full(N, 10.0))


def _e(N):
    return np.array([[1.0] * N, [0.0] * N])


def test_follow_reaches_the_parameter_on_a_pitchfork():
    c = np.array([1.0, 1.5, 0.7])
    res = lambda idx, z, a: pitchfork(z, a, c[idx])  # noqa: E731
    (z0, a0), (z1, a1), (tries, steps), why = follow(_corrector(res, 3), _e(3), c, c + 1.0)
    assert all(w is None for w in why) and (steps >= 2).all()
    assert (a0 < c + 1.0).all() and (c + 1.0 <= a1).all()
    for z, a in ((z0, a0), (z1, a1)):  # on the branch, by hand z0 = (a - c)^(1/2)
        assert z[0] == pytest.approx(np.sqrt(a - c), rel=1e-9) and np.abs(z[1]).max() < 1e-12
    # each variant as it is alone
    (_, b0), (_, b1), _, _ = follow(_corrector(lambda idx, z, a: pitchfork(z, a, 1.5), 1), _e(1), c[1:2], c[1:2] + 1)
    assert b0[0] == a0[1] and b1[0] == a1[1]


def test_follow_passes_a_fold():
    # F = (a - 1 + z0^2 - z0^4) z0 (subcritical: from (0, 1) the branch runs down in a to the fold at
    # z0^2 = 1/2, a = 3/4, then up): followed by its amplitude, it reaches a = 1.5 at z0^2 = (1 + 3^(1/2))/2
    def F(idx, z, a):
        z0, z1 = z
        g = a - 1 + z0 * z0 - z0**4
        return (np.array([g * z0, z1]), np.array([[g + z0 * (2 * z0 - 4 * z0**3), 0 * z0], [0 * z0, 1 + 0 * z0]]),
                np.array([z0, 0.0 * z0]))

    (_, a0), (z1, a1), _, why = follow(_corrector(F, 1), _e(1), np.ones(1), np.full(1, 1.5), s_max=3.0)
    assert why[0] is None and a0[0] < 1.5 <= a1[0]
    assert 1 - a1[0] + z1[0, 0] ** 4 - z1[0, 0] ** 2 == pytest.approx(0.0, abs=1e-10)  # on the branch
    assert z1[0, 0] ** 2 > 0.5  # past the fold


def test_a_branch_that_never_reaches_its_target_fails_alone():
    # the second variant's target lies beyond the amplitude s_max = 1.5 (z0^2 = a - 1 = 4)
    res = lambda idx, z, a: pitchfork(z, a)  # noqa: E731
    _, (z1, a1), _, why = follow(_corrector(res, 2), _e(2), np.ones(2), np.array([1.5, 5.0]), s_max=1.5)
    assert why[0] is None and a1[0] >= 1.5
    assert "does not reach" in why[1]


def test_newton_at_a_fixed_parameter():
    a = np.array([5.0, 2.0])
    res = lambda idx, z, tol: pitchfork(z, a[idx])[:2]  # noqa: E731
    z, ok = newton(res, np.array([[1.7, 1.2], [0.1, -0.1]]), np.ones((2, 2)), 1e-8, 1e-13)
    assert ok.all()
    assert z[0] == pytest.approx([2.0, 1.0], rel=1e-13) and np.abs(z[1]).max() < 1e-13

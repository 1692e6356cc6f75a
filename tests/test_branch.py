"""solvers.numerics.branch against closed forms: the pitchfork z0^2 = a - 1 (supercritical), a subcritical
branch with a fold, z0^2 = 1 - a + ... , and Newton at a fixed parameter."""

import numpy as np
import pytest

from mech.solvers.numerics.branch import follow, newton, on_branch


def pitchfork(z, a):
    # F = ((a - 1 - |z|^2) z0, z1): the branch leaves (0, 1) along e = (1, 0) with z0^2 = a - 1
    z0, z1 = z
    F = np.array([(a - 1 - z0 * z0 - z1 * z1) * z0, z1])
    J = np.array([[a - 1 - 3 * z0 * z0 - z1 * z1, -2 * z1 * z0], [0.0, 1.0]])
    return F, J, np.array([z0, 0.0])


def test_follow_reaches_the_parameter_on_a_pitchfork():
    corr = lambda z, a, s: on_branch(pitchfork, z, a, s, [1.0, 1.0], 1e-12, 1.0, 10.0)  # noqa: E731
    (z0, a0), (z1, a1), (tries, steps) = follow(corr, [1.0, 0.0], 1.0, 2.0)
    assert a0 < 2.0 <= a1 and steps >= 2
    for z, a in ((z0, a0), (z1, a1)):  # on the branch, by hand z0 = (a - 1)^(1/2)
        assert z[0] == pytest.approx(np.sqrt(a - 1.0), rel=1e-9) and abs(z[1]) < 1e-12


def test_follow_passes_a_fold():
    # F = (a - 1 + z0^2 - z0^4) z0 (subcritical: from (0, 1) the branch runs down in a to the fold at
    # z0^2 = 1/2, a = 3/4, then up): followed by its amplitude, it reaches a = 1.5 at z0^2 = (1 + 3^(1/2))/2
    def F(z, a):
        z0, z1 = z
        g = a - 1 + z0 * z0 - z0**4
        return (np.array([g * z0, z1]), np.array([[g + z0 * (2 * z0 - 4 * z0**3), 0.0], [0.0, 1.0]]),
                np.array([z0, 0.0]))

    corr = lambda z, a, s: on_branch(F, z, a, s, [1.0, 1.0], 1e-12, 1.0, 10.0)  # noqa: E731
    (_, a0), (z1, a1), _ = follow(corr, [1.0, 0.0], 1.0, 1.5, s_max=3.0)
    assert a0 < 1.5 <= a1
    assert 1 - a1 + z1[0] ** 4 - z1[0] ** 2 == pytest.approx(0.0, abs=1e-10)  # on the branch
    assert z1[0] ** 2 > 0.5  # past the fold


def test_newton_at_a_fixed_parameter():
    z = newton(lambda z, tol: pitchfork(z, 5.0)[:2], np.array([1.7, 0.1]), [1.0, 1.0], 1e-8, 1e-13)
    assert z[0] == pytest.approx(2.0, rel=1e-13) and abs(z[1]) < 1e-13

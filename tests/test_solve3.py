"""solvers.numerics.modes.solve3 (4.23's 3 x 3 solve by the adjugate) against numpy's LU solve."""


def test_solve3_against_numpy():
    import numpy as np

    from mech.solvers.numerics.modes import solve3

    rng = np.random.default_rng(7)
    for _ in range(20):
        A = rng.normal(size=(3, 3))
        K = A @ A.T + 3 * np.eye(3)
        b = rng.normal(size=3)
        assert np.allclose(solve3(K, b), np.linalg.solve(K, b), rtol=1e-12, atol=1e-14)

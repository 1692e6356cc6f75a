"""5.10's one-period maps at mixed tolerances (issue 41): the variants of one kind of map are integrated
together, each held to its own rtol, in one integration (they were split per decade of rtol: a class of 300
integrated its maps in 921 groups, 474 now).  Each variant's map stays within its own tolerance of the
same map integrated alone at rtol 1e-12 (the one-variant route: the scalar DOP853)."""

import numpy as np
import pytest


@pytest.mark.parametrize("mu_over_w0", [0.05, 0.002])  # the plain map, the rotating one
def test_mixed_rtols_one_integration_each_within_its_own(mu_over_w0):
    from mech.problems.ch5.ex5_10_adler_locking import _ensemble

    w0 = np.array([3.0, 2.5, 3.3])
    mu = mu_over_w0 * w0
    beta = np.array([4.0, 3.0, 5.0])
    f0 = 0.4 * mu * w0 / np.sqrt(beta)  # Delta = f0 sqrt(beta)/(4 omega0) = 0.1 mu
    rtol = np.array([1e-6, 1e-8, 1e-10])
    z = np.array([[1.9, -0.3, 2.05], [0.4, 1.95, -0.2], [0.05, -0.1, 0.2]])
    ens, _, _ = _ensemble(w0, mu, beta, f0, None)
    res, J = ens.evaluate(z, np.arange(3), rtol)
    assert len(ens.records) == 1  # one group: three (one per decade of rtol) before
    for j in range(3):
        alone, _, _ = _ensemble(w0[j:j + 1], mu[j:j + 1], beta[j:j + 1], f0[j:j + 1], None)
        r1, J1 = alone.evaluate(z[:, j:j + 1], np.array([0]), 1e-12)
        scale = max(1.0, float(np.max(np.abs(z[:2, j]))))
        assert np.max(np.abs(res[:, j] - r1[:, 0])) <= 10.0 * rtol[j] * scale
        assert np.max(np.abs(J[:, :, j] - J1[:, :, 0])) <= 10.0 * rtol[j] * scale * max(1.0, np.abs(J1).max())

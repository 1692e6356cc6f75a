"""solvers.mechanics.mathieu (shared by 5.11 and 5.12) against the leading order it corrects, by hand: for
q'' + omega0^2 (1 + mu cos 2 omega t) q = 0 without damping at exact resonance the growth is mu omega0/4 and
the zone's edges are omega - omega0 = -+mu omega0/4, each to O(mu^2); the threshold with damping is
mu_th = 4 delta/omega0 to O(mu_th^2)."""

import numpy as np
import pytest

from mech.solvers.mechanics.mathieu import first_zone_next_order


@pytest.mark.parametrize("mu", [1e-3, 1e-2, 0.05])
def test_next_order_reduces_to_the_leading_order(mu):
    w0 = 2.0
    nx = first_zone_next_order(np.array(w0), np.array(0.0), np.array(mu), np.array(w0))
    lead = mu * w0 / 4.0
    assert float(nx["growth"]) == pytest.approx(lead, rel=2 * mu)
    assert float(nx["xi_lo"]) == pytest.approx(-lead, rel=2 * mu)
    assert float(nx["xi_hi"]) == pytest.approx(lead, rel=2 * mu)
    delta = mu * w0 / 8.0  # threshold mu_th = 4 delta/omega0 = mu/2
    nt = first_zone_next_order(np.array(w0), np.array(delta), np.array(mu), np.array(w0))
    assert float(nt["mu_th"]) == pytest.approx(mu / 2.0, rel=2 * mu)


def test_threshold_solves_its_defining_equation():
    """mu_th (k = mu_th W2/2, W2 = (omega0/omega)^2) solves |(d + i)^2 + a - k^2/((d + 3i)^2 + a)|^2 = k^2,
    d = delta/omega, a = W2 - d^2 (the docstring's zone edge at sigma = d), here by 300 plain fixed-point
    steps k <- |...| from the leading order, across the exercises' limits."""
    rng = np.random.default_rng(3)
    n = 400
    w0 = rng.uniform(0.5, 3, n)
    delta = rng.uniform(0, 0.2, n) * w0
    om = w0 * (1 + rng.uniform(-0.3, 0.3, n))
    W2, d = (w0 / om) ** 2, delta / om
    a = W2 - d * d
    k = np.sqrt((W2 - 1) ** 2 + 4 * d * d)
    for _ in range(300):
        k = np.abs((d + 1j) ** 2 + a - k * k / ((d + 3j) ** 2 + a))
    got = first_zone_next_order(w0, delta, np.full(n, 0.1), om, edges=False)["mu_th"]
    assert got == pytest.approx(2 * k / W2, rel=1e-13)

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

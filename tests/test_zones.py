"""solvers.numerics.zones.negative_region against closed forms: f = (x - 1)^2 - c^2 is negative on
(1 - c, 1 + c); a dip far narrower than the grid is still found; a positive minimum is no region, one within
its error is unresolved; a region past the grid's end is flagged."""

import numpy as np
import pytest

from mech.solvers.numerics.zones import negative_region


def test_ends_of_the_negative_region():
    c2 = np.array([0.3**2, 1e-14, -0.01, -1e-20, 0.5**2])  # region half-widths 0.3, 1e-7; none; unresolved; past
    err = np.array([1e-16, 1e-17, 1e-16, 1e-18, 1e-16])

    def P(idx, x):
        return (x - 1.0) ** 2 - c2[idx], err[idx]

    grid = np.tile(np.linspace(0.55, 1.45, 9), (5, 1))
    (lo, hi), window, none, unresolved = negative_region(P, grid, np.ones(5))
    assert list(window) == [False, False, False, False, True]
    assert list(none) == [False, False, True, False, False] and list(unresolved) == [False, False, False, True, False]
    assert lo[0][0] == pytest.approx(0.7, abs=1e-14) and hi[0][0] == pytest.approx(1.3, abs=1e-14)
    assert lo[0][1] == pytest.approx(1 - 1e-7, abs=1e-13) and hi[0][1] == pytest.approx(1 + 1e-7, abs=1e-13)
    # each end's error: f's error over the slope 2c there, plus the root's tolerance (2e-15 of the scale) and
    # its rounding (8 ulp of the scale)
    assert hi[1][0] == pytest.approx(1e-16 / 0.6 + 2e-15 + 8 * 2.0**-52, rel=1e-3)
    assert np.isnan(lo[0][2]) and not lo[2][:2].any()  # no end where there is no region; both converged

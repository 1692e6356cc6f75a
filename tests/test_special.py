"""mech.solvers.numerics.special against scipy.special (an independent implementation) and known values."""

import math

import numpy as np
import pytest

from mech.solvers.numerics.special import agm, ellipk, ellipkm1

scipy_special = pytest.importorskip("scipy.special")


def test_known_values():
    assert ellipk(0.0) == pytest.approx(math.pi / 2, rel=1e-16)
    # K(1/2) = Gamma(1/4)^2 / (4 sqrt(pi))
    assert ellipk(0.5) == pytest.approx(math.gamma(0.25) ** 2 / (4 * math.sqrt(math.pi)), rel=4e-16)
    # Gauss's constant: AGM(1, sqrt 2) = 1.19814023473559220744 (OEIS A053004)
    assert agm(1.0, math.sqrt(2.0)) == pytest.approx(1.19814023473559220744, rel=4e-16)
    assert ellipk(1.0) == math.inf and ellipkm1(0.0) == math.inf
    assert math.isnan(ellipk(1.5)) and math.isnan(ellipkm1(-1e-3))


@pytest.mark.parametrize("m", list(np.linspace(-50.0, 0.999, 41)) + [1 - 1e-8, 1 - 1e-15])
def test_ellipk_matches_scipy(m):
    assert ellipk(m) == pytest.approx(float(scipy_special.ellipk(m)), rel=2e-15)


@pytest.mark.parametrize("p", [10.0 ** -k for k in range(0, 320, 7)] + [5e-324, 0.3, 0.999])
def test_ellipkm1_matches_scipy_near_one(p):
    assert ellipkm1(p) == pytest.approx(float(scipy_special.ellipkm1(p)), rel=2e-15)

"""impulse_spectrum's stepped route (DOP853 on the fundamental matrix and the two accumulators) against
closed forms, for the 2 x 2 oscillator (the Python-float right-hand side) and a 3 x 3 system (the general
one); and the Fourier quadrature's loud failure naming the panel where the integrand is not finite.

Closed forms (integrate the equation of motion against e^{i w t} by parts, the motion decaying):
  q'' + 2 d q' + q = 0, q(0) = 0, q'(0) = 1:  int_0^inf q e^{i w t} dt = 1/(1 - w^2 - 2 i d w);
  r' = -3 r, r(0) = 1:                         int_0^inf r e^{i w t} dt = 1/(3 - i w).
"""

import math

import numpy as np
import pytest

from mech.problems.spec import NumericFailure
from mech.solvers.numerics.fourier import fourier_quad, impulse_spectrum


def _chi(d, w):
    return 1.0 / complex(1.0 - w * w, -2.0 * d * w)


@pytest.mark.parametrize("d, w", [(0.05, 0.7), (0.3, 1.0), (1.0, 2.5), (3.0, 0.2), (0.01, 0.0)])
def test_oscillator_spectrum_by_dop853(d, w):
    A = np.array([[0.0, 1.0], [-1.0, -2.0 * d]])
    b, c = np.array([0.0, 1.0]), np.array([1.0, 0.0])
    slow = d - math.sqrt(d * d - 1.0) if d > 1.0 else d
    seg = min(1.0 / slow, 8.0 * math.pi / math.sqrt(max(1.0 - d * d, 1e-300))) if d < 1.0 else 1.0 / slow
    spec = impulse_spectrum(A, b, c, w, rtol=1e-10, segment=seg)
    exact = _chi(d, w)
    assert abs(spec.value - exact) <= 1e-7 * abs(exact)
    assert abs(spec.liouville_drift) <= 1e-8  # det Phi(D) = exp(-2 d D)
    assert spec.traj.method == "DOP853"


@pytest.mark.parametrize("d, w", [(0.2, 0.9), (2.0, 0.4)])
def test_three_by_three_spectrum_by_dop853(d, w):
    """The oscillator and an uncoupled decaying coordinate r, observed together as q + r, struck together
    (q' = 1, r = 1): the transform is the sum of the two closed forms (the general right-hand side)."""
    A = np.array([[0.0, 1.0, 0.0], [-1.0, -2.0 * d, 0.0], [0.0, 0.0, -3.0]])
    b, c = np.array([0.0, 1.0, 1.0]), np.array([1.0, 0.0, 1.0])
    seg = 2.0
    spec = impulse_spectrum(A, b, c, w, rtol=1e-10, segment=seg)
    exact = _chi(d, w) + 1.0 / complex(3.0, -w)
    assert abs(spec.value - exact) <= 1e-7 * abs(exact)
    assert abs(spec.liouville_drift) <= 1e-8  # det Phi(D) = exp(D tr A)


def test_a_non_finite_integrand_names_its_panel():
    """Not a number beyond w = 2.5 on [0, 4] cut at 1, 2, 3: the first panel where it shows is [2, 3]."""
    with pytest.raises(NumericFailure, match=r"not finite on \[2, 3\]"):
        fourier_quad(lambda w: np.where(w > 2.5, np.nan, 1.0 / (1.0 + w * w)), 0.0, 4.0, 3.0,
                     points=[1.0, 2.0, 3.0])

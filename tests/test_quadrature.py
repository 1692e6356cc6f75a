"""mech.solvers.numerics.quadrature against integrals known in closed form and against scipy's QUADPACK."""

import math

import numpy as np
import pytest

from mech.solvers.numerics.quadrature import quad


@pytest.mark.parametrize(
    "f, a, b, exact",
    [
        (math.sin, 0.0, math.pi, 2.0),
        (lambda x: math.exp(-x * x), -3.0, 5.0, 0.5 * math.sqrt(math.pi) * (math.erf(5.0) + math.erf(3.0))),
        (lambda x: 1.0 / (1.0 + 25.0 * x * x), -1.0, 1.0, 0.4 * math.atan(5.0)),
        # Gauss's lemniscate integral: int_0^(pi/2) dt / sqrt(1 + sin^2 t) = K(-1)
        (lambda t: 1.0 / math.sqrt(1.0 + math.sin(t) ** 2), 0.0, 0.5 * math.pi, 1.3110287771460599),
        (lambda x: math.sqrt(x), 0.0, 1.0, 2.0 / 3.0),  # endpoint singularity in the derivative
        (math.cos, 1.0, 0.0, -math.sin(1.0)),  # reversed limits
    ],
)
def test_known_integrals(f, a, b, exact):
    val, err = quad(f, a, b, epsabs=0.0, epsrel=1e-13, limit=400)
    assert val == pytest.approx(exact, rel=2e-13)
    assert err <= 1e-13 * abs(val) + 1e-300


def test_breakpoint_and_vectorized():
    f = lambda x: np.abs(x - 0.3)  # noqa: E731  a kink at 0.3
    val, _ = quad(f, 0.0, 1.0, points=[0.3], vectorized=True, epsabs=0.0, epsrel=1e-14)
    assert val == pytest.approx(0.5 * (0.3**2 + 0.7**2), rel=1e-14)


def test_matches_quadpack():
    integrate = pytest.importorskip("scipy.integrate")
    f = lambda t: math.log1p(0.9 * math.sin(t) ** 2) * math.cos(3 * t) ** 2  # noqa: E731
    ours, _ = quad(f, 0.0, 2.0, epsabs=0.0, epsrel=1e-13)
    theirs, _ = integrate.quad(f, 0.0, 2.0, epsabs=0.0, epsrel=1e-13, limit=200)
    assert ours == pytest.approx(theirs, rel=1e-13)


def test_failure_is_loud():
    from mech.problems.spec import NumericFailure

    with pytest.raises(NumericFailure):
        quad(lambda x: math.sin(1.0 / x), 1e-9, 1.0, epsabs=0.0, epsrel=1e-14, limit=50)

"""solvers/linear_flow: the numpy matrix exponential against scipy.linalg.expm and against exact
rotations and damped flows evaluated to 100 digits (tests/hiprec.py)."""

import math

import numpy as np
import pytest

import hiprec
from mech.solvers.numerics.linear_flow import expm, expm_many, expm_minus_identity, rounding_bound

U = 2.0**-53


@pytest.mark.parametrize("n", [2, 3, 4])
@pytest.mark.parametrize("scale", [1e-3, 1.0, 3.0])  # (at 10 scipy itself is off by 3e-12: checked at 60 digits)
def test_against_scipy(n, scale):
    from scipy.linalg import expm as scipy_expm

    rng = np.random.default_rng(n * 100 + int(math.log10(scale) + 5))
    a = rng.normal(size=(n, n)) * scale
    ref = scipy_expm(a)
    assert np.max(np.abs(expm(a) - ref)) <= 1e-12 * np.max(np.abs(ref))


def test_damped_generator_against_scipy():
    from scipy.linalg import expm as scipy_expm

    # a damped, driven oscillator's generator in (q, q', cos, sin): stiff and non-normal
    a = np.array([[0.0, 1.0, 0.0, 0.0], [-4.0, -300.0, 1.0, 0.0], [0.0, 0.0, 0.0, -7.0], [0.0, 0.0, 7.0, 0.0]])
    for t in (1e-3, 0.1, 3.0):
        ref = scipy_expm(a * t)
        assert np.max(np.abs(expm(a * t) - ref)) <= 1e-12 * np.max(np.abs(ref))


@pytest.mark.parametrize("theta", [0.3, 1e3, 7.5e6, 1e10, 3.3e12])
def test_long_rotation_within_the_rounding_bound(theta):
    # exp([[0, th], [-th, 0]]) = [[cos th, sin th], [-sin th, cos th]], th exact as a double
    gen = np.array([[0.0, 1.0], [-1.0, 0.0]])
    e = expm(gen * theta)
    s, c = hiprec.sincos(hiprec.D(theta))
    err = max(abs(e[0, 0] - float(c)), abs(e[0, 1] - float(s)), abs(e[1, 0] + float(s)))
    assert err <= rounding_bound(gen, theta)
    assert err <= 10.0 * U * (1.0 + theta)  # the bound is not absurdly loose: the error is within 10 u theta


def test_minus_identity_keeps_a_slow_mode_digits():
    # q'' + q' + k q = 0 with k = 1e-8 over t = 1e-3: (exp(A t) - I)[0, 0] = -k t^2/2 (1 - t/3 + ...)
    k, t = 1e-8, 1e-3
    d = expm_minus_identity(np.array([[0.0, 1.0], [-k, -1.0]]) * t)
    exact = -k * t * t / 2.0 * (1.0 - t / 3.0 + t * t / 12.0 - k * t * t / 12.0)
    assert d[0, 0] == pytest.approx(exact, rel=1e-12)


def test_many_times_at_once_equal_one_at_a_time():
    a = np.array([[0.0, 1.0], [-1.0, -2.0e6]])
    ts = np.array([0.0, 1e-9, 3e-7, 1.0, 2.5e3, 1e7])
    many = expm_many(a, ts)
    for t, e in zip(ts, many):
        assert np.array_equal(e, expm(a * t))


@pytest.mark.parametrize("zeta, tau", [(1e3, 1e-2), (1e3, 2.5e3), (1e3, 1.4e4), (1e6, 1e-6), (1e6, 1.5e6),
                                       (1e6, 9e6)])
def test_stiff_damped_flow_against_80_digits(zeta, tau):
    """x'' + 2 zeta x' + x = 0 from (1, 0): with rates l1,2 = zeta -+ (zeta^2 - 1)^(1/2),
    x = (l2 e^{-l1 t} - l1 e^{-l2 t})/(l2 - l1), x' = l1 l2 (e^{-l2 t} - e^{-l1 t})/(l2 - l1), in Decimal.
    The squarings (up to 2^45 of them) keep the slow mode to a few u times its exponent l1 tau (<= 23)."""
    from decimal import localcontext

    with localcontext() as ctx:
        ctx.prec = hiprec.PREC
        z, t = hiprec.D(zeta), hiprec.D(tau)
        s = (z * z - 1).sqrt()
        l1, l2 = z - s, z + s
        e1, e2 = hiprec.exp(-l1 * t), hiprec.exp(-l2 * t)
        x = (l2 * e1 - l1 * e2) / (l2 - l1)
        v = l1 * l2 * (e2 - e1) / (l2 - l1)
        x, v = float(x), float(v)
    y = expm(np.array([[0.0, 1.0], [-1.0, -2.0 * zeta]]) * tau) @ np.array([1.0, 0.0])
    assert abs(y[0] - x) <= 1e-13 * abs(x)
    assert abs(y[1] - v) <= 1e-13 * abs(v)

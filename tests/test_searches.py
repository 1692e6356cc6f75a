"""solvers/numerics/searches.py: many roots and maxima at once, against the one-point bisection and by hand."""

import math

import numpy as np
import pytest

from mech.solvers.numerics.roots import bracketed_root
from mech.solvers.numerics.searches import bisect_bits, golden_max


def test_bisection_to_the_last_bit_is_the_one_point_bisection_variant_by_variant():
    # roots of x^3 - k from 1e-30 to 1e30, brackets of every width; and one bracket with an exact zero at an end
    k = np.array([1e-90, 2.0, 3.0, 1e30, 7.5, 8.0])
    lo = np.array([1e-40, 0.5, 1.0, 1.0, 1.0, 2.0])
    hi = np.array([1.0, 2.0, 1e5, 1e20, 3.0, 4.0])

    def f(idx, x):
        return x**3 - k[idx]

    got = bisect_bits(f, lo, hi, lo**3 - k, hi**3 - k)
    for j in range(k.size):
        assert got[j] == bracketed_root(lambda x: x**3 - k[j], lo[j], hi[j])
        assert abs(got[j] ** 3 / k[j] - 1) <= 1e-15
    assert got[-1] == 2.0


def test_bisection_refuses_an_unbracketed_root():
    with pytest.raises(ValueError):
        bisect_bits(lambda i, x: x - 5.0, np.array([1.0]), np.array([2.0]), np.array([-4.0]), np.array([-3.0]))


def test_golden_sections_find_each_maximum():
    # f = v - w (x - m)^2 on [lo, hi]: the maximum at m (by hand), of value v; at an end where m lies outside
    m = np.array([0.3, 1e-6, 5e3, 2.0])
    v = np.array([1.0, -2.0, 7e10, 0.5])
    w = np.array([1.0, 1e12, 3e-3, 1.0])
    lo, hi = np.array([0.0, 0.0, 1e3, 3.0]), np.array([1.0, 4e-6, 1e4, 4.0])

    def f(idx, x):
        return v[idx] - w[idx] * (x - m[idx]) ** 2

    xtol = 1e-9 * hi
    x, fx = golden_max(f, lo, hi, xtol)
    want_x = np.clip(m, lo, hi)
    want_f = v - w * (want_x - m) ** 2
    eps = np.finfo(float).eps
    # the value: to round-off of v and the bracket's width; never above the maximum (beyond round-off)
    assert np.all(np.abs(fx - want_f) <= 4 * eps * np.abs(v) + w * xtol**2 + 2 * w * np.abs(want_x - m) * xtol)
    # the place: to the bracket, widened where f is flat to round-off (w dx^2 below eps |v|)
    assert np.all(np.abs(x - want_x) <= xtol + np.sqrt(8 * eps * np.abs(v) / w))
    assert math.isclose(x[3], 3.0, abs_tol=4e-9)


def test_the_parabolic_step_leaves_a_smooth_maximum_to_round_off():
    # cos(x - m) + 2: not a parabola; its maximum 3 at m (by hand), brackets of 1e-4 of their width
    m = np.array([0.3, -5.0, 1e3, 7.25])
    lo, hi = m - 1.0, m + 2.0

    def f(idx, x):
        return np.cos(x - m[idx]) + 2.0

    x, fx = golden_max(f, lo, hi, 1e-4 * (hi - lo))
    assert np.all(np.abs(fx - 3.0) <= 4.5e-16 * 3.0)
    assert np.all(np.abs(x - m) <= 1e-4 * (hi - lo))

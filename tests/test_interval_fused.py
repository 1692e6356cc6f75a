"""The precise backend's fused interval + * / (``_Precise.interval_add``, ``interval_mul``, ``interval_div``)
give the very numbers, types and masks of the array code they replace: every corner rounded outward at
``prec`` bits, numpy's object minimum and maximum, the NaN and exact-zero rules (written out below as the
reference), on random endpoints (of prec bits: rounded products) with zeros, infinities, NaNs, Python ints, points and reversed ends."""

from __future__ import annotations

import random

import mpmath
import numpy as np
import pytest

from mech.solvers.numerics import interval as iv


def _draw(rng, prec):
    k = rng.random()
    if k < 0.4:  # prec bits of mantissa: its products and quotients are rounded
        with mpmath.workprec(prec):
            return mpmath.mpf(rng.getrandbits(prec) | 1) * rng.choice([1, -1]) * mpmath.ldexp(1, rng.randint(-600, 200))
    if k < 0.05:
        return mpmath.mpf(0)
    if k < 0.08:
        return mpmath.inf * rng.choice([1, -1])
    if k < 0.09:
        return mpmath.nan
    if k < 0.12:
        return rng.choice([0, 1])
    if k < 0.2:
        return mpmath.mpf(rng.randint(-3, 3))
    return mpmath.mpf(rng.uniform(-1, 1)) * mpmath.mpf(2) ** rng.randint(-400, 400)


def _ordered(lo, hi):
    pairs = [(p, q) if p != p or q != q or p <= q else (q, p) for p, q in zip(lo, hi)]  # a NaN stays
    return np.array([p for p, _ in pairs], object), np.array([q for _, q in pairs], object)


def _mul(B, a, b):
    xs = (a[0],) if a[0] is a[1] else a
    ys = (b[0],) if b[0] is b[1] else b
    pairs = [(B.mul(x, y, -1), B.mul(x, y, 1)) for x in xs for y in ys]
    lo, hi = pairs[0]
    nan = B.isnan(lo) | B.isnan(hi)
    for x, y in pairs[1:]:
        nan = nan | B.isnan(x) | B.isnan(y)
        lo, hi = np.minimum(lo, x), np.maximum(hi, y)
    zero = ((a[0] == 0) & (a[1] == 0)) | ((b[0] == 0) & (b[1] == 0))
    lo, hi = iv._unknown(B, lo, hi, nan & ~zero)
    return np.where(zero, 0, lo), np.where(zero, 0, hi)


def _div(B, a, b):
    (lo, hi), zero = iv.corner_div(B, a, b)
    return lo, hi, zero


def _same(got, want):
    key = lambda v: (type(v).__name__, getattr(v, "_mpf_", v))  # noqa: E731  exact: the raw mpf
    return [key(v) for v in np.asarray(got, object).tolist()] == [key(v) for v in np.asarray(want, object).tolist()]


@pytest.mark.parametrize("prec", [128, 2048])
def test_fused_operations_are_the_array_code(prec):
    rng = random.Random(prec)
    B = iv.precise(prec)
    for a_point in (False, True):
        for b_point in (False, True):
            for _ in range(60):
                x0, y0 = (np.array([_draw(rng, prec) for _ in range(4)], object) for _ in range(2))
                x1 = x0 if a_point else np.array([_draw(rng, prec) for _ in range(4)], object)
                y1 = y0 if b_point else np.array([_draw(rng, prec) for _ in range(4)], object)
                if rng.random() < 0.5 and not a_point:  # ends in order (the usual interval)
                    x0, x1 = _ordered(x0, x1)
                if rng.random() < 0.5 and not b_point:
                    y0, y1 = _ordered(y0, y1)
                a, b = (x0, x1), (y0, y1)
                for got, want in zip(iv.mul(B, a, b), _mul(B, a, b)):
                    assert _same(got, want), (a, b)
                lo, hi = iv.add(B, a, b)
                assert _same(lo, iv._unknown(B, B.add(x0, y0, -1), B.add(x1, y1, 1), False)[0]), (a, b)
                assert _same(hi, iv._unknown(B, B.add(x0, y0, -1), B.add(x1, y1, 1), False)[1]), (a, b)
                (lo, hi), zero = iv.div(B, a, b)
                w_lo, w_hi, w_zero = _div(B, a, b)
                assert _same(lo, w_lo) and _same(hi, w_hi), (a, b)
                assert zero.dtype == bool and zero.tolist() == w_zero.tolist()


def test_a_function_at_equal_ends_is_the_function_at_each():
    B = iv.precise(512)
    x = np.array([mpmath.mpf(3) / 7, mpmath.mpf(10) ** 20, mpmath.mpf(-2)], object)
    y = np.array([mpmath.mpf(3) / 7, mpmath.mpf(10) ** 20 + 1, mpmath.mpf(-2)], object)  # same, other, same
    for name in ("cos", "exp", "atan"):
        lo, hi = B.fn_both(name, x, y)
        assert _same(lo, B.fn(name, x)) and _same(hi, B.fn(name, y))

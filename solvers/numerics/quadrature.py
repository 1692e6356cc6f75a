"""Adaptive Gauss-Legendre quadrature on numpy alone (for smooth integrands on finite intervals).

scipy.integrate costs 0.6-0.9 s to import; the analytic and numeric routes
that need a definite integral of a smooth function over a finite interval
use this instead.

Method: every interval gets the n-point Gauss-Legendre rule on the whole and
on its two halves; the halves' sum is the value, the difference of the two
the error estimate (pessimistic: it is the coarse rule's error, and the
halves are far better for a smooth integrand).  The interval with the largest
estimate is split until the summed estimate is below
``max(epsabs, epsrel |I|)``.  Breakpoints (``points``) start the partition,
for kinks and sharp bends.  Failing to converge in ``limit`` intervals
raises ``NumericFailure``, never returns a guess.

The integrand may take a scalar (``math`` functions) or an array; it is
called point by point unless ``vectorized``.
"""

from __future__ import annotations

import heapq
import math
from typing import Callable, Sequence

import numpy as np

from mech.core.errors import NumericFailure

__all__ = ["quad"]

_RULES: dict[int, tuple[np.ndarray, np.ndarray]] = {}


def _rule(n: int):
    if n not in _RULES:
        _RULES[n] = np.polynomial.legendre.leggauss(n)
    return _RULES[n]


def _gauss(f, a: float, b: float, n: int, vectorized: bool) -> float:
    x, w = _rule(n)
    mid, half = 0.5 * (a + b), 0.5 * (b - a)
    u = mid + half * x
    vals = np.asarray(f(u), float) if vectorized else np.array([f(float(t)) for t in u])
    return half * float(w @ vals)


def quad(
    f: Callable,
    a: float,
    b: float,
    *,
    epsabs: float = 1.49e-8,
    epsrel: float = 1.49e-8,
    limit: int = 200,
    points: Sequence[float] | None = None,
    n: int = 15,
    vectorized: bool = False,
) -> tuple[float, float]:
    """``(value, error estimate)`` of the integral of ``f`` over the finite interval ``[a, b]``."""
    a, b = float(a), float(b)
    if not (math.isfinite(a) and math.isfinite(b)):
        raise ValueError("quad: finite limits only")
    if a == b:
        return 0.0, 0.0
    sign = 1.0
    if b < a:
        a, b, sign = b, a, -1.0
    cuts = sorted({a, b, *(float(p) for p in (points or ()) if a < float(p) < b)})
    heap, total, total_err = [], 0.0, 0.0

    def piece(lo, hi):
        whole = _gauss(f, lo, hi, n, vectorized)
        m = 0.5 * (lo + hi)
        halves = _gauss(f, lo, m, n, vectorized) + _gauss(f, m, hi, n, vectorized)
        if not math.isfinite(halves):
            raise NumericFailure(f"quad: the integrand is not finite on [{lo:.6g}, {hi:.6g}]")
        return halves, abs(halves - whole)

    for lo, hi in zip(cuts[:-1], cuts[1:]):
        v, e = piece(lo, hi)
        heapq.heappush(heap, (-e, lo, hi, v))
        total += v
        total_err += e
    count = len(heap)
    while total_err > max(epsabs, epsrel * abs(total)):
        if count >= limit:
            raise NumericFailure(
                f"quad: error estimate {total_err:.3g} above the tolerance after {count} intervals"
            )
        neg_e, lo, hi, v = heapq.heappop(heap)
        m = 0.5 * (lo + hi)
        if not (lo < m < hi):  # the interval cannot be split further in floating point
            raise NumericFailure(f"quad: interval [{lo:.17g}, {hi:.17g}] too narrow to refine")
        v1, e1 = piece(lo, m)
        v2, e2 = piece(m, hi)
        heapq.heappush(heap, (-e1, lo, m, v1))
        heapq.heappush(heap, (-e2, m, hi, v2))
        count += 1
        # re-sum rather than update, so that round-off in the running sums cannot accumulate
        total = math.fsum(item[3] for item in heap)
        total_err = math.fsum(-item[0] for item in heap)
    return sign * total, total_err

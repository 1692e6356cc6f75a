"""Complete elliptic integrals of the first and second kinds on the standard library alone.

scipy.special costs 0.3-0.4 s to import, more than the solves that need
K(m).  The arithmetic-geometric mean gives it to a few ulp in a handful of
iterations (Gauss):  K(m) = pi / (2 AGM(1, sqrt(1 - m))).

* ``ellipk(m)``    K(m) for m <= 1 (m = 1 gives inf);
* ``ellipkm1(p)``  K(1 - p) with p = 1 - m given directly, so that m -> 1
  keeps its precision (p down to the smallest subnormal);
* ``ellipe(m)``    E(m) for m <= 1, from the same mean: the half-differences
  c_n of the AGM sequence give E = K (1 - sum_n 2^(n-1) c_n^2), with c_0^2 = m.

The names and parameter conventions are scipy.special's, so the two can be
compared point for point (tests/test_special.py does).
"""

from __future__ import annotations

import math

__all__ = ["agm", "ellipk", "ellipkm1", "ellipe"]


def _out(x, scalar: bool):
    """A result as its argument came: a float for a number, an array for an array."""
    return float(x) if scalar else x


def agm(a, b):
    """The arithmetic-geometric mean of two non-negative numbers (numbers or arrays of them, elementwise)."""
    import numpy as np

    scalar = np.ndim(a) == 0 and np.ndim(b) == 0
    a, b = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    a, b = a.copy(), b.copy()
    bad = (a < 0) | (b < 0) | np.isnan(a) | np.isnan(b)
    zero = ~bad & ((a == 0.0) | (b == 0.0))
    inf = ~bad & ~zero & (np.isinf(a) | np.isinf(b))
    live = ~bad & ~zero & ~inf
    with np.errstate(invalid="ignore", over="ignore"):
        for _ in range(100):
            live &= ~(np.abs(a - b) <= 2e-16 * a)
            if not live.any():
                break
            a, b = np.where(live, 0.5 * (a + b), a), np.where(live, np.sqrt(a * b), b)
        out = np.where(bad, np.nan, np.where(zero, 0.0, np.where(inf, np.inf, 0.5 * (a + b))))
    return _out(out, scalar)


def ellipkm1(p):
    """K(m) at m = 1 - p, for p >= 0 (a number or an array)."""
    import numpy as np

    scalar = np.ndim(p) == 0
    p = np.asarray(p, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        k = math.pi / (2.0 * np.asarray(agm(1.0, np.sqrt(np.where(p > 0, p, 1.0)))))
        out = np.where(np.isnan(p) | (p < 0), np.nan, np.where(p == 0.0, np.inf, np.where(np.isinf(p), 0.0, k)))
    return _out(out, scalar)


def ellipk(m):
    """K(m) = integral_0^(pi/2) (1 - m sin^2 t)^(-1/2) dt, for m <= 1 (a number or an array)."""
    import numpy as np

    scalar = np.ndim(m) == 0
    m = np.asarray(m, dtype=float)
    out = np.where(m > 1.0, np.nan, np.asarray(ellipkm1(np.where(m > 1.0, 0.5, 1.0 - m))))
    return _out(out, scalar)


def ellipe(m: float) -> float:
    """E(m) = integral_0^(pi/2) (1 - m sin^2 t)^(1/2) dt, for m <= 1."""
    m = float(m)
    if math.isnan(m) or m > 1.0:
        return math.nan
    if m == 1.0:
        return 1.0
    if math.isinf(m):
        return math.inf
    if m < -1e300:  # E(m) ~ sqrt(-m) for m -> -inf, homogeneous: E(m) = sqrt(1 - m) E(m / (m - 1))
        return math.sqrt(-m) * ellipe(m / (m - 1.0)) * math.sqrt(1.0 - 1.0 / m)
    a, b = 1.0, math.sqrt(1.0 - m)
    total = 0.5 * m  # 2^(-1) c_0^2 with c_0^2 = m
    weight = 0.5
    for _ in range(100):
        c = 0.5 * (a - b)
        a, b = 0.5 * (a + b), math.sqrt(a * b)
        weight *= 2.0
        total += weight * c * c
        if abs(a - b) <= 4e-16 * a:  # the next c is round-off: its square is nothing against the total
            break
    return math.pi / (2.0 * a) * (1.0 - total)

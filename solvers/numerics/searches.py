"""Searches over N functions at once: a root to the last bit by bisection, a maximum by golden sections.

* ``bisect_bits(f, lo, hi, flo, fhi)``: the root of each of N functions in its own bracket
  [lo, hi] (0 < lo < hi, opposite signs at the ends), by bisection on the floats' bit patterns:
  at most ~64 halvings whatever the root's magnitude (``roots.bracketed_root``'s rule, each pass
  evaluating every unfinished function once).
* ``golden_max(f, lo, hi, xtol)``: the maximum of each of N unimodal functions on its own
  [lo, hi], by golden sections down to a bracket of ``xtol``, then one parabolic step through the
  bracket's inner points and its middle: the best value evaluated.  The golden sections alone leave
  the value to f'' xtol^2; the parabola's vertex of a smooth maximum is off by ~ (f'''/f'') xtol^2,
  its value by the square of that (a bracket of 1e-4 of the abscissa: round-off).

``f(idx, x)`` evaluates the functions ``idx`` (indices into the N) at ``x`` (one value each), as
``batch.illinois`` and ``batch.scan_up`` take it.  numpy only; each pass counts as a step of work.
"""

from __future__ import annotations

import numpy as np

from mech.core import budget

__all__ = ["bisect_bits", "golden_max"]

_GOLD = 0.5 * (3.0 - np.sqrt(5.0))  # 0.381966..., the golden section's smaller part


def bisect_bits(f, lo, hi, flo, fhi):
    """Roots of N functions, each in its own [lo, hi] with 0 < lo < hi and f(lo), f(hi) (``flo``, ``fhi``) of
    opposite signs, to the last bit: of the two adjacent floats that bracket it, the one where |f| is smaller
    (an end where f is exactly zero: that end)."""
    lo, hi = np.array(lo, dtype=float), np.array(hi, dtype=float)
    flo, fhi = np.array(flo, dtype=float), np.array(fhi, dtype=float)
    if np.any(~(lo > 0) | ~(hi > lo)) or np.any(np.sign(flo) * np.sign(fhi) > 0):
        raise ValueError("bisect_bits: each root must be bracketed in 0 < lo < hi")
    ka, kb = lo.view(np.int64).copy(), hi.view(np.int64).copy()  # positive floats order as their bits
    exact = np.where(flo == 0, lo, np.where(fhi == 0, hi, np.nan))
    a_pos = flo > 0
    todo = np.flatnonzero(np.isnan(exact) & (kb - ka > 1))
    while todo.size:
        budget.check("batched bisection")
        km = ka[todo] + (kb[todo] - ka[todo]) // 2
        fm = np.asarray(f(todo, km.view(np.float64)), dtype=float)
        hit = fm == 0.0
        exact[todo[hit]] = km[hit].view(np.float64)
        same = (fm > 0) == a_pos[todo]
        ka[todo[same & ~hit]] = km[same & ~hit]
        kb[todo[~same & ~hit]] = km[~same & ~hit]
        todo = todo[~hit & (kb[todo] - ka[todo] > 1)]
    a, b = ka.view(np.float64), kb.view(np.float64)
    left = np.flatnonzero(np.isnan(exact))
    if left.size:
        fa, fb = np.asarray(f(left, a[left]), dtype=float), np.asarray(f(left, b[left]), dtype=float)
        exact[left] = np.where(np.abs(fa) <= np.abs(fb), a[left], b[left])
    return exact


def golden_max(f, lo, hi, xtol):
    """(x, f(x)) at the maximum of each of N functions on its own [lo, hi], by golden sections until the
    bracket is within ``xtol`` (a number or one per function), then a parabolic step; the best point
    evaluated is returned."""
    a, b = np.array(lo, dtype=float), np.array(hi, dtype=float)
    n = a.size
    xtol = np.broadcast_to(np.asarray(xtol, dtype=float), (n,))
    every = np.arange(n)
    c, d = a + _GOLD * (b - a), b - _GOLD * (b - a)
    fc, fd = np.asarray(f(every, c), dtype=float), np.asarray(f(every, d), dtype=float)
    todo = np.flatnonzero(b - a > xtol)
    while todo.size:
        budget.check("batched golden section")
        right = fd[todo] > fc[todo]  # the maximum lies in [c, b]: c <- d, a new d
        R, L = todo[right], todo[~right]
        a[R], c[R], fc[R] = c[R], d[R], fd[R]
        b[L], d[L], fd[L] = d[L], c[L], fc[L]
        x_new = np.where(right, b[todo] - _GOLD * (b[todo] - a[todo]), a[todo] + _GOLD * (b[todo] - a[todo]))
        f_new = np.asarray(f(todo, x_new), dtype=float)
        d[R], fd[R] = x_new[right], f_new[right]
        c[L], fc[L] = x_new[~right], f_new[~right]
        todo = todo[b[todo] - a[todo] > xtol[todo]]
    # one parabolic step through c, the middle and d (the vertex kept within the bracket)
    m = 0.5 * (a + b)
    fm = np.asarray(f(every, m), dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        num = (m - c) ** 2 * (fm - fd) - (m - d) ** 2 * (fm - fc)
        den = (m - c) * (fm - fd) - (m - d) * (fm - fc)
        xv = m - 0.5 * num / den
    xv = np.clip(np.where(np.isfinite(xv), xv, m), a, b)
    fv = np.asarray(f(every, xv), dtype=float)
    xs, fs = np.stack([c, d, m, xv]), np.stack([fc, fd, fm, fv])
    best = np.argmax(np.where(np.isnan(fs), -np.inf, fs), axis=0)
    return xs[best, every], fs[best, every]

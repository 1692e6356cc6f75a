"""The region where a function of one variable is negative around its minimum, for N functions at once.

For each of N points f(x) (with its own absolute error) is sampled on a grid; where its least sampled value
is not negative a golden-section search for the minimum runs, stopped as soon as a negative value is seen
(a narrow dip of depth 1e-14 is found without locating the minimum itself), and a minimum within its own
error leaves the answer open (``unresolved``) rather than guessing "no region".  The region's two ends
are then the roots on either side, bracketed by the nearest grid point where f > 0 and found by the
Illinois method, each with its absolute error: f's error at the root over the slope there, plus the root's
own tolerance.  5.11 finds its unstable zone's edges in omega with it.

Tested against closed forms (tests/test_zones.py).
"""

from __future__ import annotations

import math

import numpy as np

from mech.solvers.numerics.batch import illinois

__all__ = ["negative_region"]


def negative_region(P, grid, scale):
    """The ends of the region where f < 0 around f's minimum, at N points.

    ``P(idx, x)`` -> (f, its absolute error) of the points ``idx`` at x (one value each); ``grid``: (N, m)
    sample abscissae, increasing; ``scale``: per point, the size of x (tolerances are relative to it).
    Returns ([(lower ends, their errors, not converged), (upper ends, ...)], window, none, unresolved):
    ``window`` where f <= 0 at an end of the grid (the region reaches past it), ``none`` where the minimum
    is positive beyond its error (no region), ``unresolved`` where it is within its error."""
    scale = np.asarray(scale, dtype=float)
    n, ncol = grid.shape
    allp = np.arange(n)
    vals = np.stack([P(allp, grid[:, j])[0] for j in range(ncol)], axis=1)
    window = (vals[:, 0] <= 0) | (vals[:, -1] <= 0)
    k = np.argmin(vals, axis=1)
    w_in = grid[allp, k]
    p_in = vals[allp, k]
    found = (p_in < 0) & ~window
    none = np.zeros(n, dtype=bool)
    unresolved = np.zeros(n, dtype=bool)  # the minimum is within the error of F: whether a zone exists is open
    # golden-section search for the minimum, stopped as soon as F < 0 is seen
    g = 0.5 * (math.sqrt(5.0) - 1.0)
    a = grid[allp, np.maximum(k - 1, 0)]
    b = grid[allp, np.minimum(k + 1, ncol - 1)]
    c, d = b - g * (b - a), a + g * (b - a)
    active = ~found & ~window
    fc, fd = np.full(n, np.inf), np.full(n, np.inf)
    ec, ed = np.zeros(n), np.zeros(n)
    idx = np.flatnonzero(active)
    if idx.size:
        fc[idx], ec[idx] = P(idx, c[idx])
        fd[idx], ed[idx] = P(idx, d[idx])
    while active.any():
        idx = np.flatnonzero(active)
        hit = np.minimum(fc[idx], fd[idx]) < 0
        h = idx[hit]
        use_c = fc[h] < fd[h]
        w_in[h] = np.where(use_c, c[h], d[h])
        p_in[h] = np.where(use_c, fc[h], fd[h])
        found[h] = True
        active[h] = False
        idx = idx[~hit]
        narrow = b[idx] - a[idx] <= 1e-11 * scale[idx]
        nn = idx[narrow]
        resolved = np.where(fc[nn] < fd[nn], fc[nn] > ec[nn], fd[nn] > ed[nn])
        none[nn[resolved]] = True
        unresolved[nn[~resolved]] = True
        active[idx[narrow]] = False
        idx = idx[~narrow]
        if not idx.size:
            break
        left = fc[idx] < fd[idx]
        L, R = idx[left], idx[~left]
        b[L], d[L], fd[L], ed[L] = d[L], c[L], fc[L], ec[L]
        c[L] = b[L] - g * (b[L] - a[L])
        a[R], c[R], fc[R], ec[R] = c[R], d[R], fd[R], ed[R]
        d[R] = a[R] + g * (b[R] - a[R])
        x = np.where(left, c[idx], d[idx])
        fx, ex = P(idx, x)
        fc[L], fd[R] = fx[left], fx[~left]
        ec[L], ed[R] = ex[left], ex[~left]
    edges = []
    go = np.flatnonzero(found)
    for sgn in (-1.0, 1.0):
        value, ab = np.full(n, np.nan), np.zeros(n)
        conv = np.ones(n, dtype=bool)
        if go.size:
            gg, vv, wi = grid[go], vals[go], w_in[go]
            if sgn < 0:  # the last grid point below w_in where P > 0
                mask = (gg < wi[:, None]) & (vv > 0)
                j = ncol - 1 - np.argmax(mask[:, ::-1], axis=1)
                end, fend = gg[np.arange(go.size), j], vv[np.arange(go.size), j]
                lo_, hi_, flo, fhi = end, wi, fend, p_in[go]
            else:  # the first grid point above w_in where P > 0
                mask = (gg > wi[:, None]) & (vv > 0)
                j = np.argmax(mask, axis=1)
                end, fend = gg[np.arange(go.size), j], vv[np.arange(go.size), j]
                lo_, hi_, flo, fhi = wi, end, p_in[go], fend
            xtol = 1e-15 * scale[go]
            w, ok = illinois(lambda x, i: P(go[i], x)[0], lo_, hi_, flo, fhi, xtol=xtol, rtol=4 * 2.0**-52)
            # the slope over a step well inside the zone's half-width (a zone may be 1e-7 omega0 wide)
            dw = np.minimum(1e-7 * scale[go], 1e-2 * np.abs(w - wi))
            ew = P(go, w)[1]
            slope = np.abs(P(go, w + sgn * dw)[0]) / dw
            value[go] = w
            with np.errstate(divide="ignore", invalid="ignore"):
                ab[go] = ew / slope + 2.0 * xtol + 8 * 2.0**-52 * scale[go]
            conv[go] = ok
        edges.append((value, ab, ~conv))
    return edges, window, none, unresolved

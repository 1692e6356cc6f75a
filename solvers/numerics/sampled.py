"""Functions sampled on a fixed grid, many rows at once (numpy only): their discrete extrema without
evaluating every sample, and roots of monotonic functions by safeguarded Newton.

``sparse_samples`` evaluates a pointwise function of (row, grid index) on every ``stride``-th index and then
on every index of the strides next to a sampled extremum, to the edge of a run of NaN samples (a gap; not
within one) or to a row's end, and of
the strides next to a least coarse step (a dent: two extrema within a stride), and of the strides a caller
marks dense: elsewhere the row is NaN.  Where a row is monotonic between its extrema on
the grid's scale (no wiggles within a stride), each discrete extremum of the full row has its two neighbours
evaluated, so ``vertices`` finds the same ones as on the full row, at the same values: the samples are the
full row's, bit for bit (the function is pointwise).  ``vertices`` is the parabola's vertex through each
local extremum and its neighbours, NaN elsewhere (a NaN neighbour makes none)."""

from __future__ import annotations

import numpy as np


def sparse_samples(fn, rows: int, n: int, stride: int, dense=None):
    """fn(r, i) -> values at rows r and grid indices i (flat int arrays); (rows, n) with NaN where not
    evaluated, and the strides evaluated whole (their rows, first and last indices).  ``dense``: (rows,
    strides) bool, strides to evaluate whole (beside the automatic ones)."""
    coarse = np.arange(0, n, stride)
    if coarse[-1] != n - 1:
        coarse = np.append(coarse, n - 1)
    k = coarse.size - 1  # strides: [coarse[j], coarse[j + 1]]
    r = np.repeat(np.arange(rows), coarse.size)
    xc = fn(r, np.tile(coarse, rows)).reshape(rows, coarse.size)
    d = np.diff(xc, axis=1)
    mark = np.zeros((rows, coarse.size), dtype=bool)  # sampled points whose strides either side go whole
    gap = np.isnan(xc)
    # an extremum, a flat step or a gap's edge (not the inside of a gap)
    mark[:, 1:-1] = ~(d[:, :-1] * d[:, 1:] > 0) & ~(gap[:, :-2] & gap[:, 1:-1] & gap[:, 2:])
    mark[:, [0, -1]] = True
    whole = mark[:, :-1] | mark[:, 1:]
    # a pair of extrema within one stride dents the coarse steps: the strides about each least |step| go whole
    mag = np.abs(d)
    dip = np.zeros((rows, k), dtype=bool)
    dip[:, 1:-1] = (mag[:, 1:-1] <= mag[:, :-2]) & (mag[:, 1:-1] <= mag[:, 2:])
    whole |= dip
    whole[:, 1:] |= dip[:, :-1]
    whole[:, :-1] |= dip[:, 1:]
    if dense is not None:
        whole |= dense
    out = np.full((rows, n), np.nan)
    out[:, coarse] = xc
    rr, jj = np.nonzero(whole)
    if rr.size:
        lens = coarse[jj + 1] - coarse[jj] - 1
        idx = np.repeat(coarse[jj] + 1 - np.cumsum(np.r_[0, lens[:-1]]), lens) + np.arange(lens.sum())
        rows_flat = np.repeat(rr, lens)
        out[rows_flat, idx] = fn(rows_flat, idx)
    return out, (rr, coarse[jj], coarse[jj + 1])


def sparse_extrema(fn, rows: int, n: int, stride: int, dense=None):
    """``vertices`` of ``sparse_samples``' rows, computed only over the strides evaluated whole (each index in
    one: a stride's own indices past its left end, with its neighbours): (the row, the vertex) of each."""
    x, (rr, a, b) = sparse_samples(fn, rows, n, stride, dense)
    cols = a[:, None] + np.arange(stride + 2)
    win = np.where(cols <= np.minimum(b + 1, n - 1)[:, None], x[rr[:, None], np.minimum(cols, n - 1)], np.nan)
    v = vertices(win)
    hit = np.isfinite(v)
    return np.broadcast_to(rr[:, None], v.shape)[hit], v[hit]


def vertices(x):
    """(rows, n) samples: at each interior local extremum (its differences of opposite signs) the vertex
    y1 - (y2 - y0)^2/(8 (y0 - 2 y1 + y2)) of the parabola through it and its neighbours (y1 where that
    curvature is 0); NaN elsewhere."""
    y0, y1, y2 = x[:, :-2], x[:, 1:-1], x[:, 2:]
    turn = (y1 - y0) * (y2 - y1) < 0
    curv = y0 - 2.0 * y1 + y2
    with np.errstate(divide="ignore", invalid="ignore"):
        v = np.where(curv != 0, y1 - 0.125 * (y2 - y0) ** 2 / curv, y1)
    out = np.full(x.shape, np.nan)
    out[:, 1:-1] = np.where(turn, v, np.nan)
    return out


def monotonic_root(h, dh, lo, hi, x0, increasing, iters: int = 60):
    """Roots of h (arrays, elementwise) monotonic on [lo, hi] (``increasing`` or not) with a sign change
    there, from x0 inside: Newton's steps kept inside the bracket (bisection otherwise), the bracket narrowed
    by each value's sign, until the steps are within 2 ulps (at most ``iters``)."""
    lo, hi, x = (np.array(v, dtype=float) for v in (lo, hi, x0))
    with np.errstate(divide="ignore", invalid="ignore"):
        for _ in range(iters):
            f = h(x)
            below = (f < 0) == increasing
            lo, hi = np.where(below, x, lo), np.where(below, hi, x)
            nx = x - f / dh(x)
            nx = np.where(f == 0, x, np.where((nx > lo) & (nx < hi), nx, 0.5 * (lo + hi)))
            if np.all(np.abs(nx - x) <= 4.5e-16 * np.abs(x)):
                return nx
            x = nx
    return x

"""A circle map's increment as a Fourier series, and its rotation number, for many maps at once.

A map theta -> theta + d(theta) (mod 2 pi) sampled at some angles: ``fourier_fit`` fits d with K harmonics by
least squares (with the largest residual, an honest error of the fit); ``rotation_number`` is the mean
increment per iterate, by the weighted Birkhoff average of d along an orbit (weights exp(-1/(s (1 - s))),
which converges faster than any power of the orbit's length for a smooth quasi-periodic orbit).  Both take
stacks of maps (rows; a single map is a stack of one).  5.10 uses them for the beat of an oscillator just
outside its locking range.  ``invariant_circle`` finds, by Newton's method, the closed curve a planar map
carries onto itself (the section of an attracting torus), where iterating onto it would take ~1/(1 - lambda)
iterates at a transverse multiplier lambda near 1.
"""

from __future__ import annotations

import cmath
import math
from array import array

import numpy as np

__all__ = ["fourier_fit", "rotation_number", "invariant_circle"]

# invariant_circle: how much rougher than the finest a map far from the circle may be, and the steps below
# which the radial derivatives of the last difference are kept
LOOSE_MAX = 100.0
FRESH_BELOW = 1e-4
# a long orbit of a map that barely bends (_alone): stretches of STRETCH_MIN to STRETCH_MAX iterates solved at
# once, each sweep of Picard's iteration contracting the error at least STRETCH_CONTRACTION-fold, at most
# STRETCH_SWEEPS of them
STRETCH_MIN, STRETCH_MAX, STRETCH_CONTRACTION, STRETCH_SWEEPS = 512, 8192, 1e-3, 12
# below this many maps still iterating, each is iterated alone on plain complex numbers (a numpy call on a
# few numbers costs more than the arithmetic)
ALONE_BELOW = 6


def _basis(theta, K):
    k = np.arange(1, K + 1)
    ang = np.asarray(theta, dtype=float)[..., None] * k
    return np.concatenate([np.ones(ang.shape[:-1] + (1,)), np.cos(ang), np.sin(ang)], axis=-1)


def fourier_fit(theta, d, K):
    """(coefficients [c0, a_1..a_K, b_1..b_K], the largest residual) of d ~ c0 + sum a_k cos k theta +
    b_k sin k theta, least squares (QR); theta, d: (n,) for one map or (R, n) for R maps at once."""
    B = _basis(theta, K)
    d = np.asarray(d, dtype=float)
    q, r = np.linalg.qr(B)
    coef = np.linalg.solve(r, np.einsum("...ji,...j->...i", q, d)[..., None])[..., 0]
    resid = np.max(np.abs(np.einsum("...ij,...j->...i", B, coef) - d), axis=-1)
    return coef, resid


def _length(c0):
    """Iterates of the orbit: the quasi-period in iterations is about 2 pi/|c0| (c0 ~ the mean of d); many
    of them are needed."""
    slip = 2.0 * math.pi / np.maximum(np.abs(c0), 1e-12)
    return np.minimum(np.maximum(400.0, 25.0 * slip), 200000).astype(int)


def _series(c0, c):
    """theta (m,) -> d(theta) = c0 + Re sum_k c_k e^(i k theta) (c: (K,), lowest harmonic first), on arrays:
    the powers of e^(i theta) by doubling."""
    K = c.size
    col = c[:, None]

    def d(theta):
        powers = np.empty((K, theta.size), dtype=complex)
        powers[0] = np.exp(1j * theta)
        m = 1
        while m < K:
            np.multiply(powers[:min(m, K - m)], powers[m - 1], out=powers[m:2 * m])
            m *= 2
        powers *= col
        return c0 + powers.sum(axis=0).real

    return d


def _stretch(d, theta, m, bend):
    """m iterates of theta -> theta + d(theta) from theta at once: the orbit theta_j = theta + sum_{i<j} d(theta_i)
    by Picard's iteration over the whole stretch from the rigid rotation by d(theta).  Each sweep multiplies
    the error by at most q = m bend (bend >= max|d'|; q below STRETCH_CONTRACTION): a sweep that moved the
    orbit by delta leaves it within q delta of the fixed point, and it stops when that is 4 ulp of the angle
    (the increments, at the orbit before the sweep, are then off by bend delta <= 4 eps |theta|/m).  (The m
    increments, the angle after them), or None if the sweeps did not settle."""
    th = theta + d(np.array([theta]))[0] * np.arange(m)
    partial = np.empty(m)
    q = m * bend
    for _ in range(STRETCH_SWEEPS):
        dd = d(th)
        partial[0], partial[1:] = theta, dd[:-1]
        new = np.cumsum(partial)  # the sums in the order the iterates add them
        if q * np.max(np.abs(new - th)) <= 4.0 * np.finfo(float).eps * np.max(np.abs(new)):
            return dd, float(new[-1] + dd[-1])
        th = new
    return None


def _alone(c0, c, n, i0=0, theta=0.0, sums=(0.0, 0.0, 0.0, 0.0)):
    """The weighted Birkhoff averages of one map over its orbit of n and the first n // 2 of it, from the
    iterate i0 on (theta, and the four sums so far); c: the harmonics' coefficients, lowest first.  The
    increments are weighted afterwards, all at once.  Where the map barely bends (a stretch of
    STRETCH_MIN iterates or more keeps the sweeps' contraction, from |d'| <= sum k |c_k|: a slow slip far
    from locking), the orbit is solved a stretch at a time on arrays; else iterated one by one (Horner in
    e^(i theta) on plain complex numbers)."""
    c = np.asarray(c, dtype=complex)
    total = max(n - i0, 0)
    bend = float(np.sum(np.arange(1, c.size + 1) * np.abs(c)))
    if not math.isfinite(bend):  # no series to bound (a NaN map): one by one, as it always was
        span = 0
    else:
        span = STRETCH_MAX if bend * STRETCH_MAX <= STRETCH_CONTRACTION else int(STRETCH_CONTRACTION / bend)
    d_of = _series(c0, c) if span >= STRETCH_MIN else None
    incr = np.empty(total)
    k = 0
    while k < total:
        m = min(span, total - k) if d_of is not None else total - k
        got = _stretch(d_of, theta, m, bend) if d_of is not None and m >= STRETCH_MIN else None
        if got is None:
            got = _one_by_one(c0, [complex(x) for x in c[::-1]], theta, m)
        incr[k:k + m], theta = got[0], math.fmod(got[1], 2.0 * math.pi)
        k += m
    mid = np.arange(i0, n) + 0.5
    out = []
    for r, length in ((0, n), (2, max(n // 2, 1))):
        s = mid / length
        wgt = np.exp(-1.0 / np.maximum(s * (1.0 - s), 1e-300))
        out.append((sums[r] + float(wgt @ incr)) / (sums[r + 1] + float(wgt.sum())))
    return out[0], out[1]


def _one_by_one(c0, c, theta, m):
    """m iterates of the map from theta on plain complex numbers (c highest harmonic first): (the increments,
    the angle after them)."""
    cexp, fmod, turn = cmath.exp, math.fmod, 2.0 * math.pi
    incr = array("d", bytes(8 * m))
    for k in range(m):
        z = cexp(1j * theta)
        acc = 0j
        for ck in c:
            acc = (acc + ck) * z
        dd = c0 + acc.real
        incr[k] = dd
        theta = fmod(theta + dd, turn)
    return np.frombuffer(incr, dtype=float), theta


def rotation_number(coef, K, length=1.0, with_error=False):
    """Weighted Birkhoff average of d along an orbit of theta -> theta + d(theta) (mod 2 pi), d the series
    of ``coef`` (``fourier_fit``'s order; (2K + 1,) for one map, (R, 2K + 1) for R): a number, or R of them.
    Each map runs its own orbit length (``length`` times ``_length``'s); the maps iterate together while many
    are left, then one by one.  ``with_error``: the average over twice that orbit, and its difference from
    the average over the first half, the error estimate (the average converges faster than any power of
    the orbit's length, but near a locking edge 25 quasi-periods leave 1e-4 of it)."""
    coef = np.asarray(coef, dtype=float)
    one = coef.ndim == 1
    coef = np.atleast_2d(coef)
    R = coef.shape[0]
    c0 = coef[:, 0]
    # sum_k a_k cos k theta + b_k sin k theta = Re sum_k (a_k - i b_k) e^(i k theta)
    c = coef[:, 1:K + 1] - 1j * coef[:, K + 1:]
    n = np.maximum(4, (_length(c0) * length * (2 if with_error else 1)).astype(int))
    sums = np.zeros((4, R))  # the weighted sums of d and of the weights, over the orbit and its first half
    th, i = _together(c0, c, n, sums)
    with np.errstate(invalid="ignore", divide="ignore"):  # the maps left to run alone are filled in below
        out, out_h = sums[0] / sums[1], sums[2] / sums[3]
    for j in np.flatnonzero(n > i):  # the few longest orbits, on alone
        out[j], out_h[j] = _alone(float(c0[j]), c[j], int(n[j]), i, float(th[j]),
                                  tuple(float(x) for x in sums[:, j]))
    if with_error:
        err = np.abs(out - out_h)
        return (float(out[0]), float(err[0])) if one else (out, err)
    return float(out[0]) if one else out


def _together(c0, c, n, sums):
    """The maps' orbits iterated together, each its own n iterates, while at least ALONE_BELOW of them are
    still running: (each map's angle where it stopped, the iterate reached).  ``sums`` is filled in place,
    rows: the weighted sum of d and the sum of the weights over the orbit, the same over its first n // 2.
    An iterate costs a handful of numpy calls whatever K (the powers e^(i k theta) by doubling, d one
    dot product); the increments are kept and weighted a stretch at a time, between two maps' ends."""
    R, K = c.shape
    half = np.maximum(n // 2, 1)
    th = np.zeros(R)
    act = np.arange(R)
    stop = np.sort(n)[::-1]
    i = 0
    while act.size >= ALONE_BELOW:
        # to the next map's end (or to where fewer than ALONE_BELOW would be left)
        upto = int(min(n[act].min(), stop[ALONE_BELOW - 1]))
        c0a, cca, tha = c0[act], np.ascontiguousarray(c[act].T), th[act]
        powers = np.empty((K, act.size), dtype=complex)
        doubling, m = [], 1  # z^(m+1..2m) = z^(1..m) z^m
        while m < K:
            doubling.append((powers[:min(m, K - m)], powers[m - 1], powers[m:2 * m]))
            m *= 2
        incr = np.empty((upto - i, act.size))
        terms = np.empty_like(powers)
        total = np.empty(act.size, dtype=complex)
        itheta = np.zeros(act.size, dtype=complex)
        for row in incr:
            itheta.imag = tha
            np.exp(itheta, out=powers[0])
            for low, top, out in doubling:
                np.multiply(low, top, out=out)
            np.multiply(powers, cca, out=terms)
            np.add.reduce(terms, axis=0, out=total)
            np.add(c0a, total.real, out=row)
            tha += row
            np.fmod(tha, 2.0 * math.pi, out=tha)
        # the bump exp(-1/(s (1 - s))), s = (i + 1/2)/n, over the whole orbit and over its first half (past
        # the half s (1 - s) <= 0, floored at a tiny positive number: the weight is 0 there)
        mid = np.arange(i, upto)[:, None] + 0.5
        for r, length in ((0, n[act]), (2, half[act])):
            s = mid / length
            wgt = np.exp(-1.0 / np.maximum(s * (1.0 - s), 1e-300))
            sums[r, act] += np.einsum("ij,ij->j", wgt, incr)
            sums[r + 1, act] += wgt.sum(axis=0)
        th[act] = tha
        i = upto
        act = act[n[act] > i]
    return th, i


def _basis_and_slope(theta, K, c):
    """``_basis`` at theta (R, n) and the slope d rho/d theta there of the series c (R, 2K+1), from one set of
    cosines and sines."""
    k = np.arange(1, K + 1)
    ang = theta[..., None] * k
    cos, sin = np.cos(ang), np.sin(ang)
    basis = np.concatenate([np.ones(ang.shape[:-1] + (1,)), cos, sin], axis=-1)
    slope = np.einsum("rnk,rk->rn", sin, -k * c[:, 1:K + 1]) + np.einsum("rnk,rk->rn", cos, k * c[:, K + 1:])
    return basis, slope


def invariant_circle(advance, rho0, stretch, K, n, tol, n_out=None, max_iter=12, h=1e-7):
    """The invariant circles of R planar maps at once, as graphs rho(theta) over the angle theta = atan2(p, q):
    Gauss-Newton on the K-harmonic Fourier coefficients of rho, collocated at the n > 2 K + 1 angles 2 pi j/n.

    ``advance(y, idx, loose)``: the maps idx (those still iterating) applied to points y of shape
    (2, k len(idx), n), rows q and stretch * p: each map's points, and with k = 2 the same points then pushed
    out along rho by h rho0 (the Jacobian's difference, both taken by the same steps of the caller's
    integrator).  ``loose`` (len(idx),) >= 1: how many times the finest error the evaluation may make, where
    the finest moves the circle by about tol/30 (far from the circle a rougher map does as well; the first
    map and the step that stops are always taken at 1).  While every step left is below FRESH_BELOW the
    radial derivatives of the last difference taken on the finest map are kept (k = 1: the Jacobian's other
    parts are taken at each iterate).  ``rho0``:
    (R, 1) starting radii; ``stretch``: (R, 1) (5.10: the velocity, -omega0 p).  The residual at theta_j is
    the image's radius less rho at the image's angle; each Newton step stops below ``tol`` (relative to
    rho0; a number or (R,)).  Returns (the points on the circle at the n_out (default n) angles 2 pi j/n_out,
    (2, R, n_out); the last Newton step over rho0, (R,); converged, (R,) bool)."""
    R = rho0.shape[0]
    th = 2.0 * math.pi * np.arange(n) / n
    B = _basis(th, K)  # (n, 2K+1)
    cs = np.stack([np.cos(th), np.sin(th)])
    coef = np.zeros((R, 2 * K + 1))
    coef[:, 0] = rho0[:, 0]
    step = np.full(R, np.inf)
    tol = np.broadcast_to(np.asarray(tol, dtype=float), (R,))
    # the first map the finest: a start already close stops there, as a rough map would not let it
    loose = np.ones(R)
    da_kept, dpsi_kept = np.zeros((R, n)), np.zeros((R, n))
    fine = np.zeros(R, dtype=bool)  # the kept derivatives were taken on the finest map
    converged = np.zeros(R, dtype=bool)
    act = np.arange(R)  # the maps still iterating: a converged one stops
    for it in range(max_iter):
        fresh = not np.all((step[act] < FRESH_BELOW) & fine[act])
        c, r0, st = coef[act], rho0[act], stretch[act]
        rho = c @ B.T  # (R', n)
        dr = h * r0
        m = act.size
        pts = (np.concatenate([rho, rho + dr], axis=0) if fresh else rho)[None] * cs[:, None, :]
        pts[1] *= np.concatenate([st, st]) if fresh else st
        ask = np.full(m, loose[act].min())  # the maps iterated together share the finest asked of any
        img = advance(pts, act, ask)
        q, p = img[0, :m], img[1, :m] / st
        a, psi = np.hypot(q, p), np.arctan2(p, q)
        if fresh:
            q2, p2 = img[0, m:], img[1, m:] / st
            da_kept[act] = (np.hypot(q2, p2) - a) / dr
            dpsi_kept[act] = (np.mod(np.arctan2(p2, q2) - psi + math.pi, 2.0 * math.pi) - math.pi) / dr
            fine[act] = ask == 1.0
        Bpsi, slope = _basis_and_slope(psi, K, c)  # (R', n, 2K+1), (R', n)
        resid = a - np.einsum("rnk,rk->rn", Bpsi, c)
        J = (da_kept[act] - slope * dpsi_kept[act])[..., None] * B[None] - Bpsi
        qm, rm = np.linalg.qr(J)
        delta = -np.linalg.solve(rm, np.einsum("rji,rj->ri", qm, resid)[..., None])[..., 0]
        coef[act] += delta
        step[act] = np.max(np.abs(delta), axis=1) / r0[:, 0]
        converged[act] = (step[act] < tol[act]) & (ask == 1.0)
        # the next map's error kept to a hundredth of the next step (~ this one squared), in units of tol/30;
        # after the first, never rougher again (a step measured on a finer map does not license a rougher one)
        rough = np.clip(0.3 * step[act] ** 2 / tol[act], 1.0, LOOSE_MAX)
        loose[act] = rough if it == 0 else np.minimum(loose[act], rough)
        act = act[~converged[act]]
        if not act.size:
            break
    th = 2.0 * math.pi * np.arange(n_out or n) / (n_out or n)
    pts = (coef @ _basis(th, K).T)[None] * np.stack([np.cos(th), np.sin(th)])[:, None, :]
    pts[1] *= stretch
    return pts, step, converged

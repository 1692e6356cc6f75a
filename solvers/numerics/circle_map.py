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

import math

import numpy as np

__all__ = ["fourier_fit", "rotation_number", "invariant_circle"]

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


def _weight(i, n):
    """The bump exp(-1/(s(1 - s))) at the iterate i of orbits of n (an array, each n > i)."""
    s = (i + 0.5) / n
    return np.exp(-1.0 / (s * (1.0 - s)))


def _alone(c0, c, n, i0=0, theta=0.0, sums=(0.0, 0.0, 0.0, 0.0)):
    """The weighted Birkhoff averages of one map over its orbit of n and the first n // 2 of it (Horner in
    e^(i theta) on plain complex numbers), from the iterate i0 on (theta, and the four sums so far)."""
    num, den, num_h, den_h = sums
    half = n // 2
    exp, cos, sin, fmod, turn = math.exp, math.cos, math.sin, math.fmod, 2.0 * math.pi
    for i in range(i0, n):
        s = (i + 0.5) / n
        wgt = exp(-1.0 / (s * (1.0 - s)))
        z = complex(cos(theta), sin(theta))
        acc = 0j
        for ck in c:
            acc = (acc + ck) * z
        dd = c0 + acc.real
        num += wgt * dd
        den += wgt
        if i < half:
            s = (i + 0.5) / half
            wh = exp(-1.0 / (s * (1.0 - s)))
            num_h += wh * dd
            den_h += wh
        theta = fmod(theta + dd, turn)
    return num / den, num_h / den_h
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
    # sum_k a_k cos k theta + b_k sin k theta = Re sum_k (a_k - i b_k) e^(i k theta): Horner in e^(i theta)
    c = (coef[:, 1:K + 1] - 1j * coef[:, K + 1:])[:, ::-1]  # highest harmonic first
    n = np.maximum(4, (_length(c0) * length * (2 if with_error else 1)).astype(int))
    out, out_h = np.full(R, np.nan), np.full(R, np.nan)
    # the maps still iterating, compressed whenever some finish: (theta, the four sums, c0, n, the harmonics
    # as columns, highest first)
    act = np.arange(R)
    th, c0a, na, cc = np.zeros(R), c0.copy(), n.copy(), np.ascontiguousarray(c.T)
    num, den, num_h, den_h = np.zeros(R), np.zeros(R), np.zeros(R), np.zeros(R)
    i = 0
    while act.size >= ALONE_BELOW:
        z = np.exp(1j * th)
        acc = cc[0] * z
        for k in range(1, K):
            acc += cc[k]
            acc *= z
        dd = c0a + acc.real
        wgt = _weight(i, na)
        num += wgt * dd
        den += wgt
        wh = np.where(i < na // 2, _weight(i, np.maximum(na // 2, i + 1)), 0.0)
        num_h += wh * dd
        den_h += wh
        th = np.fmod(th + dd, 2.0 * math.pi)
        i += 1
        fin = na <= i
        if fin.any():
            out[act[fin]], out_h[act[fin]] = num[fin] / den[fin], num_h[fin] / den_h[fin]
            keep = ~fin
            act, th, c0a, na, cc = act[keep], th[keep], c0a[keep], na[keep], cc[:, keep]
            num, den, num_h, den_h = num[keep], den[keep], num_h[keep], den_h[keep]
    for r, j in enumerate(act):  # the few longest orbits, on alone
        out[j], out_h[j] = _alone(float(c0[j]), [complex(x) for x in c[j]], int(n[j]), i, float(th[r]),
                                  (float(num[r]), float(den[r]), float(num_h[r]), float(den_h[r])))
    if with_error:
        err = np.abs(out - out_h)
        return (float(out[0]), float(err[0])) if one else (out, err)
    return float(out[0]) if one else out


def _dbasis(theta, K):
    """d/dtheta of ``_basis``."""
    k = np.arange(1, K + 1)
    ang = np.asarray(theta, dtype=float)[..., None] * k
    return np.concatenate([np.zeros(ang.shape[:-1] + (1,)), -k * np.sin(ang), k * np.cos(ang)], axis=-1)


def invariant_circle(advance, rho0, stretch, K, n, tol, n_out=None, max_iter=12, h=1e-7):
    """The invariant circles of R planar maps at once, as graphs rho(theta) over the angle theta = atan2(p, q):
    Gauss-Newton on the K-harmonic Fourier coefficients of rho, collocated at the n > 2 K + 1 angles 2 pi j/n.

    ``advance(y, idx)``: the maps idx (those still iterating) applied to points y of shape (2, 2 len(idx), n),
    rows q and stretch * p (each map's points, then the same points pushed out along rho by h rho0: the
    Jacobian's difference, both taken by the same steps of the caller's integrator).  ``rho0``: (R, 1) starting radii; ``stretch``: (R, 1) (5.10: the
    velocity, -omega0 p).  The residual at theta_j is the image's radius less rho at the image's angle; each
    Newton step stops below ``tol`` (relative to rho0; a number or (R,)).  Returns (the points on the circle at
    the n_out (default n) angles 2 pi j/n_out, (2, R, n_out); the last Newton step over rho0, (R,); converged,
    (R,) bool)."""
    R = rho0.shape[0]
    th = 2.0 * math.pi * np.arange(n) / n
    B = _basis(th, K)  # (n, 2K+1)
    cs = np.stack([np.cos(th), np.sin(th)])
    coef = np.zeros((R, 2 * K + 1))
    coef[:, 0] = rho0[:, 0]
    step = np.full(R, np.inf)
    tol = np.broadcast_to(np.asarray(tol, dtype=float), (R,))
    act = np.arange(R)  # the maps still iterating: a converged one stops
    for _ in range(max_iter):
        c, r0, st = coef[act], rho0[act], np.concatenate([stretch[act], stretch[act]])
        rho = c @ B.T  # (R', n)
        dr = h * r0
        pts = np.concatenate([rho, rho + dr], axis=0)[None] * cs[:, None, :]
        pts[1] *= st
        img = advance(pts, act)
        q, p = img[0], img[1] / st
        a, psi = np.hypot(q, p), np.arctan2(p, q)
        m = act.size
        da = (a[m:] - a[:m]) / dr
        dpsi = (np.mod(psi[m:] - psi[:m] + math.pi, 2.0 * math.pi) - math.pi) / dr
        Bpsi = _basis(psi[:m], K)  # (R', n, 2K+1)
        slope = np.einsum("rnk,rk->rn", _dbasis(psi[:m], K), c)
        resid = a[:m] - np.einsum("rnk,rk->rn", Bpsi, c)
        J = (da - slope * dpsi)[..., None] * B[None] - Bpsi
        qm, rm = np.linalg.qr(J)
        delta = -np.linalg.solve(rm, np.einsum("rji,rj->ri", qm, resid)[..., None])[..., 0]
        coef[act] += delta
        step[act] = np.max(np.abs(delta), axis=1) / r0[:, 0]
        act = act[~(step[act] < tol[act])]
        if not act.size:
            break
    th = 2.0 * math.pi * np.arange(n_out or n) / (n_out or n)
    pts = (coef @ _basis(th, K).T)[None] * np.stack([np.cos(th), np.sin(th)])[:, None, :]
    pts[1] *= stretch
    return pts, step, step < tol

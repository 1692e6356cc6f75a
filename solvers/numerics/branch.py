"""Following branches of solutions of F(z, a) = 0 (z in R^n, a a parameter) by their amplitude, N at once.

N independent problems (variants), each a branch that leaves z = 0 at a = a0 along a direction e (a
bifurcation), parametrized by the amplitude s = |z / scale|: each point solves F(z, a) = 0 together with
|z / scale|^2 = s^2 by Newton's method on (z, a) (the bordered system, ``on_branch``), from a secant
prediction through the last two points (``follow``).  Parametrizing by s rather than by a passes folds of
the branch in a (a subcritical bifurcation turns back before it rises through the a asked for); a variant's
step in s halves wherever its Newton fails (a secant overshooting a sharp turn) and grows by 1.5 after a
success.  The variants step in lock-step, each with its own step; one that fails says why, alone.

Arrays: z is (n, N), a, s (N,); ``residual(idx, z, a)`` evaluates the variants ``idx`` (z (n, m), a (m,))
and returns (F (n, m), dF/dz (n, n, m), dF/da (n, m)).  One problem is the batch of one.

Tested against closed forms (tests/test_branch.py): the pitchfork z^2 = a - 1 and a fold.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

__all__ = ["on_branch", "follow", "newton"]


def _solve(A, b):
    """x with A x = b for a stack (m, k, k), (m, k); NaN for the singular ones."""
    ok = np.isfinite(A).all(axis=(1, 2)) & np.isfinite(b).all(axis=1)
    ok[ok] = np.abs(np.linalg.det(A[ok])) > 0.0
    x = np.full(b.shape, np.nan)
    if ok.any():
        x[ok] = np.linalg.solve(A[ok], b[ok][..., None])[..., 0]
    return x


def on_branch(residual: Callable, idx, z, a, s, scale, tol: float, a_scale, a_max, max_iter: int = 10):
    """(z, a, ok): the variants ``idx`` put on their branches at the amplitudes s by Newton from (z, a);
    not ok where Newton leaves the neighbourhood (a outside (0, a_max), |z / scale| beyond 2 s + 0.5) or does
    not converge to ``tol`` (in z / scale, and tol * a_scale in a) within ``max_iter`` steps.  z, a, s: those of
    the variants idx ((n, m), (m,), (m,)); ``scale``, ``a_scale``, ``a_max``: of all N ((n, N), (N,), (N,))."""
    z, a = np.array(z, dtype=float), np.array(a, dtype=float)
    scale, a_scale, a_max = scale[:, idx], a_scale[idx], a_max[idx]
    n, m = z.shape
    live, ok = np.ones(m, dtype=bool), np.zeros(m, dtype=bool)
    for _ in range(max_iter):
        zs = z / scale
        with np.errstate(invalid="ignore"):
            live &= (0.0 < a) & (a < a_max) & (np.sqrt((zs * zs).sum(axis=0)) <= 2.0 * s + 0.5)
        k = np.flatnonzero(live)
        if k.size == 0:
            break
        r, J, ra = residual(idx[k], z[:, k], a[k])
        Jf = np.zeros((k.size, n + 1, n + 1))
        Jf[:, :n, :n] = np.moveaxis(J, 2, 0)
        Jf[:, :n, n] = ra.T
        Jf[:, n, :n] = (zs[:, k] / scale[:, k]).T
        F = np.concatenate([r, 0.5 * ((zs[:, k] ** 2).sum(axis=0) - s[k] ** 2)[None]]).T
        du = _solve(Jf, -F)
        z[:, k] += du[:, :n].T
        a[k] += du[:, n]
        with np.errstate(invalid="ignore"):
            conv = (np.sqrt(((du[:, :n].T / scale[:, k]) ** 2).sum(axis=0)) < 10 * tol) & \
                (np.abs(du[:, n]) < 10 * tol * a_scale[k])
        live[k[~np.isfinite(du).all(axis=1)]] = False  # singular or lost: not on the branch
        ok[k[conv]] = a[k[conv]] > 0.0
        live[k[conv]] = False
    return z, a, ok


def follow(corrector: Callable, e, a0, target, *, ds: float = 0.02, s_max: float = 3.0, max_tries: int = 200,
           ds_min: float = 1e-6):
    """Follow each variant's branch leaving (0, a0) along e ((n, N)) until a crosses its ``target``: the
    two points around the crossing ((z, a) before, (z, a) after), (tries, accepted steps) and why each
    variant failed (None: it did not).  ``corrector(idx, z, a, s)`` puts guesses on the branches of the
    variants idx at the amplitudes s (``on_branch``): (z, a, ok)."""
    e = np.asarray(e, dtype=float)
    a0, target = np.asarray(a0, dtype=float), np.asarray(target, dtype=float)
    n, N = e.shape
    z_prev, z_cur, z_new = np.zeros((n, N)), np.zeros((n, N)), np.full((n, N), np.nan)
    a_prev, a_cur, a_new = a0.copy(), a0.copy(), np.full(N, np.nan)
    s_prev, s_cur = np.zeros(N), np.zeros(N)
    ds = np.full(N, float(ds))
    steps, tries = np.zeros(N, dtype=int), np.zeros(N, dtype=int)
    why = np.full(N, None, dtype=object)
    live = np.ones(N, dtype=bool)
    while live.any():
        k = np.flatnonzero(live)
        s = s_cur[k] + ds[k]
        tries[k] += 1
        over = (tries[k] > max_tries) | (s > s_max)
        why[k[over]] = f"the branch does not reach the pivot amplitude asked within the amplitude {s_max:g}"
        live[k[over]] = False
        k, s = k[~over], s[~over]
        if k.size == 0:
            break
        first = steps[k] == 0
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(first, 0.0, (s - s_cur[k]) / np.where(first, 1.0, s_cur[k] - s_prev[k]))
        zg = np.where(first, s * e[:, k], z_cur[:, k] + t * (z_cur[:, k] - z_prev[:, k]))
        ag = np.where(first, a0[k], np.maximum(a_cur[k] + t * (a_cur[k] - a_prev[k]), 0.5 * a_cur[k]))
        zn, an, ok = corrector(k, zg, ag, s)
        bad = k[~ok]
        ds[bad] *= 0.5
        lost = bad[ds[bad] < ds_min]
        why[lost] = [f"the branch could not be followed at the amplitude s = {x:.3g}" for x in s_cur[lost] + ds[lost]]
        live[lost] = False
        g, zn, an, s = k[ok], zn[:, ok], an[ok], s[ok]
        steps[g] += 1
        crossed = (((an - target[g]) * (a_cur[g] - target[g]) <= 0.0) & (steps[g] > 1)) | \
            ((steps[g] == 1) & (an >= target[g]) & (target[g] > a0[g]))
        done = g[crossed]
        z_new[:, done], a_new[done] = zn[:, crossed], an[crossed]
        live[done] = False
        on = g[~crossed]
        z_prev[:, on], a_prev[on], s_prev[on] = z_cur[:, on], a_cur[on], s_cur[on]
        z_cur[:, on], a_cur[on], s_cur[on] = zn[:, ~crossed], an[~crossed], s[~crossed]
        ds[on] = np.minimum(1.5 * ds[on], 0.1)
    return (z_cur, a_cur), (z_new, a_new), (tries, steps), why


def newton(residual: Callable, z, scale, crude: float, rtol: float, max_iter: int = 30):
    """Points of the branches at fixed parameters: Newton on ``residual(idx, z, tol) = (F (n, m), dF/dz
    (n, n, m))`` for the variants idx, each variant's first steps with F evaluated at the loose tolerance
    ``crude``, its last ones at ``rtol`` (from a step below 1e3 crude), until a step at rtol is below rtol (in
    z / scale).  (z, converged)."""
    z = np.array(z, dtype=float)
    N = z.shape[1]
    at_rtol, done = np.zeros(N, dtype=bool), np.zeros(N, dtype=bool)
    for _ in range(max_iter):
        for tight, tol in ((False, crude), (True, rtol)):
            k = np.flatnonzero(~done & (at_rtol == tight))
            if k.size == 0:
                continue
            r, J = residual(k, z[:, k], tol)
            dz = _solve(np.moveaxis(J, 2, 0), -r.T).T
            z[:, k] += dz
            step = np.sqrt(((dz / scale[:, k]) ** 2).sum(axis=0))
            with np.errstate(invalid="ignore"):
                done[k] = tight & (step < rtol)
                at_rtol[k] |= step < 1e3 * crude
            done[k[~np.isfinite(step)]] = True  # lost (NaN): not converged, below
        if done.all():
            break
    return z, done & np.isfinite(z).all(axis=0)

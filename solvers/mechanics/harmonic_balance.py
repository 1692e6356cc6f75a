"""Periodic responses of driven Duffing oscillators by harmonic balance, many parameter sets at once.

The equation is q'' + 2 delta q' + omega0^2 q + alpha q^3 = f0 cos(omega t).  Scaled by the drive phase
tau = omega t, the length Q = f0/(2 omega0 delta) and the detuning omega = omega0 + delta w, and divided
by omega0 delta, it reads

    (1 + d w)^2 x''/d + 2 (1 + d w) x' + x/d + gamma x^3 = 2 cos tau,
    d = delta/omega0,  gamma = alpha Q^2/(omega0 delta),

so a problem is the pair (d, gamma) alone.  The drag and the cubic are odd, so the response that grows
out of the linear one keeps x(tau + pi) = -x(tau): a sum of odd harmonics,
x = sum_k a_k cos k tau + b_k sin k tau (k = 1, 3, ..., 2m - 1).  Each harmonic balances (Galerkin: the
cubic projected by the trapezoidal rule on 8m points, exact for these trigonometric polynomials):

    D_k a_k + 2k (1 + d w) b_k + gamma C_k[x^3] = 2 [k = 1],
    D_k b_k - 2k (1 + d w) a_k + gamma S_k[x^3] = 0,      D_k = (1 - k^2 (1 + d w)^2)/d,

with D_1 = -w (2 + d w) written without the cancellation of 1 - (1 + d w)^2.  Nothing is expanded in a
small parameter: the only truncation is the harmonics beyond the (2m - 1)th, whose size is checked.

The branch of periodic responses (the resonance curve) is parametrized by the phase phi of the
fundamental, (a_1, b_1) = R (cos phi, sin phi): the work of the drive over a period is f0 pi R sin phi
times positive factors and equals the dissipation, so phi runs once through (0, pi) along the whole
curve, through its folds, and at fixed phi the unknowns (R, w, a_3, b_3, ...) solve a square system by
Newton's method.  Along phi: dw/dphi (zero at a fold, where the curve turns back in frequency) and the
swing A (half the peak-to-peak of x, its largest |x| by the symmetry) with dA/dphi, from the tangent
-J^-1 dF/dphi at the converged point.

Along the branch, over many problems at once: ``grid_brackets`` (sign changes of dA/dphi and dw/dphi on a
grid of phases), ``hermite_stationary`` (a start inside a bracket from the grid's values and slopes),
``narrowed`` (a short bracket around that start), ``roots_along`` (Illinois on dA/dphi or dw/dphi),
``least_slope`` (the least dw/dphi between two phases: near a cusp both folds lie between grid phases).

``one_harmonic``: the fundamental alone (no rotating-wave linearization), its peak and folds: an estimate,
a next order over the rotating-wave one, on a fixed grid along the curve.

No physics of one exercise lives here; numpy only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mech.core import budget
from mech.solvers.numerics.batch import illinois
from mech.solvers.numerics.sampled import sparse_extrema

__all__ = ["DuffingBalance", "BranchValues", "grid_brackets", "roots_along", "least_slope", "hermite_stationary",
           "narrowed", "branch_value", "one_harmonic"]

NOISE = 1e-14  # |dA/dphi| or |dw/dphi| (over max(1, |w|)) taken for zero: their round-off is ~3e-15


@dataclass
class BranchValues:
    """What the branch gives at phases phi of the problems idx (arrays over them)."""

    w: np.ndarray  # detuning over delta
    dw: np.ndarray  # dw/dphi: zero at a fold
    A: np.ndarray  # swing over Q
    dA: np.ndarray  # dA/dphi: zero at the largest swing
    tail: np.ndarray  # the highest harmonic's amplitude over the fundamental's
    ok: np.ndarray  # Newton converged


class DuffingBalance:
    """The harmonic-balance system of N problems (arrays ``d``, ``gamma``) with ``harmonics`` odd harmonics.

    ``evaluate(phi, idx)`` solves the problems idx at their phases phi (Newton from the last solution kept
    for each problem, or from the linear response's phase relation at the first call) and returns their
    ``BranchValues``; the solutions are kept as the next starts.  ``newton_steps`` counts the linear solves.
    """

    def __init__(self, d, gamma, *, harmonics: int = 7, tol: float = 1e-13, max_iter: int = 60):
        self.d = np.asarray(d, dtype=float)
        self.gamma = np.asarray(gamma, dtype=float)
        n = self.d.size
        self.m = m = int(harmonics)
        self.k = 2.0 * np.arange(m) + 1.0
        P = 8 * m  # x^3 holds harmonics up to 3(2m - 1): 8m points project it on the first 2m - 1 exactly
        tau = 2.0 * math.pi * np.arange(P) / P
        B = np.empty((P, 2 * m))
        B[:, 0::2] = np.cos(np.outer(tau, self.k))
        B[:, 1::2] = np.sin(np.outer(tau, self.k))
        self.B, self.proj = B, (2.0 / P) * B.T
        self.k2 = self.k * self.k
        self.k2x = np.repeat(2.0 * self.k, 2)
        self.swap = np.arange(2 * m) ^ 1  # a_k <-> b_k
        self.sign = np.tile([1.0, -1.0], m)
        self.eye = np.eye(2 * m)
        # the drag's coupling: +2k(1 + dw) b_k in the cos row, -2k(1 + dw) a_k in the sin row
        self.rot = np.zeros((2 * m, 2 * m))
        self.rot[2 * np.arange(m), 2 * np.arange(m) + 1] = 1.0
        self.rot[2 * np.arange(m) + 1, 2 * np.arange(m)] = -1.0
        self.tol, self.max_iter = float(tol), int(max_iter)
        self.c = np.zeros((n, 2 * m))
        self.w = np.zeros(n)
        self.started = np.zeros(n, dtype=bool)
        self.phi = np.zeros(n)  # the phase of the kept solution
        self.du = np.zeros((n, 2 * m))  # its tangent d(R, w, a_3, b_3, ...)/dphi: the next start's predictor
        self.newton_steps = 0

    def seed(self, mine, other: "DuffingBalance", theirs) -> None:
        """Start the problems ``mine`` from the solutions kept by ``other`` for its problems ``theirs``."""
        for name in ("c", "w", "phi", "du", "started"):
            getattr(self, name)[mine] = getattr(other, name)[theirs]

    def _system(self, c, w, idx):
        """The residual F (n, 2m), dF/dc (n, 2m, 2m) and dF/dw (n, 2m) at coefficients c and detunings w."""
        d, g, k2 = self.d[idx], self.gamma[idx], self.k2
        s = 1.0 + d * w
        D = (1.0 - (s * s)[:, None] * k2) / d[:, None]
        D[:, 0] = -w * (2.0 + d * w)
        damp = s[:, None] * self.k2x  # 2k (1 + d w), each twice: (n, 2m)
        swap = c[:, self.swap] * self.sign  # (b_k, -a_k) interleaved
        x = c @ self.B.T
        x2 = x * x
        F = np.repeat(D, 2, axis=1) * c + damp * swap + g[:, None] * ((x2 * x) @ self.proj.T)
        F[:, 0] -= 2.0
        Fw = np.repeat(-2.0 * s[:, None] * k2, 2, axis=1) * c + d[:, None] * self.k2x * swap  # d/dw
        Jc = (3.0 * g)[:, None, None] * ((self.proj[None, :, :] * x2[:, None, :]) @ self.B)
        Jc += np.repeat(D, 2, axis=1)[:, :, None] * self.eye + damp[:, None, :] * self.rot
        return F, Jc, Fw

    def _bordered(self, Jc, Fw, cp, sp):
        """The Jacobian in the unknowns (R, w, a_3, b_3, ...) at fixed phase."""
        J = Jc.copy()
        J[:, :, 0] = Jc[:, :, 0] * cp[:, None] + Jc[:, :, 1] * sp[:, None]
        J[:, :, 1] = Fw
        return J

    def evaluate(self, phi, idx) -> BranchValues:
        phi = np.asarray(phi, dtype=float)
        idx = np.asarray(idx, dtype=int)
        cp, sp = np.cos(phi), np.sin(phi)
        c, w = self.c[idx].copy(), self.w[idx].copy()
        # from the kept solution moved along its tangent (zero where none was kept)
        step, du0 = phi - self.phi[idx], self.du[idx]
        R = np.hypot(c[:, 0], c[:, 1]) + du0[:, 0] * step
        w += du0[:, 1] * step
        c[:, 2:] += du0[:, 2:] * step[:, None]
        fresh = ~self.started[idx]
        if fresh.any():  # a first start: the undamped linear response's relation between phase and detuning
            c[fresh] = 0.0
            R[fresh] = sp[fresh]
            w[fresh] = -cp[fresh] / sp[fresh]
        c[:, 0], c[:, 1] = R * cp, R * sp
        ok = np.zeros(idx.size, dtype=bool)
        tangent = np.zeros_like(c)
        live = np.arange(idx.size)
        for _ in range(self.max_iter):
            budget.check("harmonic balance (Newton)")
            F, Jc, Fw = self._system(c[live], w[live], idx[live])
            # the Newton step and the tangent d(R, w, a_3, ...)/dphi = -J^-1 dF/dphi, from the same Jacobian: at
            # the last step that is the Jacobian of the iterate one step (below tol) short of the solution
            Fphi = Jc[:, :, 0] * (-R[live] * sp[live])[:, None] + Jc[:, :, 1] * (R[live] * cp[live])[:, None]
            both = np.linalg.solve(self._bordered(Jc, Fw, cp[live], sp[live]), -np.stack([F, Fphi], axis=2))
            du, tangent[live] = both[:, :, 0], both[:, :, 1]
            self.newton_steps += live.size
            R[live] += du[:, 0]
            w[live] += du[:, 1]
            c[live, 2:] += du[:, 2:]
            c[live, 0], c[live, 1] = R[live] * cp[live], R[live] * sp[live]
            step = np.maximum(np.maximum(np.abs(du[:, 0]), np.abs(du[:, 1]) / (1.0 + np.abs(w[live]))),
                              np.max(np.abs(du[:, 2:]), axis=1, initial=0.0))
            done = step <= self.tol * np.maximum(1.0, np.abs(R[live]))
            ok[live[done]] = True
            bad = ~np.isfinite(step)
            live = live[~done & ~bad]
            if live.size == 0:
                break
        out, du = self._along(c, w, R, cp, sp, tangent, ok)
        keep = idx[out.ok]
        self.c[keep], self.w[keep], self.phi[keep], self.du[keep] = c[out.ok], w[out.ok], phi[out.ok], du[out.ok]
        self.started[keep] = True
        return out

    def _along(self, c, w, R, cp, sp, du, ok):
        """The swing and its derivative along the branch at the solved points (``du``: their tangents)."""
        dc = du.copy()
        dc[:, 0] = du[:, 0] * cp - R * sp
        dc[:, 1] = du[:, 0] * sp + R * cp
        # the largest x lies near tau = phi (the fundamental's crest): Newton on x' = 0 there, with
        # x = Re sum z_k e^{i k tau}, z_k = a_k - i b_k
        z = c[:, 0::2] - 1j * c[:, 1::2]
        k = self.k
        tau = np.arctan2(sp, cp)
        for _ in range(3):  # from |tau - phi| ~ 3 |z_3/z_1| < 1e-2: quadratic, below 1e-15 after three
            e = z * np.exp(1j * np.outer(tau, k))
            tau = tau - (e.imag @ k) / (e.real @ self.k2)  # x' = -Im sum k z e, x'' = -Re sum k^2 z e
        e = np.exp(1j * np.outer(tau, k))
        A = (z * e).real.sum(axis=1)
        dA = ((dc[:, 0::2] - 1j * dc[:, 1::2]) * e).real.sum(axis=1)  # x' = 0 at the crest: only c moves A
        tail = np.abs(z[:, -1]) / np.abs(R)
        ok = ok & np.isfinite(du).all(axis=1) & np.isfinite(A) & np.isfinite(dA)
        return BranchValues(w=w, dw=du[:, 1], A=A, dA=dA, tail=tail, ok=ok), du


# -- searches along the branch, over many problems at once ---------------------------------------------------
def grid_brackets(dA, dw):
    """Per variant (rows), from the grid's signs: the peak's interval (index i: [i, i + 1]), the folds'
    intervals (-1 where none) and the failures."""
    up = np.diff(np.sign(dA), axis=1) < 0
    peak = np.argmax(up, axis=1)
    no_peak = up.sum(axis=1) != 1
    neg = dw < 0
    into, out = np.diff(neg.astype(int), axis=1) == 1, np.diff(neg.astype(int), axis=1) == -1
    many = (into.sum(axis=1) > 1) | neg[:, 0] | neg[:, -1]
    has = into.any(axis=1) & ~many
    lo = np.where(has, np.argmax(into, axis=1), -1)
    hi = np.where(has, np.argmax(out, axis=1), -1)
    return peak, lo, hi, no_peak, many


def roots_along(hb, slots, a, b, fa, fb, which, xtol):
    """Illinois on dA (which 0) or dw (which 1) between a and b for the problems ``slots`` of hb; (phi, failed)."""
    failed = np.zeros(slots.size, dtype=bool)

    def f(x, idx):
        v = hb.evaluate(x, slots[idx])
        failed[idx[~v.ok]] = True
        return branch_value(v, which[idx])

    x, conv = illinois(f, a, b, fa, fb, xtol=xtol, rtol=0.0)
    return x, failed | ~conv


def least_slope(hb, lo, hi, xtol):
    """Where dw/dphi is least between lo and hi (a root of its central difference), and its value there."""
    s = 1e-5
    failed = np.zeros(lo.size, dtype=bool)

    def slope(x, idx):
        up, dn = hb.evaluate(x + s, idx), hb.evaluate(x - s, idx)
        failed[idx[~(up.ok & dn.ok)]] = True
        return np.where(up.ok & dn.ok, (up.dw - dn.dw) / (2.0 * s), 0.0)

    everyone = np.arange(lo.size)
    x, conv = illinois(slope, lo, hi, slope(lo, everyone), slope(hi, everyone), xtol=xtol, rtol=0.0)
    v = hb.evaluate(x, everyone)
    return x, v, failed | ~conv | ~v.ok


def hermite_stationary(x0, x1, f0, f1, d0, d1):
    """Where the derivative of the cubic with values f and slopes d at x0, x1 vanishes, within [x0, x1] (the
    midpoint where it does not): a start for a root of d from the grid's values and slopes."""
    h = x1 - x0
    # f' on t in [0, 1] is a quadratic a t^2 + b t + c (Hermite basis)
    c = d0 * h
    b = 6.0 * (f1 - f0) - 4.0 * d0 * h - 2.0 * d1 * h
    a = -6.0 * (f1 - f0) + 3.0 * (d0 + d1) * h
    disc = np.sqrt(np.maximum(b * b - 4.0 * a * c, 0.0))
    with np.errstate(all="ignore"):
        t = np.where(np.abs(a) > 1e-12 * np.abs(b), (-b + np.sign(b + (b == 0)) * -disc) / (2.0 * a), -c / b)
        t2 = np.where(np.abs(a) > 1e-12 * np.abs(b), c / (a * t), t)
    t = np.where((t >= 0) & (t <= 1), t, np.where((t2 >= 0) & (t2 <= 1), t2, 0.5))
    return x0 + t * h


def narrowed(hb, slots, a, b, fa, fb, guess, which, width):
    """Brackets of the roots from a start inside the grid's [a, b]: the start itself where it is a root (within
    round-off), else [start, start -+ width] where that changes sign, else the side of [a, b] it leaves."""
    first = hb.evaluate(guess, slots)
    failed = ~first.ok
    v = branch_value(first, which)
    right = np.sign(v) * np.sign(fa) > 0  # the root lies between the start and b
    end = np.where(right, np.minimum(guess + width, b), np.maximum(guess - width, a))
    y = np.zeros_like(v)
    go = np.flatnonzero(v != 0)
    second = hb.evaluate(end[go], slots[go])
    failed[go] |= ~second.ok
    y[go] = branch_value(second, which[go])
    near = (v != 0) & (np.sign(y) * np.sign(v) < 0)
    far_end, far_val = np.where(right, b, a), np.where(right, fb, fa)
    lo = np.where(v == 0, guess, np.where(near, guess, np.where(right, end, far_end)))
    hi = np.where(v == 0, guess, np.where(near, end, np.where(right, far_end, end)))
    flo = np.where(v == 0, 0.0, np.where(near, v, np.where(right, y, far_val)))
    fhi = np.where(v == 0, 0.0, np.where(near, y, np.where(right, far_val, y)))
    return lo, hi, flo, fhi, failed


def branch_value(v, which):
    """dA/dphi (which 0) or dw/dphi (which 1), zero within round-off (about 1e-15 of the terms summed) and where
    Newton failed (the caller keeps that failure)."""
    y = np.where(which == 0, v.dA, v.dw)
    return np.where(v.ok & (np.abs(y) > NOISE * np.maximum(1.0, np.abs(v.w))), y, 0.0)


_U = 1.0 - np.geomspace(0.999, 1e-8, 6001)  # the fold search's grid in s/s_top (``one_harmonic``)


def one_harmonic(omega0, delta, alpha, f0, where=None):
    """q'' + 2 delta q' + omega0^2 q + alpha q^3 = f0 cos(omega t) in one harmonic over arrays of problems:
    q = A cos(omega t - phi) balanced without the rotating-wave linearization (omega^2 - omega0^2 kept whole,
    the drag 2 delta omega):
        A^2 [(omega0^2 - omega^2 + 3 alpha A^2/4)^2 + 4 delta^2 omega^2] = f0^2
    (Nayfeh & Mook, Nonlinear Oscillations, sec. 4.1; Landau & Lifshitz, Mechanics, sec. 29).  The peak
    (dA/domega = 0): omega0^2 - omega^2 + 3 alpha A^2/4 = 2 delta^2, A = f0/(2 delta sqrt(omega^2 + delta^2));
    the folds (only where ``where``): the extrema of omega along the curve, parametrized by s = A^2.  Returns
    (the peak's A, its omega - omega0, the folds' least and greatest omega - omega0), the folds NaN where this
    curve has no two."""
    o0, d, al, f0 = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (omega0, delta, alpha, f0)))
    w, d2, dd, oo, q, r = o0, 2.0 * d, d * d, o0 * o0, 0.75 * al, 2.0 * d * d
    for _ in range(60):  # at a fixed point to the last bit every further pass gives the same: stop there
        A = f0 / (d2 * np.sqrt(w * w + dd))
        w, last = np.sqrt(np.maximum(oo + q * A * A - r, 1e-300)), w
        if (w == last).all():
            break
    out = [A, w - o0, np.full(o0.size, np.nan), np.full(o0.size, np.nan)]  # the folds flat
    rows = np.flatnonzero(np.ones(o0.size, dtype=bool) if where is None else where)
    if not rows.size:
        return out
    o0, d, al, f0 = (np.ravel(v) for v in (o0, d, al, f0))
    # s = A^2 (1 - u), u geometric: the upper fold lies within (delta/omega0)^2 of the tip at high Q
    # the tip, where the two branches meet: f0^2 = 4 delta^2 s (omega0^2 + 3 alpha s/4)
    o0, d, al, f0 = o0[rows], d[rows], al[rows], f0[rows]
    d4o4 = np.float_power(d, 4) * np.float_power(o0, 4)  # pow's, as for one float (an array's x**4 differs in ulps)
    s_top = 2.0 * f0 * f0 / (4.0 * d * d * o0 * o0 + np.sqrt(16.0 * d4o4 + 12.0 * al * d * d * f0 * f0))

    def omega(r, i):  # both halves of the curve (r = 2 k + half), 20 passes of its fixed point, at s_i
        k, sign = r // 2, np.where(r % 2 == 0, 1.0, -1.0)
        s, w0, dd, a, ff = _U[i] * s_top[k], o0[k], d[k], al[k], f0[k]
        ws, fs, d4, c = w0, ff * ff / s, 4.0 * dd * dd, w0 * w0 + 0.75 * a * s
        for _ in range(20):
            arg = fs - d4 * ws * ws
            ws = np.sqrt(np.maximum(c + sign * np.sqrt(np.maximum(arg, 0.0)), 1e-300))
        return np.where(arg > 0, ws - w0, np.nan)

    r, ext = sparse_extrema(omega, 2 * rows.size, _U.size, 25)
    lo, hi = np.full(rows.size, np.inf), np.full(rows.size, -np.inf)
    np.minimum.at(lo, r // 2, ext)
    np.maximum.at(hi, r // 2, ext)
    two = np.bincount(r // 2, minlength=rows.size) >= 2  # the outermost: round-off wiggles near the tip can add more
    out[2][rows[two]], out[3][rows[two]] = lo[two], hi[two]
    return out

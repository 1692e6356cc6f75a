"""Rotating-frame machinery for the restricted three-body problem and kin.

Units: lengths in the bodies' separation d, times in 1/Omega, masses in M1 + M2
(so G (M1 + M2) = 1 and Omega = 1).  The heavier or first body (mass fraction
nu = M1/(M1+M2)) sits at x = -mu, the other (mu = M2/(M1+M2)) at x = nu; both
fractions are passed separately so that neither is formed as 1 - other.

The effective potential per unit mass is U = -nu/r1 - mu/r2 - (x^2 + y^2)/2.
Because the origin is the center of mass, r = nu d1 + mu d2 (d_k = r - r_k),
and its gradient is written without the O(1) cancellation between gravity and
the centrifugal term:
    grad U = nu (r1^-3 - 1) d1 + mu (r2^-3 - 1) d2.
The Hessian likewise: H = sum_k m_k [(r_k^-3 - 1) I - 3 d_k d_k^T / r_k^5]
(exact second derivatives, no finite differences).

Also here: a bracket search that walks from a start toward a geometric limit
until the sign changes, a bracketed root (brentq to the last bits), Newton's
method on the gradient for an off-axis equilibrium, and the characteristic
exponents of the linearized rotating-frame motion with an error estimate that
stays honest near a defective (merging) pair.
"""

from __future__ import annotations

import math
import struct
from dataclasses import dataclass
from typing import Callable

import numpy as np

from mech.problems.spec import NumericFailure

__all__ = [
    "mass_fractions",
    "walk_to_sign_change",
    "bracketed_root",
    "grad_eff",
    "hess_eff",
    "hess_eigen",
    "newton_equilibrium",
    "linearized_matrix",
    "Exponents",
    "characteristic_exponents",
]

EPS = np.finfo(float).eps


def mass_fractions(M1: float, M2: float) -> tuple[float, float]:
    """(nu, mu) = (M1, M2)/(M1 + M2), each to full relative precision."""
    total = M1 + M2
    return M1 / total, M2 / total


def walk_to_sign_change(
    f: Callable[[float], float], start: float, step: Callable[[float], float], sign: float, max_steps: int = 4000
) -> float:
    """From ``start``, apply ``step`` until ``f`` has the given sign; the walk is the caller's geometry
    (halving toward a body, doubling toward infinity).  Failing to get there is a failure, not a guess."""
    x = start
    for _ in range(max_steps):
        v = f(x)
        if v != 0.0 and math.copysign(1.0, v) == sign:
            return x
        nxt = step(x)
        if nxt == x:
            break
        x = nxt
    raise NumericFailure(f"no sign change found walking from {start:g} (stopped at {x:.17g})")


def _float_key(x: float) -> int:
    """An integer that orders like the float (for x >= 0: its bit pattern)."""
    return struct.unpack("<q", struct.pack("<d", x))[0]


def _key_float(k: int) -> float:
    return struct.unpack("<d", struct.pack("<q", k))[0]


def bracketed_root(f: Callable[[float], float], lo: float, hi: float) -> float:
    """The root of ``f`` in [lo, hi] (opposite signs required), to the last bit.

    Bisection on the floats' bit patterns: at most ~64 halvings whatever the
    magnitude of the root (1e-30 or 1e3), and no scipy import."""
    flo, fhi = f(lo), f(hi)
    if flo == 0.0:
        return lo
    if fhi == 0.0:
        return hi
    if (flo > 0) == (fhi > 0):
        raise NumericFailure(f"root not bracketed in [{lo:.17g}, {hi:.17g}]: f = {flo:.3g}, {fhi:.3g}")
    if lo < 0.0 < hi:  # split at zero so that both ends share a sign
        f0 = f(0.0)
        if f0 == 0.0:
            return 0.0
        if (f0 > 0) == (flo > 0):
            lo, flo = 0.0, f0
        else:
            hi = 0.0
    neg = hi <= 0.0
    a, b = (0.0 - hi, 0.0 - lo) if neg else (lo + 0.0, hi + 0.0)  # 0 <= a < b (no -0.0); g(t) = f(+-t)
    fa_pos = (flo > 0) if not neg else (fhi > 0)
    ka, kb = _float_key(a), _float_key(b)
    while kb - ka > 1:
        km = (ka + kb) // 2
        m = _key_float(km)
        fm = f(-m if neg else m)
        if fm == 0.0:
            return -m if neg else m
        if (fm > 0) == fa_pos:
            ka = km
        else:
            kb = km
    a, b = _key_float(ka), _key_float(kb)
    fa, fb = f(-a if neg else a), f(-b if neg else b)
    best = a if abs(fa) <= abs(fb) else b
    return -best if neg else best


def _offsets(r: np.ndarray, mu: float, nu: float):
    d1 = np.array([r[0] + mu, r[1]])
    d2 = np.array([r[0] - nu, r[1]])
    return d1, d2, math.hypot(*d1), math.hypot(*d2)


def grad_eff(r, mu: float, nu: float) -> np.ndarray:
    """Gradient of U_eff in the plane (scaled units), cancellation-free."""
    d1, d2, r1, r2 = _offsets(np.asarray(r, float), mu, nu)
    return nu * (r1**-3 - 1.0) * d1 + mu * (r2**-3 - 1.0) * d2


def hess_eff(r, mu: float, nu: float) -> np.ndarray:
    """Exact Hessian of U_eff in the plane (scaled units)."""
    d1, d2, r1, r2 = _offsets(np.asarray(r, float), mu, nu)
    H = np.zeros((2, 2))
    for m, d, rk in ((nu, d1, r1), (mu, d2, r2)):
        H += m * ((rk**-3 - 1.0) * np.eye(2) - 3.0 * np.outer(d, d) / rk**5)
    return H


def hess_eigen(r, mu: float, nu: float) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues and eigenvectors of the Hessian, each eigenvalue to its own relative precision.

    In the frame (n1, t1) of the direction from body 1 the first body's part is
    diagonal, nu [(r1^-3 - 1 - 3 r1^-3), (r1^-3 - 1)], so the weak curvature along
    t1 (of order mu near L4) is not the difference of O(1) numbers; the 2x2 is then
    diagonalized with the small eigenvalue taken as det / large one."""
    d1, d2, r1, r2 = _offsets(np.asarray(r, float), mu, nu)
    n1 = d1 / r1
    t1 = np.array([-n1[1], n1[0]])
    R = np.column_stack([n1, t1])
    A2 = (r2**-3 - 1.0) * np.eye(2) - 3.0 * np.outer(d2, d2) / r2**5
    B = mu * (R.T @ A2 @ R)
    a = nu * (r1**-3 - 1.0 - 3.0 * r1**-3) + B[0, 0]
    c = nu * (r1**-3 - 1.0) + B[1, 1]
    b = B[0, 1]
    half = 0.5 * (a - c)
    rad = math.hypot(half, b)
    det = a * c - b * b
    if a + c >= 0.0:
        plus = 0.5 * (a + c) + rad
        minus = det / plus if plus != 0.0 else 0.0
    else:
        minus = 0.5 * (a + c) - rad
        plus = det / minus
    ang = 0.5 * math.atan2(2.0 * b, a - c)  # (cos, sin) of ang in (n1, t1) belongs to `plus`
    cs, sn = math.cos(ang), math.sin(ang)
    Q = R @ np.array([[cs, -sn], [sn, cs]])
    lam0, lam1 = plus, minus
    return np.array([lam0, lam1]), Q


def newton_equilibrium(r0, mu: float, nu: float, max_iter: int = 200, max_step: float = 0.1) -> tuple[np.ndarray, int]:
    """A maximum of U_eff by Newton's method on its gradient (exact Hessian).

    Far from the maximum the Hessian need not be negative definite, and a plain
    Newton step would head for a saddle: each step uses the Hessian with its
    eigenvalues made negative (|lambda| flipped) and is capped at ``max_step``
    (units of d).  Converged when the step stops
    shrinking at the round-off level; returns (point, iterations)."""
    r = np.asarray(r0, float).copy()
    g = grad_eff(r, mu, nu)
    last = math.inf
    for it in range(1, max_iter + 1):
        w, V = hess_eigen(r, mu, nu)
        w = -np.maximum(np.abs(w), 1e-300)
        step = -(V @ ((V.T @ g) / w))
        size = float(np.linalg.norm(step))
        if size > max_step:
            step *= max_step / size
        trial = r + step
        gt = grad_eff(trial, mu, nu)
        size = float(np.linalg.norm(trial - r))
        r, g = trial, gt
        if size <= 4 * EPS * max(1.0, float(np.linalg.norm(r))) or (size >= last and size < 1e-12):
            return r, it
        last = size
    raise NumericFailure(f"Newton's method on grad U_eff did not converge in {max_iter} iterations")


def linearized_matrix(H: np.ndarray) -> np.ndarray:
    """The 4x4 first-order matrix of small in-plane motion about an equilibrium (scaled, Omega = z):
    x'' - 2 y' = -H_xx x - H_xy y,  y'' + 2 x' = -H_xy x - H_yy y."""
    A = np.zeros((4, 4))
    A[0, 2] = A[1, 3] = 1.0
    A[2:, :2] = -H
    A[2, 3] = 2.0
    A[3, 2] = -2.0
    return A


@dataclass
class Exponents:
    """Characteristic exponents (scaled) with error estimates.

    growth: largest Re; slow, fast: smallest and largest |Im|; err_*: absolute
    error estimates of each (first-order perturbation theory, capped by the
    square-root law that holds where two exponents merge)."""

    values: np.ndarray
    growth: float
    slow: float
    fast: float
    err_growth: float
    err_slow: float
    err_fast: float


def characteristic_exponents(H: np.ndarray) -> Exponents:
    """Eigenvalues of the linearized rotating-frame matrix, and how far round-off can move them.

    The eigenvalues come in pairs lambda^2 = Lambda with two values Lambda_1, 2.  A
    perturbation of the entries by e (relative round-off of H and the backward
    error of the eigen-solver) moves Lambda by ~ (|Lambda| + 1) e / |Lambda_1 - Lambda_2|,
    but never by more than ~ 2 ((|Lambda| + 1) e)^(1/2) (the merging, defective case);
    the exponents move by dLambda / (2 |lambda|), capped by dLambda^(1/2)."""
    A = linearized_matrix(H)
    lam = np.linalg.eigvals(A)
    scale = max(1.0, float(np.max(np.abs(H))))
    e = 16.0 * EPS * scale * scale
    Lam = lam**2
    # the two distinct Lambda values: pair the exponents by their squares
    order = np.argsort(np.abs(lam.imag))
    L_slow, L_fast = Lam[order[0]], Lam[order[-1]]
    sep = abs(L_fast - L_slow)

    def dLam(L):
        first = (abs(L) + 1.0) * e / sep if sep > 0 else math.inf
        return min(first, 2.0 * math.sqrt((abs(L) + 1.0) * e))

    def d_exp(L, size):
        dl = dLam(L)
        return min(dl / (2.0 * size), math.sqrt(dl)) if size > 0 else math.sqrt(dl)

    im = np.abs(lam.imag)
    growth = float(np.max(lam.real))
    slow, fast = float(np.min(im)), float(np.max(im))
    return Exponents(
        values=lam,
        growth=growth,
        slow=slow,
        fast=fast,
        err_growth=max(d_exp(L_slow, abs(lam[order[0]])), d_exp(L_fast, abs(lam[order[-1]]))),
        err_slow=d_exp(L_slow, abs(lam[order[0]])),
        err_fast=d_exp(L_fast, abs(lam[order[-1]])),
    )

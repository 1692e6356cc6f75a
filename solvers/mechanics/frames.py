"""Frames and rotations: every rotation in mech, and the co-rotating frame of two bodies.

Rotations (lab = R @ body throughout):
* ``skew(v)``: the matrix of v x (.); ``rotation(axis, angle)``: Rodrigues' formula (a complex angle
  is allowed, for complex-step derivatives); ``rotate2``/``cross_z``: the same in the plane.
* Unit quaternions (w, x, y, z): ``quat_mul``, ``quat_to_matrix`` (one quaternion or 4 x N of them),
  ``quat_from_axis_angle``, ``quat_from_matrix`` (Shepperd), ``quat_aligning`` (the shortest turn of
  one direction onto another), ``rotate_many`` (lab components along a sampled attitude).

The co-rotating frame of the restricted three-body problem:
units: lengths in the bodies' separation d, times in 1/Omega, masses in M1 + M2
(so G (M1 + M2) = 1 and Omega = 1).  The heavier or first body (mass fraction
nu = M1/(M1+M2)) sits at x = -mu, the other (mu = M2/(M1+M2)) at x = nu; both
fractions are passed separately so that neither is formed as 1 - other.

The effective potential per unit mass is U = -nu/r1 - mu/r2 - (x^2 + y^2)/2.
Because the origin is the center of mass, r = nu d1 + mu d2 (d_k = r - r_k),
and its gradient is written without the O(1) cancellation between gravity and
the centrifugal term:
    grad U = nu (r1^-3 - 1) d1 + mu (r2^-3 - 1) d2.
The Hessian likewise: H = sum_k m_k [(r_k^-3 - 1) I - 3 d_k d_k^T / r_k^5]
(exact second derivatives, no finite differences).  Also here: Newton's method
in polar coordinates for an off-axis equilibrium, and the characteristic
exponents of the linearized rotating-frame motion with an error estimate that
stays honest near a defective (merging) pair.  (The bracket walk and the
bit-exact bracketed root these exercises use live in ``numerics.roots``.)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mech.core.errors import NumericFailure

__all__ = [
    "skew",
    "rotation",
    "rotate2",
    "cross_z",
    "quat_mul",
    "quat_to_matrix",
    "quat_from_axis_angle",
    "quat_from_matrix",
    "quat_aligning",
    "rotate_many",
    "mass_fractions",
    "grad_eff",
    "hess_eff",
    "polar_derivatives",
    "polar_hessian_at",
    "newton_equilibrium",
    "linearized_matrix",
    "Exponents",
    "characteristic_exponents",
]

EPS = np.finfo(float).eps


# ---------------------------------------------------------------------------------------------
# Rotations
# ---------------------------------------------------------------------------------------------


def skew(v) -> np.ndarray:
    """The matrix K with K @ u = v x u."""
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def rotation(axis, angle) -> np.ndarray:
    """The rotation matrix by ``angle`` about ``axis`` (Rodrigues); a complex angle gives the analytic
    continuation (complex-step derivatives)."""
    a = np.asarray(axis, dtype=float)
    K = skew(a / np.linalg.norm(a))
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * (K @ K)


def cross_z(omega: float, r: np.ndarray) -> np.ndarray:
    """omega z x r for plane vectors r (shape (..., 2))."""
    r = np.asarray(r, dtype=float)
    return omega * np.stack([-r[..., 1], r[..., 0]], axis=-1)


def rotate2(r: np.ndarray, angle: float) -> np.ndarray:
    """Plane vectors r (shape (..., 2)) turned counterclockwise by ``angle``."""
    r = np.asarray(r, dtype=float)
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * r[..., 0] - s * r[..., 1], s * r[..., 0] + c * r[..., 1]], axis=-1)


def quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    a0, a1, a2, a3 = a
    b0, b1, b2, b3 = b
    return np.array(
        [
            a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
            a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
            a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1,
            a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0,
        ]
    )


def quat_to_matrix(q: np.ndarray) -> np.ndarray:
    """The rotation matrix R (lab = R @ body) of a quaternion, normalized first; for 4 x N quaternions
    the 3 x 3 x N stack."""
    q = np.asarray(q, dtype=float)
    w, x, y, z = q / (np.linalg.norm(q) if q.ndim == 1 else np.linalg.norm(q, axis=0))
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def quat_from_axis_angle(axis, angle: float) -> np.ndarray:
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    return np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * a])


def quat_from_matrix(Rm) -> np.ndarray:
    """Unit quaternion of a rotation matrix (Shepperd's method: the largest diagonal term first)."""
    tr = np.trace(Rm)
    cands = [tr, Rm[0, 0], Rm[1, 1], Rm[2, 2]]
    k = int(np.argmax(cands))
    if k == 0:
        w = 0.5 * math.sqrt(1 + tr)
        q = [w, (Rm[2, 1] - Rm[1, 2]) / (4 * w), (Rm[0, 2] - Rm[2, 0]) / (4 * w), (Rm[1, 0] - Rm[0, 1]) / (4 * w)]
    elif k == 1:
        x = 0.5 * math.sqrt(1 + 2 * Rm[0, 0] - tr)
        q = [(Rm[2, 1] - Rm[1, 2]) / (4 * x), x, (Rm[0, 1] + Rm[1, 0]) / (4 * x), (Rm[0, 2] + Rm[2, 0]) / (4 * x)]
    elif k == 2:
        y = 0.5 * math.sqrt(1 + 2 * Rm[1, 1] - tr)
        q = [(Rm[0, 2] - Rm[2, 0]) / (4 * y), (Rm[0, 1] + Rm[1, 0]) / (4 * y), y, (Rm[1, 2] + Rm[2, 1]) / (4 * y)]
    else:
        z = 0.5 * math.sqrt(1 + 2 * Rm[2, 2] - tr)
        q = [(Rm[1, 0] - Rm[0, 1]) / (4 * z), (Rm[0, 2] + Rm[2, 0]) / (4 * z), (Rm[1, 2] + Rm[2, 1]) / (4 * z), z]
    q = np.array(q)
    return q / np.linalg.norm(q)


def quat_aligning(v, target=(0.0, 0.0, 1.0)) -> np.ndarray:
    """The quaternion of the shortest rotation taking the direction of ``v`` to that of ``target``."""
    a = np.asarray(v, dtype=float) / np.linalg.norm(v)
    b = np.asarray(target, dtype=float) / np.linalg.norm(target)
    axis = np.cross(a, b)
    s = np.linalg.norm(axis)
    c = float(a @ b)
    if s == 0.0:
        if c > 0:
            return np.array([1.0, 0.0, 0.0, 0.0])
        # antiparallel: any axis perpendicular to a
        perp = np.cross(a, [1.0, 0.0, 0.0] if abs(a[0]) < 0.9 else [0.0, 1.0, 0.0])
        return np.concatenate([[0.0], perp / np.linalg.norm(perp)])
    angle = np.arctan2(s, c)
    return np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * axis / s])


def rotate_many(q, v) -> np.ndarray:
    """Lab components (3 x N) of body vectors ``v`` (3 or 3 x N) for quaternions ``q`` (4 x N)."""
    q = np.asarray(q, dtype=float)
    v = np.asarray(v, dtype=float)
    if v.ndim == 1:
        v = v[:, None]
    return np.einsum("ijn,jn->in", quat_to_matrix(q), np.broadcast_to(v, (3, q.shape[1])))


# ---------------------------------------------------------------------------------------------
# The co-rotating frame of two bodies
# ---------------------------------------------------------------------------------------------


def mass_fractions(M1: float, M2: float) -> tuple[float, float]:
    """(nu, mu) = (M1, M2)/(M1 + M2), each to full relative precision."""
    total = M1 + M2
    return M1 / total, M2 / total


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


def polar_derivatives(rho: float, theta: float, mu: float, nu: float):
    """Gradient and Hessian of U_eff in polar coordinates (rho, theta) about body 1, cancellation-free.

    With n1 = (cos theta, sin theta), t1 its normal, d2 = rho n1 - (1, 0) and
    a2 = mu (r2^-3 - 1): body 1's part of the gradient is radial, so
      U_rho = nu (rho^-3 - 1) rho + a2 (d2 . n1),   U_theta = rho a2 (d2 . t1),
    and body 1's radial force drops out of the angular curvature too:
      U_rho,rho = nu (-2 rho^-3 - 1) + B_nn,  U_rho,theta = rho B_nt + a2 (d2 . t1),
      U_theta,theta = rho^2 B_tt - rho a2 (d2 . n1),
    B = mu (n1, t1)^T [(r2^-3 - 1) I - 3 d2 d2^T / r2^5] (n1, t1).  Every angular
    entry carries the factor mu, to its own relative precision."""
    c, s = math.cos(theta), math.sin(theta)
    n1, t1 = np.array([c, s]), np.array([-s, c])
    d2 = np.array([rho * c - 1.0, rho * s])
    r2 = math.hypot(*d2)
    a2 = mu * (r2**-3 - 1.0)
    d2n, d2t = float(d2 @ n1), float(d2 @ t1)
    A2 = (r2**-3 - 1.0) * np.eye(2) - 3.0 * np.outer(d2, d2) / r2**5
    Rm = np.column_stack([n1, t1])
    B = mu * (Rm.T @ A2 @ Rm)
    g = np.array([nu * (rho**-3 - 1.0) * rho + a2 * d2n, rho * a2 * d2t])
    H = np.array([
        [nu * (-2.0 * rho**-3 - 1.0) + B[0, 0], rho * B[0, 1] + a2 * d2t],
        [rho * B[0, 1] + a2 * d2t, rho * rho * B[1, 1] - rho * a2 * d2n],
    ])
    return g, H


def polar_hessian_at(r, mu: float, nu: float) -> tuple[float, np.ndarray]:
    """(rho, Hessian of U_eff in (rho, theta) about the heavier body) at the point r of the scaled plane.

    At a stationary point det H_polar = rho^2 det H (the gradient term of the change
    of coordinates vanishes), and here the angular entries keep their relative
    precision where the Cartesian ones carry eps next to a curvature of order mu.
    With body 2 the heavier the mirror image x -> -x is used (it swaps the bodies)."""
    r = np.asarray(r, float)
    if mu > nu:
        r, mu, nu = np.array([-r[0], r[1]]), nu, mu
    rho, theta = math.hypot(r[0] + mu, r[1]), math.atan2(r[1], r[0] + mu)
    return rho, polar_derivatives(rho, theta, mu, nu)[1]


def newton_equilibrium(r0, mu: float, nu: float, max_iter: int = 200, max_step: float = 0.1) -> tuple[np.ndarray, int]:
    """A maximum of U_eff off the line of the bodies, by Newton's method (exact derivatives).

    The iteration runs in polar coordinates (rho, theta) about body 1: for a small
    mass ratio U_eff is nearly flat along the circle rho = d, and in Cartesian
    coordinates the weak angular curvature (of order mu) is swamped by body 1's
    radial force times the circle's curvature (a radial offset of 1e-5 outweighs
    mu = 1e-5; at mu < 1e-25 the iteration stopped at a point that was no
    equilibrium, and at mu = 4.4e-5 capped steps cycled).  In polar form every
    angular entry is proportional to mu (polar_derivatives), so the angular
    Newton step is of order one for any mu.  The angular curvature is the Schur
    complement U_tt - U_rt^2 / U_rr; a non-negative one (or U_rr) is flipped
    so every step climbs.  Steps are capped at ``max_step`` in rho (units of d)
    and 2 max_step in theta, and the angular cap halves whenever the angular
    gradient changes sign (the maximum was stepped over).  Converged when the
    step stops shrinking at the round-off level; returns (point, iterations).
    With body 2 the heavier, the flat circle is about body 2: the iteration runs on
    the mirror image x -> -x, which swaps the bodies and keeps y."""
    r0 = np.asarray(r0, float)
    if mu > nu:
        r, it = _newton_polar(np.array([-r0[0], r0[1]]), nu, mu, max_iter, max_step)
        return np.array([-r[0], r[1]]), it
    return _newton_polar(r0, mu, nu, max_iter, max_step)


def _newton_polar(r0, mu, nu, max_iter, max_step):
    from mech.core import budget

    rho, theta = math.hypot(r0[0] + mu, r0[1]), math.atan2(r0[1], r0[0] + mu)
    cap_theta = 2.0 * max_step
    last = math.inf
    g_theta_last = None
    for it in range(1, max_iter + 1):
        budget.check("Newton's method for an equilibrium")
        g, H = polar_derivatives(rho, theta, mu, nu)
        h_rr = -abs(H[0, 0])
        schur = H[1, 1] - H[0, 1] * H[0, 1] / h_rr
        schur = -max(abs(schur), 1e-300)
        d_theta = -(g[1] - H[0, 1] * g[0] / h_rr) / schur
        if g_theta_last is not None and g[1] * g_theta_last < 0.0:
            cap_theta *= 0.5
        g_theta_last = g[1]
        if abs(d_theta) > cap_theta:
            d_theta = math.copysign(cap_theta, d_theta)
        d_rho = -(g[0] + H[0, 1] * d_theta) / h_rr
        if abs(d_rho) > max_step:
            d_rho = math.copysign(max_step, d_rho)
        rho, theta = rho + d_rho, theta + d_theta
        size = math.hypot(d_rho, rho * d_theta)
        if size <= 4 * EPS * max(1.0, rho) or (size >= last and size < 1e-12):
            return np.array([rho * math.cos(theta) - mu, rho * math.sin(theta)]), it
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


def potential_eff(x, y, mu: float, nu: float):
    """U_eff = -nu/r1 - mu/r2 - (x^2 + y^2)/2 in the plane (scaled units; arrays welcome): gravity of the
    two bodies and the centrifugal term, for pictures of the rotating frame (its gradient is ``grad_eff``)."""
    with np.errstate(divide="ignore"):  # -inf at a body's own place
        return -nu / np.hypot(x + mu, y) - mu / np.hypot(x - nu, y) - 0.5 * (x * x + y * y)

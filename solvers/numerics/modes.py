"""Small oscillations: mass and stiffness matrices built numerically from T and U, then the modes.

The kinetic energy is a quadratic form in the velocities, so its matrix follows
exactly (to round-off) by polarization.  The potential's Hessian is taken by
central differences with one Richardson step (error O(h^4) plus round-off
~ eps |U| / h^2); pass ``scale``, the length over which U changes, so the step
suits the problem.
"""

from __future__ import annotations

import math

from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from mech.core.errors import NumericFailure

__all__ = ["mass_matrix", "hessian", "gradient", "normal_modes", "Modes", "pair_shapes", "pair_roots", "solve3"]


def mass_matrix(T: Callable[[np.ndarray, np.ndarray], float], q0: Sequence[float]) -> np.ndarray:
    """``M`` with ``T(q0, v) = v.M.v / 2``, by polarization of the quadratic form (exact for a quadratic)."""
    q0 = np.asarray(q0, dtype=float)
    n = q0.size
    eye = np.eye(n)
    diag = np.array([T(q0, eye[i]) for i in range(n)])
    M = np.diag(2.0 * diag)
    for i in range(n):
        for j in range(i + 1, n):
            M[i, j] = M[j, i] = T(q0, eye[i] + eye[j]) - diag[i] - diag[j]
    return M


def _steps(q0: np.ndarray, scale) -> np.ndarray:
    s = np.broadcast_to(np.asarray(scale, dtype=float), q0.shape)
    return 1e-3 * s


def gradient(U: Callable[[np.ndarray], float], q0: Sequence[float], scale=1.0) -> np.ndarray:
    """Gradient by fourth-order central differences."""
    q0 = np.asarray(q0, dtype=float)
    h = _steps(q0, scale)
    g = np.empty(q0.size)
    for i in range(q0.size):
        e = np.zeros(q0.size)
        e[i] = h[i]
        g[i] = (8 * (U(q0 + e) - U(q0 - e)) - (U(q0 + 2 * e) - U(q0 - 2 * e))) / (12 * h[i])
    return g


def hessian(U: Callable[[np.ndarray], float], q0: Sequence[float], scale=1.0) -> np.ndarray:
    """Hessian of ``U`` at ``q0`` by central differences at steps h and h/2, Richardson-combined."""
    q0 = np.asarray(q0, dtype=float)
    n = q0.size
    h0 = _steps(q0, scale)

    def at(h):
        H = np.empty((n, n))
        u0 = U(q0)
        for i in range(n):
            ei = np.zeros(n)
            ei[i] = h[i]
            H[i, i] = (U(q0 + ei) - 2 * u0 + U(q0 - ei)) / h[i] ** 2
            for j in range(i + 1, n):
                ej = np.zeros(n)
                ej[j] = h[j]
                H[i, j] = H[j, i] = (
                    U(q0 + ei + ej) - U(q0 + ei - ej) - U(q0 - ei + ej) + U(q0 - ei - ej)
                ) / (4 * h[i] * h[j])
        return H

    coarse, fine = at(h0), at(h0 / 2)
    return fine + (fine - coarse) / 3.0


@dataclass
class Modes:
    """Normal modes: ``omega2`` ascending; ``shapes[:, k]`` is mode k, scaled to largest component +1."""

    omega2: np.ndarray
    shapes: np.ndarray

    @property
    def omega(self) -> np.ndarray:
        """Angular frequencies; NaN where omega^2 < 0 (an unstable direction)."""
        with np.errstate(invalid="ignore"):
            return np.where(self.omega2 >= 0, np.sqrt(np.abs(self.omega2)), np.nan)

    @property
    def stable(self) -> bool:
        return bool(np.all(self.omega2 > 0))


def normal_modes(M: np.ndarray, K: np.ndarray) -> Modes:
    """Solve ``K a = omega^2 M a`` (the generalized symmetric eigenproblem).

    Reduced to a standard one with the Cholesky factor M = C C^T (what LAPACK's
    sygv does): C^-1 K C^-T b = omega^2 b, a = C^-T b.  numpy alone: scipy.linalg
    would cost 0.3 s of import, as much as the rest of a ``mech solve``.
    """
    M = np.atleast_2d(np.asarray(M, dtype=float))
    K = np.atleast_2d(np.asarray(K, dtype=float))
    K = 0.5 * (K + K.T)
    try:
        C = np.linalg.cholesky(0.5 * (M + M.T))
    except np.linalg.LinAlgError as exc:
        raise NumericFailure("the mass matrix is not positive definite") from exc
    Ci = np.linalg.inv(C)
    A = Ci @ K @ Ci.T
    w2, b = np.linalg.eigh(0.5 * (A + A.T))
    vecs = Ci.T @ b
    order = np.argsort(w2)
    w2, vecs = w2[order], vecs[:, order]
    for k in range(vecs.shape[1]):
        i = int(np.argmax(np.abs(vecs[:, k])))
        vecs[:, k] /= vecs[i, k]
    return Modes(omega2=w2, shapes=vecs)


_U = 2.0**-53


def _pow2(x: float) -> float:
    """The power of two nearest below ``x`` (1 for 0, infinite or NaN ``x``): a scale that divides exactly."""
    if not (x > 0.0 and math.isfinite(x)):
        return 1.0
    return math.ldexp(1.0, math.frexp(x)[1] - 1)


def pair_shapes(M: np.ndarray, K: np.ndarray, omega2: Sequence[float], omega2_err: Sequence[float]) -> np.ndarray:
    """The two mode shapes of a 2x2 problem K a = omega^2 M a, each from one row of (K - omega^2 M) a = 0.

    An eigensolver's vector errs by u over the relative gap in every component, so a component of
    relative size 1e-100 (a light body beside one 1e200 times heavier, in balanced coordinates) comes out
    as noise.  A row (r1, r2) of K - omega^2 M gives the direction a = (-r2, r1) to the relative accuracy
    of the row itself: its entries' rounding u (|K_i| + |omega^2| |M_i|) plus the eigenvalue's error
    times |M_i|.  Each mode takes the row in which that error is the smaller fraction of the row: the
    row that does not cancel (for 4.11's heavy block the cylinder's row, M_2 . a = 0 exactly when K_2 = 0).
    Columns are scaled to their largest component +1, as ``normal_modes`` does.
    """
    M = np.asarray(M, dtype=float)
    K = np.asarray(K, dtype=float)
    shapes = np.empty((2, 2))
    for k, (lam, dlam) in enumerate(zip(omega2, omega2_err)):
        best = None
        for i in range(2):
            # the row scaled by a power of two near its size (exact, so no digit moves): a row of omega^2 M
            # near 1e-300 (4.11's block 1e300 times the cylinder) would lose its small entry to underflow
            c = _pow2(max(float(np.max(np.abs(K[i]))), abs(lam) * float(np.max(np.abs(M[i])))))
            r = K[i] / c - (lam / c) * M[i]
            size = float(np.max(np.abs(r)))
            err = (4.0 * _U * float(np.max(np.abs(K[i]) / c + abs(lam / c) * np.abs(M[i])))
                   + (dlam / c) * float(np.max(np.abs(M[i]))))
            if size == 0.0 or not np.isfinite(size):
                continue
            score = err / size
            if best is None or score < best[0]:
                best = (score, np.array([-r[1], r[0]]))
        if best is None:
            raise NumericFailure(f"mode {k}: K - omega^2 M vanishes in both rows")
        a = best[1]
        shapes[:, k] = a / a[int(np.argmax(np.abs(a)))]
    return shapes


def pair_roots(M: np.ndarray, K: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The two roots omega^2 of det(K - omega^2 M) = 0 for a 2x2 problem, ascending, and their absolute errors.

    The characteristic polynomial A w^4 - B w^2 + C (A = det M, B = K11 M22 + K22 M11 - 2 K12 M12,
    C = det K) is solved without cancellation and without squaring B: the large root as
    B (1 + sqrt(1 - t)) / (2A) with t = 4AC/B^2 formed as (4A (C/B))/B, the small one as C / (A large).
    So a spread of the two roots by 1e200 (4.12 with a thread 1e+-200 times the bar) keeps both to a few
    ulps, where an eigensolver rounds the low root to 0 (and the inverse solve, the high one).  M must be
    positive definite and K positive semi-definite (C = 0 gives the zero root exactly).

    Errors: the rounding of A, B and C (the two products of each, a few u), carried through; the
    square root's argument 1 - t cancels as the two roots meet, and the bound grows accordingly
    (u / (1 - t) relative), as a symmetric problem's close roots do not, so it is honest, not tight.
    """
    M = np.asarray(M, dtype=float)
    K = np.asarray(K, dtype=float)
    m12 = 0.5 * (M[0, 1] + M[1, 0])
    k12 = 0.5 * (K[0, 1] + K[1, 0])
    A = M[0, 0] * M[1, 1] - m12 * m12
    B = K[0, 0] * M[1, 1] + K[1, 1] * M[0, 0] - 2.0 * k12 * m12
    C = K[0, 0] * K[1, 1] - k12 * k12
    dA = 2 * _U * (abs(M[0, 0] * M[1, 1]) + m12 * m12)
    dB = 3 * _U * (abs(K[0, 0] * M[1, 1]) + abs(K[1, 1] * M[0, 0]) + 2 * abs(k12 * m12))
    dC = 2 * _U * (abs(K[0, 0] * K[1, 1]) + k12 * k12)
    if not all(np.isfinite(x) for x in (A, B, C)):
        raise NumericFailure("2x2 modes: the characteristic polynomial's coefficients are not finite")
    if not (A > dA and B > dB and C >= -dC):
        raise NumericFailure(f"2x2 modes: expected M positive definite and K positive semi-definite "
                             f"(det M = {A:.3g}, trace term {B:.3g}, det K = {C:.3g})")
    C = max(C, 0.0)
    t = (4.0 * A * (C / B)) / B
    rel_t = dA / A + 2 * dB / B + (dC / C if C > 0 else 0.0) + 4 * _U
    one_minus_t = 1.0 - t
    if one_minus_t < -rel_t * t - _U:
        raise NumericFailure(f"2x2 modes: complex roots (1 - 4 det M det K / B^2 = {one_minus_t:.3g})")
    s = np.sqrt(max(one_minus_t, 0.0))
    big = B * (1.0 + s) / (2.0 * A)
    # d(1 - t) = t rel_t + u; ds = d(1 - t) / (2 s), unbounded as the roots meet (s -> 0)
    ds = (t * rel_t + _U) / (2.0 * s) if s > 0 else np.sqrt(t * rel_t + _U)
    rel_big = dB / B + dA / A + ds / (1.0 + s) + 3 * _U
    small = C / (A * big)
    err_small = (dC + C * (dA / A + rel_big + 2 * _U)) / (A * big)
    return np.array([small, big]), np.array([err_small, rel_big * big])


def solve3(K, b):
    """K^-1 b for a 3 x 3 system by the adjugate (cofactors in plain floats: a fraction of numpy.linalg.solve's
    call overhead in a right-hand side evaluated thousands of times); K well conditioned (symmetric positive
    definite in 4.23)."""
    (k00, k01, k02), (k10, k11, k12), (k20, k21, k22) = K.tolist() if hasattr(K, "tolist") else K
    c00 = k11 * k22 - k12 * k21
    c01 = k12 * k20 - k10 * k22
    c02 = k10 * k21 - k11 * k20
    det = k00 * c00 + k01 * c01 + k02 * c02
    b0, b1, b2 = b
    return (
        (c00 * b0 + (k02 * k21 - k01 * k22) * b1 + (k01 * k12 - k02 * k11) * b2) / det,
        (c01 * b0 + (k00 * k22 - k02 * k20) * b1 + (k02 * k10 - k00 * k12) * b2) / det,
        (c02 * b0 + (k01 * k20 - k00 * k21) * b1 + (k00 * k11 - k01 * k10) * b2) / det,
    )

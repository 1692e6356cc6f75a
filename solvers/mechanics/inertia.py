"""Inertia tensors of mass distributions given as weighted point sets (quadrature or exact lumping).

A body is a set of points ``r`` (N x 3) with masses ``w`` (N); the tensor is
taken about the set's own center of mass, so no parallel-axis theorem enters.
Quadrature builders return point sets for common shapes with total mass 1 and
unit size; scale them (mass by M, lengths by R) in the exercise.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "center_of_mass",
    "inertia_tensor",
    "principal_moments",
    "degenerate_groups",
    "gauss_legendre",
    "periodic",
    "hoop",
    "disk",
    "shell",
    "ball",
]


def center_of_mass(r: np.ndarray, w: np.ndarray) -> np.ndarray:
    return (w[:, None] * r).sum(axis=0) / w.sum()


def inertia_tensor(r: np.ndarray, w: np.ndarray, about: np.ndarray | None = None) -> np.ndarray:
    """``I_jk = sum w (|r|^2 delta_jk - r_j r_k)`` with r measured from ``about`` (default: the center of mass)."""
    r = np.asarray(r, dtype=float)
    w = np.asarray(w, dtype=float)
    origin = center_of_mass(r, w) if about is None else np.asarray(about, dtype=float)
    d = r - origin
    S = np.einsum("n,ni,nj->ij", w, d, d)  # second moments
    # I_xx = S_yy + S_zz directly: forming sum m r^2 - sum m x^2 would cancel for slender bodies
    I = -S.copy()
    for i in range(3):
        I[i, i] = S[(i + 1) % 3, (i + 1) % 3] + S[(i + 2) % 3, (i + 2) % 3]
    return 0.5 * (I + I.T)


def principal_moments(I: np.ndarray) -> np.ndarray:
    """Eigenvalues of the symmetric tensor, ascending."""
    return np.linalg.eigvalsh(I)


def degenerate_groups(values, rel: float = 1e-9) -> list[list[int]]:
    """Indices of ascending values grouped where neighbours agree to ``rel`` of the largest (scale-free)."""
    values = np.asarray(values, dtype=float)
    scale = np.max(np.abs(values))
    groups: list[list[int]] = [[0]]
    for i in range(1, values.size):
        if abs(values[i] - values[groups[-1][-1]]) <= rel * scale:
            groups[-1].append(i)
        else:
            groups.append([i])
    return groups


def gauss_legendre(n: int, a: float = -1.0, b: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (b - a) * x + 0.5 * (b + a), 0.5 * (b - a) * w


def periodic(n: int, offset: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """The trapezoid rule on [0, 2 pi): exact for trigonometric polynomials of degree < n."""
    phi = offset + 2 * np.pi * np.arange(n) / n
    return phi, np.full(n, 2 * np.pi / n)


def _normalize(r, w):
    return np.asarray(r, dtype=float), np.asarray(w, dtype=float) / np.sum(w)


def hoop(n_phi: int = 16):
    phi, w = periodic(n_phi, 0.3)
    return _normalize(np.stack([np.cos(phi), np.sin(phi), np.zeros_like(phi)], axis=1), w)


def disk(n_r: int = 8, n_phi: int = 16):
    rr, wr = gauss_legendre(n_r, 0.0, 1.0)
    phi, wp = periodic(n_phi, 0.3)
    R, P = np.meshgrid(rr, phi, indexing="ij")
    W = np.outer(wr * rr, wp)
    pts = np.stack([R * np.cos(P), R * np.sin(P), np.zeros_like(R)], axis=-1).reshape(-1, 3)
    return _normalize(pts, W.ravel())


def shell(n_theta: int = 8, n_phi: int = 16):
    c, wc = gauss_legendre(n_theta)
    phi, wp = periodic(n_phi, 0.3)
    C, P = np.meshgrid(c, phi, indexing="ij")
    S = np.sqrt(1 - C**2)
    pts = np.stack([S * np.cos(P), S * np.sin(P), C], axis=-1).reshape(-1, 3)
    return _normalize(pts, np.outer(wc, wp).ravel())


def ball(n_r: int = 8, n_theta: int = 8, n_phi: int = 16):
    rr, wr = gauss_legendre(n_r, 0.0, 1.0)
    s_pts, s_w = shell(n_theta, n_phi)
    pts = (rr[:, None, None] * s_pts[None, :, :]).reshape(-1, 3)
    w = np.outer(wr * rr**2, s_w).ravel()
    return _normalize(pts, w)

"""Quadrature point sets of simple bodies: rods, triangles (plates), tetrahedra and solid cones.

Each builder returns ``(points, weights)`` with the weights summing to one: the
mass fractions of a uniform body, so ``M * weights`` are the point masses.  The
rules are Gauss products, collapsed (Duffy) onto the simplex, so that they are
exact for polynomial integrands up to a known degree: a rule built with ``n``
Gauss nodes per direction integrates every polynomial of total degree
``2 n - 1`` or less in the Cartesian coordinates exactly on a rod, ``2 n - 2``
on a triangle and ``2 n - 3`` on a tetrahedron (the collapse adds one or two
powers of the radial variable to the integrand).  Second moments (inertia tensors) need degree 2, so
``n = 3`` is plenty; the defaults are more generous.

No physics of an exercise here: only geometry and weights.
"""

from __future__ import annotations

import numpy as np

from mech.solvers.mechanics.inertia import gauss_legendre, periodic

__all__ = ["rod", "triangle", "tetrahedron", "cone", "rod_polyline"]


def _normalized(points, weights):
    w = np.asarray(weights, dtype=float)
    return np.asarray(points, dtype=float), w / w.sum()


def rod(a, b, n: int = 4):
    """A thin uniform rod from point ``a`` to point ``b`` (any dimension): Gauss-Legendre nodes."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    s, w = gauss_legendre(n, 0.0, 1.0)
    return _normalized(a[None, :] + s[:, None] * (b - a)[None, :], w)


def rod_polyline(vertices, n: int = 4, closed: bool = True):
    """Thin uniform rods along the edges of a polygon; each rod's mass is proportional to its length."""
    v = np.asarray(vertices, dtype=float)
    edges = list(zip(v, np.roll(v, -1, axis=0))) if closed else list(zip(v[:-1], v[1:]))
    pts, wts = [], []
    for a, b in edges:
        p, w = rod(a, b, n)
        pts.append(p)
        wts.append(w * np.linalg.norm(b - a))
    return _normalized(np.concatenate(pts), np.concatenate(wts))


def triangle(v0, v1, v2, n: int = 5):
    """A uniform triangular plate: the collapsed Gauss product rule x = v0 + u (v1-v0) + u s (v2-v1).

    The Jacobian is proportional to u; exact for polynomials of total degree <= 2n - 2.
    """
    v0, v1, v2 = (np.asarray(v, dtype=float) for v in (v0, v1, v2))
    u, wu = gauss_legendre(n, 0.0, 1.0)
    s, ws = gauss_legendre(n, 0.0, 1.0)
    U, S = np.meshgrid(u, s, indexing="ij")
    W = np.outer(wu * u, ws)
    pts = v0 + U[..., None] * (v1 - v0) + (U * S)[..., None] * (v2 - v1)
    return _normalized(pts.reshape(-1, v0.size), W.ravel())


def tetrahedron(v0, v1, v2, v3, n: int = 5):
    """A uniform solid tetrahedron: x = v0 + u (v1-v0) + u s (v2-v1) + u s t (v3-v2), Jacobian ~ u^2 s.

    Exact for polynomials of total degree <= 2n - 3.
    """
    v0, v1, v2, v3 = (np.asarray(v, dtype=float) for v in (v0, v1, v2, v3))
    g, wg = gauss_legendre(n, 0.0, 1.0)
    U, S, T = np.meshgrid(g, g, g, indexing="ij")
    W = (wg * g**2)[:, None, None] * (wg * g)[None, :, None] * wg[None, None, :]
    pts = (
        v0
        + U[..., None] * (v1 - v0)
        + (U * S)[..., None] * (v2 - v1)
        + (U * S * T)[..., None] * (v3 - v2)
    )
    return _normalized(pts.reshape(-1, 3), W.ravel())


def cone(height: float, radius: float, n_axis: int = 5, n_r: int = 4, n_phi: int = 8, volume: bool = False):
    """A uniform solid right circular cone, apex at the origin, axis along +z, base at z = height.

    Nodes: z = height u, cylindrical radius = radius u t, azimuth phi (trapezoid rule);
    weight ~ u^2 t.  Exact for polynomials of degree <= min(2 n_axis - 3, 2 n_r - 2)
    in the Cartesian coordinates whose azimuthal order is below n_phi.
    With ``volume=True`` also returns the rule's volume, sum of the raw weights times
    the Jacobian height * radius^2 (exact: the integrand 1 is a polynomial).
    """
    u, wu = gauss_legendre(n_axis, 0.0, 1.0)
    t, wt = gauss_legendre(n_r, 0.0, 1.0)
    phi, wp = periodic(n_phi, 0.1)
    U, Tt, P = np.meshgrid(u, t, phi, indexing="ij")
    W = (wu * u**2)[:, None, None] * (wt * t)[None, :, None] * wp[None, None, :]
    rr = radius * U * Tt
    pts = np.stack([rr * np.cos(P), rr * np.sin(P), height * U], axis=-1)
    out = _normalized(pts.reshape(-1, 3), W.ravel())
    return (*out, float(W.sum()) * height * radius**2) if volume else out

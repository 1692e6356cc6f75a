"""Gravity seen from an orbiting frame: tidal (Hill) fields and the exact relative field without cancellation.

Frame: origin on a body in a circular orbit of radius R about a point mass
GM, turning with the orbit at Omega = (GM/R^3)^(1/2); x along the radius
(outward), y along the orbital velocity, z along the orbit normal.

* ``hill_acceleration(r, Omega)``: the linearized field plus centrifugal force
  per unit mass, (3 Omega^2 x, 0, -Omega^2 z); ``hill_potential``.
* ``relative_gravity(r, R, GM)``: g(R e_x + r) - g(R e_x) exactly, written so
  that no term of size GM/R^2 is subtracted from another (the offsets may be
  1e-9 of R): 1/|p|^3 - 1/R^3 goes through R^2 - |p|^2 = -(2 R x + |r|^2).
* ``relative_potential(r, R, GM)``: the potential of that field,
  -GM/|p| + GM/R - GM x/R^2, again without cancellation (it is of order
  GM |r|^2/R^3).
* ``coriolis(v, Omega)``: -2 Omega e_z x v.
"""

from __future__ import annotations

import numpy as np

__all__ = ["hill_acceleration", "hill_potential", "relative_gravity", "relative_potential", "coriolis"]


def hill_acceleration(r, Omega: float) -> np.ndarray:
    r = np.asarray(r, dtype=float)
    return np.array([3.0 * Omega**2 * r[0], 0.0, -(Omega**2) * r[2]])


def hill_potential(r, Omega: float) -> float:
    r = np.asarray(r, dtype=float)
    return Omega**2 * (-1.5 * r[0] ** 2 + 0.5 * r[2] ** 2)


def coriolis(v, Omega: float) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    return np.array([2.0 * Omega * v[1], -2.0 * Omega * v[0], 0.0])


def _pieces(r, R):
    """(x, |r|^2, |p|, |p| - R) for one offset r (3 numbers) or N of them (3 x N, R one per column or one)."""
    x = r[0]
    rr = r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
    p = np.sqrt(R * R + 2.0 * R * x + rr)  # |R e_x + r|
    d = (2.0 * R * x + rr) / (p + R)  # |p| - R without cancellation
    return x, rr, p, d


def relative_gravity(r, R: float, GM: float) -> np.ndarray:
    """g(R e_x + r) - g(R e_x), g(p) = -GM p/|p|^3; r: 3 numbers, or 3 x N offsets (R and GM numbers or N)."""
    r = np.asarray(r, dtype=float)
    x, rr, p, d = _pieces(r, R)
    # R/|p|^3 - 1/R^2 = (R^3 - |p|^3)/(R^2 |p|^3), R^3 - |p|^3 = -(|p| - R)(R^2 + R|p| + |p|^2)
    # written as a sum so that no intermediate overflows for offsets ~1e-90 of R (units of the offset)
    k = -d * (1.0 / p**3 + 1.0 / (R * p * p) + 1.0 / (R * R * p))
    out = -GM * (r / p**3)
    out[0] = out[0] - GM * k
    return out


def relative_potential(r, R: float, GM: float) -> float:
    """-GM/|p| + GM/R - GM x/R^2: the potential of ``relative_gravity``, zero at r = 0 (r: 3 numbers or 3 x N)."""
    r = np.asarray(r, dtype=float)
    x, rr, p, d = _pieces(r, R)
    # = GM [R (|p| - R) - x |p|] / (R^2 |p|); numerator = R (rr - x d)/(|p| + R) - x d, all of order |r|^2
    num = R * (rr - x * d) / (p + R) - x * d
    return GM * (num / R) / (R * p)

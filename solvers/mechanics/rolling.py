"""Plane rigid-body kinematics for bodies that roll or slide on a surface, and well-scaled normal modes.

Everything here is geometry, no exercise's answer:

* ``rolling_spin``: the angular velocity (about the axis normal to the plane of
  motion) at which a round body's material point in contact moves with the
  surface it touches: the no-slip condition solved for the spin.
* ``plane_kinetic_energy``: T of a rigid body as a quadrature sum of w |v|^2 / 2
  over its mass points, with the rigid velocity field v = v_ref + omega z x r.
* ``scaled_mass_matrix``: smallosc.mass_matrix probed with velocities of a
  chosen size per coordinate, so that every probe moves the body at comparable
  speeds and the polarization's cross terms do not drown in round-off.
* ``balanced_modes``: the generalized eigenproblem K a = omega^2 M a after a
  diagonal rescaling that makes every diagonal element of M equal to 1; it
  removes the trivial ill-conditioning of coordinates with very different
  units or scales (an angle next to a displacement, a mass 1e6 times another).
"""

from __future__ import annotations

import numpy as np

from mech.core.errors import NumericFailure
from mech.solvers.mechanics.frames import cross_z
from mech.solvers.numerics.modes import Modes, mass_matrix, normal_modes, pair_shapes

__all__ = ["rolling_spin", "plane_kinetic_energy", "balanced_modes", "scaled_mass_matrix"]


def rolling_spin(v_center, v_surface, n, radius: float) -> float:
    """Spin omega (counterclockwise positive) of a round body rolling without slip.

    The contact point is ``center + radius * n`` (``n`` the unit vector from the
    body's center of curvature to the contact); its material velocity is
    ``v_center + omega z x (radius n)``.  No slip asks its tangential component
    to equal the surface's (the normal components agree by the contact itself),
    which fixes omega.
    """
    n = np.asarray(n, dtype=float)
    t = np.array([-n[1], n[0]])  # z x n: the direction omega z x (R n) points along
    rel = np.asarray(v_center, dtype=float) - np.asarray(v_surface, dtype=float)
    return -float(rel @ t) / radius


def plane_kinetic_energy(weights, r_rel, v_ref, omega: float) -> float:
    """sum_i w_i |v_ref + omega z x r_i|^2 / 2 for the mass points r_i (relative to the reference point)."""
    v = np.asarray(v_ref, dtype=float)[None, :] + cross_z(omega, r_rel)
    return 0.5 * float(np.sum(np.asarray(weights) * np.sum(v * v, axis=1)))


def scaled_mass_matrix(T, q0, velocity_scale) -> np.ndarray:
    """The mass matrix of T(q, qdot), polarized with probe velocities ``velocity_scale[i] * e_i``.

    smallosc.mass_matrix probes with unit velocities; when a unit rate of one
    coordinate moves the masses 1e7 times slower than a unit rate of another,
    the cross terms lose digits in T(e_i + e_j) - T(e_i) - T(e_j).  Choose the
    scales so that each probe gives speeds of the same order.
    """
    s = np.asarray(velocity_scale, dtype=float)
    Ms = mass_matrix(lambda q, u: T(q, s * np.asarray(u)), q0)
    return Ms / np.outer(s, s)


def balanced_modes(M: np.ndarray, K: np.ndarray) -> Modes:
    """Normal modes of K a = omega^2 M a, solved with M rescaled to unit diagonal.

    With D = diag(M_ii^-1/2) the problem (D K D) b = omega^2 (D M D) b has the same
    eigenvalues and a = D b; the shapes are returned in the original coordinates,
    each scaled to its largest component (in the balanced units) equal to +1.

    A symmetric eigensolver errs by eps times the largest eigenvalue, so with
    widely separated frequencies (omega_max^2 / omega_min^2 = 1e7) the low modes
    would lose seven digits.  When K is positive definite the problem is solved a
    second time the other way round, M b = omega^-2 K b, where the low modes are the
    large eigenvalues and keep their digits: each mode is taken from the solve in
    which it lies in the upper half of the spectrum.
    """
    M = np.atleast_2d(np.asarray(M, dtype=float))
    K = np.atleast_2d(np.asarray(K, dtype=float))
    d = 1.0 / np.sqrt(np.diag(M))
    Mb, Kb = M * np.outer(d, d), K * np.outer(d, d)
    modes = normal_modes(Mb, Kb)
    omega2, shapes = modes.omega2.copy(), modes.shapes.copy()
    n = omega2.size
    # each eigenvalue's error: eps times the largest (symmetric solver on the balanced problem)...
    err = np.full(n, 8.0 * 2.0**-53 * float(np.max(np.abs(omega2))))
    # (a low root rounded to 0 or below it too: with K positive definite the inverse solve gets it)
    if n > 1 and omega2[-1] > 0 and omega2[-1] > 1e3 * omega2[0]:
        try:
            inverse = normal_modes(Kb, Mb)  # eigenvalues omega^-2, ascending: the highest mode first
        except NumericFailure:
            inverse = None
        if inverse is not None and np.all(inverse.omega2 > 0):
            middle = np.sqrt(omega2[0] * omega2[-1])
            for k in range(n):
                if omega2[k] < middle:
                    omega2[k] = 1.0 / inverse.omega2[n - 1 - k]
                    shapes[:, k] = inverse.shapes[:, n - 1 - k]
                    err[k] = 8.0 * 2.0**-53 * omega2[k]  # ... or of itself, from the inverse problem
    if n == 2:
        # the shapes from the rows of (K - omega^2 M) a = 0: a component 1e-100 of the other survives
        shapes = pair_shapes(Mb, Kb, omega2, err)
    return Modes(omega2=omega2, shapes=shapes * d[:, None])

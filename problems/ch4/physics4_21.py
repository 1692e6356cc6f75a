"""4.21's physics, declared for sympy (``mech show 4.21 --derive``; problems/physics.py).

A heavy symmetric top (mass M, moment I3 about its axis and I1 about a transverse axis through its center
of mass) turning about a fixed frictionless point support A on its axis, the center at the distance l from
A, in uniform gravity g.  Coordinates: the Euler angles (precession psi about the vertical, nutation theta
from it, spin phi about the axis, z-x-z); the Lagrangian of the rigid body about its center of mass.
The module integrates the axis n3 and the angular momentum about A, both in lab components; they are given
here as functions of the angles and their rates.
"""

from __future__ import annotations

import math

import numpy as np
from sympy.physics.mechanics import Lagrangian, Point, ReferenceFrame, RigidBody, inertia

from mech.problems.ch4.ex4_21_heavy_top_precession import exercise


@exercise.physics
def physics(d):
    psi, theta, phi = d.coordinates("psi theta phi")
    M, l, I1, I3, g = d.params("M l I1 I3 g")
    t = d.t
    N = ReferenceFrame("N")                              # N.z up
    B = N.orientnew("B", "Body", [psi, theta, phi], "ZXZ")  # B.z: the axis n3
    A = Point("A")
    A.set_vel(N, 0)
    C = A.locatenew("C", l * B.z)
    C.v2pt_theory(A, N, B)
    top = RigidBody("top", C, B, M, (inertia(B, I1, I1, I3), C))
    top.potential_energy = M * g * C.pos_from(A).dot(N.z)
    d.lagrangian(Lagrangian(N, top))
    L = top.angular_momentum(A, N)
    d.states([B.z.dot(N.x), B.z.dot(N.y), B.z.dot(N.z), L.dot(N.x), L.dot(N.y), L.dot(N.z)], inverse=_inverse)


def _inverse(x, p):
    """The Euler angles (spin angle 0: it does not enter) and their rates of an axis n and a momentum L."""
    n, L = np.array(x[0:3]), np.array(x[3:6])
    theta = math.atan2(math.hypot(n[0], n[1]), n[2])
    psi = math.atan2(n[0], -n[1])
    IA = p.I1 + p.M * p.l**2
    L3 = L @ n
    omega = (L - L3 * n) / IA + L3 / p.I3 * n
    node = np.array([math.cos(psi), math.sin(psi), 0.0])
    rates = np.linalg.solve(np.stack([[0.0, 0.0, 1.0], node, n], axis=1), omega)
    return [psi, theta, 0.0], list(rates)

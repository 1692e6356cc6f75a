"""4.23's physics, declared for sympy (``mech show 4.23 --derive``; problems/physics.py).

A thin uniform disk (mass M, radius r) rolling without slipping on a horizontal floor in uniform gravity,
by Kane's method.  Coordinates: the yaw psi of its ground tangent about the vertical, its lean phi
from the vertical (about that tangent), its spin angle chi about its own normal, and the contact point (x, y) on
the floor.  Speeds: the disk's angular velocity in the leaning frame (u1, u2, u3) and the contact point's
velocity (u4, u5), the last two fixed by the rolling condition (nonholonomic): the material point at the
contact is at rest.  Friction does no work and needs no load; gravity acts at the center.

The module integrates the body rates (body axis 3 = the disk's normal), the attitude quaternion (scalar
first, body to lab), the center's position and velocity; those are given here as functions of the
coordinates and speeds, with their inverse.
"""

from __future__ import annotations

import math

import numpy as np
import sympy as sp
from sympy.physics.mechanics import Point, ReferenceFrame, RigidBody, dot, inertia

from mech.problems.ch4.ex4_23_rolling_coin import exercise
from mech.problems.physics import quaternion_product, turn_quaternion
from mech.solvers.mechanics.frames import quat_to_matrix


@exercise.physics
def physics(d):
    psi, phi, chi, x, y = d.coordinates("psi phi chi x y")
    u1, u2, u3, u4, u5 = d.speeds("u1 u2 u3 u4 u5")
    r, g = d.params("r g")
    M = d.constant("M", 1.0, "kg", "the coin's mass drops out of the motion")
    t = d.t
    N = ReferenceFrame("N")                                   # the floor, z up
    Y = N.orientnew("Y", "Axis", [psi, N.z])                  # Y.x: the ground tangent
    L = Y.orientnew("L", "Axis", [phi, Y.x])                  # L.y: the disk's normal, L.z: contact -> center
    D = L.orientnew("D", "Axis", [chi, L.y])                 # the disk itself
    O = Point("O")
    O.set_vel(N, 0)
    P = O.locatenew("P", x * N.x + y * N.y)                   # the contact point (geometric)
    P.set_vel(N, u4 * N.x + u5 * N.y)
    C = P.locatenew("C", r * L.z)                             # the center
    C.set_vel(N, P.vel(N) + (r * L.z).dt(N))
    # the speeds: the disk's angular velocity (from the angles' rates) in L, and the contact point's velocity
    w = L.ang_vel_in(N) + chi.diff(t) * L.y
    kin = [u1 - dot(w, L.x), u2 - dot(w, L.y), u3 - dot(w, L.z), u4 - x.diff(t), u5 - y.diff(t)]
    D.set_ang_vel(N, u1 * L.x + u2 * L.y + u3 * L.z)
    contact = C.locatenew("Pd", -r * L.z)                     # the disk's material point at the contact
    contact.v2pt_theory(C, N, D)
    rolling = [dot(contact.vel(N), N.x), dot(contact.vel(N), N.y)]
    disk = RigidBody("disk", C, D, M, (inertia(L, M * r**2 / 4, M * r**2 / 2, M * r**2 / 4), C))
    d.kane(N, kinematics=kin, bodies=[disk], loads=[(C, -M * g * N.z)], u_dependent=[u4, u5],
           velocity_constraints=rolling)

    # the module's states: body rates (body axes: 1 = D.z, 2 = D.x, 3 = D.y, the normal), the quaternion
    # of that body frame, the center and its velocity (the center turns about the resting contact point)
    w_vec = u1 * L.x + u2 * L.y + u3 * L.z
    body = (D.z, D.x, D.y)
    rates = [dot(w_vec, e) for e in body]
    q_fix = (sp.Rational(1, 2), -sp.Rational(1, 2), -sp.Rational(1, 2), -sp.Rational(1, 2))  # D's axes -> body axes
    quat = quaternion_product(quaternion_product(quaternion_product(turn_quaternion(psi, 2), turn_quaternion(phi, 0)),
                                                   turn_quaternion(chi, 1)), q_fix)
    center = [dot(C.pos_from(O), e) for e in (N.x, N.y, N.z)]
    v_center = w_vec.cross(r * L.z)
    d.states(rates + list(quat) + center + [dot(v_center, e) for e in (N.x, N.y, N.z)],
             inverse=_inverse, sizes={"phi": _lean_size, "psi": 1.0, "chi": 1.0})


def _lean_size(p, phi):
    """The draws' spread of the lean: a fifth of its distance to the flat disk (where the contact jumps)."""
    return 0.2 * (math.pi / 2 - abs(phi))


def _inverse(xs, p):
    """(coordinates, independent speeds) of the module's SI states."""
    w_body, quat, c = np.array(xs[0:3]), np.array(xs[3:7]), np.array(xs[7:10])
    Rm = quat_to_matrix(quat)
    e1, n = Rm[:, 0], Rm[:, 2]
    phi = math.asin(n[2])
    psi = math.atan2(-n[0], n[1])
    Lx = np.array([math.cos(psi), math.sin(psi), 0.0])
    Lz = np.array([math.sin(psi) * math.sin(phi), -math.cos(psi) * math.sin(phi), math.cos(phi)])
    chi = math.atan2(e1 @ Lx, e1 @ Lz)
    w = Rm @ w_body
    contact = c - p.r * Lz
    return [psi, phi, chi, contact[0], contact[1]], [w @ Lx, w @ n, w @ Lz]

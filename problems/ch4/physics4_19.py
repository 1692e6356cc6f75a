"""4.19's physics, declared for sympy (``mech show 4.19 --derive``; problems/physics.py).

A thin flat uniform round disk (mass M, radius R) turning freely about its center of mass at rest, by
Kane's method: I3 = M R^2/2 about its normal, I1 = I2 = M R^2/4 about any diameter (the perpendicular-axis
theorem).  Its attitude by three body-fixed turns (x, y, z), its speeds the angular velocity's components
on its axes (3 = the normal).  The module integrates those components and the attitude quaternion
(scalar first, body to lab), given here in terms of the turns.
"""

from __future__ import annotations

import numpy as np
from sympy.physics.mechanics import Point, ReferenceFrame, RigidBody, dot, inertia

from mech.problems.ch4.ex4_19_disk_precession import exercise
from mech.problems.physics import body_xyz_angles, body_xyz_quaternion
from mech.solvers.mechanics.frames import quat_to_matrix


@exercise.physics
def physics(d):
    a, b, c = d.coordinates("a b c")
    w1, w2, w3 = d.speeds("w1 w2 w3")
    M = d.constant("M", 1.0, "kg", "the mass drops out (I3 = 2 I1)")
    R = d.constant("R", 1.0, "m", "the radius drops out (I3 = 2 I1)")
    N = ReferenceFrame("N")
    B = N.orientnew("B", "Body", [a, b, c], "XYZ")       # B.z: the disk's normal
    w = B.ang_vel_in(N)
    kin = [w1 - dot(w, B.x), w2 - dot(w, B.y), w3 - dot(w, B.z)]
    B.set_ang_vel(N, w1 * B.x + w2 * B.y + w3 * B.z)
    O = Point("O")
    O.set_vel(N, 0)
    disk = RigidBody("disk", O, B, M, (inertia(B, M * R**2 / 4, M * R**2 / 4, M * R**2 / 2), O))
    d.kane(N, kinematics=kin, bodies=[disk], loads=[])
    d.states([w1, w2, w3, *body_xyz_quaternion(a, b, c)], inverse=_inverse)


def _inverse(x, p):
    return list(body_xyz_angles(quat_to_matrix(np.asarray(x[3:7])))), list(x[0:3])

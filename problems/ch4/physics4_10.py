"""4.10's physics, declared for sympy (``mech show 4.10 --derive``; problems/physics.py).

A rigid body of mass M on a fixed horizontal frictionless axis A in uniform gravity: its center of mass
at the distance l from the axis, its moment of inertia I about the parallel axis through the center.
One coordinate: the angle phi of the line from A to the center, from the downward vertical.
"""

from __future__ import annotations

from sympy.physics.mechanics import Lagrangian, Point, ReferenceFrame, RigidBody, inertia

from mech.problems.ch4.ex4_10_physical_pendulum import exercise


@exercise.physics
def physics(d):
    phi = d.coordinates("phi")
    M, I, l, g = d.params("M I l g")
    t = d.t
    N = ReferenceFrame("N")                         # N.x horizontal, N.y up, the axis A along N.z
    B = N.orientnew("B", "Axis", [phi, N.z])        # the body; -B.y points from A to the center
    A = Point("A")
    A.set_vel(N, 0)
    C = A.locatenew("C", -l * B.y)
    C.v2pt_theory(A, N, B)
    body = RigidBody("body", C, B, M, (inertia(B, 0, 0, I), C))  # a turn about A sees only I about N.z
    body.potential_energy = M * g * C.pos_from(A).dot(N.y)
    d.lagrangian(Lagrangian(N, body))
    d.states([phi, phi.diff(t)])

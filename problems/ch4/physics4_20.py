"""4.20's physics, declared for sympy (``mech show 4.20 --derive``; problems/physics.py).

A free rigid body (no torque, its center of mass at rest) with principal moments I1, I2, I3, by Kane's
method: its attitude by three body-fixed turns (x, y, z), its speeds the angular velocity's components
on the principal axes.  The module integrates those three components alone (the attitude does not enter
a free body's rates).
"""

from __future__ import annotations

from sympy.physics.mechanics import Point, ReferenceFrame, RigidBody, dot, inertia

from mech.problems.ch4.ex4_20_intermediate_axis import exercise


@exercise.physics
def physics(d):
    a, b, c = d.coordinates("a b c")
    w1, w2, w3 = d.speeds("w1 w2 w3")
    I1, I2, I3 = d.params("I1 I2 I3")
    M = d.constant("M", 1.0, "kg", "the mass does not enter the rotation")
    N = ReferenceFrame("N")
    B = N.orientnew("B", "Body", [a, b, c], "XYZ")       # the principal axes
    w = B.ang_vel_in(N)
    kin = [w1 - dot(w, B.x), w2 - dot(w, B.y), w3 - dot(w, B.z)]
    B.set_ang_vel(N, w1 * B.x + w2 * B.y + w3 * B.z)
    O = Point("O")
    O.set_vel(N, 0)                                      # the center of mass, at rest
    body = RigidBody("body", O, B, M, (inertia(B, I1, I2, I3), O))
    d.kane(N, kinematics=kin, bodies=[body], loads=[])
    d.states([w1, w2, w3], inverse=_inverse, sizes={"a": 0.3, "b": 0.3, "c": 0.3})


def _inverse(x, p):
    """Any attitude (a free body's rates do not depend on it), and the rates themselves."""
    return [0.1, 0.2, 0.3], list(x)

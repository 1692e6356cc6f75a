"""4.18's physics, declared for sympy (``mech show 4.18 --derive``; problems/physics.py).

A uniform solid ball (mass M, radius R: I = 2 M R^2/5 about any diameter) rolling without slipping on a
horizontal table that turns at the constant rate Omega about the vertical z axis through the origin, by
Kane's method.  Coordinates: the center's place (x, y) and the ball's attitude (three body-fixed turns);
speeds: the ball's angular velocity in lab components (w1, w2, w3) and the center's velocity (vx, vy), the
last two fixed by the no-slip condition (nonholonomic): the ball's material point at the contact moves with
the table's point under it.  The normal force balances gravity; friction does no net work and needs no
load.  The module integrates the center's place and velocity and the change of the angular velocity since
the start (where no slip fixes its horizontal part; its vertical spin, which does not enter, is 0 there).
"""

from __future__ import annotations

import numpy as np
from sympy.physics.mechanics import RigidBody, dot, inertia

from mech.problems.ch4.ex4_18_ball_on_turntable import exercise
from mech.problems.physics import ball_on_table, body_xyz_matrix


@exercise.physics
def physics(d):
    Omega, R, x0, y0, vx0, vy0 = d.params("Omega R x0 y0 vx0 vy0")
    M = d.constant("M", 1.0, "kg", "the ball's mass drops out of the motion")
    ball_ = ball_on_table(d, R)                              # N: the lab, z up
    N, B, O, C, contact = ball_.N, ball_.B, ball_.O, ball_.C, ball_.P
    x, y, vx, vy, kin = ball_.x, ball_.y, ball_.vx, ball_.vy, ball_.kinematics
    table = (Omega * N.z).cross(contact.pos_from(O))         # the table's velocity under it
    no_slip = [dot(contact.vel(N) - table, N.x), dot(contact.vel(N) - table, N.y)]
    ball = RigidBody("ball", C, B, M, (inertia(B, 2 * M * R**2 / 5, 2 * M * R**2 / 5, 2 * M * R**2 / 5), C))
    d.kane(N, kinematics=kin, bodies=[ball], loads=[], u_dependent=[vx, vy], velocity_constraints=no_slip)
    # the start's angular velocity: no slip at (x0, y0) with the velocity (vx0, vy0), no vertical spin
    w10, w20 = -(vy0 - Omega * x0) / R, (vx0 + Omega * y0) / R
    omega = B.ang_vel_in(N)
    d.states([x, y, vx, vy, dot(omega, N.x) - w10, dot(omega, N.y) - w20, dot(omega, N.z)],
             inverse=_inverse, sizes={"a": 0.3, "b": 0.3, "c": 0.3})


ATTITUDE = (0.1, 0.2, 0.3)  # any attitude: it does not enter the motion


def _inverse(s, p):
    """The center's place, an attitude, and the angular velocity on the ball's axes."""
    a, b, c = ATTITUDE
    Rm = body_xyz_matrix(a, b, c)  # the ball's axes in the lab (sympy's Body XYZ)
    w10, w20 = -(p.vy0 - p.Omega * p.x0) / p.R, (p.vx0 + p.Omega * p.y0) / p.R
    w_lab = np.array([s[4] + w10, s[5] + w20, s[6]])
    return [s[0], s[1], *ATTITUDE], list(Rm.T @ w_lab)


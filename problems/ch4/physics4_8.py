"""4.8's physics, declared for sympy (``mech show 4.8 --derive``; problems/physics.py).

The sliding phase of a uniform solid ball (mass M, radius R: I = 2 M R^2/5) on a horizontal table, by
Kane's method: gravity at its center, the table's normal force M g and the Coulomb friction mu M g against
the slip of the contact point, at the contact.  Coordinates: the center's displacement (x, y) since the
strike and the ball's attitude (three body-fixed turns); speeds: the angular velocity on the ball's axes
(w1, w2, w3) and the center's velocity (vx, vy), all independent while it slides.  The strike before it
(a short pulse) is the module's lead-in leg, not declared; the states compared are the sliding leg's: the
contact point's slip velocity, the angular velocity (lab components) and the displacement.
"""

from __future__ import annotations

import numpy as np
import sympy as sp
from sympy.physics.mechanics import RigidBody, dot, inertia

from mech.problems.ch4.ex4_8_billiard_ball import exercise
from mech.problems.physics import ball_on_table, body_xyz_matrix


@exercise.physics
def physics(d):
    M, R, mu, g = d.params("M R mu g")
    ball_ = ball_on_table(d, R)                              # N: x along the cue, z up
    N, B, C, P, x, y = ball_.N, ball_.B, ball_.C, ball_.P, ball_.x, ball_.y
    kin = ball_.kinematics
    slip = P.vel(N)                                          # P: the ball's material point at the contact
    friction = -mu * M * g * slip / sp.sqrt(dot(slip, slip))
    ball = RigidBody("ball", C, B, M, (inertia(B, 2 * M * R**2 / 5, 2 * M * R**2 / 5, 2 * M * R**2 / 5), C))
    d.kane(N, kinematics=kin, bodies=[ball], loads=[(C, -M * g * N.z), (P, M * g * N.z + friction)])
    omega = B.ang_vel_in(N)
    d.states([dot(slip, N.x), dot(slip, N.y), dot(slip, N.z), dot(omega, N.x), dot(omega, N.y),
              dot(omega, N.z), x, y, 0], inverse=_inverse, sizes={"a": 0.3, "b": 0.3, "c": 0.3},
             within=_sliding_on)


def _sliding_on(x, x0):
    """The module's friction law holds while the slip keeps the sense it started with (past the event the
    module continues it smoothly, on purpose)."""
    return float(np.dot(x[0:3], x0[0:3])) > 0.0


ATTITUDE = (0.1, 0.2, 0.3)  # any attitude: a ball's does not enter its motion


def _inverse(s, p):
    """The displacement, an attitude, the angular velocity on the ball's axes, the center's velocity."""
    Rm = body_xyz_matrix(*ATTITUDE)
    slip, w_lab = np.array(s[0:3]), np.array(s[3:6])
    v = slip - np.cross(w_lab, [0.0, 0.0, -p.R])             # the slip is v + w x (-R z)
    return [s[6], s[7], *ATTITUDE], [*(Rm.T @ w_lab), v[0], v[1]]


"""4.7's physics, declared for sympy (``mech show 4.7 --derive``; problems/physics.py).

A thin uniform rod (length 2 l, mass m: I = m l^2/3 about its center) free in a plane, and a bullet (a point
mass m_b) that hits its end, during the impact: Lagrange's equations of the rod's center (X, Y) and angle
theta and of the bullet's displacement (bx, by), with no other force than their interaction.  Before the
impact the rod lies along y, centered at the origin, and the bullet is at its end (0, l).  The
interaction is the module's contact model, a spring and a damper between the bullet and the rod's end,
F = -K d - C d' on the bullet (d: the bullet's place less the rod's end), acting at the bullet's point on
both (equal and opposite), with the matrices K and C that make the contact critically damped over the pulse
(their values are the module's, from the pulse time it takes: constants of the model, not of the motion).
The energy dissipated is the damper's, d'.C.d', a quadrature.
"""

from __future__ import annotations

import sympy as sp
from sympy.physics.mechanics import Lagrangian, Particle, Point, ReferenceFrame, RigidBody, inertia

from mech.problems.ch4.ex4_7_bullet_in_rod import PULSE, _contact, exercise


def _entry(matrix: int, i: int, j: int):
    """The SI value of the contact's K (matrix 0, N/m) or C (matrix 1, N s/m) entry (i, j): the module's,
    in its units m = l = v0 = 1 (time l/v0)."""
    def value(p):
        K, C = _contact(p.m_b / p.m, PULSE)[1:3]
        return (K[i, j] * p.m * p.v0**2 / p.l**2) if matrix == 0 else (C[i, j] * p.m * p.v0 / p.l)
    return value


@exercise.physics
def physics(d):
    X, Y, theta, bx, by = d.coordinates("X Y theta bx by")
    m, l, m_b = d.params("m l m_b")
    why = "the contact's {}: the module's, critically damped over the pulse"
    k00, k01, k11 = (d.constant(f"K{i}{j}", _entry(0, i, j), "N/m", why.format("stiffness"))
                     for i, j in ((0, 0), (0, 1), (1, 1)))
    c00, c01, c11 = (d.constant(f"C{i}{j}", _entry(1, i, j), "N*s/m", why.format("damping"))
                     for i, j in ((0, 0), (0, 1), (1, 1)))
    K = sp.Matrix([[k00, k01], [k01, k11]])
    C = sp.Matrix([[c00, c01], [c01, c11]])
    t = d.t
    N = ReferenceFrame("N")
    rod_frame = N.orientnew("rod", "Axis", [theta, N.z])
    O = Point("O")
    O.set_vel(N, 0)
    center = O.locatenew("center", X * N.x + Y * N.y)
    center.set_vel(N, X.diff(t) * N.x + Y.diff(t) * N.y)
    rod = RigidBody("rod", center, rod_frame, m, (inertia(rod_frame, 0, 0, m * l**2 / 3), center))
    bullet_at = O.locatenew("bullet", bx * N.x + (l + by) * N.y)
    bullet_at.set_vel(N, bullet_at.pos_from(O).dt(N))
    bullet = Particle("bullet", bullet_at, m_b)
    end = center.locatenew("end", l * rod_frame.y)                 # the struck end
    gap = bullet_at.pos_from(end)
    dvec = sp.Matrix([gap.dot(N.x), gap.dot(N.y)])
    ddot = dvec.diff(t)
    F = -K * dvec - C * ddot                                       # on the bullet
    force = F[0] * N.x + F[1] * N.y
    touch = center.locatenew("touch", bullet_at.pos_from(center))  # the rod's material point under the bullet
    touch.set_vel(N, center.vel(N) + rod_frame.ang_vel_in(N).cross(touch.pos_from(center)))
    d.lagrangian(Lagrangian(N, rod, bullet), loads=[(bullet_at, force), (touch, -force)], frame=N)
    rates = [q.diff(t) for q in (X, Y, theta, bx, by)]
    d.states([X, Y, theta, bx, by, *rates, d.rate((ddot.T * C * ddot)[0])])
    d.unsolved("Solved for the accelerations, the five coupled equations of the contact give long forms that "
               "take sympy half a minute to simplify; they are not printed.")

"""4.29's physics, declared for sympy (``mech show 4.29 --derive``; problems/physics.py).

A bead of mass m on a straight frictionless rod that turns at the constant rate omega in a horizontal
plane about a fixed vertical axis crossing it.  One coordinate, the bead's signed place r along the rod;
the rod's angle omega t is imposed (a rheonomic constraint: the time enters the Lagrangian).  Gravity is
vertical and does not enter the horizontal motion.
"""

from __future__ import annotations

from sympy.physics.mechanics import Lagrangian, Particle, Point, ReferenceFrame

from mech.problems.ch4.ex4_29_bead_on_rotating_rod import exercise


@exercise.physics
def physics(d):
    r = d.coordinates("r")
    m, omega = d.params("m omega")
    t = d.t
    N = ReferenceFrame("N")
    rod = N.orientnew("rod", "Axis", [omega * t, N.z])
    O = Point("O")
    O.set_vel(N, 0)
    P = O.locatenew("P", r * rod.x)
    P.set_vel(N, P.pos_from(O).dt(N))
    d.lagrangian(Lagrangian(N, Particle("bead", P, m)))
    d.states([r, r.diff(t)])

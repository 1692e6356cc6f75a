"""4.34's physics, declared for sympy (``mech show 4.34 --derive``; problems/physics.py).

A thin rigid rod (a dumbbell: two masses m at its ends, a length l apart) whose center of mass circles
the Earth (gravitational parameter GM) on a circular orbit of radius R at Omega = (GM/R^3)^(1/2), in the
gravity-gradient model: in the frame turning with the orbit (x up, y along the orbital velocity), the
Earth's pull less the center's own acceleration, to first order in the distance from the center, is the
tidal field of the potential -(GM/R^3)(x^2 - y^2/2 - z^2/2) per unit mass.  One coordinate: the pitch
angle theta of the rod from the local vertical, in the orbital plane.
"""

from __future__ import annotations

import sympy as sp
from sympy.physics.mechanics import Lagrangian, Particle, Point, ReferenceFrame

from mech.problems.ch4.ex4_34_gravity_gradient_rod import exercise


@exercise.physics
def physics(d):
    theta = d.coordinates("theta")
    R, GM = d.params("R GM")
    m = d.constant("m", 1.0, "kg", "the masses drop out of the motion")
    l = d.constant("l", 2.0, "m", "the rod's length drops out of the motion")
    t = d.t
    Omega = sp.sqrt(GM / R**3)
    N = ReferenceFrame("N")
    F = N.orientnew("F", "Axis", [Omega * t, N.z])       # the orbit's frame
    C = Point("C")
    C.set_vel(F, 0)
    ends = []
    for k, sign in enumerate((1, -1)):
        r = sign * l / 2 * (sp.cos(theta) * F.x + sp.sin(theta) * F.y)
        P = C.locatenew(f"P{k}", r)
        P.set_vel(N, r.dt(N))                            # the center's own motion is in the tidal field
        end = Particle(f"end{k}", P, m)
        x, y = r.dot(F.x), r.dot(F.y)
        end.potential_energy = -m * GM / R**3 * (x**2 - y**2 / 2)
        ends.append(end)
    d.lagrangian(Lagrangian(N, *ends))
    d.states([theta, theta.diff(t)])

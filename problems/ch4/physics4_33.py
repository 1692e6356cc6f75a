"""4.33's physics, declared for sympy (``mech show 4.33 --derive``; problems/physics.py).

A small free body (mass m) near a satellite that circles a point-mass Earth (gravitational parameter GM)
on a circular orbit of radius R at Omega = (GM/R^3)^(1/2).  Coordinates: the body's place (x, y) in the
orbital plane relative to the satellite, in the frame turning with the orbit (x outward along the radius,
y along the orbital velocity).  The satellite's motion is imposed (its own mass and attraction left out),
so the time enters the Lagrangian; the Earth's gravity is exact, GM m/|r|.
"""

from __future__ import annotations

import sympy as sp
from sympy.physics.mechanics import Lagrangian, Particle, Point, ReferenceFrame

from mech.problems.ch4.ex4_33_hill_relative_ellipse import exercise


@exercise.physics
def physics(d):
    x, y = d.coordinates("x y")
    R, GM = d.params("R GM")
    m = d.constant("m", 1.0, "kg", "the body's mass drops out of the motion")
    t = d.t
    Omega = sp.sqrt(GM / R**3)
    N = ReferenceFrame("N")                                # inertial, centered on the Earth
    F = N.orientnew("F", "Axis", [Omega * t, N.z])         # turning with the orbit: F.x outward
    E = Point("E")
    E.set_vel(N, 0)
    r = (R + x) * F.x + y * F.y                            # the body from the Earth's center
    P = E.locatenew("P", r)
    P.set_vel(N, r.dt(N))
    body = Particle("body", P, m)
    body.potential_energy = -GM * m / sp.sqrt(r.dot(r))
    d.lagrangian(Lagrangian(N, body))
    d.states([x, y, x.diff(t), y.diff(t)])
    d.note("The derived form subtracts the Earth's pull from the centrifugal term, nearly equal for a "
           "body close to the satellite: it is evaluated at 40 digits (the module's own form does not cancel).")

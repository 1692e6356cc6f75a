"""4.31's physics, declared for sympy (``mech show 4.31 --derive``; problems/physics.py).

A small body (mass m) falling near the ground at colatitude theta, in the Earth's frame E (x east, y north,
z up), which turns at omega_E about the polar axis, (0, sin theta, cos theta) in E, relative to an inertial
frame.  Gravity is the uniform effective g down the local vertical: the centrifugal force at the site is in
it, and its variation over the fall is left out, so the potential is m g z plus (m/2)|omega x r|^2, which
cancels the centrifugal term of the kinetic energy in the turning frame (what stays is the Coriolis term).
"""

from __future__ import annotations

import sympy as sp
from sympy.physics.mechanics import Lagrangian, Particle, Point, ReferenceFrame

from mech.problems.ch4.ex4_31_eastward_deflection import exercise


@exercise.physics
def physics(d):
    x, y, z = d.coordinates("x y z")
    h, theta, g, omega_E = d.params("h theta g omega_E")
    m = d.constant("m", 1.0, "kg", "the body's mass drops out of the motion")
    t = d.t
    N = ReferenceFrame("N")
    axis = sp.sin(theta) * N.y + sp.cos(theta) * N.z       # the polar axis, fixed in both frames
    E = N.orientnew("E", "Axis", [omega_E * t, axis])
    O = Point("O")                                         # the foot of the plumb line
    O.set_vel(N, 0)
    r = x * E.x + y * E.y + z * E.z
    P = O.locatenew("P", r)
    P.set_vel(N, r.dt(N))
    body = Particle("body", P, m)
    spin = E.ang_vel_in(N)
    body.potential_energy = m * g * z + m / 2 * spin.cross(r).dot(spin.cross(r))
    d.lagrangian(Lagrangian(N, body))
    d.states([x, y, z, x.diff(t), y.diff(t), z.diff(t)])

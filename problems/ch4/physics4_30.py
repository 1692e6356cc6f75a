"""4.30's physics, declared for sympy (``mech show 4.30 --derive``; problems/physics.py).

The small swing of a pendulum's bob (mass m) at colatitude theta, in the Earth's frame, which turns at
omega_E about the polar axis; the bob's velocity is horizontal to first order, so only the vertical
component omega_z = omega_E cos(theta) of the Earth's rotation enters: the frame E of the local east (x)
and north (y) turns at omega_z about the vertical in an inertial frame.  The model's restoring force is
m omega0^2 toward the equilibrium, omega0^2 = g/l, with the centrifugal force taken into g (its variation
across the swing neglected): so the potential is (m/2)(omega0^2 + omega_z^2) rho^2, whose extra part
cancels the centrifugal term of the kinetic energy in the turning frame.
"""

from __future__ import annotations

import sympy as sp
from sympy.physics.mechanics import Lagrangian, Particle, Point, ReferenceFrame

from mech.problems.ch4.ex4_30_foucault_pendulum import exercise


@exercise.physics
def physics(d):
    x, y = d.coordinates("x y")
    theta, l, g, omega_E = d.params("theta l g omega_E")
    m = d.constant("m", 1.0, "kg", "the bob's mass drops out of the motion")
    t = d.t
    wz = omega_E * sp.cos(theta)
    N = ReferenceFrame("N")                                 # inertial, z the local vertical
    E = N.orientnew("E", "Axis", [wz * t, N.z])             # the ground: E.x east, E.y north
    O = Point("O")
    O.set_vel(N, 0)
    P = O.locatenew("P", x * E.x + y * E.y)
    P.set_vel(N, P.pos_from(O).dt(N))
    bob = Particle("bob", P, m)
    bob.potential_energy = m / 2 * (g / l + wz**2) * (x**2 + y**2)
    d.lagrangian(Lagrangian(N, bob))
    d.states([x, y, x.diff(t), y.diff(t)])

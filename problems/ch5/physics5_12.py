"""5.12's physics, declared for sympy (``mech show 5.12 --derive``; problems/physics.py).

A bob of mass M on a massless rod of length l, its pivot driven along the vertical, z_pivot = a cos(Omega t)
(a rheonomic constraint: the time enters the Lagrangian), in uniform gravity g; the swing is damped by a
friction torque proportional to the angular velocity, written as a Rayleigh dissipation function with the
damping rate delta (amplitude decaying as exp(-delta t)).  One coordinate: the angle theta from the
downward vertical.
"""

from __future__ import annotations

import sympy as sp

from mech.problems.ch5.ex5_12_pumped_pendulum import exercise, jacobian


@exercise.physics
def physics(d):
    theta = d.coordinates("theta")
    l, g, delta, a, Omega = d.params("l g delta a Omega")
    M = d.constant("M", 1.0, "kg", "the bob's mass drops out of the motion")
    t = d.t
    x = l * sp.sin(theta)                               # the bob, horizontally from the pivot's line
    z = a * sp.cos(Omega * t) - l * sp.cos(theta)       # and its height: the pivot's, less the rod's
    T = M / 2 * (x.diff(t) ** 2 + z.diff(t) ** 2)
    d.lagrangian(T - M * g * z, rayleigh=M * l**2 * delta * theta.diff(t) ** 2)
    d.states([theta, theta.diff(t)])
    d.jacobian(jacobian)

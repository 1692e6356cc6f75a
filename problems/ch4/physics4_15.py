"""4.15's physics, declared for sympy (``mech show 4.15 --derive``; problems/physics.py).

A thin uniform rod (mass M, length l) with its top on a frictionless vertical wall (x = 0) and its foot
on a frictionless floor (y = 0).  Coordinates: its angle theta to the floor and its center (x, y); the
two contacts are holonomic constraints, each with a multiplier (the normal forces).  The only horizontal
force on the rod is the wall's, so the wall's normal force is M x'' (the motion's event).
"""

from __future__ import annotations

import sympy as sp

from mech.problems.ch4.ex4_15_sliding_ladder import exercise


@exercise.physics
def physics(d):
    theta, x, y = d.coordinates("theta x y")
    l, g = d.params("l g")
    M = d.constant("M", 1.0, "kg", "the rod's mass drops out of the motion; the run's unit of mass")
    t = d.t
    T = M / 2 * (x.diff(t) ** 2 + y.diff(t) ** 2) + (M * l**2 / 12) / 2 * theta.diff(t) ** 2
    U = M * g * y
    d.lagrangian(T - U,
                 constraints=[x - l / 2 * sp.cos(theta),   # the top slides on the wall x = 0
                              y - l / 2 * sp.sin(theta)],  # the foot slides on the floor y = 0
                 dependent=[x, y])
    d.states([theta, theta.diff(t)])
    d.event(M * x.diff(t, 2))  # the wall's normal force: the one horizontal force on the rod

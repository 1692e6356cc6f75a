"""4.9's physics, declared for sympy (``mech show 4.9 --derive``; problems/physics.py).

A round cylinder (radius R, mass M) rolling without slipping on a horizontal floor in uniform gravity,
its center of mass at the distance l from the geometric axis, its moment of inertia I about the parallel
axis through the center of mass.  Coordinates: the rotation angle phi (counterclockwise; phi = 0 with
the center of mass straight below the axis) and the axis's horizontal place x.  Rolling on a straight
line is a holonomic constraint, x + R phi = 0 (its multiplier is the floor's friction).
"""

from __future__ import annotations

import sympy as sp

from mech.problems.ch4.ex4_9_offcenter_cylinder import exercise


@exercise.physics
def physics(d):
    phi, x = d.coordinates("phi x")
    M, R, l, I, g = d.params("M R l I g")
    t = d.t
    cx, cy = x + l * sp.sin(phi), R - l * sp.cos(phi)   # the center of mass
    T = M / 2 * (cx.diff(t) ** 2 + cy.diff(t) ** 2) + I / 2 * phi.diff(t) ** 2
    d.lagrangian(T - M * g * cy, constraints=[x + R * phi], dependent=[x])
    d.states([phi, phi.diff(t)])

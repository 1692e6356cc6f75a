"""5.2's physics, declared for sympy (``mech show 5.2 --derive``; problems/physics.py).

A mass m on a linear spring of stiffness m omega0^2 (so omega0 is its own frequency), no friction, pushed by
an external force that is F0 from t = 0 until t = T and zero otherwise: a rectangular pulse, an explicit
function of the time entering as the generalized force on the one coordinate q (the displacement from the
spring's rest length).

The generic comparison reads the module's first leg, the pulse itself (drawn times fall inside
0 < t < min(T, t1, 2 pi/omega0)), in the scaled x = q/q_st, tau = omega0 t; tests/test_physics_derived.py
also follows the chain to the free leg after a short pulse (``then=``).  A pulse longer than one free
period, and x at t1 after it, the module carries by the exact flow of its linear equations (a matrix
exponential, no ODE stepped): that route has no right-hand side to compare, but its generators do, as
right-hand sides in (x, x', 1) and (x, x'), and the test compares them with the derived equations too.
"""

from __future__ import annotations

import sympy as sp

from mech.problems.ch5.ex5_2_force_pulse import exercise


@exercise.physics
def physics(d):
    q = d.coordinates("q")
    m, omega0, F0, T = d.params("m omega0 F0 T")
    t = d.t
    kinetic = m / 2 * q.diff(t) ** 2
    potential = m * omega0**2 / 2 * q**2          # the spring, stiffness m omega0^2
    pulse = sp.Piecewise((F0, (t >= 0) & (t < T)), (0, True))  # on at t = 0, off at t = T
    d.lagrangian(kinetic - potential, forces={q: pulse})
    d.states([q, q.diff(t)])

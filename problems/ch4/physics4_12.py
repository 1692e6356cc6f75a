"""4.12's physics, declared for sympy (``mech show 4.12 --derive``; problems/physics.py).

From the statement: a thin uniform bar (mass M, length l, a line mass M/l) hangs on a light inextensible
thread of length l' tied to its upper end; one vertical plane, uniform gravity g. The thread stays taut (a
rigid massless link), so two coordinates: phi, the thread's angle from the downward vertical, and psi, the
bar's. The point of the bar at the distance s from its upper end is at l' (sin phi, -cos phi) +
s (sin psi, -cos psi); its kinetic and potential energies, integrated over the bar, give the Lagrangian.
The exercise integrates no motion (its answer is the normal modes), so no states are declared.
"""

from __future__ import annotations

import sympy as sp

from mech.problems.ch4.ex4_12_chime import exercise


@exercise.physics
def physics(d):
    phi, psi = d.coordinates("phi psi")
    M, l, l_prime, g = d.params("M l l_prime g")
    t = d.t
    s = sp.Symbol("s", nonnegative=True)  # along the bar, from its upper end
    x = l_prime * sp.sin(phi) + s * sp.sin(psi)
    y = -l_prime * sp.cos(phi) - s * sp.cos(psi)  # up is +y
    density = M / l
    # cos phi cos psi + sin phi sin psi = cos(phi - psi): the form a reader expects (trigsimp, on a small T)
    T = sp.trigsimp(sp.integrate(density / 2 * (x.diff(t) ** 2 + y.diff(t) ** 2), (s, 0, l)))
    U = sp.integrate(density * g * y, (s, 0, l))
    d.lagrangian(T - U)
    d.note("the exercise integrates no motion: its answer is the normal modes of these equations, "
           "linearized about phi = psi = 0")

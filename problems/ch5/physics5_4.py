"""5.4's physics, declared for sympy (``mech show 5.4 --derive``; problems/physics.py).

A mass M on a linear spring of own frequency omega0 (potential M omega0^2 q^2/2) with viscous friction,
the force -2 M delta q' with delta = zeta omega0, written as the Rayleigh dissipation function
F = M delta q'^2 = M zeta omega0 q'^2.  One coordinate, the displacement q; released from rest at q0.

The module integrates x = q/q0 against tau = omega0 t with the dissipated work carried as a third row (a
quadrature no state depends on: left out of the comparison).  For zeta > 5 its numeric route steps no
ODE: the state is the exact linear flow exp(A tau) y0, whose generator A is the upper block of its
hand-written Jacobian; that Jacobian is compared here, so the flow's generator is checked against the
derived equations too (the rows of the right-hand side and of the Jacobian that the flow uses).
"""

from __future__ import annotations

from mech.problems.ch5.ex5_4_overdamped_relaxation import _jac, exercise


@exercise.physics
def physics(d):
    q = d.coordinates("q")
    omega0, zeta = d.params("omega0 zeta")
    M = d.constant("M", 1.0, "kg", "the mass drops out of the motion (the model is per unit mass)")
    t = d.t
    d.lagrangian(M / 2 * q.diff(t) ** 2 - M * omega0**2 / 2 * q**2,
                 rayleigh=M * zeta * omega0 * q.diff(t) ** 2)   # friction force -2 M zeta omega0 q'
    d.states([q, q.diff(t)])
    d.jacobian(lambda p: _jac(p.zeta))

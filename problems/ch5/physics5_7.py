"""5.7's physics, declared for sympy (``mech show 5.7 --derive``; problems/physics.py).

A mass M on a nonlinear spring whose potential energy is M (omega0^2 q^2/2 + alpha q^4/4): the linear
restoring force of own frequency omega0 and a cubic one, hardening for alpha > 0 and softening for
alpha < 0; no damping, no drive.  One coordinate, the displacement q.

The module integrates x = q/A against sigma = S omega0 t (S^2 = 1 + alpha A^2/omega0^2 for a stiff spring),
and near the softening barrier the distance s = x_b - x from its top (an affine map of the declared
states, inverted from the motion's ``to_states``); both are compared.  Its c3 integrals are tool runs of
the same oscillator in the deviation r = x - cos(ws s) from the harmonic motion, a map that moves with the
time (the affine comparison does not take it): tests/test_physics_derived.py maps the derived equation
through it by hand (r'' = x'' + ws^2 cos(ws s)) and compares their right-hand side too.
"""

from __future__ import annotations

from mech.problems.ch5.ex5_7_duffing_free import exercise


@exercise.physics
def physics(d):
    q = d.coordinates("q")
    omega0, alpha = d.params("omega0 alpha")
    M = d.constant("M", 1.0, "kg", "the mass drops out of the motion (alpha is a force per unit mass)")
    t = d.t
    U = M * (omega0**2 * q**2 / 2 + alpha * q**4 / 4)
    d.lagrangian(M / 2 * q.diff(t) ** 2 - U)
    d.show("potential energy U", U)
    d.states([q, q.diff(t)])

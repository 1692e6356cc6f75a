"""5.9's physics, declared for sympy (``mech show 5.9 --derive``; problems/physics.py).

A van der Pol self-oscillator of mass M: a linear spring of own frequency omega0 (potential
M omega0^2 q^2/2) and a nonlinear friction force M mu (1 - beta q^2) q', which pumps energy in while
q^2 < 1/beta and takes it out beyond; a damping that can be negative is no Rayleigh function, so it is
the generalized force on q.  No drive.

The module integrates x = sqrt(beta) q against tau = omega0 t for mu/omega0 <= 4, and for a relaxation
oscillation x and u = x'/eps (eps = mu/omega0) against the slow time tau/eps, with int (1 - x^2) carried
as a third row (a quadrature: left out); both are compared, with their hand-written Jacobians.
"""

from __future__ import annotations

from mech.problems.ch5.ex5_9_van_der_pol import RELAX_EPS, _jac, _slow, exercise


def _hand_jacobian(p):
    eps = p.mu / p.omega0
    if eps <= RELAX_EPS:
        return lambda t, y: _jac(t, y, eps)
    return _slow(eps)[1]


@exercise.physics
def physics(d):
    q = d.coordinates("q")
    omega0, mu, beta = d.params("omega0 mu beta")
    M = d.constant("M", 1.0, "kg", "the mass drops out of the motion (the model is per unit mass)")
    t = d.t
    friction = M * mu * (1 - beta * q**2) * q.diff(t)   # negative damping below q^2 = 1/beta
    d.lagrangian(M / 2 * q.diff(t) ** 2 - M * omega0**2 / 2 * q**2, forces={q: friction})
    d.states([q, q.diff(t)])
    d.jacobian(_hand_jacobian)

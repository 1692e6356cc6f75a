"""5.5's physics, declared for sympy (``mech show 5.5 --derive``; problems/physics.py).

A mass M on a linear spring of own frequency omega0 with viscous friction, the force -2 M delta q',
written as the Rayleigh dissipation function F = M delta q'^2.  The equation is linear and the ringdown
starts from rest at q0, so the coordinate is the displacement in units of its start, x = q/q0 (the
exercise's states are q/q0 and its rate).

The comparison reads the declared motion, the ringdown in x against tau = omega0 t with the dissipated
work carried as a third row (a quadrature: left out); past delta = 0.9 omega0 the module declares no
motion (the loss then comes from the decrement), and those draws are skipped.  The amplitude-phase flows
(x = r cos th, x' = -r sin th, in time or with th as the clock) are tool runs of the same oscillator,
compared through that map (by the chain rule) in tests/test_physics_derived.py.  The resonance curve's
orbit maps are not compared: they integrate the oscillator driven at a frequency the search varies (not a
parameter of the exercise, so not in this declaration), in variation-of-constants variables.
"""

from __future__ import annotations

from mech.problems.ch5.ex5_5_q_factor import exercise


@exercise.physics
def physics(d):
    x = d.coordinates("x")
    omega0, delta = d.params("omega0 delta")
    M = d.constant("M", 1.0, "kg", "the mass (times q0^2) drops out of the motion")
    t = d.t
    d.lagrangian(M / 2 * x.diff(t) ** 2 - M * omega0**2 / 2 * x**2,
                 rayleigh=M * delta * x.diff(t) ** 2)   # friction force -2 M delta x'
    d.states([x, x.diff(t)])

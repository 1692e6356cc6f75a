"""5.6's physics, declared for sympy (``mech show 5.6 --derive``; problems/physics.py).

A simple pendulum: a bob of mass M on a massless rod of length l, the pivot fixed, uniform gravity g, no
friction.  One coordinate, the angle theta from the downward vertical.

The module integrates theta against tau = sqrt(g/l) t below 90 degrees of amplitude, and above it the
deviation phi = pi - theta from the upright position with its rate (an affine map of the declared states,
inverted from the motion's ``to_states``); both are compared.
"""

from __future__ import annotations

import sympy as sp

from mech.problems.ch5.ex5_6_pendulum_period import exercise


@exercise.physics
def physics(d):
    theta = d.coordinates("theta")
    l, g = d.params("l g")
    M = d.constant("M", 1.0, "kg", "the bob's mass drops out of the motion")
    t = d.t
    x, z = l * sp.sin(theta), -l * sp.cos(theta)    # the bob, from the pivot (z up)
    T = M / 2 * (x.diff(t) ** 2 + z.diff(t) ** 2)
    d.lagrangian(T - M * g * z)
    d.states([theta, theta.diff(t)])

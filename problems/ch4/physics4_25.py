"""4.25: no physics declared for sympy, and why (``mech show 4.25 --derive``; problems/physics.py)."""

from __future__ import annotations

from mech.problems.ch4.ex4_25_top_friction_rise import exercise

exercise.physics_withheld(
    "its declared motion is a reduced model, the fast top's angular momentum kept along its axis "
    "(L = I3 omega3 n3: the transverse inertia, hence the nutation, dropped) and driven by the sliding "
    "friction at the tip, in a frame turning with the precession and a rescaled time; no Lagrangian gives "
    "that first-order flow, and the sliding friction is not a Rayleigh function of generalized speeds")

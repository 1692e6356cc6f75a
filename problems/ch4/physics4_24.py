"""4.24: no physics declared for sympy, and why (``mech show 4.24 --derive``; problems/physics.py)."""

from __future__ import annotations

from mech.problems.ch4.ex4_24_driven_fast_top import exercise

exercise.physics_withheld(
    "its declared motion is a reduced model, the guiding center of the axis with the nutation averaged out "
    "(a first-order flow for one unit vector in the frame turning with the force, to next order in 1/spin), "
    "which no Lagrangian of the top gives (the top's full equations are what its numeric route integrates "
    "by a splitting)")

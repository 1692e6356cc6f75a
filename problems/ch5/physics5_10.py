"""5.10's physics, declared for sympy (``mech show 5.10 --derive``; problems/physics.py).

A van der Pol self-oscillator of mass M driven by a sinusoidal force: a linear spring of own frequency
omega0 (potential M omega0^2 q^2/2), a nonlinear friction force M mu (1 - beta q^2) q' that pumps energy
in while q^2 < 1/beta and takes it out beyond (negative damping at small amplitude: no Rayleigh function
gives it, so it is a generalized force), and the drive M f0 cos(omega t), an explicit function of the time.

The comparison reads the declared motion, one drive period of the driven oscillator in SI (the ensemble
the beat is read from is its vectorized form).  The one-period orbit maps that find the edges of the
locking range are not compared: they integrate force functions written inside the numeric route (closures
no test reaches) through solvers/mechanics/continuation.py, and below mu/omega0 = 5e-3 in the frame
turning with the drive (slow amplitude and phase, a map that moves with the time).  The test's skip says
so too.
"""

from __future__ import annotations

import sympy as sp

from mech.problems.ch5.ex5_10_adler_locking import exercise


@exercise.physics
def physics(d):
    q = d.coordinates("q")
    omega0, mu, beta, f0, omega = d.params("omega0 mu beta f0 omega")
    M = d.constant("M", 1.0, "kg", "the mass drops out (f0 is the drive's amplitude per unit mass)")
    t = d.t
    friction = M * mu * (1 - beta * q**2) * q.diff(t)   # negative damping below q^2 = 1/beta
    drive = M * f0 * sp.cos(omega * t)
    d.lagrangian(M / 2 * q.diff(t) ** 2 - M * omega0**2 / 2 * q**2, forces={q: friction + drive})
    d.states([q, q.diff(t)])

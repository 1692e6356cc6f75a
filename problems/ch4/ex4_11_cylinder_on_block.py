"""4.11 Cylinder rolling on a spring-held block: frequency and mode.

Analytic: no slip at the contact (below the axis) gives R phi' = X' - x', so
T = M' X'^2/2 + M x'^2/2 + (M R^2/2) phi'^2/2 = M' X'^2/2 + M x'^2/2 + M (X' - x')^2/4,
U = kappa X^2/2.  x is cyclic: p_x = (3/2) M x' - M X'/2 = 0 in the drift-free
mode, so x = X/3 and phi = (X - x)/R = 2X/(3R).  Then T = (M' + M/3) X'^2/2 and
omega^2 = kappa / (M' + M/3).

Numeric, in units of M, R and sqrt(M/kappa) (the mass ratio M'/M the only parameter left):
T(q, q') for q = (X, x) is M' X'^2/2 plus the quadrature sum over a
discretized disk cross-section of the cylinder of w |v_axis + phi' z x r|^2/2,
with phi' solved at each call from the no-slip condition at the contact
(solvers.mechanics.rolling; the moment of inertia never enters).  Mass matrix by
polarization (body by body), stiffness by central differences of U, the balanced generalized
eigenproblem; the zero root is discarded and the other eigenvector scaled to
X = 1; phi/X is the no-slip spin at the mode's velocities.  The shapes come from the rows of
(K - omega^2 M) a = 0 (numerics.modes.pair_shapes), so a block 1e200 times heavier than the cylinder
keeps x/X = 1/3, which an eigenvector in balanced coordinates carries as 1e-100 noise.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems import ranges
from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.inertia import disk
from mech.solvers.mechanics.rolling import balanced_modes, plane_kinetic_energy, rolling_spin
from mech.solvers.numerics.modes import hessian, mass_matrix

exercise = Exercise(
    "4.11",
    formulas=[
        "no slip: R φ = X - x;  T = M' X'²/2 + M x'²/2 + M (X' - x')²/4,  U = κ X²/2",
        "x cyclic, p_x = 0: x = X/3, φ = 2X/(3R)",
        "ω² = κ / (M' + M/3)",
    ],
)

# the route works in units of M: the block's mass is the ratio M'/M, which must be a double
ranges.declare(exercise, ranges.Scale("M'/M", {"M_prime": 1, "M": -1}, "the mass ratio", low=-math.inf, high=307.0))


@exercise.analytic
def analytic(p):
    return {
        "omega": np.sqrt(p.kappa / (p.M_prime + p.M / 3.0)),
        "x_over_X": 1.0 / 3.0,
        "phi_over_X": 2.0 / (3.0 * p.R),
    }


@exercise.numeric
def numeric(p, run):
    # in units of the cylinder's mass M, its radius R and the time sqrt(M/kappa): the block's mass is the
    # ratio M'/M and nothing else has a scale, so R or kappa at 1e+-200 of their defaults change nothing
    M, R, Mb, kappa = 1.0, 1.0, p.M_prime / p.M, 1.0
    pts3, w = disk(6, 12)
    r_rel = R * pts3[:, :2]  # the cross-section in the plane of motion, about the axis
    w = M * w
    down = np.array([0.0, -1.0])  # from the axis to the contact with the block's top

    def spin(qdot):
        return rolling_spin([qdot[1], 0.0], [qdot[0], 0.0], down, R)

    def T_block(q, qdot):
        return 0.5 * Mb * qdot[0] ** 2

    def T_cylinder(q, qdot):
        return plane_kinetic_energy(w, r_rel, [qdot[1], 0.0], spin(qdot))

    def U(q):
        return 0.5 * kappa * q[0] ** 2

    q0 = np.zeros(2)
    # T is polarized body by body: a heavy block's T would otherwise swamp the
    # cylinder's small cross term in round-off (mass ratio 1e6)
    Mm = mass_matrix(T_block, q0) + mass_matrix(T_cylinder, q0)
    K = hessian(U, q0, scale=R)
    modes = balanced_modes(Mm, K)
    w2 = modes.omega2
    if not (w2[1] > 0 and abs(w2[0]) < 1e-9 * w2[1]):
        raise NumericFailure(f"expected one zero and one positive root, got {w2}")
    shape = modes.shapes[:, 1] / modes.shapes[0, 1]  # X = 1
    run.info["zero_root_over_omega2"] = float(w2[0] / w2[1])
    # polarization and the disk rule are exact for the quadratic T; U is quadratic so its
    # central differences are exact up to round-off; eigh of the balanced 2x2 problem: ~1e-15
    for name in ("omega", "x_over_X", "phi_over_X"):
        run.claim(name, rel=1e-11)
    return {"omega": np.sqrt(w2[1]) * np.sqrt(p.kappa) / np.sqrt(p.M), "x_over_X": shape[1],
            "phi_over_X": spin(shape) / p.R}

"""4.16 Hinged hexagon of six rods pushed at the middle of one side: the first accelerations.

Analytic: by the mirror symmetry through the pushed and the opposite rods, the
hexagon starts moving in two coordinates only, the displacements X and X' of
those two rods along F.  The hinge between two oblique rods then moves by
((X + X')/2, -sqrt(3)(X' - X)/2), each oblique rod turns at (X - X')/l, and
the kinetic energy is T = (m/2)[(10/3)(V^2 + V'^2) - (2/3) V V'] with V, V'
the two rods' velocities.  Lagrange's equations with the generalized forces (F, 0) give
a = 10 F/(33 m), a' = F/(33 m), and |alpha| = (a - a')/l = 3 F/(11 m l).

Numeric: no symmetry assumed and the hexagon placed at a generic angle.  The
18 Newton-Euler equations of the six rods (center x, y and l*angle each, so
that every mass entry is m or m/12) and the 12 hinge conditions
differentiated twice (at rest only the Jacobian term survives) form the
saddle-point system [[M, J^T], [J, 0]] [q''; lambda] = [Q; 0], solved once, in
units of m, l and F/m (the hard cases with tiny rods or tiny masses are then
the same well-conditioned system).  The center of mass must come out at
F/(6m) and the four oblique rods at equal |angular accelerations|; a failure of
either is a NumericFailure.
"""

from __future__ import annotations

import numpy as np

from mech.problems.spec import Exercise, NumericFailure

exercise = Exercise(
    "4.16",
    formulas=[
        "a = 10F/(33m)",
        "a' = F/(33m)  (same direction as F)",
        "|α| = (a - a')/l = 3F/(11 m l)",
        "(Lagrange in X, X' with T = (m/2)[(10/3)(Ẋ² + Ẋ'²) - (2/3)ẊẊ'])",
    ],
)

# the hexagon is laid at an arbitrary angle so that nothing lines up with the axes
TILT = 0.37


@exercise.analytic
def analytic(p):
    return {
        "a": 10.0 * p.F / (33.0 * p.m),
        "a_prime": p.F / (33.0 * p.m),
        "alpha_adj": 3.0 * p.F / (11.0 * p.m * p.l),
    }


def _saddle_point_accelerations():
    """Accelerations (x'', y'', l theta'') of the six rods, in units of F/m with m = l = F = 1.

    Rod k joins vertex k to vertex k+1 of the regular hexagon (circumradius = side = 1).
    The push is on rod 0, at its midpoint, toward the hexagon's center.
    Returns (acc[6, 3], force direction unit vector, residual of the linear solve).
    """
    n = 6
    phi = TILT + 2.0 * np.pi * np.arange(n) / n
    verts = np.stack([np.cos(phi), np.sin(phi)], axis=1)
    centers = 0.5 * (verts + np.roll(verts, -1, axis=0))
    edges = np.roll(verts, -1, axis=0) - verts
    theta = np.arctan2(edges[:, 1], edges[:, 0])
    # mass matrix for the coordinates (x, y, u = l theta): m, m, I/l^2 = m/12
    Mdiag = np.tile([1.0, 1.0, 1.0 / 12.0], n)
    # hinge k: end "+" of rod k coincides with end "-" of rod k+1
    #   c_k + (1/2) e(theta_k) - c_{k+1} + (1/2) e(theta_{k+1}) = 0,  e = (cos, sin)
    # d/du of (1/2) e(theta) with u = theta (l = 1) is (1/2)(-sin, cos)
    J = np.zeros((2 * n, 3 * n))
    for k in range(n):
        j = (k + 1) % n
        rows = slice(2 * k, 2 * k + 2)
        J[rows, 3 * k:3 * k + 2] = np.eye(2)
        J[rows, 3 * k + 2] = 0.5 * np.array([-np.sin(theta[k]), np.cos(theta[k])])
        J[rows, 3 * j:3 * j + 2] = -np.eye(2)
        J[rows, 3 * j + 2] = 0.5 * np.array([-np.sin(theta[j]), np.cos(theta[j])])
    fdir = -centers[0] / np.linalg.norm(centers[0])
    Q = np.zeros(3 * n)
    Q[0:2] = fdir  # applied at the rod's center: no torque
    K = np.zeros((5 * n, 5 * n))
    K[: 3 * n, : 3 * n] = np.diag(Mdiag)
    K[: 3 * n, 3 * n:] = J.T
    K[3 * n:, : 3 * n] = J
    rhs = np.concatenate([Q, np.zeros(2 * n)])
    sol = np.linalg.solve(K, rhs)
    residual = np.linalg.norm(K @ sol - rhs)
    return sol[: 3 * n].reshape(n, 3), fdir, residual


@exercise.numeric
def numeric(p, run):
    acc, fdir, residual = _saddle_point_accelerations()
    scale_a = p.F / p.m
    a = acc[0, :2] @ fdir
    a_opp = acc[3, :2] @ fdir
    alphas = np.abs(acc[[1, 2, 4, 5], 2])  # u'' = l theta'' = theta'' with l = 1
    # Newton for the whole hexagon: total mass 6 m, total force F
    com = acc[:, :2].mean(axis=0)
    com_err = np.linalg.norm(com - fdir / 6.0) * 6.0
    spread = (alphas.max() - alphas.min()) / alphas.max()
    run.info["linear_residual"] = residual
    run.info["com_acc_rel_err"] = com_err
    run.info["oblique_alpha_spread"] = spread
    run.info["pushed_rod_turning"] = abs(acc[0, 2])
    if com_err > 1e-12 or spread > 1e-12 or residual > 1e-12:
        raise NumericFailure(
            f"the saddle-point solution is inconsistent: center of mass off by {com_err:.2g}, "
            f"oblique rods' |alpha| spread {spread:.2g}, residual {residual:.2g}"
        )
    run.method = "saddle-point linear solve (18 Newton-Euler + 12 hinge rows)"
    for name in ("a", "a_prime", "alpha_adj"):
        run.claim(name, rel=1e-12)
    return {"a": a * scale_a, "a_prime": a_opp * scale_a, "alpha_adj": alphas.mean() * scale_a / p.l}

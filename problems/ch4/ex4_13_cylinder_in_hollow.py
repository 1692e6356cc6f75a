"""4.13 Cylinder rolling in the cylindrical hollow of a sliding block.

Analytic: with rho = R' - R, the cylinder's axis is at X + rho sin theta,
-rho cos theta from the hollow's axis; no slip at the contact gives
R phi' = -rho theta' (lab rotation).  So
T = M' X'^2/2 + (M/2)[(X' + rho theta' cos theta)^2 + rho^2 theta'^2 sin^2 theta]
    + (M R^2/4) phi'^2,   U = -M g rho cos theta.
At theta = 0: mass matrix [[M + M', M rho], [M rho, 3 M rho^2/2]], stiffness
diag(0, M g rho).  X is cyclic: zero momentum gives X = -M rho theta/(M + M'), and
omega^2 = g / (rho [3/2 - M/(M + M')]) = 2 g (M + M') / (rho (M + 3 M')).
The mode: X/theta = -M rho/(M + M'), x_c/X = 1 + rho theta/X = -M'/M,
phi/theta = -rho/R.  At M' = M, R' = 2R: omega^2 = g/R.

Numeric, in units of M, rho and sqrt(rho/g) (left: M'/M and R/rho): T(q, q') for q = (X, theta) is M' X'^2/2 plus a quadrature sum over a
discretized disk cross-section with v = v_axis + phi' z x r, phi' solved at each
call from the no-slip condition at the contact point (solvers.mechanics.rolling; no moment
of inertia used); U from the axis's height above its equilibrium,
2 M g rho sin^2(theta/2).  Mass matrix by polarization (body by body, with theta' probed at 1/rho),
stiffness by Richardson differences with the X step scaled by rho, balanced
generalized eigenproblem, zero root discarded, eigenvector scaled to theta = 1.
"""

from __future__ import annotations

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.inertia import disk
from mech.solvers.mechanics.rolling import balanced_modes, plane_kinetic_energy, rolling_spin, scaled_mass_matrix
from mech.solvers.numerics.modes import hessian, mass_matrix

exercise = Exercise(
    "4.13",
    formulas=[
        "ρ = R' - R;  no slip: R φ' = -ρ θ'",
        "T = M' X'²/2 + (M/2)[(X' + ρ θ' cos θ)² + ρ² θ'² sin² θ] + (M R²/4) φ'²,  U = -M g ρ cos θ",
        "ω² = 2 g (M + M') / (ρ (M + 3M'))   (= g/R at M' = M, R' = 2R)",
        "X/θ = -M ρ/(M + M'),  x_c/X = -M'/M,  φ/θ = -ρ/R",
    ],
)


exercise.declare_limits(
    "R' > R: the cylinder fits in the hollow",
)


@exercise.constraint
def constraint(p):
    if not p.R_prime > p.R:
        return f"R' = {p.R_prime:g} m must exceed R = {p.R:g} m (the cylinder must fit in the hollow)"


@exercise.analytic
def analytic(p):
    M, Mb, R = p.M, p.M_prime, p.R
    rho = p.R_prime - p.R
    return {
        "omega": np.sqrt(2.0 * p.g * (M + Mb) / (rho * (M + 3.0 * Mb))),
        "X_over_theta": -M * rho / (M + Mb),
        "xc_over_X": -Mb / M,
        "phi_over_theta": -rho / R,
    }


@exercise.numeric
def numeric(p, run):
    # in units of the cylinder's mass M, the gap rho = R' - R and the time sqrt(rho/g): what is left is the
    # mass ratio M'/M and the radius R/rho, so no choice of the SI scales (1e+-200) reaches the round-off
    rho_si = p.R_prime - p.R
    M, Mb, R, g, rho = 1.0, p.M_prime / p.M, p.R / rho_si, 1.0, 1.0
    pts3, w = disk(6, 12)
    r_rel = R * pts3[:, :2]
    w = M * w

    def axis_velocity(q, qdot):
        # axis at (X + rho sin theta, -rho cos theta) relative to the hollow's axis at rest
        th = q[1]
        return np.array([qdot[0] + rho * qdot[1] * np.cos(th), rho * qdot[1] * np.sin(th)])

    def spin(q, qdot):
        n = np.array([np.sin(q[1]), -np.cos(q[1])])  # from the cylinder's axis to the contact
        return rolling_spin(axis_velocity(q, qdot), [qdot[0], 0.0], n, R)

    def T_block(q, qdot):
        return 0.5 * Mb * qdot[0] ** 2

    def T_cylinder(q, qdot):
        return plane_kinetic_energy(w, r_rel, axis_velocity(q, qdot), spin(q, qdot))

    def U(q):
        return M * g * 2.0 * rho * np.sin(q[1] / 2.0) ** 2

    q0 = np.zeros(2)
    # the cylinder's T is probed with theta' = 1/rho, so both probes move it at speeds of
    # order 1 (a gap of 1e-7 m would otherwise leave the cross term at the round-off of T)
    Mm = mass_matrix(T_block, q0) + scaled_mass_matrix(T_cylinder, q0, [1.0, 1.0 / rho])
    K = hessian(U, q0, scale=[rho, 1.0])
    modes = balanced_modes(Mm, K)
    w2 = modes.omega2
    if not (w2[1] > 0 and abs(w2[0]) < 1e-9 * w2[1]):
        raise NumericFailure(f"expected one zero and one positive root, got {w2}")
    shape = modes.shapes[:, 1] / modes.shapes[1, 1]  # theta = 1
    v_axis = axis_velocity(q0, shape)
    run.info["zero_root_over_omega2"] = float(w2[0] / w2[1])
    run.info["momentum_of_mode"] = float(Mb * shape[0] + M * v_axis[0])
    # polarization and the disk rule are exact for quadratic T; the Hessian of the
    # sin^2 potential has truncation h^4/1440 ~ 1e-15; the balanced 2x2 eigh ~ 1e-15.
    # x_c/X = 1 + rho/X_over_theta is exactly 0 for a massless block: absolute claim
    for name in ("omega", "X_over_theta", "phi_over_theta"):
        run.claim(name, rel=1e-11)
    run.claim("xc_over_X", rel=1e-11, abs=1e-12)
    return {
        "omega": np.sqrt(w2[1]) * (np.sqrt(p.g) / np.sqrt(rho_si)),
        "X_over_theta": shape[0] * rho_si,
        "xc_over_X": v_axis[0] / shape[0],
        "phi_over_theta": spin(q0, shape),
    }

"""4.17 Cuboid turned at constant rate about a space diagonal: the torque that keeps it going.

Analytic: in the body's principal axes (along the edges) I_1 = M(a2^2 + a3^2)/12
and cyclic, M = rho a1 a2 a3.  L = I omega is fixed in the body, so in the lab
dL/dt = omega x L, and the torque is tau = omega x (I omega), constant in the
body.  With omega = omega (a1, a2, a3)/d, d^2 = a1^2 + a2^2 + a3^2:
  tau_1 = K a2 a3 (a2^2 - a3^2), tau_2 = K a3 a1 (a3^2 - a1^2),
  tau_3 = K a1 a2 (a1^2 - a2^2),  K = rho a1 a2 a3 omega^2 / (12 d^2),
evaluated with (a_i - a_j)(a_i + a_j) so that a near-cube keeps its digits.

Numeric: Newton's second law for each volume element, without principal
moments: the element at r moves on a circle, its acceleration is
omega x (omega x r), and the torque is the volume integral of
rho r x [omega x (omega x r)], by a 3x3x3 Gauss-Legendre rule (exact for this
quadratic integrand).  Check: the inertia tensor by the same rule, the body
turned about the fixed axis, L(t) = R(t) I R(t)^T omega, differentiated at t = 0
by a complex step (no subtraction error); the two torques must agree.
The quadrature sums terms of the natural size rho V d^2 omega^2 that cancel
for a near-cube, so the accuracy claimed is absolute, a few ulps of that size.
"""

from __future__ import annotations

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.frames import rotation
from mech.solvers.mechanics.inertia import gauss_legendre, inertia_tensor

exercise = Exercise(
    "4.17",
    formulas=[
        "τ = ω × (I ω), constant in the body frame",
        "τ₁ = K a₂a₃(a₂² - a₃²), τ₂ = K a₃a₁(a₃² - a₁²), τ₃ = K a₁a₂(a₁² - a₂²)",
        "K = ρ a₁a₂a₃ ω² / (12 (a₁² + a₂² + a₃²))",
        "|τ| = K (Σ a_j² a_k² (a_j² - a_k²)²)^(1/2) over the three pairs",
    ],
)


@exercise.analytic
def analytic(p):
    a1, a2, a3 = p.a1, p.a2, p.a3
    K = p.rho * a1 * a2 * a3 * p.omega**2 / (12.0 * (a1 * a1 + a2 * a2 + a3 * a3))
    t1 = K * a2 * a3 * (a2 - a3) * (a2 + a3)
    t2 = K * a3 * a1 * (a3 - a1) * (a3 + a1)
    t3 = K * a1 * a2 * (a1 - a2) * (a1 + a2)
    return {"tau": float(np.sqrt(t1 * t1 + t2 * t2 + t3 * t3)), "tau1": t1, "tau2": t2, "tau3": t3}


def _box_points(a, n=3):
    """Tensor Gauss-Legendre points (N x 3) and volumes (N) for the box [-a/2, a/2]^3."""
    axes = [gauss_legendre(n, -ai / 2.0, ai / 2.0) for ai in a]
    X, Y, Z = np.meshgrid(axes[0][0], axes[1][0], axes[2][0], indexing="ij")
    W = np.einsum("i,j,k->ijk", axes[0][1], axes[1][1], axes[2][1])
    return np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=1), W.ravel()


@exercise.numeric
def numeric(p, run):
    a = np.array([p.a1, p.a2, p.a3])
    d = np.linalg.norm(a)
    omega = p.omega * a / d
    r, vol = _box_points(a)
    dm = p.rho * vol
    # Newton for each element: force dm * omega x (omega x r); its torque about the center
    acc = np.cross(omega, np.cross(omega, r))
    tau = (dm[:, None] * np.cross(r, acc)).sum(axis=0)

    # check through the angular momentum of the turning body, d/dt by a complex step
    I = inertia_tensor(r, dm, about=np.zeros(3))
    h = 1e-20 / p.omega
    R = rotation(omega / p.omega, p.omega * 1j * h)
    L = R @ I @ R.T @ omega
    tau_check = L.imag / h

    scale = p.rho * np.prod(a) * d * d * p.omega**2
    abs_claim = 1e-15 * scale
    mismatch = np.max(np.abs(tau - tau_check))
    run.info["mass"] = dm.sum()
    run.info["torque_routes_mismatch_over_scale"] = mismatch / scale
    if mismatch > abs_claim:
        raise NumericFailure(
            f"element-by-element torque and dL/dt disagree by {mismatch:.3g} N m (scale {scale:.3g})"
        )
    run.method = "Gauss-Legendre 3x3x3 volume sum"
    for name in ("tau", "tau1", "tau2", "tau3"):
        run.claim(name, rel=1e-12, abs=abs_claim)
    return {"tau": float(np.linalg.norm(tau)), "tau1": tau[0], "tau2": tau[1], "tau3": tau[2]}

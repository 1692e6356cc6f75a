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
Both sides work with the edges in units of the longest one and give the torque
in units rho omega^2 A^5, scaled back at the end; a torque scale beyond
1e+-290 N m is refused (it leaves the floating-point range).
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems import ranges
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


def _log10_squares(p):
    """log10(a1^2 + a2^2 + a3^2), summed in logs (no square overflows)."""
    a = sorted((p.a1, p.a2, p.a3))
    return 2 * math.log10(a[2]) + math.log10(1.0 + (a[0] / a[2]) ** 2 + (a[1] / a[2]) ** 2)


ranges.declare(exercise, ranges.Scale(
    "rho a1 a2 a3 (a1^2 + a2^2 + a3^2) omega^2", {"rho": 1, "a1": 1, "a2": 1, "a3": 1, "omega": 2},
    "the torque scale", low=-290.0, high=290.0, log_factor=_log10_squares))


def _unit(p):
    """rho omega^2 A^5 (A the longest edge), the torque unit of the scaled box, multiplied in an order
    that keeps every partial product in range (the constraint keeps the result itself in range)."""
    A = max(p.a1, p.a2, p.a3)
    factors = [p.rho, p.omega, p.omega, A, A, A, A, A]
    product, log_product = 1.0, 0.0
    while factors:
        k = min(range(len(factors)), key=lambda i: abs(log_product + math.log(factors[i])))
        f = factors.pop(k)
        product *= f
        log_product += math.log(f)
    return product


@exercise.analytic
def analytic(p):
    # edges in units of the longest one, the torque in units rho omega^2 A^5: nothing overflows
    A = max(p.a1, p.a2, p.a3)
    a1, a2, a3 = p.a1 / A, p.a2 / A, p.a3 / A
    K = a1 * a2 * a3 / (12.0 * (a1 * a1 + a2 * a2 + a3 * a3))
    t1 = K * a2 * a3 * (a2 - a3) * (a2 + a3)
    t2 = K * a3 * a1 * (a3 - a1) * (a3 + a1)
    t3 = K * a1 * a2 * (a1 - a2) * (a1 + a2)
    unit = _unit(p)
    return {"tau": math.sqrt(t1 * t1 + t2 * t2 + t3 * t3) * unit, "tau1": t1 * unit, "tau2": t2 * unit,
            "tau3": t3 * unit}


def _box_points(a, n=3):
    """Tensor Gauss-Legendre points (N x 3) and volumes (N) for the box [-a/2, a/2]^3."""
    axes = [gauss_legendre(n, -ai / 2.0, ai / 2.0) for ai in a]
    X, Y, Z = np.meshgrid(axes[0][0], axes[1][0], axes[2][0], indexing="ij")
    W = np.einsum("i,j,k->ijk", axes[0][1], axes[1][1], axes[2][1])
    return np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=1), W.ravel()


@exercise.numeric
def numeric(p, run):
    # lengths in units of the longest edge A, masses in rho A^3, time in 1/omega: the torque comes out
    # in units rho omega^2 A^5 and is scaled back at the end (no overflow for a kilometre box)
    A = max(p.a1, p.a2, p.a3)
    a = np.array([p.a1, p.a2, p.a3]) / A
    d = np.linalg.norm(a)
    omega = a / d
    r, vol = _box_points(a)
    dm = vol
    # Newton for each element: force dm * omega x (omega x r); its torque about the center
    acc = np.cross(omega, np.cross(omega, r))
    tau = (dm[:, None] * np.cross(r, acc)).sum(axis=0)

    # check through the angular momentum of the turning body, d/dt by a complex step
    I = inertia_tensor(r, dm, about=np.zeros(3))
    h = 1e-20
    R = rotation(omega, 1j * h)
    L = R @ I @ R.T @ omega
    tau_check = L.imag / h

    scale = np.prod(a) * d * d
    abs_claim = 1e-15 * scale
    mismatch = np.max(np.abs(tau - tau_check))
    unit = _unit(p)
    run.info["mass"] = float(np.sum(dm)) * p.rho * A * A * A
    run.info["torque_routes_mismatch_over_scale"] = mismatch / scale
    if mismatch > abs_claim:
        raise NumericFailure(
            f"element-by-element torque and dL/dt disagree by {mismatch / scale:.3g} of the torque scale"
        )
    run.method = "Gauss-Legendre 3x3x3 volume sum"
    for name in ("tau", "tau1", "tau2", "tau3"):
        run.claim(name, rel=1e-12, abs=abs_claim * unit)
    return {"tau": float(np.linalg.norm(tau)) * unit, "tau1": float(tau[0]) * unit,
            "tau2": float(tau[1]) * unit, "tau3": float(tau[2]) * unit}

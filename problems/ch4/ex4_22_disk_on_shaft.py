"""4.22 Disk on a horizontal shaft rolling around a vertical axis: the floor's force.

Analytic: rolling without slipping at distance l from the axis fixes the spin
about the shaft, omega_spin = Omega l / R (the contact point's velocity
Omega l must be cancelled by the spin's R omega_spin).  The disk's angular
momentum about the joint has a horizontal part (M R^2/2) omega_spin along the
shaft that turns with the assembly, so its rate is (M R^2/2)(Omega l/R) Omega,
horizontal and perpendicular to the shaft.  Only the torques of gravity (M g l)
and of the floor's force (N l) about the joint have that direction, so
N l - M g l = M R Omega^2 l / 2:  delta_N = M R Omega^2 / 2, N = M g + delta_N,
independent of l, exact for the horizontal shaft.

Numeric: the disk is a set of mass elements (Gauss-Legendre in radius, the
trapezoid rule in angle: exact for the needed moments), placed by the composite
rotation (about the vertical at Omega, about the shaft at the spin); the spin
is the solution of the linear rolling condition (zero velocity of the material
point at the contact); each element's acceleration is the exact second
derivative of the composite rotation; sum m r x a about the joint (split into
the center's orbital part and the elements' motion about the center) equals the
torque of the floor's excess force delta_N and of a tangential friction f at
the contact (the weight's torque and that of M g at the contact cancel), solved
by least squares.  The residual of that overdetermined balance and the size of
f are checks.
"""

from __future__ import annotations

import numpy as np

from mech.problems import ranges
from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.frames import skew
from mech.solvers.mechanics.inertia import disk

exercise = Exercise(
    "4.22",
    formulas=[
        "ω_spin = Ω l / R  (rolling)",
        "δN = N - M g = M R Ω² / 2  (dL/dt of the spin's horizontal angular momentum = torque about the joint)",
        "N = M g + M R Ω² / 2",
    ],
)

# the route squares the lengths and the spin rate (R^2 in the rolling condition, s^2 in the accelerations)
ranges.declare(
    exercise,
    ranges.Scale("R", {"R": 1}, "the disk's radius and its square", low=-150, high=150),
    ranges.Scale("l", {"l": 1}, "the shaft's length and its square", low=-150, high=150),
    ranges.Scale("Omega l/R", {"Omega": 1, "l": 1, "R": -1}, "the spin rate and its square", low=-150, high=150),
)


@exercise.analytic
def analytic(p):
    dN = 0.5 * p.M * p.R * p.Omega**2
    return {"N": p.M * p.g + dN, "delta_N": dN, "omega_spin": p.Omega * p.l / p.R}


@exercise.numeric
def numeric(p, run):
    M, R, l, Om = p.M, p.R, p.l, p.Omega
    pts, w = disk(8, 16)  # unit disk in the xy plane, unit mass
    # the disk's plane is perpendicular to the shaft (x): body positions in the yz plane
    rho = R * np.stack([np.zeros(len(w)), pts[:, 0], pts[:, 1]], axis=1)
    m = M * w
    ex, ez = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])
    Kz, Kx = skew(ez), skew(ex)
    center = l * ex
    # rolling: the material point at the contact, rho_c = -R z, has zero velocity at t = 0:
    # v = Omega Kz (center + rho_c) + s Kx rho_c, linear in the spin s
    rho_c = -R * ez
    v0 = Om * Kz @ (center + rho_c)
    v1 = Kx @ rho_c
    s = -float(v0 @ v1) / float(v1 @ v1)
    if np.linalg.norm(v0 + s * v1) > 1e-12 * np.linalg.norm(v0):
        raise NumericFailure("the rolling condition has no solution for the spin")
    # r(t) = A(t)(center + B(t) rho), A about z at Omega, B about x at s: exact second derivative at t = 0
    acc_center = Om**2 * (Kz @ Kz) @ center
    # the three parts of an element's acceleration about the center (centripetal of the
    # turning, Coriolis-like cross term, centripetal of the spin), each crossed with rho
    # before scaling: rho x (Kx Kx rho) is exactly zero element by element, while
    # rho x (s^2 Kx Kx rho) rounded would leave errors of size Omega^2 l^2 when l >> R
    parts = (
        (Om**2, (Kz @ Kz @ rho.T).T),
        (2 * Om * s, (Kz @ Kx @ rho.T).T),
        (s**2, (Kx @ Kx @ rho.T).T),
    )
    # dL/dt about the joint = sum m (center + rho) x (acc_center + acc_rel), acc_rel from the parts; the elements' sum of
    # m rho vanishes (rho is measured from the center of mass), so the cross terms drop and
    # the orbital part is M center x acc_center.  Summing in this order avoids the
    # cancellation of terms of size Omega^2 l^2 when l >> R.
    run.info["center_of_mass_offset"] = float(np.linalg.norm(m @ rho) / (M * R))
    dyn = M * np.cross(center, acc_center)
    for coef, a in parts:
        dyn = dyn + coef * np.sum(m[:, None] * np.cross(rho, a), axis=0)
    # torque of (delta_N z + f y) at the contact l x - R z; weight and M g at the contact cancel
    contact = center + rho_c
    A = np.stack([np.cross(contact, ez), np.cross(contact, np.array([0.0, 1.0, 0.0]))], axis=1)
    sol, *_ = np.linalg.lstsq(A, dyn, rcond=None)
    dN, f = float(sol[0]), float(sol[1])
    scale = np.linalg.norm(A, axis=0).max() * max(abs(dN), 1e-300)
    resid = np.linalg.norm(A @ sol - dyn)
    run.info["torque_residual"] = resid / scale
    run.info["tangential_friction_N"] = f
    if resid > 1e-9 * scale or abs(f) > 1e-9 * abs(dN) * (1 + l / R):
        raise NumericFailure(f"the torque balance is inconsistent (residual {resid:.3g}, friction {f:.3g} N)")
    # quadrature exact for these moments: round-off only
    for name in ("N", "delta_N", "omega_spin"):
        run.claim(name, rel=1e-12)
    run.method = "quadrature (Gauss-Legendre x trapezoid), exact kinematics"
    return {"N": M * p.g + dN, "delta_N": dN, "omega_spin": abs(s)}

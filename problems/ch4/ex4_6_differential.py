"""4.6 Power of a torque, and the equal torque split of a differential gear.

Analytic: (a) with zero net force the power of the forces is sum F_k . (V + omega x r_k)
= omega . sum r_k x F_k = tau . omega (about the center of mass, or any point, since
the net force vanishes); (b) about a fixed axis it is tau_z omega.  (c) Rolling
without slip at the two meshes of a satellite with identical side gears gives
omega_c = (omega1 + omega2)/2.  With massless, frictionless gears the power in
equals the power out for every (virtual) motion: tau omega_c = tau1 omega1 + tau2 omega2;
taking omega1 and omega2 as independent gives tau1 = tau2 = tau/2, whatever the
shafts' actual speeds, and P1 = tau omega1/2, P2 = tau omega2/2.

Numeric: a 3D gear train with arbitrary radii: the common axis is x, side gear i
(pitch radius r_s) meshes with a satellite (pitch radius r_p) whose pin lies along a
carrier radius; the carrier rate and the satellite's spin solve the no-slip
conditions at both mesh points (linear least squares).  The mesh forces
(tangential, unknown), the pin's force and its moment normal to the pin (unknown;
the satellite is free about the pin) solve the force and moment balance of the
massless satellite and the torque balance of the carrier about x, as one linear
system; the shaft torques are the moments of the mesh forces about x and the
powers are F . v at the mesh points.  P1 + P2 = tau omega_c is checked, not used.
"""

from __future__ import annotations

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.frames import skew

exercise = Exercise(
    "4.6",
    formulas=[
        "P = τ·ω  (zero net force);  fixed axis: P = τ_z ω",
        "ω_c = (ω₁ + ω₂)/2",
        "τ₁ = τ₂ = τ/2,  P₁ = τ ω₁/2,  P₂ = τ ω₂/2",
    ],
)


@exercise.analytic
def analytic(p):
    return {
        "omega_c": 0.5 * (p.omega1 + p.omega2),
        "tau1": 0.5 * p.tau,
        "tau2": 0.5 * p.tau,
        "P1": 0.5 * p.tau * p.omega1,
        "P2": 0.5 * p.tau * p.omega2,
    }


# arbitrary geometry (m): side-gear pitch radius, satellite pitch radius, pin azimuth about x
_R_SIDE, _R_SAT, _PIN_AZIMUTH = 0.083, 0.031, 0.4


@exercise.numeric
def numeric(p, run):
    x = np.array([1.0, 0.0, 0.0])
    radial = np.array([0.0, np.cos(_PIN_AZIMUTH), np.sin(_PIN_AZIMUTH)])  # the pin's direction
    C = _R_SIDE * radial  # satellite center, on the pin
    P = [C - _R_SAT * x, C + _R_SAT * x]  # mesh points with side gears 1 (x < 0) and 2 (x > 0)
    omegas = [p.omega1, p.omega2]

    # kinematics: satellite angular velocity omega_c x + sigma radial; its pin passes through the
    # carrier axis, so a satellite point moves with (omega_c x + sigma radial) x r.
    # no slip at P_i: (omega_c x + sigma radial) x P_i = omega_i x x P_i
    A = np.vstack([np.column_stack([np.cross(x, Pi), np.cross(radial, Pi)]) for Pi in P])
    b = np.concatenate([wi * np.cross(x, Pi) for wi, Pi in zip(omegas, P)])
    (omega_c, sigma), *_ = np.linalg.lstsq(A, b, rcond=None)
    vel_scale = max(abs(p.omega1), abs(p.omega2), 1e-300) * _R_SIDE
    if np.linalg.norm(A @ [omega_c, sigma] - b) > 1e-12 * vel_scale:
        raise NumericFailure("the mesh conditions have no common solution: inconsistent gear geometry")

    # statics of the massless satellite and the carrier.  Unknowns:
    #   f1, f2: tangential mesh forces on the satellite (along t_i, the side gear's direction of motion)
    #   R (3): force of the pin on the satellite;  N (2): pin moment on the satellite, normal to the pin
    t = [np.cross(x, Pi) / np.linalg.norm(np.cross(x, Pi)) for Pi in P]
    n1 = np.cross(radial, x)
    n2 = np.cross(radial, n1)  # n1, n2 span the plane normal to the pin
    K = np.zeros((7, 7))
    rhs = np.zeros(7)
    K[0:3, 0], K[0:3, 1], K[0:3, 2:5] = t[0], t[1], np.eye(3)  # sum of forces = 0
    K[3:6, 0] = np.cross(P[0] - C, t[0])  # moments about the satellite's center = 0
    K[3:6, 1] = np.cross(P[1] - C, t[1])
    K[3:6, 5], K[3:6, 6] = n1, n2
    # carrier (massless), moment about x: tau + moment of what the satellite exerts on it (-R at C, -N) = 0
    K[6, 2:5] = -(skew(C).T @ x)  # x . (C x (-R)) = -x . (C x R) = -(skew(C)^T x) . R
    K[6, 5], K[6, 6] = -(x @ n1), -(x @ n2)
    rhs[6] = -p.tau
    sol = np.linalg.solve(K, rhs)
    forces_on_sat = [sol[0] * t[0], sol[1] * t[1]]

    taus, powers = [], []
    for Pi, Fi, wi in zip(P, forces_on_sat, omegas):
        on_shaft = -Fi  # action and reaction at the mesh
        taus.append(float(x @ np.cross(Pi, on_shaft)))
        powers.append(float(on_shaft @ (wi * np.cross(x, Pi))))

    run.method = "linear least squares (kinematics) + linear statics"
    run.info["satellite_spin"] = float(sigma)
    balance = powers[0] + powers[1] - p.tau * omega_c
    run.invariant("power balance P1 + P2 - tau omega_c", balance / max(abs(p.tau) * vel_scale / _R_SIDE, 1e-300))
    w_scale = max(abs(p.omega1), abs(p.omega2))
    run.claim("omega_c", rel=1e-12, abs=1e-14 * w_scale)
    run.claim("tau1", rel=1e-12, abs=1e-14 * abs(p.tau))
    run.claim("tau2", rel=1e-12, abs=1e-14 * abs(p.tau))
    run.claim("P1", rel=1e-12, abs=1e-14 * abs(p.tau) * w_scale)
    run.claim("P2", rel=1e-12, abs=1e-14 * abs(p.tau) * w_scale)
    return {"omega_c": float(omega_c), "tau1": taus[0], "tau2": taus[1], "P1": powers[0], "P2": powers[1]}

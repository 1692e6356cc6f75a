"""4.8 Billiard ball struck by a cue: sliding, then rolling.

Analytic: the hit point is r = (-(R^2 - b^2 - (h - R)^2)^(1/2), b, h - R) from the
center; the impulse P x gives V0 = P/M along x and I w0 = r x P x = P (0, h - R, -b),
with I = 2 M R^2 / 5.  So w_z = -5 b P / (2 M R^2), which no horizontal force at
the contact can change (its torque about the center is horizontal).  The
contact-point slip u = V + w x (0, 0, -R) starts along x, u0 = V0 (1 - 5 (h - R)/(2R))
= V0 (7 - 5 h/R)/2, and friction -mu M g sign(u0) x changes it at the rate
(1/M + R^2/I) F = -(7/2) mu g sign(u0): it stays along x and vanishes at
t_roll = 2 |u0| / (7 mu g) = P |7 - 5 h/R| / (7 M mu g).  Then
V_f = V0 - (2/7) u0 = 5 P h / (7 M R), independent of b; x_roll = (V0 + V_f) t_roll / 2.

Numeric: the sphere's moment I/(M R^2) from a Gauss quadrature of the unit ball (solvers.mechanics.inertia);
the strike is a finite force pulse P (pi / 2 tau) sin(pi t / tau) along x at the
body-fixed hit point, integrated through (the hit point turns with the ball) for
tau = 1e-3 rtol min(R/V0, V0/(mu g)), so the finite-pulse effect (|w0| tau + mu g tau / V0,
relative) stays far below the claims; friction is off during the pulse, as in the
model.  Then the 3D sliding ball: the contact slip u, w and the center's position with friction
-mu M g u/|u| at the contact and its torque, integrated in scaled units to the event
u . u0_hat = 0.  A slip below round-off plus the pulse's effect counts as rolling
from the start.  Times count from the pulse's center, the impulsive instant.
"""

from __future__ import annotations

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.inertia import ball, inertia_tensor
from mech.solvers.numerics.ode import Event

exercise = Exercise(
    "4.8",
    formulas=[
        "V₀ = P/M,  I ω₀ = r_hit × P x̂ = P (0, h - R, -b),  I = 2MR²/5",
        "V_f = 5 P h / (7 M R)   (independent of b)",
        "t_roll = P |7 - 5h/R| / (7 M μ g),  x_roll = (V₀ + V_f) t_roll / 2",
        "ω_z = -5 b P / (2 M R²)   (constant: friction has no vertical torque)",
    ],
    # the sliding phase, from the end of the strike to rolling (x along the impulse, z up): the slip
    # velocity of the contact point, the spin, and the centre's displacement since the strike
    states=[("slip_x", "m/s"), ("slip_y", "m/s"), ("slip_z", "m/s"), ("omega_x", "rad/s"),
            ("omega_y", "rad/s"), ("omega_z", "rad/s"), ("x", "m"), ("y", "m"), ("z", "m")],
)


exercise.declare_limits(
    "(h/R - 1)^2 + (b/R)^2 <= 1: the hit point lies on the ball",
)


@exercise.constraint
def constraint(p):
    if (p.h_over_R - 1.0) ** 2 + p.b_over_R**2 > 1.0 + 1e-12:
        return (f"the hit point (h/R = {p.h_over_R:g}, b/R = {p.b_over_R:g}) is off the ball: "
                "(h/R - 1)^2 + (b/R)^2 must not exceed 1")


@exercise.analytic
def analytic(p):
    V0 = p.P / p.M
    V_f = 5.0 * V0 * p.h_over_R / 7.0
    t_roll = V0 * abs(7.0 - 5.0 * p.h_over_R) / (7.0 * p.mu * p.g)
    return {
        "V_f": V_f,
        "t_roll": t_roll,
        "x_roll": 0.5 * (V0 + V_f) * t_roll,
        "omega_z": -2.5 * p.b_over_R * V0 / p.R,
    }


def _cross(a, b):
    """a x b for 3-vectors (numpy's cross costs far more per call on these tiny arrays)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def _hit_point(h_over_R, b_over_R):
    """The hit point on the rear surface, in units of R from the center."""
    z = h_over_R - 1.0
    x = -np.sqrt(max(0.0, 1.0 - b_over_R**2 - z**2))
    return np.array([x, b_over_R, z])


@exercise.numeric
def numeric(p, run):
    M, R, P, mu, g = p.M, p.R, p.P, p.mu, p.g
    V0 = P / M  # velocity unit (not an answer: the pulse's integral is checked below)
    pts, w = ball(6, 6, 12)
    # the unit ball of unit mass: I / (M R^2), so that no scale of M or R (M R^2 can leave the floating-point
    # range at R = 1e+-200 times its default) enters the inertia
    I_t = inertia_tensor(pts, w)
    moments = np.linalg.eigvalsh(I_t)
    if moments[-1] - moments[0] > 1e-12 * moments[-1]:
        raise NumericFailure(f"the ball quadrature is not isotropic: {moments}")
    I_inv_MR2 = np.linalg.inv(I_t)  # (I / M R^2)^-1, a sphere: no gyroscopic term

    # --- the strike: force P (pi/2 tau) sin(pi t/tau) x at the body-fixed hit point ---
    # far shorter than both the time to turn the ball (R/V0) and the sliding time (V0/mu g)
    tau = 1e-3 * run.rtol * min(R / V0, V0 / (mu * g))
    kappa = tau * V0 / R  # how far (in R) the ball moves or turns per unit scaled rate over the pulse
    xhat = np.array([1.0, 0.0, 0.0])

    def strike(sig, y):  # sigma = t/tau; V in V0, w in V0/R, hit point and center in R
        V, om, rh = y[0:3], y[3:6], y[6:9]
        f = 0.5 * np.pi * np.sin(np.pi * sig)  # tau F / (M V0) along x
        return np.concatenate([f * xhat, f * (I_inv_MR2 @ _cross(rh, xhat)), kappa * _cross(om, rh), kappa * V])

    y0 = np.concatenate([np.zeros(6), _hit_point(p.h_over_R, p.b_over_R), np.zeros(3)])
    pulse = run.integrate(strike, (0.0, 1.0), y0, rtol=run.rtol, atol=run.rtol * 1e-3, first_step=1e-3)
    y1 = pulse.y_end
    V1, om1, xc1 = y1[0:3], y1[3:6], y1[9:12]  # scaled
    run.info["pulse_tau_s"] = tau
    run.info["pulse_momentum_error"] = float(V1[0] - 1.0)  # M V / P - 1, from the integration
    eps_pulse = float(np.linalg.norm(om1)) * kappa + mu * g * tau / V0
    run.info["pulse_effect_rel"] = eps_pulse

    down = np.array([0.0, 0.0, -1.0])  # contact point from the center, in R

    def slip(V, om):
        return V + _cross(om, down)

    u0 = slip(V1, om1)
    u_tol = 1e-13 + 10.0 * eps_pulse  # in V0: round-off of u and what the pulse leaves
    t_unit = V0 / (mu * g)
    # absolute accuracy where outputs sit at the noise floor (zero slip, zero offset, h -> 0)
    run.claim("V_f", rel=100 * run.rtol, abs=V0 * u_tol)
    run.claim("t_roll", rel=100 * run.rtol, abs=t_unit * u_tol)
    run.claim("x_roll", rel=100 * run.rtol, abs=V0 * t_unit * u_tol)
    run.claim("omega_z", rel=100 * run.rtol + 10 * eps_pulse, abs=V0 / R * u_tol)

    if np.linalg.norm(u0) <= u_tol:
        run.info["slip_after_strike"] = "below round-off: rolls from the start"
        return {"V_f": V0 * V1[0], "t_roll": 0.0, "x_roll": R * xc1[0], "omega_z": om1[2] * V0 / R}

    # --- sliding: friction -mu M g u/|u| at the contact; time in t_unit, lengths in V0 t_unit ---
    u0_hat = u0 / np.linalg.norm(u0)

    # state (u, w, x): the slip itself is integrated (du/dt = dV/dt + dw/dt x r_contact),
    # so a slip of 1e-7 V0 is not a small difference of O(1) velocities in round-off
    def sliding(s, y):
        u, om = y[0:3], y[3:6]
        # -u/|u|, with |u| signed by u . u0_hat: the same law before the event, and its smooth
        # continuation past it, so the step that brackets the event sees no jump in the force
        F = -u / (np.linalg.norm(u) * np.sign(u @ u0_hat) or 1.0)  # in mu M g
        dom = I_inv_MR2 @ _cross(down, F)
        return np.concatenate([F + _cross(dom, down), dom, u - _cross(om, down)])

    def velocity(y):
        return y[0:3] - _cross(y[3:6], down)

    def L_contact(y):  # angular momentum about the contact point, in M R V0
        return np.linalg.solve(I_inv_MR2, y[3:6]) + _cross(-down, velocity(y))

    ys = np.concatenate([u0, om1, np.zeros(3)])
    s_ev, y_ev, traj = run.integrate_to_event(
        sliding,
        (0.0, 1e3 * max(1.0, float(np.linalg.norm(u0)))),
        ys,
        Event(lambda s, y: y[0:3] @ u0_hat, direction=-1, name="slip = 0"),
        rtol=run.rtol,
        atol=[run.rtol * 1e-3 * float(np.linalg.norm(u0))] * 3 + [run.rtol * 1e-3] * 6,
    )
    run.motion(traj, t_scale=t_unit, t_offset=0.5 * tau, y_scale=[V0] * 3 + [V0 / R] * 3 + [V0 * t_unit] * 3)
    L0, L1 = L_contact(ys), L_contact(y_ev)
    L_scale = float(np.linalg.norm(np.linalg.solve(I_inv_MR2, om1)) + np.linalg.norm(V1))
    run.invariant("L_contact", np.linalg.norm(L1 - L0) / L_scale)
    u_end = y_ev[0:3]
    if np.linalg.norm(u_end) > 1e-9 * float(np.linalg.norm(u0)):
        raise NumericFailure(f"slip left across its first direction at the event: {u_end}")
    V_end = velocity(y_ev)
    return {
        "V_f": V0 * V_end[0],
        "t_roll": 0.5 * tau + t_unit * s_ev,
        "x_roll": R * xc1[0] + V0 * t_unit * y_ev[6],
        "omega_z": y_ev[5] * V0 / R,
    }

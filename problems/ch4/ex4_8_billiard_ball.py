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
from the start.  Times count from the pulse's center, the impulsive instant.  The
strike and the sliding are one motion in two legs; the states are the sliding's.
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


def _unit_ball():
    """(I / (M R^2))^-1 of the unit ball of unit mass, from a Gauss quadrature: no scale of M or R (M R^2 can
    leave the floating-point range at R = 1e+-200 times its default) enters the inertia; a sphere, so no
    gyroscopic term."""
    pts, w = ball(6, 6, 12)
    I_t = inertia_tensor(pts, w)
    moments = np.linalg.eigvalsh(I_t)
    if moments[-1] - moments[0] > 1e-12 * moments[-1]:
        raise NumericFailure(f"the ball quadrature is not isotropic: {moments}")
    return np.linalg.inv(I_t)


DOWN = np.array([0.0, 0.0, -1.0])  # the contact point from the center, in R
XHAT = np.array([1.0, 0.0, 0.0])


def _slip(V, om):
    """The contact point's velocity V + w x (-R z) (scaled)."""
    return V + _cross(om, DOWN)


def _pulse(p, rtol):
    """The strike's length tau: far shorter than both the time to turn the ball (R/V0) and the sliding time
    (V0/mu g); and kappa = tau V0 / R, how far (in R) the ball moves or turns per unit scaled rate over it."""
    V0 = p.P / p.M
    tau = 1e-3 * rtol * min(p.R / V0, V0 / (p.mu * p.g))
    return tau, tau * V0 / p.R


def _after_strike(p, tau, kappa, y1):
    """From the strike's end state: the slip u0 (in V0), the pulse's relative effect (|w0| tau + mu g tau / V0)
    and the slip below which the ball counts as rolling (round-off of u plus what the pulse leaves)."""
    V0 = p.P / p.M
    eps_pulse = float(np.linalg.norm(y1[3:6])) * kappa + p.mu * p.g * tau / V0
    return _slip(y1[0:3], y1[3:6]), eps_pulse, 1e-13 + 10.0 * eps_pulse


def _L_contact(I_inv_MR2, y):
    """The angular momentum about the contact point, in M R V0, of a sliding state (u, w, x)."""
    velocity = y[0:3] - _cross(y[3:6], DOWN)
    return np.linalg.solve(I_inv_MR2, y[3:6]) + _cross(-DOWN, velocity)


@exercise.motion
def motion(p, rtol=None):
    """The strike, then sliding until the slip vanishes (none when the strike leaves no slip).  The strike,
    a force P (pi / 2 tau) sin(pi t / tau) along x at the body-fixed hit point over sigma = t/tau in [0, 1]
    (V in V0, w in V0/R, hit point and center in R), leads into the states and is not shown; its length
    follows the accuracy ``rtol`` (the exercise's default by default).  Sliding: friction -mu M g u/|u|
    at the contact, time in t_unit = V0/(mu g), lengths in V0 t_unit.  Times count from the pulse's
    center, the impulsive instant."""
    from mech.problems.motion import Motion

    rtol = exercise.default_rtol if rtol is None else rtol
    M, R, mu, g = p.M, p.R, p.mu, p.g
    V0 = p.P / M  # velocity unit
    I_inv_MR2 = _unit_ball()
    tau, kappa = _pulse(p, rtol)
    t_unit = V0 / (mu * g)

    def strike(sig, y):
        V, om, rh = y[0:3], y[3:6], y[6:9]
        f = 0.5 * np.pi * np.sin(np.pi * sig)  # tau F / (M V0) along x
        return np.concatenate([f * XHAT, f * (I_inv_MR2 @ _cross(rh, XHAT)), kappa * _cross(om, rh), kappa * V])

    def sliding(path):
        u0, _, u_tol = _after_strike(p, tau, kappa, path.y_end)
        if np.linalg.norm(u0) <= u_tol:
            return None  # rolls from the start
        u0_hat = u0 / np.linalg.norm(u0)

        # state (u, w, x): the slip itself is integrated (du/dt = dV/dt + dw/dt x r_contact),
        # so a slip of 1e-7 V0 is not a small difference of O(1) velocities in round-off
        def rhs(s, y):
            u, om = y[0:3], y[3:6]
            # -u/|u|, with |u| signed by u . u0_hat: the same law before the event, and its smooth
            # continuation past it, so the step that brackets the event sees no jump in the force
            F = -u / (np.linalg.norm(u) * np.sign(u @ u0_hat) or 1.0)  # in mu M g
            dom = I_inv_MR2 @ _cross(DOWN, F)
            return np.concatenate([F + _cross(dom, DOWN), dom, u - _cross(om, DOWN)])

        return Motion(rhs, np.concatenate([u0, path.y_end[3:6], np.zeros(3)]),
                      (0.0, 1e3 * max(1.0, float(np.linalg.norm(u0)))),
                      event=Event(lambda s, y: y[0:3] @ u0_hat, direction=-1, name="slip = 0"),
                      t_scale=t_unit, t_offset=0.5 * tau, y_scale=[V0] * 3 + [V0 / R] * 3 + [V0 * t_unit] * 3,
                      y_size=[float(np.linalg.norm(u0))] * 3 + [1.0] * 6)

    def as_states(y):  # (V, w, hit point, center) -> (slip, w, center)
        return [y[0] - y[4], y[1] + y[3], y[2], y[3], y[4], y[5], y[9], y[10], y[11]]

    y0 = np.concatenate([np.zeros(6), _hit_point(p.h_over_R, p.b_over_R), np.zeros(3)])
    return Motion(strike, y0, (0.0, 1.0), t_scale=tau, t_offset=-0.5 * tau,
                  y_scale=[V0] * 3 + [V0 / R] * 3 + [R] * 3, to_states=as_states,
                  options={"first_step": 1e-3}, y_size=1.0, then=sliding, shown=False)


@exercise.numeric
def numeric(p, run):
    M, R, mu, g = p.M, p.R, p.mu, p.g
    V0 = p.P / M  # velocity unit (not an answer: the pulse's integral is checked below)
    end = run.follow(motion(p, run.rtol))
    tau, kappa = _pulse(p, run.rtol)
    y1 = end.legs[0].y_end
    V1, om1, xc1 = y1[0:3], y1[3:6], y1[9:12]  # scaled
    run.info["pulse_tau_s"] = tau
    run.info["pulse_momentum_error"] = float(V1[0] - 1.0)  # M V / P - 1, from the integration
    u0, eps_pulse, u_tol = _after_strike(p, tau, kappa, y1)
    run.info["pulse_effect_rel"] = eps_pulse
    t_unit = V0 / (mu * g)
    # absolute accuracy where outputs sit at the noise floor (zero slip, zero offset, h -> 0)
    run.claim("V_f", rel=100 * run.rtol, abs=V0 * u_tol)
    run.claim("t_roll", rel=100 * run.rtol, abs=t_unit * u_tol)
    run.claim("x_roll", rel=100 * run.rtol, abs=V0 * t_unit * u_tol)
    run.claim("omega_z", rel=100 * run.rtol + 10 * eps_pulse, abs=V0 / R * u_tol)

    if len(end.legs) == 1:
        run.info["slip_after_strike"] = "below round-off: rolls from the start"
        return {"V_f": V0 * V1[0], "t_roll": 0.0, "x_roll": R * xc1[0], "omega_z": om1[2] * V0 / R}

    I_inv_MR2 = _unit_ball()
    ys, s_ev, y_ev = end.motion.y0, end.t_end, end.y_end
    L_scale = float(np.linalg.norm(np.linalg.solve(I_inv_MR2, om1)) + np.linalg.norm(V1))
    run.invariant("L_contact", np.linalg.norm(_L_contact(I_inv_MR2, y_ev) - _L_contact(I_inv_MR2, ys)) / L_scale)
    u_end = y_ev[0:3]
    if np.linalg.norm(u_end) > 1e-9 * float(np.linalg.norm(u0)):
        raise NumericFailure(f"slip left across its first direction at the event: {u_end}")
    V_end = y_ev[0:3] - _cross(y_ev[3:6], DOWN)
    return {
        "V_f": V0 * V_end[0],
        "t_roll": 0.5 * tau + t_unit * s_ev,
        "x_roll": R * xc1[0] + V0 * t_unit * y_ev[6],
        "omega_z": y_ev[5] * V0 / R,
    }

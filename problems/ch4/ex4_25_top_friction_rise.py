"""4.25 Fast top with a cylindrical tip and small sliding friction: spin-down and rise.

Analytic (fast-top model, L = I3 omega3 n3, C at rest).  With the spherical unit
vectors (n3, e_theta, e_phi) of the axis, the contact point is
P - C = -l n3 + R e_theta, the rim slides along e_phi at omega3 R, and the
torque of M g z - mu M g e_phi about C is
    M g [ (l sin theta - R cos theta) e_phi - mu l e_theta - mu R n3 ].
Its n3 part spins the top down at the constant rate
    omega_dot = mu M g R / I3,
its e_theta part tilts the axis, dtheta/dt = -mu M g l / (I3 omega3), so
theta_dot0 = mu M g l / (I3 omega0), and dividing the two rates,
dtheta = (l/R) dln omega3:
    omega_rise = omega0 exp(-(theta0 - theta1) R / l),
    t_rise = (omega0 - omega_rise)/omega_dot = -omega0 I3 expm1(-(theta0 - theta1) R/l) / (mu M g R).
The e_phi part is the precession; it does not enter.

Numeric: the vector equation dL/dt = (P - C) x (M g z - mu M g h) integrated
for the three components of L (scaled by I3 omega0, time by the precession
time I3 omega0/(M g l)), with n3 = L/|L|, P and the sliding direction h
rebuilt from n3 at every step.  The forces see the axis only through its angle
with the vertical, so the integration runs in a frame turning about z with the
axis's azimuth (the turning rate is read off the torque at every step), which
removes the precession (hundreds of turns at small mu) from what the step
size must resolve.  The event is the polar angle of n3 reaching theta1 (atan2
of the horizontal and vertical parts, well conditioned at small angles).  The
initial rates are the initial torque projected on dn3/dtheta and, for the spin,
the friction's power F . (n3 x (P - C)) (no cancellation when R << l).
Monitored: |L| + mu M g R t, which the friction's axial torque keeps constant
in this model.

The model integrated is reduced: the fast top's L kept along its axis (no
transverse inertia, so no nutation) under the sliding friction at the tip,
in a turning frame and a rescaled time.  No Lagrangian gives that first-order
flow, so it has no symbolic declaration (``mech show 4.25 --derive`` says so,
problems/ch4/physics4_25.py).
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.numerics.ode import Event

exercise = Exercise(
    "4.25",
    formulas=[
        "torque about C = M g [(l sin θ - R cos θ) e_φ - μ l e_θ - μ R n₃]",
        "ω̇ = μ M g R / I₃  (constant)",
        "θ̇₀ = μ M g l / (I₃ ω₀)",
        "θ - θ₀ = (l/R) ln(ω₃/ω₀)  ⇒  ω_rise = ω₀ exp(-(θ₀ - θ₁) R/l)",
        "t_rise = -ω₀ I₃ expm1(-(θ₀ - θ₁) R/l) / (μ M g R)",
    ],
    # the rise from theta0 to theta1: the angular momentum in the vertical plane through the axis (the
    # frame turning with the axis's azimuth), horizontal and vertical parts; the axis's tilt from the
    # vertical is atan2(L_perp, L_z) (fast top: L along the axis)
    states=[("L_perp", "kg*m^2/s"), ("L_z", "kg*m^2/s")],
)

exercise.declare_limits(
    "theta1 < theta0: the axis rises from theta0 to theta1",
)


@exercise.constraint
def constraint(p):
    if not p.theta1 < p.theta0:
        return f"theta1 = {p.theta1:g} rad must be below theta0 = {p.theta0:g} rad (the axis rises from theta0 to theta1)"


# the spin may fall by at most e^MAX_SPIN_LOG during the rise: beyond, the top has stopped
MAX_SPIN_LOG = 25.0


@exercise.constraint
def constraint_2(p):
    x = (p.theta0 - p.theta1) * p.R / p.l
    if x > MAX_SPIN_LOG:
        return (
            f"(theta0 - theta1) R / l = {x:.3g} exceeds {MAX_SPIN_LOG:g}: the spin would fall by a factor "
            f"e^{x:.3g} during the rise, the top stops and the fast-top model does not apply"
        )


@exercise.analytic
def analytic(p):
    a = p.mu * p.M * p.g * p.R / p.I3
    x = -(p.theta0 - p.theta1) * p.R / p.l
    return {
        "omega_dot": a,
        "theta_dot0": p.mu * p.M * p.g * p.l / (p.I3 * p.omega0),
        "t_rise": -p.omega0 * p.I3 * math.expm1(x) / (p.mu * p.M * p.g * p.R),
        "omega_rise": p.omega0 * math.exp(x),
    }


def _face_down(nx, ny, nz):
    """e_P: the unit vector normal to the unit axis n in the vertical plane through it, pointing
    down the face (away from z): the direction from the face's center to its lowest rim point.

    Built from -(z - (z.n) n) = (nz nx, nz ny, -(1 - nz^2)) with 1 - nz^2 written nx^2 + ny^2
    (|n| = 1): near the vertical, 1 - nz^2 kept only a part in 1e16/theta^2 of its digits and
    the noise of the rim's direction stalled the step size (97655 evaluations at theta ~ 1e-5).
    """
    hor2 = nx * nx + ny * ny
    wx, wy, wz = nz * nx, nz * ny, -hor2
    wn = math.sqrt(wx * wx + wy * wy + wz * wz)
    return wx / wn, wy / wn, wz / wn


def _contact_force(n, rl, mu):
    """(e_P, F): the rim direction and the contact force in units of M g, F = z - mu h, with h
    the sliding direction of the rim point, omega3 R n3 x e_P (omega3 > 0)."""
    nx, ny, nz = n
    ex, ey, ez = _face_down(nx, ny, nz)
    hx, hy, hz = ny * ez - nz * ey, nz * ex - nx * ez, nx * ey - ny * ex
    hn = math.sqrt(hx * hx + hy * hy + hz * hz)
    return (ex, ey, ez), (-mu * hx / hn, -mu * hy / hn, 1.0 - mu * hz / hn)


def _torque(L, rl, mu):
    """Torque about C in units of M g l, for L in any units (only its direction matters).

    Built as -n3 x F + (R/l) e_P x F, the lever split so that the small rim offset is
    not rounded away against the axis when R << l.
    """
    Lx, Ly, Lz = L[0], L[1], L[2]
    Ln = math.sqrt(Lx * Lx + Ly * Ly + Lz * Lz)
    nx, ny, nz = Lx / Ln, Ly / Ln, Lz / Ln
    (ex, ey, ez), (fx, fy, fz) = _contact_force((nx, ny, nz), rl, mu)
    tx = -(ny * fz - nz * fy) + rl * (ey * fz - ez * fy)
    ty = -(nz * fx - nx * fz) + rl * (ez * fx - ex * fz)
    tz = -(nx * fy - ny * fx) + rl * (ex * fy - ey * fx)
    return tx, ty, tz


def _axial_torque(n, rl, mu):
    """n3 . torque (units M g l) as the friction's power over omega3: F . (n3 x (P - C))."""
    # n3 x (P - C) = (R/l) n3 x e_P exactly; the weight's part is horizontal-free (h is horizontal)
    nx, ny, nz = n
    ex, ey, ez = _face_down(nx, ny, nz)
    # n3 x e_P first, scaled by R/l last: its squares would underflow for R/l below 1e-154
    vx, vy, vz = ny * ez - nz * ey, nz * ex - nx * ez, nx * ey - ny * ex
    vn = math.sqrt(vx * vx + vy * vy + vz * vz)
    return rl * (vz - mu * vn)  # F = z - mu v/|v|


def _tilt_torque(n, rl, mu):
    """e_theta . torque (units M g l), e_theta = dn3/dtheta, as F . (e_theta x (P - C)).

    e_theta is the unit vector normal to n3 in its vertical plane pointing away from z, the
    same vector as e_P (built by the same function), so the rim's part (R/l) F . (e_P x e_P)
    is zero to the bit instead of a round-off of (R/l) eps against a tilting torque of
    order mu: only F . (e_theta x (-n3)) remains.
    """
    nx, ny, nz = n
    (ex, ey, ez), (fx, fy, fz) = _contact_force(n, rl, mu)
    # e_theta x (-n3) + (R/l) e_theta x e_theta, the second term exactly zero
    cx, cy, cz = -(ey * nz - ez * ny), -(ez * nx - ex * nz), -(ex * ny - ey * nx)
    return fx * cx + fy * cy + fz * cz


@exercise.motion
def motion(p):
    """The rise from theta0 to theta1: L in the frame turning about z with the axis's azimuth, (L_x', L_z') in
    units of I3 omega0, its azimuth phi alongside for the record, in the variable s of dt = |L| ds / k.

    The forces see the axis only through its angle with the vertical, so in the frame turning with its
    azimuth, dL'/dt = tau(L') - w z x L' with w = tau_y'/L_x' keeping L' in the x'z plane: the precession
    (hundreds of turns at small mu) needs no resolving.  Not t but s (a Sundman rescaling, k = mu (1 + R/l);
    t becomes a state, integrated as k t): in t the spin falls linearly to a stop while the tilt rate grows
    as 1/|L|, a log singularity just past the event where DOP853's error control on (L_x', L_z') misses the
    tilt's error (omega_rise moved by 4e-4 between rtol and rtol/10 at a fall by e^12).  In s, |L| decays
    exponentially at the rate (R/l)/(1 + R/l) and the axis turns at the rate 1/(1 + R/l): a smooth flow.
    Time in the precession time I3 omega0/(M g l)."""
    from mech.problems.motion import Motion

    rl = p.R / p.l
    mu = p.mu
    k = mu * (1.0 + rl)

    def rhs(s, y):
        Lx, Lz = y[0], y[1]
        Ln = math.hypot(Lx, Lz)
        tx, ty, tz = _torque((Lx, 0.0, Lz), rl, mu)
        f = Ln / k
        return (f * tx, f * tz, Ln, f * ty / Lx)

    def polar_minus_theta1(s, y):
        return math.atan2(y[0], y[1]) - p.theta1

    def friction_torque(Y):
        """|L| + mu M g R t is constant (the friction's axial torque), |L| + (mu R/l) t in these units."""
        return float(np.max(np.abs(np.hypot(Y[0], Y[1]) + mu * rl * Y[2] / k - 1.0)))

    n0 = (math.sin(p.theta0), 0.0, math.cos(p.theta0))
    # the rise's length in s: about (theta0 - theta1)/(the initial tilt rate in s); in s that rate stays
    # constant in this model, but the solver does not rely on it: four times the estimate
    s_end = 4.0 * (p.theta0 - p.theta1) * k / -_tilt_torque(n0, rl, mu)
    # L_x', L_z' stay positive (0 < theta < pi/2) and |L| may fall by up to e^25 (constraint): relative
    # error control, with an absolute floor far below that.  k t grows from 0 at the rate |L| = exp(-a s),
    # a <= 1, to at least (1 - 1/e) min(s_ev, 1) at the event: an absolute floor of rtol 1e-3 min(s_ev, 1)
    # keeps it relative at the end (a relative control from 0 made DOP853 start with steps of 1e-16 and
    # spend 250 evaluations on them).  phi is only recorded.
    L0 = p.I3 * p.omega0
    return Motion(rhs, [n0[0], n0[2], 0.0, 0.0], (0.0, s_end),
                  event=Event(polar_minus_theta1, direction=-1, name="theta = theta1"),
                  monitors={"|L| + mu M g R t": friction_torque}, t_scale=L0 / (p.M * p.g * p.l), y_scale=L0,
                  y_size=[math.exp(-30.0), math.exp(-30.0), min(0.25 * s_end, 1.0), math.inf],
                  to_states=lambda y: y[:2], clock=lambda y: y[2] / k)


@exercise.numeric
def numeric(p, run):
    L0 = p.I3 * p.omega0
    Mgl = p.M * p.g * p.l
    rl = p.R / p.l
    n0 = (math.sin(p.theta0), 0.0, math.cos(p.theta0))
    omega_dot = -_axial_torque(n0, rl, p.mu) * Mgl / p.I3
    rate_theta = -_tilt_torque(n0, rl, p.mu)  # dtheta/dt in units, |L| = 1 at t = 0
    theta_dot0 = rate_theta * Mgl / L0
    if rate_theta <= 0.0:
        raise NumericFailure("the initial torque does not raise the axis")
    m = motion(p)
    end = run.follow(m)
    run.info["precession_turns"] = float(end.y_end[3] / (2 * math.pi))
    # omega_dot, theta_dot0: projections of one torque, round-off exact
    run.claim("omega_dot", rel=1e-12)
    run.claim("theta_dot0", rel=1e-12)
    return {
        "omega_dot": omega_dot,
        "theta_dot0": theta_dot0,
        "t_rise": m.clock(end.y_end) * m.t_scale,
        "omega_rise": float(math.hypot(end.y_end[0], end.y_end[1])) * p.omega0,
    }

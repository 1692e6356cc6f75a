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
size must resolve.  The independent variable is the tilt itself (u, theta =
theta0 + u (theta1 - theta0), its rate read off the torque): theta1 is the end
of the span [0, 1], the same for every variant, so N variants are one ensemble
(``numeric``), and the state's own polar angle there (atan2 of the horizontal
and vertical parts, well conditioned at small angles) is monitored.  The
initial rates are the initial torque projected on dn3/dtheta and, for the spin,
the friction's power F . (n3 x (P - C)) (no cancellation when R << l).
Monitored: |L| + mu M g R t, which the friction's axial torque keeps constant
in this model.

Which model it integrates, and why no Lagrangian.  The reduced (gyroscopic) model
of the statement, L = I3 omega3 n3 (the transverse angular momentum and the
nutation dropped), driven by the torque about C of the weight and the sliding
friction: dL/dt = torque, three first-order equations for L alone.  It is not
derived from a Lagrangian because neither part has one: sliding (Coulomb)
friction is a dissipative force with no potential (its direction follows the
slip velocity), and the gyroscopic model is a limit of Euler's equations (L along
the axis), not the Euler-Lagrange equations of a Lagrangian in the axis's angles.
(``mech show 4.25 --derive`` says so; problems/ch4/physics4_25.py.)
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise

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
def analytic(P):
    """Over arrays of variants."""
    from mech.solvers.numerics.batch import Column

    mu, M, g, R, I3, l, w0 = (P[k] for k in ("mu", "M", "g", "R", "I3", "l", "omega0"))
    x = -(P["theta0"] - P["theta1"]) * R / l
    return {
        "omega_dot": Column(mu * M * g * R / I3),
        "theta_dot0": Column(mu * M * g * l / (I3 * w0)),
        "t_rise": Column(-w0 * I3 * np.expm1(x) / (mu * M * g * R)),
        "omega_rise": Column(w0 * np.exp(x)),
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
    wn = np.sqrt(wx * wx + wy * wy + wz * wz)
    return wx / wn, wy / wn, wz / wn


def _contact_force(n, rl, mu):
    """(e_P, F): the rim direction and the contact force in units of M g, F = z - mu h, with h
    the sliding direction of the rim point, omega3 R n3 x e_P (omega3 > 0)."""
    nx, ny, nz = n
    ex, ey, ez = _face_down(nx, ny, nz)
    hx, hy, hz = ny * ez - nz * ey, nz * ex - nx * ez, nx * ey - ny * ex
    hn = np.sqrt(hx * hx + hy * hy + hz * hz)
    return (ex, ey, ez), (-mu * hx / hn, -mu * hy / hn, 1.0 - mu * hz / hn)


def _torque(L, rl, mu):
    """Torque about C in units of M g l, for L in any units (only its direction matters).

    Built as -n3 x F + (R/l) e_P x F, the lever split so that the small rim offset is
    not rounded away against the axis when R << l.
    """
    Lx, Ly, Lz = L[0], L[1], L[2]
    Ln = np.sqrt(Lx * Lx + Ly * Ly + Lz * Lz)
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
    vn = np.sqrt(vx * vx + vy * vy + vz * vz)
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


def _rise_rhs(rl, mu, span):
    """d/du of (L_x', L_z', k t, phi) (``motion``'s variables) for numbers or arrays of variants: the flow in
    the Sundman variable s, divided by the tilt's rate in s, dtheta/ds = (e_theta . torque)/k, times
    dtheta/du = span (theta1 - theta0)."""
    k = mu * (1.0 + rl)

    def rhs(u, y):
        Lx, Lz = y[0], y[1]
        Ln = np.hypot(Lx, Lz)
        tx, ty, tz = _torque((Lx, 0.0 * Lx, Lz), rl, mu)
        f = Ln / k
        c = span * k * Ln / (Lz * tx - Lx * tz)  # ds/du: e_theta . torque = (L_z t_x - L_x t_z)/|L|
        return np.array([c * f * tx, c * f * tz, c * Ln, c * f * ty / Lx])

    return rhs


@exercise.motion
def motion(p):
    """The rise from theta0 to theta1: L in the frame turning about z with the axis's azimuth, (L_x', L_z') in
    units of I3 omega0, k t (t in the precession time I3 omega0/(M g l), k = mu (1 + R/l)) and the azimuth
    phi alongside for the record, in the variable u of theta = theta0 + u (theta1 - theta0), u from 0 to 1.

    The forces see the axis only through its angle with the vertical, so in the frame turning with its
    azimuth, dL'/dt = tau(L') - w z x L' with w = tau_y'/L_x' keeping L' in the x'z plane: the precession
    (hundreds of turns at small mu) needs no resolving.  Not t but the Sundman variable s of dt = |L| ds/k:
    in t the spin falls linearly to a stop while the tilt rate grows as 1/|L|, a log singularity just past
    the end where DOP853's error control on (L_x', L_z') misses the tilt's error (omega_rise moved by 4e-4
    between rtol and rtol/10 at a fall by e^12).  In s, |L| decays exponentially at the rate (R/l)/(1 + R/l)
    and the axis turns at the rate 1/(1 + R/l): a smooth flow, whose tilt, monotone, is the variable here (u),
    its rate in s read off the torque at every step, so the end theta = theta1 is the end of the span
    [0, 1], the same for every variant (the state's own polar angle there is monitored)."""
    from mech.problems.motion import Motion

    rl, mu = p.R / p.l, p.mu
    k = mu * (1.0 + rl)
    L0 = p.I3 * p.omega0
    return Motion(_rise_rhs(rl, mu, p.theta1 - p.theta0), [math.sin(p.theta0), math.cos(p.theta0), 0.0, 0.0],
                  (0.0, 1.0), t_scale=L0 / (p.M * p.g * p.l), y_scale=L0, to_states=lambda y: y[:2],
                  clock=lambda y: y[2] / k)


@exercise.batched(("omega_dot", "theta_dot0", "t_rise", "omega_rise"))
def numeric(P, rtol, outputs, tally=None):
    """The rise of N variants at once (a one-point solve is the batch of one): the initial rates from the
    torque at theta0, the rise integrated over u (``motion``) by mech's DOP853 stepping the ensemble
    (``floquet.integrate_ensemble``; a batch that fails is integrated again variant by variant, so a variant
    fails alone).  Monitored: |L| + mu M g R t, which the friction's axial torque keeps constant in this model,
    and the polar angle of L at the end against theta1."""
    from mech.solvers.numerics.ensemble import each_alone_on_failure
    from mech.problems.spec import Tally
    from mech.solvers.mechanics.floquet import integrate_ensemble
    from mech.solvers.numerics.batch import Column

    tally = Tally() if tally is None else tally
    M, I3, l, R, mu, w0, th0, th1, g = (np.atleast_1d(np.asarray(P[k], dtype=float))
                                        for k in ("M", "I3", "l", "R", "mu", "omega0", "theta0", "theta1", "g"))
    N = M.size
    L0, Mgl, rl = I3 * w0, M * g * l, R / l
    k = mu * (1.0 + rl)
    n0 = (np.sin(th0), np.zeros(N), np.cos(th0))
    omega_dot = -_axial_torque(n0, rl, mu) * Mgl / I3
    rate = -_tilt_torque(n0, rl, mu)  # dtheta/dt in units, |L| = 1 at t = 0
    why = np.where(rate > 0.0, "", "the initial torque does not raise the axis").astype(object)
    # L_x', L_z' stay positive (0 < theta < pi/2) and |L| may fall by up to e^25 (constraint): relative error
    # control, with an absolute floor far below that.  k t grows from 0 at the rate |L| = exp(-a s), a <= 1, to
    # at least (1 - 1/e) min(s_ev, 1) at the end, s_ev ~ (theta0 - theta1) k/rate: an absolute floor of
    # rtol 1e-3 min(s_ev, 1) keeps it relative there (a relative control from 0 made DOP853 start with steps
    # of 1e-16 and spend 250 evaluations on them).  phi is only recorded.
    with np.errstate(divide="ignore", invalid="ignore"):
        s_ev = np.minimum((th0 - th1) * k / rate, 1.0)
    atol = 1e-3 * rtol * np.array([np.full(N, math.exp(-30.0)), np.full(N, math.exp(-30.0)), s_ev, np.full(N, np.inf)])
    y0 = np.array([np.sin(th0), np.cos(th0), np.zeros(N), np.zeros(N)])
    y_end = np.full((4, N), np.nan)

    def rise(idx):
        def make_rhs(sel):
            j = idx[sel]
            return _rise_rhs(rl[j], mu[j], th1[j] - th0[j])

        y_end[:, idx], results = integrate_ensemble(make_rhs, (0.0, 1.0), y0[:, idx], rtol=rtol,
                                                    atol=atol[:, idx], integrator=tally.integrator)
        for r in results:
            tally.record(r)

    go = np.flatnonzero(why == "")
    if go.size:
        each_alone_on_failure(rise, go, why)
    Ln = np.hypot(y_end[0], y_end[1])
    tally.invariant("|L| + mu M g R t", np.nan_to_num(Ln + mu * rl * y_end[2] / k - 1.0))  # 0: failed
    tally.invariant("polar angle of L at the end - theta1, over theta0 - theta1",
                    np.nan_to_num((np.arctan2(y_end[0], y_end[1]) - th1) / (th0 - th1)))
    tally.info["precession_turns"] = y_end[3] / (2 * math.pi)
    tf = exercise.tol_factor * rtol
    values = {"omega_dot": omega_dot, "theta_dot0": rate * Mgl / L0, "t_rise": y_end[2] / k * L0 / Mgl,
              "omega_rise": Ln * w0}
    # omega_dot, theta_dot0: projections of one torque, round-off exact
    rels = {"omega_dot": 1e-12, "theta_dot0": 1e-12, "t_rise": tf, "omega_rise": tf}
    failed = [(why == text, text) for text in sorted(set(why[why != ""]))]
    return {q: Column(np.where(why == "", values[q], np.nan), rel=rels[q], failed=failed) for q in outputs}

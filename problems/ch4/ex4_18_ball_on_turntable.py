"""4.18 Ball rolling without slipping on a turntable: the orbit of its center.

Analytic: the contact point of the ball moves with the table,
v - R w x z = Omega z x r.  Newton for the center, M dv/dt = f, and for the
rotation, I dw/dt = (-R z) x f, turn the time derivative of that condition into
(1 + M R^2/I) dv/dt = Omega z x v: with I = (2/5) M R^2,
dv/dt = (2/7) Omega z x v.  The speed is constant and the velocity turns
counterclockwise at omega = 2 Omega/7 (independent of where the ball is), so
the center runs on a circle of radius |v0|/omega about
(x0 - vy0/omega, y0 + vx0/omega).  Released at rest on the table
(v0 = Omega z x r0) that center is -5/2 r0 and the radius 7/2 |r0|.

Numeric: the three-dimensional Newton-Euler equations of the ball, state
(displacement of the center, its velocity, change of the angular velocity),
with I taken from a quadrature of the ball's mass, and the horizontal
friction force solved at every step from the time derivative of the no-slip
condition (a 2x2 linear system built from the cross products, not simplified
by hand); the normal force balances gravity.  Everything is in units of
1/Omega and |v0|/Omega, so tiny, huge and slow orbits are the same
integration.  The circle is a least-squares fit to the sampled path (in those
units), omega the slope of the unwrapped direction of the velocity.  The no-slip
residual, the speed and the vertical spin are monitored.  If the ball starts
at rest in the lab the friction vanishes (checked), it stays where it is, and
omega comes from a run with a probe velocity.
"""

from __future__ import annotations

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.inertia import ball, inertia_tensor

exercise = Exercise(
    "4.18",
    formulas=[
        "(1 + MR²/I) dv/dt = Ω ẑ × v, I = (2/5) MR²  ⇒  dv/dt = (2/7) Ω ẑ × v",
        "ω_orbit = 2Ω/7 (counterclockwise, like the table)",
        "r_orbit = |v₀|/ω_orbit = 7|v₀|/(2Ω)",
        "x_c = x₀ - vy₀/ω_orbit,  y_c = y₀ + vx₀/ω_orbit",
    ],
    # the ball over 60 / Omega (when it moves in the lab), lab axes: the centre's position and velocity,
    # and the change of the ball's angular velocity since the start
    states=[("x", "m"), ("y", "m"), ("vx", "m/s"), ("vy", "m/s"), ("domega_x", "rad/s"),
            ("domega_y", "rad/s"), ("domega_z", "rad/s")],
)

# Scaled time over which the orbit is followed (Omega t); the velocity must turn
# at least MIN_TURNS full turns in it, otherwise the measurement is refused.
T_SCALED = 60.0
MIN_TURNS = 2.0
N_SAMPLES = 1200


@exercise.analytic
def analytic(p):
    w = 2.0 * p.Omega / 7.0
    return {
        "omega_orbit": w,
        "r_orbit": float(np.hypot(p.vx0, p.vy0)) / w,
        "xc": p.x0 - p.vy0 / w,
        "yc": p.y0 + p.vx0 / w,
    }


def _ball_moment(M, R):
    """Moment of inertia of a uniform ball about a diameter, from a quadrature of its mass."""
    pts, w = ball()
    return float(np.mean(np.diag(inertia_tensor(pts * R, w * M))))


def _make_rhs(M, R, I, Om):
    """Newton-Euler with the no-slip condition; state [d(2), v(2), dw(3)], vertical motion suppressed."""
    z = np.array([0.0, 0.0, 1.0])
    contact = -R * z

    def ang_acc(f):  # dw/dt from the friction force at the contact point
        return np.cross(contact, f) / I

    # d/dt of the no-slip condition: dv/dt - R (dw/dt) x z = Om z x v, dv/dt = f/M
    A = np.zeros((2, 2))
    for j in range(2):
        f = np.zeros(3)
        f[j] = 1.0
        A[:, j] = (f / M - R * np.cross(ang_acc(f), z))[:2]
    A_inv = np.linalg.inv(A)
    # the friction is linear in v: f = F_of_v @ v, with Om z x v as a matrix
    turn = np.stack([Om * np.cross(z, e)[:2] for e in np.eye(3)[:2]], axis=1)
    F_of_v = np.zeros((3, 2))
    F_of_v[:2] = A_inv @ turn
    dw_of_f = np.stack([ang_acc(e) for e in np.eye(3)], axis=1)
    # so the whole system is linear: s' = S s, assembled once
    S = np.zeros((7, 7))
    S[0:2, 2:4] = np.eye(2)
    S[2:4, 2:4] = F_of_v[:2] / M
    S[4:7, 2:4] = dw_of_f @ F_of_v

    def friction(v):
        return F_of_v @ np.asarray(v, dtype=float)

    def rhs(t, s):
        return S @ s

    return rhs, friction


def _drifts(v0, R_scaled):
    """The no-slip residual (v - R w x z - Omega z x r = 0, its start subtracted exactly), the speed and the
    vertical spin: the worst over the samples (scaled units)."""
    def slip(Y):
        d, v, dw = Y[0:2], Y[2:4], Y[4:7]
        slip_x = (v[0] - v0[0]) - R_scaled * dw[1] + d[1]
        slip_y = (v[1] - v0[1]) + R_scaled * dw[0] - d[0]
        return np.max(np.hypot(slip_x, slip_y))

    return {"no-slip residual": slip,
            "speed": lambda Y: np.max(np.abs(np.hypot(Y[2], Y[3]) - 1.0)),
            "vertical spin": lambda Y: np.max(np.abs(Y[6]))}


@exercise.motion
def motion(p):
    """The ball over T_SCALED / Omega from its start, sampled N_SAMPLES times, in units of 1/Omega and
    |v0|/Omega: the state is the displacement from (x0, y0) and the velocity at unit speed, so tiny, huge
    and slow orbits are the same integration.  A ball at rest in the lab stays where it is (no friction)."""
    from mech.problems.motion import Motion

    M, R_scaled = 1.0, 1.0  # mass and radius drop out of the friction balance; kept as symbols in rhs
    rhs, _ = _make_rhs(M, R_scaled, _ball_moment(M, R_scaled), 1.0)
    speed = float(np.hypot(p.vx0, p.vy0))
    samples = {"t_eval": np.linspace(0.0, T_SCALED, N_SAMPLES)}
    if speed == 0.0:  # at rest in the lab: no friction, it stays at (x0, y0) (state in SI)
        return Motion(rhs, np.array([p.x0, p.y0] + [0.0] * 5), (0.0, T_SCALED), t_scale=1.0 / p.Omega,
                      options=samples, y_size=1.0)
    v0 = np.array([p.vx0, p.vy0]) / speed
    length = speed / p.Omega
    # integrated as the displacement from (x0, y0), in speed / Omega
    return Motion(rhs, np.concatenate([[0.0, 0.0], v0, [0.0, 0.0, 0.0]]), (0.0, T_SCALED),
                  monitors=_drifts(v0, R_scaled), t_scale=1.0 / p.Omega,
                  y_scale=[length] * 2 + [speed] * 2 + [speed / p.R] * 3,
                  to_states=lambda y: [p.x0 / length + y[0], p.y0 / length + y[1], *y[2:]],
                  options=samples, y_size=1.0)


def _turn_rate(traj):
    ang = np.unwrap(np.arctan2(traj.y[3], traj.y[2]))
    slope, _ = np.polyfit(traj.t, ang - ang[0], 1)
    turns = abs(ang[-1] - ang[0]) / (2 * np.pi)
    if turns < MIN_TURNS:
        raise NumericFailure(f"the velocity turned only {turns:.3g} times in the run: no orbit to measure")
    return slope


def _fit_circle(x, y):
    """Least-squares circle: algebraic start, then Gauss-Newton on the geometric distances."""
    A = np.stack([x, y, np.ones_like(x)], axis=1)
    b = x * x + y * y
    D, E, F = np.linalg.lstsq(A, b, rcond=None)[0]
    xc, yc = D / 2, E / 2
    r = np.sqrt(F + xc * xc + yc * yc)
    for _ in range(10):
        dx, dy = x - xc, y - yc
        rho = np.hypot(dx, dy)
        res = rho - r
        Jm = np.stack([-dx / rho, -dy / rho, -np.ones_like(x)], axis=1)
        step = np.linalg.lstsq(Jm, -res, rcond=None)[0]
        xc, yc, r = xc + step[0], yc + step[1], r + step[2]
        if np.max(np.abs(step)) < 1e-15 * max(r, 1.0):
            break
    spread = float(np.max(np.abs(np.hypot(x - xc, y - yc) - r)))
    return xc, yc, r, spread


@exercise.numeric
def numeric(p, run):
    M, R_scaled = 1.0, 1.0
    I = _ball_moment(M, R_scaled)
    _, friction = _make_rhs(M, R_scaled, I, 1.0)
    speed = float(np.hypot(p.vx0, p.vy0))
    run.info["I_over_MR2"] = I / (M * R_scaled**2)
    m = motion(p)

    if speed == 0.0:
        # at rest in the lab: no friction, so nothing moves; the rate comes from a probe
        f_rest = friction(np.zeros(2))
        if np.any(f_rest != 0.0):
            raise NumericFailure("a ball at rest in the lab feels a friction force: inconsistent model")
        probe = m.starting(y0=np.array([0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0]))
        traj = run.follow(probe, mark=False).traj  # a tool: the ball itself does not move
        run.info["probe_velocity"] = "unit speed along x (scaled)"
        return {"omega_orbit": _turn_rate(traj) * p.Omega, "r_orbit": 0.0, "xc": p.x0, "yc": p.y0}

    traj = run.follow(m).traj
    length = speed / p.Omega
    d = traj.y[0:2]
    omega_scaled = _turn_rate(traj)
    xc, yc, r, spread = _fit_circle(d[0], d[1])
    run.info["circle_fit_max_residual"] = spread
    if spread > 1e3 * run.rtol * max(r, 1.0):
        raise NumericFailure(f"the path is not a circle: points stray by {spread:.3g} of the unit length")
    tol = exercise.tol_factor * run.rtol
    for name in ("xc", "yc"):
        run.claim(name, rel=tol, abs=tol * length)
    return {
        "omega_orbit": omega_scaled * p.Omega,
        "r_orbit": r * length,
        "xc": p.x0 + xc * length,
        "yc": p.y0 + yc * length,
    }

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
omega comes from a run with a probe velocity.  The route runs over arrays of
variants (``numeric``: every ball in its own scaled units on one interval,
sampled at 60 checkpoints; a one-point solve is the batch of one).
"""

from __future__ import annotations

import numpy as np

from mech.problems.spec import Exercise
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
def analytic(P):
    """Over arrays of variants."""
    from mech.solvers.numerics.batch import Column

    Omega, x0, y0, vx0, vy0 = (np.asarray(P[k], dtype=float) for k in ("Omega", "x0", "y0", "vx0", "vy0"))
    w = 2.0 * Omega / 7.0
    return {"omega_orbit": Column(w), "r_orbit": Column(np.hypot(vx0, vy0) / w),
            "xc": Column(x0 - vy0 / w), "yc": Column(y0 + vx0 / w)}


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
    vertical spin: the worst over the samples (scaled units), of one run (7, K) or of N (7, K, N), ``v0``
    (2,) or (2, N)."""
    def slip(Y):
        d, v, dw = Y[0:2], Y[2:4], Y[4:7]
        slip_x = (v[0] - v0[0]) - R_scaled * dw[1] + d[1]
        slip_y = (v[1] - v0[1]) + R_scaled * dw[0] - d[0]
        return np.max(np.hypot(slip_x, slip_y), axis=0)

    return {"no-slip residual": slip,
            "speed": lambda Y: np.max(np.abs(np.hypot(Y[2], Y[3]) - 1.0), axis=0),
            "vertical spin": lambda Y: np.max(np.abs(Y[6]), axis=0)}


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


# the runs are sampled at CHECKPOINTS equal legs (the circle fit and the velocity's turn read the samples)
CHECKPOINTS = 60


def _samples(y0, rtol, tally):
    """N balls (scaled units, states (7, N)) followed together over T_SCALED, sampled at CHECKPOINTS + 1
    equal times: (t (K + 1,), states (K + 1, 7, N)); the integrations go to ``tally``."""
    from mech.solvers.mechanics.floquet import integrate_ensemble

    M, R_scaled = 1.0, 1.0  # mass and radius drop out of the friction balance; kept as symbols in rhs
    rhs, _ = _make_rhs(M, R_scaled, _ball_moment(M, R_scaled), 1.0)
    t = np.linspace(0.0, T_SCALED, CHECKPOINTS + 1)
    Y = np.empty((t.size,) + y0.shape)
    Y[0] = y0
    atol = np.full(y0.shape, 1e-3 * rtol)
    for j in range(CHECKPOINTS):  # the same linear law for every variant: only the starts differ
        Y[j + 1], results = integrate_ensemble(lambda sel: rhs, (t[j], t[j + 1]), Y[j], rtol=rtol, atol=atol,
                                               integrator=tally.integrator)
        for r in results:
            tally.record(r)
    return t, Y


def _turn_rate(t, vx, vy):
    """The least-squares slope of the velocity's unwrapped direction (samples (K + 1, N)), and the turns."""
    ang = np.unwrap(np.arctan2(vy, vx), axis=0)
    tc = t - t.mean()
    slope = tc @ (ang - ang.mean(axis=0)) / (tc @ tc)
    return slope, np.abs(ang[-1] - ang[0]) / (2 * np.pi)


def _fit_circle(x, y):
    """Least-squares circles through N sampled paths (x, y: (K + 1, N)): algebraic start, then Gauss-Newton
    on the geometric distances.  Returns (xc, yc, r, spread) as arrays of N."""
    one = np.ones_like(x)

    def lsq(cols, rhs):  # the normal equations, variant by variant
        A = np.stack(cols, axis=-1).transpose(1, 0, 2)  # (N, K + 1, 3)
        AtA = A.transpose(0, 2, 1) @ A
        Atb = A.transpose(0, 2, 1) @ rhs.T[:, :, None]
        return np.linalg.solve(AtA, Atb)[:, :, 0].T

    D, E, F = lsq([x, y, one], x * x + y * y)
    xc, yc = D / 2, E / 2
    r = np.sqrt(F + xc * xc + yc * yc)
    for _ in range(10):
        dx, dy = x - xc, y - yc
        rho = np.hypot(dx, dy)
        step = lsq([-dx / rho, -dy / rho, -one], -(rho - r))
        xc, yc, r = xc + step[0], yc + step[1], r + step[2]
        if np.all(np.max(np.abs(step), axis=0) < 1e-15 * np.maximum(r, 1.0)):
            break
    spread = np.max(np.abs(np.hypot(x - xc, y - yc) - r), axis=0)
    return xc, yc, r, spread


@exercise.batched(("omega_orbit", "r_orbit", "xc", "yc"))
def numeric(P, rtol, outputs, tally=None):
    """The route at N variants at once (a one-point solve is the batch of one): every ball integrated in its
    own scaled units (time 1/Omega, lengths |v0|/Omega) on the same interval; a ball at rest in the lab
    (no friction, checked) stays where it is and a probe at unit speed gives its rate."""
    from mech.problems.spec import Tally
    from mech.solvers.numerics.batch import Column

    tally = Tally() if tally is None else tally
    Omega, x0, y0, vx0, vy0 = (np.asarray(P[k], dtype=float) for k in ("Omega", "x0", "y0", "vx0", "vy0"))
    N = Omega.size
    M, R_scaled = 1.0, 1.0
    I = _ball_moment(M, R_scaled)
    _, friction = _make_rhs(M, R_scaled, I, 1.0)
    tally.info["I_over_MR2"] = np.full(N, I / (M * R_scaled**2))
    speed = np.hypot(vx0, vy0)
    rest = speed == 0.0
    with np.errstate(invalid="ignore", divide="ignore"):
        v0 = np.where(rest, [[1.0], [0.0]], np.stack([vx0, vy0]) / np.where(rest, 1.0, speed))
    failed = []
    if rest.any() and np.any(friction(np.zeros(2)) != 0.0):
        failed.append((rest, "a ball at rest in the lab feels a friction force: inconsistent model"))
    tally.info["probe_velocity"] = np.where(rest, "unit speed along x (scaled)", None)
    t, Y = _samples(np.concatenate([np.zeros((2, N)), v0, np.zeros((3, N))]), rtol, tally)
    for name, drift in _drifts(v0, R_scaled).items():
        tally.invariant(name, np.where(rest, 0.0, drift(Y.transpose(1, 0, 2))))
    omega_scaled, turns = _turn_rate(t, Y[:, 2], Y[:, 3])
    failed += [(turns < MIN_TURNS, f"the velocity turned fewer than {MIN_TURNS:g} times in the run: no orbit to "
                "measure")]
    xc, yc, r, spread = _fit_circle(Y[:, 0], Y[:, 1])
    tally.info["circle_fit_max_residual"] = np.where(rest, None, spread)
    failed += [(~rest & ~(spread <= 1e3 * rtol * np.maximum(r, 1.0)), "the path is not a circle: the points "
                "stray by more than 1e3 rtol of the unit length")]
    length = speed / Omega
    tol = exercise.tol_factor * rtol
    values = {"omega_orbit": omega_scaled * Omega, "r_orbit": np.where(rest, 0.0, r * length),
              "xc": np.where(rest, x0, x0 + xc * length), "yc": np.where(rest, y0, y0 + yc * length)}
    claims = {"omega_orbit": (tol, 0.0), "r_orbit": (tol, 0.0), "xc": (tol, tol * length), "yc": (tol, tol * length)}
    return {o: Column(values[o], rel=claims[o][0], abs=claims[o][1], failed=failed) for o in outputs}

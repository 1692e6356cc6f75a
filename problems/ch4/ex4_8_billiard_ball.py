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
The route runs over arrays of variants (``numeric``: the strikes together, then
the sliding balls together, each stopped at its own event; a one-point solve is
the batch of one).
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
def analytic(P):
    """Over arrays of variants."""
    from mech.solvers.numerics.batch import Column

    M, R, Pimp, h, b, mu, g = _arrays(P)
    V0 = Pimp / M
    V_f = 5.0 * V0 * h / 7.0
    t_roll = V0 * np.abs(7.0 - 5.0 * h) / (7.0 * mu * g)
    return {
        "V_f": Column(V_f),
        "t_roll": Column(t_roll),
        "x_roll": Column(0.5 * (V0 + V_f) * t_roll),
        "omega_z": Column(-2.5 * b * V0 / R),
    }


def _arrays(P):
    return tuple(np.asarray(P[k], dtype=float) for k in ("M", "R", "P", "h_over_R", "b_over_R", "mu", "g"))


def _cross(a, b):
    """a x b for 3-vectors, or stacks (3, N) of them (numpy's cross costs far more per call on tiny arrays)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def _hit_point(h_over_R, b_over_R):
    """The hit point on the rear surface, in units of R from the center (numbers, or arrays: (3, N))."""
    z = h_over_R - 1.0
    x = -np.sqrt(np.maximum(0.0, 1.0 - b_over_R**2 - z**2))
    return np.array([x, b_over_R, z], dtype=float)


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


def _pulse(P, rtol):
    """The strike's length tau: far shorter than both the time to turn the ball (R/V0) and the sliding time
    (V0/mu g); and kappa = tau V0 / R, how far (in R) the ball moves or turns per unit scaled rate over it."""
    M, R, Pimp, _, _, mu, g = _arrays(P)
    V0 = Pimp / M
    tau = 1e-3 * rtol * np.minimum(R / V0, V0 / (mu * g))
    return tau, tau * V0 / R


def _after_strike(P, tau, kappa, y1):
    """From the strike's end states: the slip u0 (in V0), the pulse's relative effect (|w0| tau + mu g tau / V0)
    and the slip below which the ball counts as rolling (round-off of u plus what the pulse leaves)."""
    M, _, Pimp, _, _, mu, g = _arrays(P)
    V0 = Pimp / M
    eps_pulse = np.sqrt(np.sum(y1[3:6] ** 2, axis=0)) * kappa + mu * g * tau / V0
    return _slip(y1[0:3], y1[3:6]), eps_pulse, 1e-13 + 10.0 * eps_pulse


def _L_contact(I_inv_MR2, y):
    """The angular momentum about the contact point, in M R V0, of sliding states (u, w, x)."""
    velocity = y[0:3] - _cross(y[3:6], DOWN)
    return np.linalg.solve(I_inv_MR2, y[3:6]) + _cross(-DOWN, velocity)


def _strike_rhs(I_inv_MR2, kappa):
    """The strike, a force P (pi / 2 tau) sin(pi t / tau) along x at the body-fixed hit point over sigma = t/tau
    in [0, 1]: state (V in V0, w in V0/R, hit point and center in R), (12,) or (12, N)."""
    def strike(sig, y):
        V, om, rh = y[0:3], y[3:6], y[6:9]
        f = 0.5 * np.pi * np.sin(np.pi * sig)  # tau F / (M V0) along x
        dV = np.zeros_like(V)
        dV[0] = f
        return np.concatenate([dV, f * (I_inv_MR2 @ _cross(rh, XHAT)), kappa * _cross(om, rh), kappa * V])

    return strike


def _slide_rhs(I_inv_MR2, u0_hat, rate=1.0):
    """Sliding: friction -mu M g u/|u| at the contact; state (u in V0, w in V0/R, x in V0 t_unit), time in
    t_unit = V0/(mu g) times ``rate`` (a number or one per variant); (9,) or (9, N).  The slip itself is
    integrated (du/dt = dV/dt + dw/dt x r_contact), so a slip of 1e-7 V0 is not a small difference of O(1)
    velocities in round-off.  -u/|u|, with |u| signed by u . u0_hat: the same law before the event, and its
    smooth continuation past it, so the step that brackets the event sees no jump in the force."""
    def rhs(s, y):
        u, om = y[0:3], y[3:6]
        signed = np.sqrt(np.sum(u * u, axis=0)) * np.sign(np.sum(u * u0_hat, axis=0))
        F = -u / np.where(signed == 0.0, 1.0, signed)  # in mu M g
        dom = I_inv_MR2 @ _cross(DOWN, F)
        return rate * np.concatenate([F + _cross(dom, DOWN), dom, u - _cross(om, DOWN)])

    return rhs


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
    R = p.R
    V0 = p.P / p.M  # velocity unit
    I_inv_MR2 = _unit_ball()
    tau, kappa = (float(x) for x in _pulse(p, rtol))
    t_unit = V0 / (p.mu * p.g)

    def sliding(path):
        u0, _, u_tol = _after_strike(p, tau, kappa, path.y_end)
        if np.linalg.norm(u0) <= u_tol:
            return None  # rolls from the start
        u0_hat = u0 / np.linalg.norm(u0)
        return Motion(_slide_rhs(I_inv_MR2, u0_hat), np.concatenate([u0, path.y_end[3:6], np.zeros(3)]),
                      (0.0, 1e3 * max(1.0, float(np.linalg.norm(u0)))),
                      event=Event(lambda s, y: y[0:3] @ u0_hat, direction=-1, name="slip = 0"),
                      t_scale=t_unit, t_offset=0.5 * tau, y_scale=[V0] * 3 + [V0 / R] * 3 + [V0 * t_unit] * 3,
                      y_size=[float(np.linalg.norm(u0))] * 3 + [1.0] * 6)

    def as_states(y):  # (V, w, hit point, center) -> (slip, w, center)
        return [y[0] - y[4], y[1] + y[3], y[2], y[3], y[4], y[5], y[9], y[10], y[11]]

    y0 = np.concatenate([np.zeros(6), _hit_point(p.h_over_R, p.b_over_R), np.zeros(3)])
    return Motion(_strike_rhs(I_inv_MR2, kappa), y0, (0.0, 1.0), t_scale=tau, t_offset=-0.5 * tau,
                  y_scale=[V0] * 3 + [V0 / R] * 3 + [R] * 3, to_states=as_states,
                  options={"first_step": 1e-3}, y_size=1.0, then=sliding, shown=False)


# the sliding runs' span, in units of t_unit |u0| (the slip stops at about 2/7 of it)
SLIDE_SPAN = 1e3


def _slide(I_inv_MR2, u0, om1, rtol, integrator, tally):
    """The sliding of N balls together (``batch.integrate_batch`` with each ball's terminal event
    u . u0_hat = 0; a forced ``integrator``: ball by ball, ``ode.integrate``), each in time t_unit |u0| from
    its strike's end states.  Returns (the event's time in t_unit (NaN: none), the states there (9, N), the
    start states, the reasons of balls that failed (None: none))."""
    from mech.solvers.numerics.batch import BatchEvent, integrate_batch
    from mech.solvers.numerics.ode import first_event, integrate

    N = u0.shape[1]
    size = np.sqrt(np.sum(u0 * u0, axis=0))
    u0_hat = u0 / size
    ys = np.concatenate([u0, om1, np.zeros((3, N))])
    atol = 1e-3 * rtol * np.concatenate([np.broadcast_to(size, (3, N)), np.ones((6, N))])
    why = np.full(N, None, dtype=object)
    if integrator is None:
        ev = BatchEvent(lambda s, y: np.sum(y[0:3] * u0_hat, axis=0), direction=-1, terminal=True, name="slip = 0")
        res = tally.record(integrate_batch(_slide_rhs(I_inv_MR2, u0_hat, size), (0.0, SLIDE_SPAN), ys, rtol=rtol,
                                           atol=atol, events=[ev], on_failure="mark"))
        s_ev, y_ev = res.t_events[0] * size, res.y_end
        why[res.failed] = np.array(res.why, dtype=object)[res.failed]
    else:
        s_ev, y_ev = np.full(N, np.nan), np.full((9, N), np.nan)
        for j in range(N):
            uh = u0_hat[:, j]
            ev = Event(lambda s, y, uh=uh: y[0:3] @ uh, direction=-1, name="slip = 0")
            try:
                traj = tally.record(integrate(_slide_rhs(I_inv_MR2, uh, size[j]), (0.0, SLIDE_SPAN), ys[:, j],
                                              rtol=rtol, atol=atol[:, j], events=[ev], integrator=integrator))
                t_j, y_ev[:, j] = first_event(traj)
                s_ev[j] = t_j * size[j]
            except NumericFailure as exc:
                why[j] = str(exc)
    why[(why == None) & ~np.isfinite(s_ev)] = "the slip did not vanish within the run"  # noqa: E711
    return s_ev, y_ev, ys, why


@exercise.batched(("V_f", "t_roll", "x_roll", "omega_z"))
def numeric(P, rtol, outputs, tally=None):
    """The route at N variants at once (a one-point solve is the batch of one): the strikes integrated
    together, then the sliding of the balls that slip (``_slide``), each stopped at its own event."""
    from mech.problems.spec import Tally
    from mech.solvers.mechanics.floquet import integrate_ensemble
    from mech.solvers.numerics.batch import Column

    tally = Tally() if tally is None else tally
    M, R, Pimp, h, b, mu, g = _arrays(P)
    N = M.size
    V0 = Pimp / M  # velocity unit (not an answer: the pulse's integral is checked below)
    t_unit = V0 / (mu * g)
    I_inv_MR2 = _unit_ball()
    tau, kappa = _pulse(P, rtol)
    y0 = np.concatenate([np.zeros((6, N)), _hit_point(h, b), np.zeros((3, N))])
    y1, runs = integrate_ensemble(lambda sel: _strike_rhs(I_inv_MR2, kappa[sel]), (0.0, 1.0), y0, rtol=rtol,
                                  atol=np.full((12, N), 1e-3 * rtol), integrator=tally.integrator)
    for r in runs:
        tally.record(r)
    V1, om1, xc1 = y1[0:3], y1[3:6], y1[9:12]  # scaled
    tally.info["pulse_tau_s"] = tau
    tally.info["pulse_momentum_error"] = V1[0] - 1.0  # M V / P - 1, from the integration
    u0, eps_pulse, u_tol = _after_strike(P, tau, kappa, y1)
    tally.info["pulse_effect_rel"] = eps_pulse
    rolls = np.sqrt(np.sum(u0 * u0, axis=0)) <= u_tol
    tally.info["slip_after_strike"] = np.where(rolls, "below round-off: rolls from the start", None)
    # rolling from the start
    values = {"V_f": V0 * V1[0], "t_roll": np.zeros(N), "x_roll": R * xc1[0], "omega_z": om1[2] * V0 / R}
    why = np.full(N, None, dtype=object)
    L_drift = np.zeros(N)
    go = np.flatnonzero(~rolls)
    if go.size:
        s_ev, y_ev, ys, why[go] = _slide(I_inv_MR2, u0[:, go], om1[:, go], rtol, tally.integrator, tally)
        L_scale = np.sqrt(np.sum(np.linalg.solve(I_inv_MR2, om1[:, go]) ** 2, axis=0)) + np.sqrt(
            np.sum(V1[:, go] ** 2, axis=0))
        dL = _L_contact(I_inv_MR2, y_ev) - _L_contact(I_inv_MR2, ys)
        L_drift[go] = np.sqrt(np.sum(dL * dL, axis=0)) / L_scale
        u_end = np.sqrt(np.sum(y_ev[0:3] ** 2, axis=0))
        left = (why[go] == None) & (u_end > 1e-9 * np.sqrt(np.sum(u0[:, go] ** 2, axis=0)))  # noqa: E711
        why[go[left]] = "slip left across its first direction at the event"
        V_end = y_ev[0:3] - _cross(y_ev[3:6], DOWN)
        values["V_f"][go] = V0[go] * V_end[0]
        values["t_roll"][go] = 0.5 * tau[go] + t_unit[go] * s_ev
        values["x_roll"][go] = R[go] * xc1[0, go] + V0[go] * t_unit[go] * y_ev[6]
        values["omega_z"][go] = y_ev[5] * V0[go] / R[go]
    tally.invariant("L_contact", np.nan_to_num(L_drift))
    failed = [(why == text, text) for text in sorted(set(why[why != None]))]  # noqa: E711
    # absolute accuracy where outputs sit at the noise floor (zero slip, zero offset, h -> 0)
    claims = {"V_f": (100 * rtol, V0 * u_tol), "t_roll": (100 * rtol, t_unit * u_tol),
              "x_roll": (100 * rtol, V0 * t_unit * u_tol), "omega_z": (100 * rtol + 10 * eps_pulse, V0 / R * u_tol)}
    return {o: Column(values[o], rel=claims[o][0], abs=claims[o][1], failed=failed) for o in outputs}

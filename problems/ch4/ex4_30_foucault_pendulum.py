"""4.30 Foucault pendulum: how fast the plane of oscillation turns.

Analytic.  With zeta = x + i y and w_z = w_E cos(theta) the linear Earth-frame
equations are zeta'' + 2i w_z zeta' + w0^2 zeta = 0 (w0^2 = g/l), solved by
zeta = exp(-i w_z t) [A exp(i w' t) + B exp(-i w' t)], w'^2 = w0^2 + w_z^2:
in a frame turning at -w_z about the vertical the bob runs on a fixed ellipse.
So Omega_F = -w_E cos(theta) exactly (clockwise in the north), T_F = 2 pi/|Omega_F|
(infinite on the equator).  Released at rest at (a, 0): A + B = a and
w'(A - B) = w_z a, so the ellipse's semi-axes are |A| + |B| = a and
||A| - |B|| = a |w_z|/w', which is the closest approach b_miss.

Numeric.  DOP853 on the linear Earth-frame equations in units of a,
over at least 20 half-swings (time unit 1/(w0 + |w_z|), so a fast rotation
costs no more steps than a slow one).  The events
rho rho' = x x' + y y' = 0 give the far (maximum rho) and near (minimum rho)
turning points.  Far points: the bob's azimuth, taken modulo pi, is the plane's
orientation; near points (used only where the path is open enough for their
direction to be well defined) give it as azimuth - pi/2, and with them a sample
every quarter swing, which unwraps the orientation unambiguously.  Omega_F is the
least-squares slope of the far-point orientations against time (the Runge-Kutta
map commutes with rotations about the vertical, so its errors are relative to the
precession itself and a few swings suffice); b_miss is the mean near distance.
Monitored: the energy v^2/2 + w0^2 rho^2/2 and the inertial-frame angular momentum
x y' - y x' + w_z rho^2.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure, Undefined
from mech.solvers.numerics.ode import Event

EQUATOR = "on the equator the plane does not turn (Omega_F = 0)"

exercise = Exercise(
    "4.30",
    formulas=[
        "Ω_F = -ω_E cos θ  (clockwise in the northern hemisphere)",
        "T_F = 2π/(ω_E |cos θ|)  (infinite on the equator)",
        "b_miss = a ω_E |cos θ| / (g/l + ω_E² cos²θ)^(1/2)",
        "(exact in the linear model: ζ = e^(-iω_z t)[A e^(iω't) + B e^(-iω't)], ω'² = g/l + ω_z²)",
    ],
    # about 20 half-swings of the bob, horizontal ground-frame coordinates (small-swing model): x along
    # the release direction, y a quarter turn counterclockwise seen from above
    states=[("x", "m"), ("y", "m"), ("vx", "m/s"), ("vy", "m/s")],
)

HALF_SWINGS = 20
OPEN_PATH = 1e-3  # near points define a direction only where b_miss/a exceeds this


def _omega_z(p):
    # sin(pi/2 - theta) is exactly 0 at the float pi/2 (cos would give 6e-17)
    return p.omega_E * math.sin(math.pi / 2 - p.theta)


@exercise.analytic
def analytic(p):
    wz = _omega_z(p)
    w0sq = p.g / p.l
    return {
        "Omega_F": -wz,
        "T_F": Undefined(EQUATOR, infinite=True) if wz == 0.0 else 2.0 * math.pi / abs(wz),
        "b_miss": p.a * abs(wz) / math.sqrt(w0sq + wz * wz),
    }


def _wrap(x):
    """x modulo pi, into [-pi/2, pi/2)."""
    return x - math.pi * math.floor(x / math.pi + 0.5)


def _line_angle(x, y):
    """Orientation of the line through (x, y), in (-pi/2, pi/2]: the vector is flipped into x >= 0
    first, so a direction near the negative x axis keeps its full relative precision (atan2 near
    pi would round it to the 4e-16 grid of pi)."""
    return math.atan2(y, x) if x >= 0.0 else math.atan2(-y, -x)


@exercise.motion
def motion(p):
    """The small swing in the Earth's frame, x'' = -w0^2 x + 2 w_z y', y'' = -w0^2 y - 2 w_z x', released from
    rest at (a, 0), over HALF_SWINGS half-swings, with its turning points (rho rho' = 0) recorded; time in
    1/(w0 + |w_z|) (the faster rate sets the steps), lengths in a."""
    from mech.problems.motion import Motion

    w0 = math.sqrt(p.g) / math.sqrt(p.l)  # roots apart: g/l leaves the range where w0 does not
    wz = _omega_z(p)
    rate = w0 + abs(wz)
    c2 = (w0 / rate) ** 2  # scaled restoring coefficient
    k = wz / rate  # scaled vertical rotation rate

    def rhs(t, y):
        return np.array([y[2], y[3], -c2 * y[0] + 2.0 * k * y[3], -c2 * y[1] - 2.0 * k * y[2]])

    def rrdot(t, y):
        return y[0] * y[2] + y[1] * y[3]

    def energy(Y):
        rho2 = Y[0] ** 2 + Y[1] ** 2
        return float(np.max(np.abs(0.5 * (Y[2] ** 2 + Y[3] ** 2 + c2 * rho2) - 0.5 * c2))) / (0.5 * c2)

    def ang_mom(Y):
        """The inertial frame's angular momentum about the vertical, x y' - y x' + w_z rho^2 (scaled)."""
        rho2 = Y[0] ** 2 + Y[1] ** 2
        return float(np.max(np.abs(Y[0] * Y[3] - Y[1] * Y[2] + k * rho2 - k))) / (1.0 + abs(k))

    far_ev = Event(rrdot, terminal=False, direction=-1.0, name="far turning point")
    near_ev = Event(rrdot, terminal=False, direction=+1.0, name="near turning point")
    # the swing frequency w' is at least rate/sqrt(2) (it is at least w0 and |w_z|)
    tau_end = HALF_SWINGS * math.sqrt(2.0) * math.pi
    # Speeds in the Earth frame stay below w0^2/rate (scaled: c2); with a fast rotation (|w_z| >> w0)
    # that is 1e-7 of the positions' scale, and an absolute tolerance sized for the positions would
    # leave the velocities, and with them the turning points (rho rho' = 0), at 1e-6 relative.
    return Motion(rhs, [1.0, 0.0, 0.0, 0.0], (0.0, tau_end), monitors={"energy": energy, "L_inertial": ang_mom},
                  t_scale=1.0 / rate, y_scale=[p.a, p.a, p.a * rate, p.a * rate],
                  y_size=np.array([1.0, 1.0, c2, c2]), options={"events": [far_ev, near_ev]})


@exercise.numeric
def numeric(p, run):
    w0 = math.sqrt(p.g) / math.sqrt(p.l)  # roots apart: g/l leaves the range where w0 does not
    wz = _omega_z(p)
    if abs(wz) > 1e8 * w0:
        # the Earth-frame path is a slow drift with loops of relative size w0^2 / (4 w_z^2) < 2.5e-17:
        # below round-off, the turning points are noise (the scatter check below fails from ~1e7 on)
        raise NumericFailure(
            f"|w_z|/w0 = {abs(wz) / w0:.3g}: the loops of the path (relative size w0^2/(4 w_z^2)) are "
            "below round-off, too small to resolve"
        )
    m = motion(p)
    traj = run.follow(m).traj
    rate = w0 + abs(wz)  # the time unit of the motion: 1/rate

    t_far = np.concatenate([[0.0], traj.t_events[0]])
    y_far = np.vstack([[1.0, 0.0, 0.0, 0.0], traj.y_events[0]]) if len(traj.t_events[0]) else None
    t_near, y_near = traj.t_events[1], traj.y_events[1]
    if y_far is None or len(t_far) < 3 or len(t_near) < 2:
        raise NumericFailure(f"too few turning points in {HALF_SWINGS} half-swings: {len(t_far)} far, {len(t_near)} near")
    near_dist = np.hypot(y_near[:, 0], y_near[:, 1])
    b = float(np.mean(near_dist))
    use_near = b > OPEN_PATH

    samples = [(t, _line_angle(y[0], y[1]), True) for t, y in zip(t_far, y_far)]
    if use_near:  # the major axis is the near point's direction turned by -90 degrees
        samples += [(t, _line_angle(y[1], -y[0]), False) for t, y in zip(t_near, y_near)]
    samples.sort(key=lambda s: s[0])
    psi = [samples[0][1]]
    steps = []
    for _, raw, _ in samples[1:]:
        step = _wrap(raw - psi[-1])
        steps.append(step)
        psi.append(psi[-1] + step)
    if not use_near and max(abs(s) for s in steps) > math.pi / 4:
        raise NumericFailure("the plane turns too far per half-swing to unwrap from the far turning points alone")
    tf = np.array([s[0] for s in samples if s[2]])
    pf = np.array([ps for ps, s in zip(psi, samples) if s[2]])
    slope = float(np.polyfit(tf, pf, 1)[0]) if np.any(pf != pf[0]) else 0.0
    resid = pf - (pf[0] + slope * (tf - tf[0]))
    run.info["far_points"] = len(tf)
    run.info["near_points"] = len(t_near)
    run.info["orientation_fit_residual_rad"] = float(np.max(np.abs(resid - np.mean(resid))))
    run.info["b_miss_spread"] = float(np.ptp(near_dist)) * p.a

    tol = exercise.tol_factor * run.rtol
    run.claim("b_miss", rel=tol, abs=tol * 1e-3 * p.a)
    if slope != 0.0:
        # the scatter of the orientations about the fitted line bounds the slope's error; where the
        # rotation is so fast (|w_z|/w0 > 1e7) that the loops of the path are below round-off, the
        # turning points are noise and the scatter says so
        fit_rel = 4.0 * run.info["orientation_fit_residual_rad"] / (abs(slope) * (tf[-1] - tf[0]))
        if fit_rel > 1e-3:
            raise NumericFailure(
                f"the turning points scatter by {run.info['orientation_fit_residual_rad']:.2g} rad about a "
                f"steadily turning line (|w_z|/w0 = {abs(wz) / w0:.3g}: the loops of the path are too small to resolve)"
            )
        if fit_rel > tol:
            run.claim("Omega_F", rel=fit_rel)
            run.claim("T_F", rel=fit_rel)
    Omega_F = slope * rate
    return {
        "Omega_F": Omega_F,
        "T_F": Undefined(EQUATOR, infinite=True) if Omega_F == 0.0 else 2.0 * math.pi / abs(Omega_F),
        "b_miss": b * p.a,
    }

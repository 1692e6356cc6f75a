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
over 20 half-swings (time unit 1/(w0 + |w_z|), so a fast rotation
costs no more steps than a slow one), a half-swing a leg: from a far turning point
the events rho rho' = x x' + y y' = 0 upward (the near point, minimum rho) and
downward (the next far point, maximum rho, where the leg ends and the next starts).  The route is
written once over arrays of variants (mech's DOP853 stepping them together, each
variant's events its own; a one-point solve is the batch of one).  Far points: the bob's azimuth, taken modulo pi, is the plane's
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

from mech.problems.spec import Exercise
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


def _scaled(P):
    """(w0, w_z, rate = w0 + |w_z|, c2 = (w0/rate)^2, k = w_z/rate) over arrays: time in 1/rate, lengths in a."""
    theta, l, g, omega_E = (np.asarray(P[k], dtype=float) for k in ("theta", "l", "g", "omega_E"))
    w0 = np.sqrt(g) / np.sqrt(l)  # roots apart: g/l leaves the range where w0 does not
    # sin(pi/2 - theta) is exactly 0 at the float pi/2 (cos would give 6e-17)
    wz = omega_E * np.sin(math.pi / 2 - theta)
    rate = w0 + np.abs(wz)
    return w0, wz, rate, (w0 / rate) ** 2, wz / rate


@exercise.analytic
def analytic(P):
    """Over arrays of variants; T_F infinite on the equator."""
    from mech.solvers.numerics.batch import Column

    _, wz, _, _, _ = _scaled(P)
    g, l, a = (np.asarray(P[k], dtype=float) for k in ("g", "l", "a"))
    with np.errstate(divide="ignore"):
        T = 2.0 * math.pi / np.abs(wz)
    return {"Omega_F": Column(-wz), "T_F": Column(T, undefined=[(wz == 0.0, EQUATOR)]),
            "b_miss": Column(a * np.abs(wz) / np.sqrt(g / l + wz * wz))}


def _wrap(x):
    """x modulo pi, into [-pi/2, pi/2) (arrays)."""
    return x - math.pi * np.floor(x / math.pi + 0.5)


def _line_angle(x, y):
    """Orientation of the line through (x, y), in (-pi/2, pi/2] (arrays): the vector is flipped into x >= 0
    first, so a direction near the negative x axis keeps its full relative precision (atan2 near pi would
    round it to the 4e-16 grid of pi)."""
    return np.where(x >= 0.0, np.arctan2(y, x), np.arctan2(-y, -x))


def _rhs(c2, k):
    """The scaled Earth-frame equations (numbers, or arrays of variants)."""

    def rhs(t, y):
        return np.array([y[2], y[3], -c2 * y[0] + 2.0 * k * y[3], -c2 * y[1] - 2.0 * k * y[2]])

    return rhs


def _rrdot(t, y):
    """rho rho' = x x' + y y': zero at the turning points."""
    return y[0] * y[2] + y[1] * y[3]


def _drifts(Y, c2, k):
    """The energy v^2/2 + w0^2 rho^2/2 and the inertial frame's angular momentum about the vertical,
    x y' - y x' + w_z rho^2, their drifts from the release at rest at (1, 0), scaled (states 4 x ...)."""
    rho2 = Y[0] ** 2 + Y[1] ** 2
    energy = np.abs(0.5 * (Y[2] ** 2 + Y[3] ** 2 + c2 * rho2) - 0.5 * c2) / (0.5 * c2)
    return energy, np.abs(Y[0] * Y[3] - Y[1] * Y[2] + k * rho2 - k) / (1.0 + np.abs(k))


@exercise.motion
def motion(p):
    """The small swing in the Earth's frame, x'' = -w0^2 x + 2 w_z y', y'' = -w0^2 y - 2 w_z x', released from
    rest at (a, 0), over HALF_SWINGS half-swings, with its turning points (rho rho' = 0) recorded; time in
    1/(w0 + |w_z|) (the faster rate sets the steps), lengths in a."""
    from mech.problems.motion import Motion

    w0, wz, rate, c2, k = (float(x) for x in _scaled({n: np.float64(p[n]) for n in ("theta", "l", "g", "omega_E")}))
    far_ev = Event(_rrdot, terminal=False, direction=-1.0, name="far turning point")
    near_ev = Event(_rrdot, terminal=False, direction=+1.0, name="near turning point")
    # the swing frequency w' is at least rate/sqrt(2) (it is at least w0 and |w_z|)
    tau_end = HALF_SWINGS * math.sqrt(2.0) * math.pi
    # Speeds in the Earth frame stay below w0^2/rate (scaled: c2); with a fast rotation (|w_z| >> w0)
    # that is 1e-7 of the positions' scale, and an absolute tolerance sized for the positions would
    # leave the velocities, and with them the turning points (rho rho' = 0), at 1e-6 relative.
    return Motion(_rhs(c2, k), [1.0, 0.0, 0.0, 0.0], (0.0, tau_end),
                  monitors={"energy": lambda Y: float(np.max(_drifts(Y, c2, k)[0])),
                            "L_inertial": lambda Y: float(np.max(_drifts(Y, c2, k)[1]))},
                  t_scale=1.0 / rate, y_scale=[p.a, p.a, p.a * rate, p.a * rate],
                  y_size=np.array([1.0, 1.0, c2, c2]), options={"events": [far_ev, near_ev]})


# the longest a half-swing (far point to far point) can last, in 1/rate: half the swing's period pi/w',
# w' >= rate/sqrt(2); and the time from a leg's start before which its far point is not looked for
LEG, GATE = 6.0, 0.1


def _far_after_start(t, y):
    """rho rho', shifted down by GATE - t before GATE: a leg starts at a far point (rho rho' = 0 there, its
    round-off of either sign), which the event of the next far point (downward) must not take for it."""
    return _rrdot(t, y) - np.maximum(GATE - t, 0.0)


def _turning_points(c2, k, rtol, tally):
    """The HALF_SWINGS near and far turning points of N variants at once, a half-swing a leg: from a far
    point, the next near one (rho rho' = 0 upward) and the next far one (downward, where the leg stops),
    events on the ensemble's continuous extension; the equations are autonomous, so each leg starts at 0.
    Returns (times and states of the far points, the release at t = 0 first: (H + 1,), (H + 1, 4, N); of the
    near ones; the worst energy and angular momentum drifts at them; failures)."""
    from mech.solvers.numerics.batch import BatchEvent

    N = c2.size
    H = HALF_SWINGS
    t_far, y_far = np.full((H + 1, N), np.nan), np.full((H + 1, 4, N), np.nan)
    t_near, y_near = np.full((H, N), np.nan), np.full((H, 4, N), np.nan)
    t_far[0], y_far[0] = 0.0, np.array([1.0, 0.0, 0.0, 0.0])[:, None]
    why = np.full(N, "", dtype=object)
    atol = 1e-3 * rtol * np.stack([np.ones(N), np.ones(N), c2, c2])
    events = [BatchEvent(_rrdot, direction=1.0, name="near turning point"),
              BatchEvent(_far_after_start, direction=-1.0, terminal=True, name="far turning point")]
    for j in range(H):
        go = np.flatnonzero(why == "")
        if not go.size:
            break
        got = tally.follow(lambda sel: _rhs(c2[go][sel], k[go][sel]), (0.0, LEG), y_far[j][:, go], rtol=rtol,
                     atol=atol[:, go], events=events)
        why[go] = got.why
        lost = (got.why == "") & ~(np.isfinite(got.t_events[0]) & np.isfinite(got.t_events[1]))
        why[go[lost]] = f"too few turning points in {H} half-swings: none within {LEG:g}/(w0 + |w_z|)"
        t_near[j, go], y_near[j][:, go] = t_far[j, go] + got.t_events[0], got.y_events[0]
        t_far[j + 1, go], y_far[j + 1][:, go] = t_far[j, go] + got.t_events[1], got.y_events[1]
    drift_e, drift_l = _drifts(np.concatenate([y_far, y_near], axis=0).transpose(1, 0, 2), c2, k)
    return t_far, y_far, t_near, y_near, np.nanmax(drift_e, axis=0), np.nanmax(drift_l, axis=0), why


def _orientations(t_far, y_far, y_near, use_near):
    """The plane's orientation at the far points, unwrapped (H + 1, N), and the largest step between samples:
    far points give it as the bob's azimuth modulo pi; near points (where the path is open enough,
    ``use_near``) as the azimuth - pi/2, a sample every quarter swing, which unwraps it unambiguously."""
    far = _line_angle(y_far[:, 0], y_far[:, 1])
    near = _line_angle(y_near[:, 1], -y_near[:, 0])  # the major axis: the near point's direction turned by -90 deg
    both = np.empty((2 * far.shape[0] - 1,) + far.shape[1:])
    both[0::2], both[1::2] = far, near
    psi_both = both[0] + np.concatenate([np.zeros((1,) + far.shape[1:]), np.cumsum(_wrap(np.diff(both, axis=0)),
                                                                                       axis=0)])
    steps = _wrap(np.diff(far, axis=0))
    psi_far = far[0] + np.concatenate([np.zeros((1,) + far.shape[1:]), np.cumsum(steps, axis=0)])
    return np.where(use_near, psi_both[0::2], psi_far), np.max(np.abs(steps), axis=0)


@exercise.batched(("Omega_F", "T_F", "b_miss"))
def numeric(P, rtol, outputs, tally=None):
    """The swings of N variants at once (a one-point solve is the batch of one): their turning points
    (``_turning_points``), the plane's orientation there (``_orientations``), Omega_F the least-squares slope
    of the far points' orientations against time (the Runge-Kutta map commutes with rotations about the
    vertical, so its errors are relative to the precession itself), b_miss the mean near distance; each
    variant's claim from its fit's scatter."""
    from mech.problems.spec import Tally
    from mech.solvers.numerics.batch import Column

    tally = Tally() if tally is None else tally
    w0, wz, rate, c2, k = _scaled(P)
    a = np.asarray(P["a"], dtype=float)
    N = w0.size
    # the Earth-frame path is a slow drift with loops of relative size w0^2/(4 w_z^2) < 2.5e-17: below
    # round-off, the turning points are noise (the scatter check below fails from ~1e7 on)
    fast = ~(np.abs(wz) <= 1e8 * w0)
    c2s, ks = np.where(fast, 1.0, c2), np.where(fast, 0.0, k)
    t_far, y_far, t_near, y_near, drift_e, drift_l, why = _turning_points(c2s, ks, rtol, tally)
    why[fast] = ""
    tol = exercise.tol_factor * rtol
    with np.errstate(all="ignore"):
        near_dist = np.hypot(y_near[:, 0], y_near[:, 1])
        b = np.mean(near_dist, axis=0)
        use_near = b > OPEN_PATH
        psi, step_max = _orientations(t_far, y_far, y_near, use_near)
        tm, pm = np.mean(t_far, axis=0), np.mean(psi, axis=0)
        flat = np.all(psi == psi[0], axis=0)
        slope = np.where(flat, 0.0, np.sum((t_far - tm) * (psi - pm), axis=0) / np.sum((t_far - tm) ** 2, axis=0))
        resid = psi - (psi[0] + slope * (t_far - t_far[0]))
        scatter = np.max(np.abs(resid - np.mean(resid, axis=0)), axis=0)
        # the scatter of the orientations about the fitted line bounds the slope's error
        fit_rel = np.where(slope != 0.0, 4.0 * scatter / (np.abs(slope) * (t_far[-1] - t_far[0])), 0.0)
        Omega_F = slope * rate
        T_F = 2.0 * math.pi / np.abs(Omega_F)
    ran = (why == "") & ~fast
    tally.invariant("energy", np.where(ran, drift_e, 0.0))
    tally.invariant("L_inertial", np.where(ran, drift_l, 0.0))
    tally.info.update(far_points=np.full(N, HALF_SWINGS + 1.0), near_points=np.full(N, float(HALF_SWINGS)),
                      orientation_fit_residual_rad=scatter, b_miss_spread=np.ptp(near_dist, axis=0) * a)
    ratio = np.abs(wz) / w0
    failed = [(fast, "the loops of the path (relative size w0^2/(4 w_z^2)) are below round-off, too small to "
               "resolve (|w_z|/w0 above 1e8)")]
    failed += [(why == text, text) for text in sorted(set(why[why != ""]))]
    failed += [(ran & ~use_near & (step_max > math.pi / 4),
                "the plane turns too far per half-swing to unwrap from the far turning points alone"),
               (ran & (fit_rel > 1e-3), "the turning points scatter about a steadily turning line: the loops of "
                "the path are too small to resolve"),
               (ran & ~(np.maximum(drift_e, drift_l) <= tol), "an invariant (energy, L_inertial) drifts by more "
                "than the method allows: the integration is not to be trusted")]
    tally.info["wz_over_w0"] = ratio
    claim = np.maximum(fit_rel, tol)
    cols = {"Omega_F": Column(Omega_F, rel=claim, failed=failed),
            "T_F": Column(T_F, rel=claim, undefined=[(ran & (Omega_F == 0.0), EQUATOR)], failed=failed),
            "b_miss": Column(b * a, rel=tol, abs=tol * 1e-3 * a, failed=failed)}
    return {o: cols[o] for o in outputs}

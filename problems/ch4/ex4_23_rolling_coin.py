"""4.23 Coin rolling steadily around a circle: period, turning rate, spin.

Analytic.  Contact point on the circle of radius R, lean theta toward the
center, symmetry axis n3 = cos(theta) e_r + sin(theta) z.  The configuration
turns at Omega about z; rolling (zero velocity of the material point at the
contact) fixes the spin relative to the turning frame: omega_spin = Omega R / r
(the contact point's orbit, 2 pi R per turn, is unrolled from the rim).  With
omega = Omega z - omega_spin n3, I3 = M r^2/2, I1 = M r^2/4, the angular momentum
about the center turns rigidly: dL/dt = Omega z x L
= Omega^2 cos(theta) M r (r sin(theta)/4 - R/2) e_phi; the contact force is
(M g, centripetal M Omega^2 (R - r sin theta)) and its torque about the center is
M r (Omega^2 (R - r sin theta) cos theta - g sin theta) e_phi.  Equating:
    Omega^2 = 4 g tan(theta) / (6 R - 5 r sin(theta)),   T = 2 pi / Omega,
which needs R > 5 r sin(theta)/6 (at R = r sin(theta), the Euler disk,
Omega^2 = 4 g /(r cos theta)).

Numeric.  Newton-Euler of the rigid thin disk (inertia by quadrature) with the rolling constraint
differentiated once (the contact point moves along the rim: its geometric velocity enters), the attitude a
quaternion (solvers.mechanics.rolling_disk, on floats or on arrays of variants).  Omega is the root of the
tilt acceleration d^2(n3 . z)/dt^2 in the steady initial state (center velocity from the turning, spin from
the rolling condition, both solved numerically); the motion is followed from that state over 1.3 root periods
and T is the time of one full turn of the axis's horizontal projection, or, with more than 60 spin turns an
orbit (R >> r), 2 pi over the azimuth's rate fitted over 20 spin turns; T's claim is at least 3 times its
departure from the root's (measured error).  The spin at the end must match the rolling condition's; the
tilt, the energy (potential from the contact point), the slip and the contact height are monitored.  The
route is written once over arrays of variants (``numeric``: a class's variants at once, a one-point solve
the batch of one); the turn is timed from the axis's azimuth at the root period (its departure from 2 pi
over its rate there).  Units: r = g = M = 1.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.frames import quat_from_matrix, quat_to_matrix
from mech.solvers.mechanics.inertia import disk, inertia_tensor
from mech.solvers.mechanics.rolling_disk import drifts, monitors, rates, steady_rolling, tilt_acceleration
from mech.solvers.numerics.ode import Event

exercise = Exercise(
    "4.23",
    formulas=[
        "Ω² = 4 g tan θ / (6 R - 5 r sin θ)   (needs R > 5 r sin θ / 6)",
        "T = 2π / Ω",
        "ω_spin = Ω R / r  (rolling)",
    ],
    # Tuned from `mech bench 4.23` (DOP853): the error achieved is ~0.01 rtol (1e-7: 9e-10, 1e-8: 1.1e-10, 1e-10:
    # 1.5e-12), so rtol 1e-8 claiming 1 x rtol keeps a margin ~100 at half the cost (3482 against 5972 calls).
    default_rtol=1e-8,
    tol_factor=1.0,
    # the run from the steady rolling: body-axis rates (3 = the coin's normal), attitude quaternion
    # (scalar first, body -> lab), the centre's position (z up, circle centred on the origin) and velocity
    states=[("omega1", "rad/s"), ("omega2", "rad/s"), ("omega3", "rad/s"), ("q0", "1"), ("q1", "1"),
            ("q2", "1"), ("q3", "1"), ("x_c", "m"), ("y_c", "m"), ("z_c", "m"), ("vx_c", "m/s"),
            ("vy_c", "m/s"), ("vz_c", "m/s")],
)

# relative margin above R = 5 r sin(theta)/6, where Omega diverges and the period loses its digits
MARGIN = 1e-6
# the longest run, in spin turns, over which one full revolution is timed by an event
MAX_SPIN_TURNS = 60.0


exercise.declare_limits(
    f"R > (1 + {MARGIN:g}) 5 r sin(theta)/6: steady rolling with this lean",
)


@exercise.constraint
def constraint(p):
    Rmin = 5.0 * p.r * math.sin(p.theta) / 6.0
    if not p.R > Rmin * (1 + MARGIN):
        return (
            f"R = {p.R:g} m must exceed 5 r sin(theta)/6 = {Rmin:.6g} m (by a relative {MARGIN:g}): "
            "no steady rolling with this lean on a smaller circle"
        )


@exercise.analytic
def analytic(P):
    """Over arrays of variants, the scale sqrt(g/r) taken apart (4 g sin(theta) loses its digits at
    g = 5e-324)."""
    from mech.solvers.numerics.batch import Column

    r, theta, R, g = (np.asarray(P[k], dtype=float) for k in ("r", "theta", "R", "g"))
    s, c, Rs = np.sin(theta), np.cos(theta), R / r
    Om = np.sqrt(g) / np.sqrt(r) * np.sqrt(4.0 * s / (c * (6.0 * Rs - 5.0 * s)))
    return {"T": Column(2 * math.pi / Om), "Omega": Column(Om), "omega_spin": Column(Om * Rs)}


# --------------------------------------------------------------------------- numeric


class _Disk:
    """Newton-Euler of a rolling thin disk, radius 1, mass 1, g = 1 (solvers.mechanics.rolling_disk)."""

    def __init__(self):
        pts, w = disk(8, 16)  # unit disk in the body xy plane: the symmetry axis is body z
        self.I_body = inertia_tensor(pts, w)
        self.z = np.array([0.0, 0.0, 1.0])
        # the disk is a body of revolution about body z: I_lab = I1 1 + (I3 - I1) n n^T, which lets the
        # right-hand side skip the matrix products (it was 2/3 of the solve); checked on the tensor itself
        Ib = self.I_body
        self.I1, self.I3 = 0.5 * (Ib[0, 0] + Ib[1, 1]), Ib[2, 2]
        off = max(abs(Ib[0, 1]), abs(Ib[0, 2]), abs(Ib[1, 2]), abs(Ib[0, 0] - Ib[1, 1]))
        if off > 1e-14 * self.I3:
            raise NumericFailure(f"the disk's inertia tensor is not axisymmetric (off by {off:.3g})")

    def geometry(self, Rm, omega):
        """(n3, P - C, d(P - C)/dt) for the lowest rim point, whose place on the rim moves."""
        n = Rm[:, 2]
        wv = np.array([-n[2] * n[0], -n[2] * n[1], n[0] ** 2 + n[1] ** 2])
        wn = np.linalg.norm(wv)
        u = wv / wn
        ndot = np.cross(omega, n)
        wdot = -ndot[2] * n - n[2] * ndot
        udot = (wdot - u * (u @ wdot)) / wn
        return n, -u, -udot

    def rhs(self, t, y):
        """Newton-Euler with the rolling constraint (``rolling_disk.rates``: the 3 x 3 system for alpha)."""
        return np.array(rates(y, self.I1, self.I3))

    def steady_state(self, theta, Rs, Om):
        """State [omega_body, q, C, v_C] of the steady motion turning at Om (contact at (Rs, 0, 0)) and omega."""
        Rm, omega, C, vC, _, residual = steady_rolling(theta, Rs, Om)
        if residual > 1e-12:
            raise NumericFailure("the rolling condition cannot be met by a spin about the axis")
        Rm, omega = np.array(Rm, dtype=float), np.array(omega, dtype=float)
        return np.concatenate([Rm.T @ omega, quat_from_matrix(Rm), C, vC]), Rm, omega


_BODY = _Disk()  # the inertia by quadrature, once


def _roots(theta, Rs):
    """(Omega, failure code) over arrays (units r = g = 1): the root of the tilt acceleration in the steady
    state, bracketed by doubling from 1, then to rtol 1e-15 (Illinois).  Codes: 1 a coin at rest does not
    fall, 2 no turning rate holds the tilt, 3 not converged."""
    from mech.solvers.numerics.batch import illinois, scan_up

    I1, I3 = _BODY.I1, _BODY.I3
    n = theta.size
    f = lambda idx, Om: tilt_acceleration(theta[idx], Rs[idx], Om, I1, I3)  # noqa: E731
    # at rest the coin falls (the tilt grows): f(0) > 0; a root exists where turning holds it
    f0 = f(np.arange(n), np.zeros(n))
    code = np.where(f0 > 0, 0.0, 1.0)
    Om = np.full(n, np.nan)
    go = np.flatnonzero(code == 0)
    lo, hi, flo, fhi, none = scan_up(lambda i, x: f(go[i], x), np.zeros(go.size), np.ones(go.size), factor=2.0,
                                     limit=2.0**200, flo=f0[go])
    code[go[none]] = 2.0
    ok = ~none
    go, lo, hi, flo, fhi = go[ok], lo[ok], hi[ok], flo[ok], fhi[ok]
    x, conv = illinois(lambda x, i: f(go[i], x), lo, hi, flo, fhi, xtol=1e-300, rtol=1e-15, max_iter=500)
    Om[go] = x
    code[go[~conv]] = 3.0
    return Om, code


_ROOT_FAILS = {1.0: "a coin at rest does not fall: the setup is wrong", 2.0: "no turning rate holds the tilt",
               3.0: "the root search for the turning rate did not converge"}


def _turning_rate(body, theta, Rs):
    """Omega (units r = g = 1): ``_roots`` at one point."""
    Om, code = _roots(np.array([float(theta)]), np.array([float(Rs)]))
    if code[0]:
        raise NumericFailure(_ROOT_FAILS[float(code[0])])
    return float(Om[0])


def _start(body, theta, Rs, Om):
    """The steady state turning at Om and its spin (from the rolling condition)."""
    y0, _, omega0 = body.steady_state(theta, Rs, Om)
    return y0, float(np.linalg.norm(omega0 - Om * body.z))


def _fallen(n3z0):
    """The event that stops a run whose steady motion is lost for good (the tilt off by 1e-3)."""
    return Event(lambda t, y: abs(quat_to_matrix(y[3:7])[2, 2] - n3z0) - 1e-3, terminal=True, direction=1,
                 name="tilt lost")


@exercise.motion
def motion(p, Om=None):
    """The steady rolling, integrated from the steady state turning at Omega (the root of the tilt
    acceleration, found here when not given), units r = g = M = 1: one full turn of the axis's horizontal
    projection (timed by the event of its azimuth passing 2 pi), or, when a turn has more than
    MAX_SPIN_TURNS spin turns, 20 spin turns (the azimuth's rate is fitted).  Stopped where the tilt is
    lost for good."""
    from mech.problems.motion import Motion

    Rs, theta, body = p.R / p.r, p.theta, _Disk()
    if Om is None:
        Om = _turning_rate(body, theta, Rs)
    y0, spin0 = _start(body, theta, Rs, Om)
    T_root = 2 * math.pi / Om
    fall = _fallen(math.sin(theta))
    if spin0 * T_root / (2 * math.pi) <= MAX_SPIN_TURNS:
        # one full turn of the axis's projection: n3_y crosses zero upward again at azimuth 2 pi
        turn = Event(lambda t, y: quat_to_matrix(y[3:7])[1, 2], terminal=False, direction=1,
                     name="axis azimuth 2 pi")
        span, events, max_step = (0.0, 1.3 * T_root), [turn, fall], T_root / 64
    else:
        t_run = 20.0 * 2 * math.pi / spin0
        span, events, max_step = (0.0, t_run), [fall], t_run / 64
    size = ([max(spin0, Om)] * 3 + [1.0] * 4 + [max(Rs, 1.0)] * 3 + [max(Om * Rs, Om, 1e-300)] * 3)
    # square roots taken apart: r/g overflows for g below 1e-308 where its root does not
    w_unit, v_unit = math.sqrt(p.g) / math.sqrt(p.r), math.sqrt(p.g) * math.sqrt(p.r)
    return Motion(body.rhs, y0, span, t_scale=math.sqrt(p.r) / math.sqrt(p.g),
                  y_scale=[w_unit] * 3 + [1.0] * 4 + [p.r] * 3 + [v_unit] * 3, y_size=size,
                  options={"events": events, "max_step": max_step})


def _drifts(Y, n3z0, tilt_tol, scale, E0):
    """``rolling_disk.drifts`` of the samples Y (13 x K x N) of runs from the tilt n3z0 and energy E0."""
    return drifts(Y, _BODY.I1, _BODY.I3, n3z0, tilt_tol, scale, E0)


def _assess(rtol, Om, spin0, Rs, many, T_s, fit_rel, drifts, lost, spin_end, t_len):
    """What the runs answer and earn, over arrays of runs: (T, claims {output: rel}, invariants {name: (drift,
    allowed)}, failures [(mask, reason)]).  ``T_s``: the timed turn (NaN: none); ``fit_rel``: the fitted
    azimuth rate's claim (``many``); ``lost``: the tilt left its value by tilt_tol (an unstable steady motion)."""
    Om, spin0, Rs, T_s, fit_rel, spin_end, t_len, lost, *drifts = np.broadcast_arrays(
        *(np.asarray(x, dtype=float) for x in (Om, spin0, Rs, T_s, fit_rel, spin_end, t_len, lost, *drifts)))
    many, lost = np.broadcast_to(np.asarray(many, dtype=bool), Om.shape), lost.astype(bool)
    tf = exercise.tol_factor * rtol
    tilt_tol = max(1e-7, 1e3 * rtol)
    T_root = 2 * math.pi / Om
    # the root's round-off: the tilt acceleration balances terms of size Om^2 Rs against the spin's
    # (Om Rs)^2, so it keeps a part in ~eps Rs of its digits (2.7e-8 at Rs = 1.7e9: 0.15 eps Rs)
    root_rel = np.maximum(tf, 4e-16 * np.maximum(Rs, 1.0))
    # T: the timed turn.  The root T_root is exact to round-off, so the turn's departure from it is
    # this integration's error, measured (3x for the rerun's comparison); at least the default claim
    # (the departure grows to 55 rtol at theta = 0.03, R/r = 17, 0.01 rtol at the defaults)
    T_err = np.where(lost, 0.0, np.abs(T_s / T_root - 1.0))
    T_claim = np.maximum(np.maximum(np.where(many, fit_rel, tf), 3.0 * np.nan_to_num(T_err)), root_rel)
    # On an unstable steady motion (a slowly rolling, nearly upright coin falls away from it) round-off grows
    # until the tilt leaves its value: the answer is the steady state itself, the root of the tilt
    # acceleration, with the rolling condition's spin; its monitors hold to the default claim
    T = np.where(lost, T_root, T_s)
    T_claim = np.where(lost, root_rel, T_claim)
    earned = np.where(lost, tf, T_claim)
    # the invariants drift by the run's global error, which T's departure from the root measures (1.4e-8
    # contact height against 2.4e-8 in T at theta = 0.068, R/r = 17, rtol 1e-8): what the run earns.  The
    # contact height is held only through its second derivative (the rolling constraint differentiated once):
    # it drifts by up to the largest slip speed times the run's length (5e-8 at R/r = 50, theta = 0.54)
    tilt, roll, height, e = drifts
    slip_integral = roll * np.maximum(np.maximum(Om * Rs, Om), spin0) * t_len
    invariants = {"energy": (e, earned), "rolling (slip speed)": (roll, earned),
                  "contact height / r": (height, np.where(lost, tf, np.maximum(T_claim, slip_integral))),
                  # the tilt is no conserved quantity: it stays only on a stable steady motion
                  "tilt n3.z": (np.where(lost, 0.0, tilt), np.full(Om.shape, tilt_tol))}
    # the spin read off the state at the end of the run is |omega - Omega z|, two vectors of size Omega (rel.
    # error ~ rtol r/R), carrying whatever mode the turn excited (moved by 1.1e-7 at rtol/10 with a tilt drift
    # 4.4e-6 at theta = 0.032, R/r = 0.19): it is only checked
    spin_tol = max(tilt_tol, 1e3 * rtol) * np.maximum(Om, spin0)
    failures = [(~lost & ~many & ~np.isfinite(T_s), "the axis did not complete a turn"),
                (~lost & many & ~np.isfinite(T_s), "the axis does not turn"),
                (~lost & ~(np.abs(spin_end - spin0) <= spin_tol), "the spin does not stay at its rolling value")]
    claims = {"T": T_claim, "Omega": root_rel, "omega_spin": root_rel}
    return T, claims, invariants, failures


def _fit_rel(rtol, rate, t_run):
    """The fitted azimuth rate's claim: its error is absolute (about 1e3 rtol), relative to the swept angle."""
    return np.maximum(exercise.tol_factor * rtol, 1e3 * rtol / np.maximum(rate * t_run, 1e-300))


# -- every variant at once: the same equations, roots and judgement over arrays ---------------------------

# states kept along each run (the monitors' samples; the azimuth's, unwrapped), TURN_AT of them over one root
# period: a run over one turn goes on to 1.3 of it, as ``motion``'s does, for the tilt's sake
CHECKPOINTS, TURN_AT = 26, 20
# a batched step's fixed cost and a step of one variant alone (plain floats), in variants' worth of arithmetic
# (``chunks_by_work``): measured (``follow_batch``'s process time) ~470 us a step at 40 variants + 1.3 us a
# variant (to 300), 185 us alone
STEP_OVERHEAD, STEP_ALONE = 360.0, 140.0


def _follow_variants(theta, Rs, Om, spin0, y0, rtol, why, tally):
    """``numeric``'s runs at N variants at once (``rolling_disk.follow_batch``, in chunks of like step counts):
    each run over 1.3 root periods (the turn timed from the axis's azimuth at the root period: its departure
    from 2 pi over its rate there), or over 20 spin turns with more than MAX_SPIN_TURNS per orbit (the azimuth's rate
    fitted over the checkpoints).  Returns ``_assess``'s arguments after rtol; ``why``: each variant's failure
    (a chunk's integration failing), filled in."""
    from mech.solvers.numerics.ensemble import each_alone_on_failure
    from mech.solvers.mechanics.rolling_disk import follow_batch
    from mech.solvers.numerics.batch import chunks_by_work

    N = Om.size
    T_root = 2 * math.pi / Om
    many = spin0 * T_root / (2 * math.pi) > MAX_SPIN_TURNS
    span = np.where(many, 20.0 * 2 * math.pi / spin0, T_root * CHECKPOINTS / TURN_AT)
    big = np.maximum(spin0, Om)
    size = np.stack([big] * 3 + [np.ones(N)] * 4 + [np.maximum(Rs, 1.0)] * 3
                    + [np.maximum(np.maximum(Om * Rs, Om), 1e-300)] * 3)
    scale, n3z0 = np.maximum(np.maximum(Om * Rs, Om), spin0), np.sin(theta)
    E0 = monitors(y0, _BODY.I1, _BODY.I3)[4]
    tilt_tol = max(1e-7, 1e3 * rtol)
    s_pts = np.arange(1, CHECKPOINTS + 1) / CHECKPOINTS
    Y = np.full((CHECKPOINTS + 1, 13, N), np.nan)
    todo = np.flatnonzero(np.isfinite(y0).all(axis=0) & (why == ""))
    def follow(idx):  # a chunk that fails is followed again variant by variant: a failure is that variant's
        got = follow_batch(y0[:, idx], span[idx], _BODY.I1, _BODY.I3, s_pts, rtol=rtol,
                           atol=1e-3 * rtol * size[:, idx], tilt0=n3z0[idx], tilt_tol=tilt_tol,
                           integrator=tally.integrator)
        Y[:, :, idx] = got[0]
        for r in got[2]:
            tally.record(r)

    # the expected steps: ~17 a turn of the fastest rate, at least ~4 turns' worth (the legs' ends)
    for chunk in chunks_by_work(big[todo] * span[todo] / (2 * math.pi) + 4.0, STEP_OVERHEAD, STEP_ALONE):
        each_alone_on_failure(follow, todo[chunk], why)
    Yt = Y.transpose(1, 0, 2)
    drifts, k = _drifts(Yt, n3z0, tilt_tol, scale, E0)
    lost = k <= CHECKPOINTS
    n, _, _, _, _, omega = monitors(Yt, _BODY.I1, _BODY.I3)
    with np.errstate(invalid="ignore", divide="ignore"):
        az = np.unwrap(np.arctan2(n[1], n[0]), axis=0)
        # one turn: the azimuth at the root period is 2 pi off by the integration's error; the turn's end is that
        # departure over the azimuth's rate, (n x n')_z / (n_x^2 + n_y^2), n' = omega x n
        j = TURN_AT
        nx, ny, nz = n[0][j], n[1][j], n[2][j]
        dn = (omega[1][j] * nz - omega[2][j] * ny, omega[2][j] * nx - omega[0][j] * nz)
        rate_end = (nx * dn[1] - ny * dn[0]) / (nx * nx + ny * ny)
        turned = np.abs(az[j] - az[0] - 2 * math.pi) < 0.5
        T_turn = np.where(turned, span * (j / CHECKPOINTS) - np.arctan2(ny, nx) / rate_end, np.nan)
        # many spin turns: the least-squares slope of the azimuth over the run
        sc = np.concatenate([[0.0], s_pts]) - 0.5
        rate = (sc @ (az - az.mean(axis=0))) / (sc @ sc) / span
        T_fit = np.where(rate > 0, 2 * math.pi / rate, np.nan)
        j = np.where(many, CHECKPOINTS, TURN_AT)  # the spin at the end of the turn, or of the fit
        o = [np.take_along_axis(x, j[None, :], axis=0)[0] for x in omega]
        spin_end = np.sqrt(o[0] ** 2 + o[1] ** 2 + (o[2] - Om) ** 2)
    T_s = np.where(many, T_fit, T_turn)
    return many, T_s, _fit_rel(rtol, rate, span), drifts, lost, spin_end, span


def _report(tally, rtol, Om, many, T_s, lost, span, invariants):
    """Each variant's invariant drifts and allowances, and how its turn was timed, to ``tally``."""
    for name, (drift, allowed) in invariants.items():
        tally.invariant(name, drift, allowed)
    T_root = 2 * math.pi / Om
    tally.info["Omega_root_scaled"] = Om
    unstable = [f"unstable: the tilt leaves its value by {max(1e-7, 1e3 * rtol):g} within {s / T:.3g} of a turn; "
                "Omega is the steady-state root, not a timed turn" for s, T in zip(span, T_root)]
    tally.info["steady_motion"] = np.where(lost, np.array(unstable, dtype=object), None)
    timed = np.where(many, "azimuth rate fitted over 20 spin turns", "azimuth at the root period: one turn")
    tally.info["timed_by"] = np.where(lost, None, timed.astype(object))
    with np.errstate(invalid="ignore"):
        tally.info["timed_turn_vs_root"] = np.where(lost, None, np.abs(T_s / T_root - 1.0))


@exercise.batched(("T", "Omega", "omega_spin"))
def numeric(P, rtol, outputs, memo=None, tally=None):
    """The route at N variants at once (a one-point solve is the batch of one): the roots together (once per
    distinct (theta, R/r), kept in ``memo`` for the rerun), the runs together (``_follow_variants``), each
    variant judged by ``_assess``; every failure and every invariant beyond its allowance fails that variant's
    outputs.  The invariants' drifts and how each turn was timed go to ``tally``."""
    from mech.problems.spec import Tally
    from mech.solvers.numerics.batch import Column, by_rows

    tally = Tally() if tally is None else tally

    r, theta, R, g = (np.asarray(P[k], dtype=float) for k in ("r", "theta", "R", "g"))
    Rs = R / r
    memo = {} if memo is None else memo
    Om, code = by_rows(memo, "4.23 root", (theta, Rs), _roots)
    N = Om.size
    why = np.full(N, "", dtype=object)
    for c, text in _ROOT_FAILS.items():
        why[code == c] = text
    y0, spin0 = np.full((13, N), np.nan), np.full(N, np.nan)
    for k in np.flatnonzero(code == 0):
        try:
            y0[:, k], spin0[k] = _start(_BODY, float(theta[k]), float(Rs[k]), float(Om[k]))
        except NumericFailure as exc:
            why[k] = str(exc)
    many, T_s, fit_rel, drifts, lost, spin_end, span = _follow_variants(theta, Rs, Om, spin0, y0, rtol, why,
                                                                        tally)
    T, claims, invariants, failures = _assess(rtol, Om, spin0, Rs, many, T_s, fit_rel, drifts, lost, spin_end,
                                              span)
    _report(tally, rtol, Om, many, T_s, lost, span, invariants)
    ran = why == ""
    failed = [(why == text, text) for text in sorted(set(why[~ran]))]
    failed += [(ran & mask, why_) for mask, why_ in failures]
    failed += [(ran & ~(drift <= allowed), f"the invariant '{name}' drifts by more than the method allows: the "
                "integration is not to be trusted") for name, (drift, allowed) in invariants.items()]
    t_unit = np.sqrt(r) / np.sqrt(g)
    values = {"T": T * t_unit, "Omega": Om / t_unit, "omega_spin": spin0 / t_unit}
    return {o: Column(values[o], rel=claims[o], failed=failed) for o in outputs}

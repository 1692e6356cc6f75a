"""4.29 Bead on a rotating rod: the two descriptions of its motion.

Analytic.  Rotating frame: along the rod only the centrifugal force acts
(the Coriolis force is across the rod and is balanced by the rod), so
r'' = omega^2 r and r = A e^(omega t) + B e^(-omega t), A, B = (r0 +- v0/omega)/2
(written with the two exponentials, not cosh/sinh, so the decaying solution
v0 = -omega r0 is exact; for omega t <= 1, r0 cosh + v0 t sinh(omega t)/(omega t),
where v0/omega may overflow and cosh - sinh loses at most a factor 4).  The
rotating-frame acceleration is r'' = omega^2 r along e_r; the rod's force
balances the Coriolis force, N = 2 m omega r'.
Lab frame: in polar coordinates the radial acceleration r'' - omega^2 r is 0 and
the azimuthal one is 2 omega r', so |a_lab| = 2 omega |r'| = |N|/m: in the lab the
rod's force is the only force and the whole acceleration is across the rod.

Numeric: the bead as a point mass in the rotating plane, in units of time
T0 = 1/omega and length L = max(|r0|, |v0| T0) (T0 = t where omega t < 1 and
v0/omega overflows while the answer does not), with the
centrifugal and Coriolis forces
and the rod's reaction as a Lagrange multiplier that keeps the transverse
coordinate at zero (solved from the twice-differentiated constraint).
DOP853 integrates (x, y, vx, vy) to omega t.  The equations are autonomous and
linear, so each Runge-Kutta step maps the decaying solution onto itself:
integration errors do not feed the growing branch.  The lab acceleration is
obtained from the rotating-frame one by the frame transformation (Eq. 4.90).
The rotating-frame Jacobi integral v^2/2 - omega^2 r^2/2 is monitored.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems import ranges
from mech.problems.spec import Exercise, NumericFailure

exercise = Exercise(
    "4.29",
    formulas=[
        "r(t) = A e^(ωt) + B e^(-ωt), A, B = (r₀ ± v₀/ω)/2",
        "a_rot = r'' = ω² r (along the rod: the centrifugal force)",
        "N = 2 m ω r' (balances the Coriolis force), r' = ω (A e^(ωt) - B e^(-ωt))",
        "a_lab = 2 ω |r'| = |N|/m (across the rod; the radial part r'' - ω² r vanishes)",
    ],
    # the bead from 0 to t (when it moves): its coordinate along the rod and its velocity relative to it
    states=[("r", "m"), ("r_dot", "m/s")],
)

# the distance r <= (|r0| + |v0| t) e^(omega t): beyond 1e306 m it (or omega^2 r) soon is no double
ranges.declare(exercise, ranges.Scale(
    "(|r0| + |v0| t) e^(omega t)", {}, "the bead's distance", low=-math.inf, high=306.0,
    factor=lambda p: (abs(p.r0) + abs(p.v0) * p.t) * math.exp(min(p.omega * p.t, 1000.0))))

MAX_OMEGA_T = 100.0


exercise.declare_limits(
    f"omega t <= {MAX_OMEGA_T:g}: the bead stays on a rod of any real length",
)


@exercise.constraint
def constraint(p):
    if p.omega * p.t > MAX_OMEGA_T:
        return (
            f"omega t = {p.omega * p.t:.4g} exceeds {MAX_OMEGA_T:g}: the bead would run e^{p.omega * p.t:.0f} "
            "times its initial distance out along the rod, which no rod is long enough for"
        )


def _arrays(P):
    return (np.asarray(P[k], dtype=float) for k in ("m", "omega", "r0", "v0", "t"))


@exercise.analytic
def analytic(P):
    """Over arrays of variants: for omega t <= 1, r0 cosh + v0 t sinh(wt)/(wt) (no v0/omega, which overflows
    where r does not: omega = 1e-300 rad/s, v0 = 1e290 m/s, r ~ v0 t; below wt = 1 cosh - sinh loses at most a
    factor 4); beyond, the two exponentials."""
    from mech.solvers.numerics.batch import Column

    m, w, r0, v0, t = _arrays(P)
    wt = w * t
    with np.errstate(all="ignore"):
        sinhc = np.where(wt > 1e-8, np.sinh(wt) / np.where(wt > 0, wt, 1.0), 1.0 + wt * wt / 6.0)
        r_short = r0 * np.cosh(wt) + v0 * t * sinhc
        rd_short = w * r0 * np.sinh(wt) + v0 * np.cosh(wt)
        A, B = 0.5 * (r0 + v0 / w), 0.5 * (r0 - v0 / w)
        grow, decay = np.exp(wt), np.exp(-wt)
        r_long, rd_long = A * grow + B * decay, w * (A * grow - B * decay)
    short = wt <= 1.0
    r, rdot = np.where(short, r_short, r_long), np.where(short, rd_short, rd_long)
    return {"r": Column(r), "a_rot": Column(w * (w * r)), "a_lab": Column(2.0 * w * np.abs(rdot)),
            "N": Column(2.0 * m * w * rdot)}


def _forces(y, k):
    """Scaled rotating-frame accelerations and the rod's reaction n = N T0^2/(m L), each divided by
    k = omega T0 (so that k^2 x, 1e-600 at omega t = 1e-300, is never formed); y: 4 numbers or 4 x N."""
    x, yy, vx, vy = y
    n = 2.0 * vx - k * yy
    return k * x + 2.0 * vy, k * yy - 2.0 * vx + n, n


def _units(w, t, r0, v0):
    """(T0, k, L, V, tau_end, out of range) over arrays: the time unit T0, k = omega T0, the length and velocity
    units and the run's end in T0; L = 0 for a bead at rest on the axis."""
    # time unit T0: 1/omega, or t itself where |v0|/omega (or 1/omega) leaves the floating-point range in a run
    # shorter than 1/omega (omega = 1e-100 rad/s, v0 = 1e250 m/s, t = 1e-200 s: r ~ v0 t = 1e50 m); then
    # k = omega T0 < 1, and the velocity unit V = L/t is |v0| (the part r0 omega^2 t of the speed that it
    # leaves below round-off is less than 1e-308 r0 omega t of it)
    with np.errstate(all="ignore"):
        T0 = 1.0 / w
        L = np.maximum(np.abs(r0), np.abs(v0) * T0)
        short = ~(np.isfinite(L) & np.isfinite(T0) & np.isfinite(L * w)) & (0.0 < w * t) & (w * t < 1.0)
        T0 = np.where(short, t, T0)
        k = np.where(short, w * t, 1.0)
        L = np.maximum(np.abs(r0), np.abs(v0) * T0)
        V = np.where(short, L / T0, L * w)  # velocity unit
        tau_end = np.where(short, t / T0, w * t)
    bad = (L != 0.0) & ~(np.isfinite(L) & np.isfinite(V) & (V > 0.0))
    return T0, k, L, V, tau_end, bad


def _rhs(k, tau_end):
    """The scaled equations over s = tau/tau_end in [0, 1] (numbers, or arrays of variants)."""

    def rhs(s, y):
        fx, fy, _ = _forces(y, k)
        return tau_end * np.array([y[2], y[3], k * fx, k * fy])

    return rhs


def _jacobi(y, k):
    """The Jacobi integral (v^2 - k^2 r^2)/2 and its size (v^2 + k^2 r^2)/2 (states 4 x ...)."""
    v2, r2 = y[2] ** 2 + y[3] ** 2, k * k * (y[0] ** 2 + y[1] ** 2)
    return 0.5 * (v2 - r2), 0.5 * (v2 + r2)


@exercise.motion
def motion(p):
    """The bead in the rotating frame, in units T0, L, V (``_units``): along the rod (x) and across it (y,
    held at zero by the rod's reaction), from (r0, v0) for the time t, in s = t/(the run's length).  None for a
    bead at rest on the axis (an equilibrium)."""
    from mech.problems.motion import Motion

    T0, k, L, V, tau_end, bad = (float(x) for x in _units(*(np.float64(p[n]) for n in ("omega", "t", "r0", "v0"))))
    if L == 0.0:
        return None
    if bad:
        raise NumericFailure(f"the length unit {L:.3g} m or velocity unit {V:.3g} m/s leaves the floating-point range")
    # |d y/d tau| <= k |y| for this system, so |y| >= e^(-k tau) |y0|: an absolute tolerance below that
    # keeps the error control relative all the way
    return Motion(_rhs(k, tau_end), np.array([p.r0 / L, 0.0, p.v0 / V, 0.0]), (0.0, 1.0),
                  t_scale=T0 * tau_end, y_scale=[L, V], to_states=lambda Y: Y[[0, 2]],  # across the rod: 0
                  y_size=math.exp(-k * tau_end))


@exercise.batched(("r", "a_rot", "a_lab", "N"))
def numeric(P, rtol, outputs, tally=None):
    """The bead at N variants at once (a one-point solve is the batch of one): each in its own units
    (``_units``), its run of length t mapped onto s in [0, 1], integrated together (``variants.follow``); the
    rotating-frame accelerations and the rod's reaction from the state at the end, the lab acceleration by the
    frame transformation; the Jacobi integral's drift and the transverse coordinate reported to ``tally``."""
    from mech.problems.spec import Tally
    from mech.solvers.numerics.batch import Column

    tally = Tally() if tally is None else tally
    m, w, r0, v0, t = _arrays(P)
    T0, k, L, V, tau_end, bad = _units(w, t, r0, v0)
    N = w.size
    rest = L == 0.0  # at rest on the axis: an equilibrium, every output 0
    go = ~rest & ~bad
    with np.errstate(all="ignore"):
        y0 = np.stack([r0 / L, np.zeros(N), v0 / V, np.zeros(N)])
    y0[:, ~go] = 0.0
    run = np.flatnonzero(go & (tau_end > 0.0))
    y = y0.copy()
    if run.size:
        atol = 1e-3 * rtol * np.exp(-k[run] * tau_end[run]) * np.ones((4, 1))
        got = tally.follow(lambda sel: _rhs(k[run][sel], tau_end[run][sel]), (0.0, 1.0), y0[:, run], rtol=rtol,
                           atol=atol)
        y[:, run], why_run = got.y_end, got.why
    else:
        why_run = np.array([], dtype=object)
    why = np.full(N, "", dtype=object)
    why[run] = why_run
    why[bad] = "the length or velocity unit leaves the floating-point range"
    J0, _ = _jacobi(y0, k)
    J, size = _jacobi(y, k)
    with np.errstate(all="ignore"):
        drift = np.where(go, np.abs(J - J0) / np.maximum(size, np.finfo(float).tiny), 0.0)
    tally.invariant("jacobi", np.nan_to_num(drift))
    tally.invariant("constraint", np.where(go, np.nan_to_num(np.abs(y[1])), 0.0))
    fx, fy, n = _forces(y, k)
    lab = (fx - 2.0 * y[3] - k * y[0], fy + 2.0 * y[2] - k * y[1])  # over k, like the forces
    scale = np.maximum(np.abs(y[0]), np.abs(y[2]))
    tol = exercise.tol_factor * rtol
    # an acceleration k q in units L/T0^2 is q omega V in SI (1/T0 = omega/k): the unit over k formed first (q
    # omega alone can underflow)
    wV = w * V
    values = {"r": y[0] * L, "a_rot": fx * wV, "a_lab": np.hypot(*lab) * wV, "N": n * wV * m}
    absolute = {"r": tol * L * scale, "a_rot": tol * k * scale * wV, "a_lab": tol * 2.0 * scale * wV,
                "N": tol * 2.0 * m * scale * wV}
    failed = [(why == text, text) for text in sorted(set(why[why != ""]))]
    failed.append((go & ~(drift <= tol), "the invariant 'jacobi' drifts by more than the method allows: the "
                   "integration is not to be trusted"))
    return {o: Column(np.where(rest, 0.0, values[o]), rel=tol, abs=np.where(rest, 0.0, absolute[o]), failed=failed)
            for o in outputs}

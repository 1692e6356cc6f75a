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


@exercise.analytic
def analytic(p):
    w, t = p.omega, p.t
    wt = w * t
    if wt <= 1.0:
        # r0 cosh(wt) + v0 t sinh(wt)/(wt): no v0/omega, which overflows where r does not (omega = 1e-300
        # rad/s, v0 = 1e290 m/s: r ~ v0 t); below wt = 1 cosh - sinh loses at most a factor 4
        sinhc = 1.0 if wt == 0.0 else (math.sinh(wt) / wt if wt > 1e-8 else 1.0 + wt * wt / 6.0)
        r = p.r0 * math.cosh(wt) + p.v0 * t * sinhc
        rdot = w * p.r0 * math.sinh(wt) + p.v0 * math.cosh(wt)
    else:
        A = 0.5 * (p.r0 + p.v0 / w)
        B = 0.5 * (p.r0 - p.v0 / w)
        grow, decay = math.exp(wt), math.exp(-wt)
        r = A * grow + B * decay
        rdot = w * (A * grow - B * decay)
    return {
        "r": r,
        "a_rot": w * (w * r),
        "a_lab": 2.0 * w * abs(rdot),
        "N": 2.0 * p.m * w * rdot,
    }


def _forces(y, k):
    """Scaled rotating-frame accelerations and the rod's reaction n = N T0^2/(m L), each divided by
    k = omega T0 (so that k^2 x, 1e-600 at omega t = 1e-300, is never formed)."""
    x, yy, vx, vy = y
    n = 2.0 * vx - k * yy
    return k * x + 2.0 * vy, k * yy - 2.0 * vx + n, n


def _units(p):
    """(T0, k, L, V, tau_end): the time unit T0, k = omega T0, the length and velocity units and the run's
    end in T0; L = 0 for a bead at rest on the axis."""
    w, t = p.omega, p.t
    # time unit T0: 1/omega, or t itself where |v0|/omega (or 1/omega) leaves the floating-point range in a run
    # shorter than 1/omega (omega = 1e-100 rad/s, v0 = 1e250 m/s, t = 1e-200 s: r ~ v0 t = 1e50 m); then
    # k = omega T0 < 1, and the velocity unit V = L/t is |v0| (the part r0 omega^2 t of the speed that it
    # leaves below round-off is less than 1e-308 r0 omega t of it)
    T0, k = 1.0 / w, 1.0
    L = max(abs(p.r0), abs(p.v0) * T0)
    short = not (math.isfinite(L) and math.isfinite(T0) and math.isfinite(L * w)) and 0.0 < w * t < 1.0
    if short:
        T0, k = t, w * t
        L = max(abs(p.r0), abs(p.v0) * T0)
    if L == 0.0:
        return T0, k, L, 0.0, 0.0
    V = L / T0 if short else L * w  # velocity unit
    if not (math.isfinite(L) and math.isfinite(V) and V > 0.0):
        raise NumericFailure(f"the length unit {L:.3g} m or velocity unit {V:.3g} m/s leaves the floating-point range")
    return T0, k, L, V, t / T0 if short else w * t


@exercise.motion
def motion(p):
    """The bead in the rotating frame, in units T0, L, V (``_units``): along the rod (x) and across it (y,
    held at zero by the rod's reaction), from (r0, v0) for the time t.  None for a bead at rest on the axis
    (an equilibrium)."""
    from mech.problems.motion import Motion

    T0, k, L, V, tau_end = _units(p)
    if L == 0.0:
        return None

    def rhs(t, y):
        fx, fy, _ = _forces(y, k)
        return np.array([y[2], y[3], k * fx, k * fy])

    def jacobi(Y):
        """The Jacobi integral (v^2 - k^2 r^2)/2 at every step, relative to (v^2 + k^2 r^2)/2 there."""
        jac = 0.5 * (Y[2] ** 2 + Y[3] ** 2 - k * k * (Y[0] ** 2 + Y[1] ** 2))
        size = 0.5 * (Y[2] ** 2 + Y[3] ** 2 + k * k * (Y[0] ** 2 + Y[1] ** 2))
        return float(np.max(np.abs(jac - jac[0]) / np.maximum(size, np.finfo(float).tiny)))

    # |d y/d tau| <= k |y| for this system, so |y| >= e^(-k tau) |y0|: an absolute tolerance below that
    # keeps the error control relative all the way
    return Motion(rhs, np.array([p.r0 / L, 0.0, p.v0 / V, 0.0]), (0.0, tau_end),
                  monitors={"jacobi": jacobi, "constraint": lambda Y: float(np.max(np.abs(Y[1])))},
                  t_scale=T0, y_scale=[L, V], to_states=lambda Y: Y[[0, 2]],  # across the rod: 0
                  y_size=math.exp(-k * tau_end))


@exercise.numeric
def numeric(p, run):
    w = p.omega
    m = motion(p)
    if m is None:  # at rest on the axis: an equilibrium
        return {"r": 0.0, "a_rot": 0.0, "a_lab": 0.0, "N": 0.0}
    T0, k, L, V, tau_end = _units(p)
    y = run.follow(m).y_end if tau_end > 0.0 else m.y0
    fx, fy, n = _forces(y, k)
    lab = np.array([fx - 2.0 * y[3] - k * y[0], fy + 2.0 * y[2] - k * y[1]])  # over k, like the forces
    scale = max(abs(y[0]), abs(y[2]))
    tol = exercise.tol_factor * run.rtol
    # an acceleration k q in units L/T0^2 is q omega V in SI (1/T0 = omega/k)
    wV = w * V  # the acceleration unit over k, formed first (q omega alone can underflow)
    acc = lambda q: q * wV  # noqa: E731
    run.claim("r", rel=tol, abs=tol * L * scale)
    run.claim("a_rot", rel=tol, abs=tol * k * scale * wV)
    run.claim("a_lab", rel=tol, abs=tol * 2.0 * scale * wV)
    run.claim("N", rel=tol, abs=tol * 2.0 * p.m * scale * wV)
    return {
        "r": y[0] * L,
        "a_rot": acc(fx),
        "a_lab": acc(float(np.hypot(lab[0], lab[1]))),
        "N": acc(n) * p.m,
    }

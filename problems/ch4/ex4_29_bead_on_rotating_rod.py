"""4.29 Bead on a rotating rod: the two descriptions of its motion.

Analytic.  Rotating frame: along the rod only the centrifugal force acts
(the Coriolis force is across the rod and is balanced by the rod), so
r'' = omega^2 r and r = A e^(omega t) + B e^(-omega t), A, B = (r0 +- v0/omega)/2
(written with the two exponentials, not cosh/sinh, so the decaying solution
v0 = -omega r0 is exact).  The rotating-frame acceleration is r'' = omega^2 r
along e_r; the rod's force balances the Coriolis force, N = 2 m omega r'.
Lab frame: in polar coordinates the radial acceleration r'' - omega^2 r is 0 and
the azimuthal one is 2 omega r', so |a_lab| = 2 omega |r'| = |N|/m: in the lab the
rod's force is the only force and the whole acceleration is across the rod.

Numeric: the bead as a point mass in the rotating plane, in units of
L = max(|r0|, |v0|/omega) and 1/omega, with the centrifugal and Coriolis forces
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

from mech.problems.spec import Exercise

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
    A = 0.5 * (p.r0 + p.v0 / w)
    B = 0.5 * (p.r0 - p.v0 / w)
    grow, decay = math.exp(w * t), math.exp(-w * t)
    r = A * grow + B * decay
    rdot = w * (A * grow - B * decay)
    return {
        "r": r,
        "a_rot": w * w * r,
        "a_lab": 2.0 * w * abs(rdot),
        "N": 2.0 * p.m * w * rdot,
    }


def _forces(y):
    """Scaled rotating-frame accelerations and the rod's reaction n = N/(m omega^2 L)."""
    x, yy, vx, vy = y
    # centrifugal (x, y) + Coriolis (2 vy, -2 vx) + reaction (0, n); y'' = 0 fixes n
    n = 2.0 * vx - yy
    return x + 2.0 * vy, yy - 2.0 * vx + n, n


@exercise.numeric
def numeric(p, run):
    w, tau_end = p.omega, p.omega * p.t
    L = max(abs(p.r0), abs(p.v0) / w)
    if L == 0.0:  # at rest on the axis: an equilibrium
        return {"r": 0.0, "a_rot": 0.0, "a_lab": 0.0, "N": 0.0}
    y0 = np.array([p.r0 / L, 0.0, p.v0 / (w * L), 0.0])

    def rhs(t, y):
        ax, ay, _ = _forces(y)
        return np.array([y[2], y[3], ax, ay])

    if tau_end > 0.0:
        # |d y/d tau| <= |y| for this system, so |y| >= e^(-tau) |y0|: an absolute
        # tolerance below that keeps the error control relative all the way
        atol = run.rtol * 1e-3 * math.exp(-tau_end)
        # dense output only for a trajectory (a smooth curve); the steps are the same
        traj = run.integrate(rhs, (0.0, tau_end), y0, rtol=run.rtol, atol=atol, dense_output=run.keep_trajectories)
        run.motion(traj, t_scale=1.0 / w, y_scale=[L, w * L], rows=[0, 2])  # across the rod: 0
        y = traj.y_end
        jac = 0.5 * (traj.y[2] ** 2 + traj.y[3] ** 2 - traj.y[0] ** 2 - traj.y[1] ** 2)
        size = 0.5 * (traj.y[2] ** 2 + traj.y[3] ** 2 + traj.y[0] ** 2 + traj.y[1] ** 2)
        run.invariant("jacobi", float(np.max(np.abs(jac - jac[0]) / size)))
        run.invariant("constraint", float(np.max(np.abs(traj.y[1]))))
    else:
        y = y0
    ax, ay, n = _forces(y)
    # Eq. (4.90): a_lab = a_rot + 2 w x v_rot + w x (w x r), scaled (w = z)
    lab = np.array([ax - 2.0 * y[3] - y[0], ay + 2.0 * y[2] - y[1]])
    # errors are relative to the larger of the state's two parts (growing and decaying)
    scale = max(abs(y[0]), abs(y[2]))
    tol = exercise.tol_factor * run.rtol
    run.claim("r", rel=tol, abs=tol * L * scale)
    run.claim("a_rot", rel=tol, abs=tol * w * w * L * scale)
    run.claim("a_lab", rel=tol, abs=tol * 2.0 * w * w * L * scale)
    run.claim("N", rel=tol, abs=tol * 2.0 * p.m * w * w * L * scale)
    return {
        "r": y[0] * L,
        "a_rot": ax * w * w * L,
        "a_lab": float(np.hypot(lab[0], lab[1])) * w * w * L,
        "N": n * p.m * w * w * L,
    }

"""4.7 A bullet sticks in the end of a free rod: velocities right after the impact.

Analytic: let J be the impulse the bullet gives the rod (length 2l, mass m,
I = m l^2/3 about its center).  The rod: m u = J, I omega = J l, so the struck end
moves at u + omega l = 4 J/m.  The bullet: m_b (v_hit - v0) = -J with v_hit = 4J/m.
Hence J = m m_b v0/(m + 4 m_b) and
  v_hit = 4 m_b v0/(m + 4 m_b),   omega = 3 m_b v0/(l (m + 4 m_b)),
  v_end = u - omega l = -2 m_b v0/(m + 4 m_b)   (the far end moves back),
  E_loss = m_b v0^2/2 - 2 m_b^2 v0^2/(m + 4 m_b) = (m_b v0^2/2) m/(m + 4 m_b).
The same follows from the conservation of the momentum m_b v0 and of the
angular momentum m_b v0 l about the rod's center.

Numeric: a finite force pulse (the model below).  In units of m, l and v0 the rod
(center and angle, mass and moment from a Gauss rule along it) and the bullet are
tied by a contact spring-damper between the bullet and the rod's end point,
K = W^-1/tp^2 and C = 2 W^-1/tp with W the contact's inverse effective mass, so the
relative motion is critically damped with time tp << l/v0; its reaction acts on
the rod at the bullet's position, which conserves the total momentum and angular
momentum exactly (both monitored).  The planar equations are integrated in
displacement variables (DOP853) until the relative motion has died out; the
final angular velocity and the center-of-mass velocity give the rigid velocity
field, evaluated in the pre-impact geometry; the dissipated energy is integrated
with the motion.  The longer pulse is the declared motion; a second, half as
long, and the Richardson extrapolation in tp^2 (the rod turns during the pulse) give the impulsive limit and the size of the
finite-pulse effect, which enters the accuracy claim.
"""

from __future__ import annotations

import math
from typing import Callable, Mapping

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.inertia import gauss_legendre

# -- the impact as a short finite force pulse (used by this exercise alone) -------------------------
#
# Impacts as short finite force pulses: a stiff, critically damped contact integrated through.
#
# An impulsive collision is modelled as a contact spring-damper between the two
# bodies' contact points, with the force F = -K d - C d' on one body (and -F on the
# other) for the relative displacement d.  Near the contact the relative
# acceleration is d'' = W F, where W = G Minv G^T (plus 1/m for a point mass) is the
# contact's inverse effective mass matrix (the Delassus operator) built from the
# bodies' mass matrices and the contact Jacobian G.  Choosing
#     K = W^-1 / tp^2,   C = 2 W^-1 / tp
# makes the linearized relative motion critically damped with the single time
# tp in every direction: d = d'(0) t exp(-t/tp) for a contact that starts closed.
# After ``decay`` pulse times (45 by default: exp(-45) ~ 3e-20) the relative motion
# is gone to round-off and the bodies move as one (a perfectly inelastic, sticking
# impact).  For a bouncing impact, use a spring alone and stop when the force
# changes sign instead.
#
# A finite pulse lets the bodies move during the impact; the result differs from
# the impulsive limit by a power of tp (tp^2 when the leading effect is the
# turning of the bodies during an impact symmetric in time).  ``richardson``
# evaluates a pulse-dependent result at two pulse lengths, extrapolates to tp -> 0,
# and returns the size of the correction as the estimate of what is left.

__all__ = ["delassus", "critical_contact", "pulse_end", "richardson"]

DECAY = 45.0


def delassus(Minv: np.ndarray, G: np.ndarray, point_mass: float | None = None) -> np.ndarray:
    """The contact's inverse effective mass W = G Minv G^T (+ 1/m I for a point mass on the other side)."""
    G = np.atleast_2d(np.asarray(G, dtype=float))
    W = G @ np.asarray(Minv, dtype=float) @ G.T
    if point_mass is not None:
        W = W + np.eye(W.shape[0]) / point_mass
    return 0.5 * (W + W.T)


def critical_contact(W: np.ndarray, tp: float) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness and damping matrices (K, C) that make the contact critically damped with time tp."""
    Winv = np.linalg.inv(np.atleast_2d(W))
    Winv = 0.5 * (Winv + Winv.T)
    return Winv / tp**2, 2.0 * Winv / tp


def pulse_end(tp: float, decay: float = DECAY) -> float:
    """The time by which a critically damped contact pulse of time tp has died out to round-off."""
    return decay * tp


def richardson(
    fn: Callable[[float], Mapping[str, float]],
    tp: float,
    *,
    ratio: float = 2.0,
    order: float = 2.0,
) -> tuple[dict, dict, dict]:
    """Evaluate ``fn`` at tp and tp/ratio; extrapolate each value to tp -> 0 assuming an error ~ tp^order.

    Returns ``(extrapolated, correction, fine)``: the extrapolated values, the absolute size of the
    correction made (an estimate of the finite-pulse error of the fine value and an upper estimate
    of what remains in the extrapolated one) and the values at the shorter pulse.
    """
    coarse = dict(fn(tp))
    fine = dict(fn(tp / ratio))
    factor = ratio**order - 1.0
    extrapolated, correction = {}, {}
    for key, f in fine.items():
        delta = (f - coarse[key]) / factor
        extrapolated[key] = f + delta
        correction[key] = abs(delta)
    return extrapolated, correction, fine


exercise = Exercise(
    "4.7",
    formulas=[
        "J = m m' v₀ / (m + 4m')   (impulse on the rod)",
        "v_hit = 4m' v₀/(m + 4m'),  v_end = -2m' v₀/(m + 4m'),  ω = 3m' v₀/(l (m + 4m'))",
        "E_loss = (m' v₀²/2) m/(m + 4m')",
    ],
    # the collision itself (the longer of the two pulses): displacements from the pre-impact positions,
    # rod along +y centred at the origin, bullet at its end (0, l) moving along +x
    states=[("rod_dx", "m"), ("rod_dy", "m"), ("rod_theta", "rad"), ("bullet_dx", "m"), ("bullet_dy", "m"),
            ("rod_vx", "m/s"), ("rod_vy", "m/s"), ("rod_omega", "rad/s"), ("bullet_vx", "m/s"),
            ("bullet_vy", "m/s"), ("E_dissipated", "J")],
)


@exercise.analytic
def analytic(p):
    den = p.m + 4.0 * p.m_b
    return {
        "v_end": -2.0 * p.m_b * p.v0 / den,
        "v_hit": 4.0 * p.m_b * p.v0 / den,
        "omega": 3.0 * p.m_b * p.v0 / (p.l * den),
        "E_loss": 0.5 * p.m_b * p.v0**2 * p.m / den,
    }


# pulse time in units of l/v0: the rod turns by ~omega tp ~ 1e-4 rad during it
PULSE = 1e-4


def _rod_nodes(n=4):
    """Mass fractions and positions (along the rod axis, in units of l) of a Gauss rule on [-1, 1]."""
    s, w = gauss_legendre(n, -1.0, 1.0)
    return s, w / w.sum()


def _contact(mu, tp):
    """The rod's moment from its mass distribution and the critically damped contact of time tp (scaled
    units m = l = v0 = 1; before the impact the rod lies along +y, centred at the origin, the bullet at its
    end (0, 1)); and ``parts(y)``: the bullet's displacement and velocity relative to the rod's end, the
    force on the bullet and its arm from the rod's center."""
    s, w = _rod_nodes()
    I_rod = float(w @ s**2)  # moment about the center, from the mass distribution
    G = np.array([[1.0, 0.0, -1.0], [0.0, 1.0, 0.0]])  # d(end point)/d(X, Y, theta) at theta = 0
    W = delassus(np.diag([1.0, 1.0, 1.0 / I_rod]), G, point_mass=mu)
    K, C = critical_contact(W, tp)

    K00, K01, K11 = K[0, 0], K[0, 1], K[1, 1]
    C00, C01, C11 = C[0, 0], C[0, 1], C[1, 1]

    def parts(y):
        th, om = y[2], y[7]
        # end point minus its start, without cancellation: l (e(th) - e(0)), e = (-sin, cos)
        half = math.sin(0.5 * th)
        dx = y[3] - y[0] + math.sin(th)
        dy = y[4] - y[1] + 2.0 * half * half
        ux = y[8] - y[5] + om * math.cos(th)
        uy = y[9] - y[6] + om * math.sin(th)
        Fx = -(K00 * dx + K01 * dy) - (C00 * ux + C01 * uy)
        Fy = -(K01 * dx + K11 * dy) - (C01 * ux + C11 * uy)
        ax = y[3] - y[0]  # from the rod's center to the bullet
        ay = 1.0 + y[4] - y[1]
        return dx, dy, ux, uy, Fx, Fy, ax, ay

    return I_rod, K, C, parts


def _pulse(mu, tp, t_scale=1.0, y_scale=None):
    """The collision as one pulse of time tp, in scaled units (m = l = v0 = 1), until the relative motion
    has died out.  State: rod center displacement (2), angle (1), bullet displacement (2), rod velocity (2),
    angular velocity (1), bullet velocity (2), dissipated energy (1)."""
    from mech.problems.motion import Motion

    I_rod, _, C, parts = _contact(mu, tp)
    C00, C01, C11 = C[0, 0], C[0, 1], C[1, 1]

    def rhs(t, y):
        dx, dy, ux, uy, Fx, Fy, ax, ay = parts(y)
        # the reaction -F acts on the rod at the bullet's point
        return np.array([
            y[5], y[6], y[7], y[8], y[9],
            -Fx, -Fy, -(ax * Fy - ay * Fx) / I_rod, Fx / mu, Fy / mu,
            ux * (C00 * ux + C01 * uy) + uy * (C01 * ux + C11 * uy),
        ])

    y0 = np.zeros(11)
    y0[8] = 1.0
    rod_v = mu / (1.0 + mu)  # scale of the rod's velocities (J/m <= this)
    size = np.array([rod_v * tp] * 3 + [tp, tp] + [rod_v] * 3 + [1.0, 1.0] + [0.5 * mu])
    return Motion(rhs, y0, (0.0, pulse_end(tp)), t_scale=t_scale, y_scale=y_scale,
                  options={"method": "DOP853"}, y_size=size)


@exercise.motion
def motion(p):
    """The collision itself, the longer of the two pulses (PULSE l/v0), in SI."""
    l, v0 = p.l, p.v0
    return _pulse(p.m_b / p.m, PULSE, t_scale=l / v0,
                  y_scale=[l, l, 1.0, l, l, v0, v0, v0 / l, v0, v0, p.m * v0**2])


def _readings(mu, tp, y, rtol):
    """The velocities after a pulse of time tp (scaled) from its end state ``y``; the drifts of the
    invariants (exact in the model: the momentum and the angular momentum about the origin) and the
    mismatch of the energy books."""
    I_rod, K, _, parts = _contact(mu, tp)
    b0 = np.array([0.0, 1.0])
    dx, dy, ux, uy, *_ = parts(y)
    d, dd = np.array([dx, dy]), np.array([ux, uy])

    # invariants (exact in the model): momentum, angular momentum about the origin, energy balance
    P = y[5:7] + mu * y[8:10]
    rod_c = y[0:2]
    b = b0 + y[3:5]
    Lz = (rod_c[0] * y[6] - rod_c[1] * y[5]) + I_rod * y[7] + mu * (b[0] * y[9] - b[1] * y[8])
    T_now = 0.5 * (y[5:7] @ y[5:7]) + 0.5 * I_rod * y[7] ** 2 + 0.5 * mu * (y[8:10] @ y[8:10])
    U_now = 0.5 * d @ K @ d
    E0 = 0.5 * mu
    drifts = {
        "momentum": max(abs(P[0] - mu), abs(P[1])) / mu,
        "angular momentum": abs(Lz - (-mu)) / mu,  # b0 x (mu v0 x) = -mu about the origin
    }
    # Not an invariant of this model: the reaction acts at the bullet's point (which keeps the
    # angular momentum exact) while the damper works on the end point's velocity, so the
    # energy books differ by ~ |F . (omega x d)| ~ (omega tp)^2 relative; shown, not monitored.
    energy_mismatch = abs(T_now + U_now + y[10] - E0) / E0
    om = y[7]
    # after the pulse only the quasi-static stretch of the co-rotating contact remains:
    # |d| ~ omega^2 tp^2 (in units of l) and |d'| ~ omega^3 tp^2; a transient left over is a failure
    floor = 10.0 * rtol * 1e-3
    if (np.linalg.norm(d) > 10.0 * om**2 * tp**2 + floor * tp
            or np.linalg.norm(dd) > 10.0 * abs(om) ** 3 * tp**2 + floor):
        raise NumericFailure(
            f"the relative motion has not died out by the end of the pulse (|d| = {np.linalg.norm(d):.3g} l, "
            f"|d'| = {np.linalg.norm(dd):.3g} v0)"
        )

    # rigid motion after the impact, evaluated in the pre-impact geometry
    V_cm = P / (1.0 + mu)
    X_cm0 = mu * b0 / (1.0 + mu)

    def vel(point):
        r = point - X_cm0
        return V_cm + om * np.array([-r[1], r[0]])

    readings = {
        "v_end": vel(np.array([0.0, -1.0]))[0],
        "v_hit": vel(b0)[0],
        "omega": abs(om),
        "E_loss": y[10] + U_now,  # dissipated plus what the contact still holds
    }
    return readings, drifts, energy_mismatch


@exercise.numeric
def numeric(p, run):
    mu = p.m_b / p.m

    def at(tp):
        # the longer pulse is the scene's motion; the shorter one only feeds the extrapolation
        end = run.follow(motion(p)) if tp == PULSE else run.follow(_pulse(mu, tp), mark=False)
        readings, drifts, mismatch = _readings(mu, tp, end.y_end, run.rtol)
        run.info.setdefault("energy_books_mismatch_rel", []).append(float(mismatch))
        for k, v in drifts.items():
            run.invariant(k, v)
        return readings

    values, correction, fine = richardson(at, PULSE)
    units = {"v_end": p.v0, "v_hit": p.v0, "omega": p.v0 / p.l, "E_loss": p.m * p.v0**2}
    run.info["pulse_time_s"] = PULSE * p.l / p.v0
    run.info["finite_pulse_effect_rel"] = {k: float(correction[k] / abs(values[k])) for k in values}
    for k in values:
        # the integrator's accuracy, plus the finite-pulse effect (the Richardson correction
        # made, an upper estimate of what is left after it) with a margin of 10
        run.claim(k, rel=float(exercise.tol_factor * run.rtol + 10.0 * correction[k] / abs(values[k])))
    return {k: float(values[k] * units[k]) for k in values}

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
finite-pulse effect, which enters the accuracy claim.  The route runs over
arrays of variants (``numeric``: every variant's collision integrated together;
a one-point solve is the batch of one).
"""

from __future__ import annotations

import math
from typing import Callable, Mapping

import numpy as np

from mech.problems.spec import Exercise
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
    if point_mass is not None:  # a number, or one per variant (a stack of N matrices)
        W = W + np.eye(W.shape[0]) / np.asarray(point_mass, dtype=float)[..., None, None]
    return 0.5 * (W + np.swapaxes(W, -1, -2))


def critical_contact(W: np.ndarray, tp: float) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness and damping matrices (K, C) that make the contact critically damped with time tp (W: one
    matrix or a stack of them)."""
    Winv = np.linalg.inv(np.atleast_2d(W))
    Winv = 0.5 * (Winv + np.swapaxes(Winv, -1, -2))
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
def analytic(P):
    """Over arrays of variants."""
    from mech.solvers.numerics.batch import Column

    m, l, mb, v0 = (np.asarray(P[k], dtype=float) for k in ("m", "l", "m_b", "v0"))
    den = m + 4.0 * mb
    return {
        "v_end": Column(-2.0 * mb * v0 / den),
        "v_hit": Column(4.0 * mb * v0 / den),
        "omega": Column(3.0 * mb * v0 / (l * den)),
        "E_loss": Column(0.5 * mb * v0**2 * m / den),
    }


# pulse time in units of l/v0: the rod turns by ~omega tp ~ 1e-4 rad during it
PULSE = 1e-4


def _rod_nodes(n=4):
    """Mass fractions and positions (along the rod axis, in units of l) of a Gauss rule on [-1, 1]."""
    s, w = gauss_legendre(n, -1.0, 1.0)
    return s, w / w.sum()


def _entries(A):
    """The entries (00, 01, 11) of a symmetric 2 x 2 matrix or of a stack of them."""
    return A[..., 0, 0], A[..., 0, 1], A[..., 1, 1]


def _contact(mu, tp):
    """The rod's moment from its mass distribution and the critically damped contact of time tp (scaled
    units m = l = v0 = 1; before the impact the rod lies along +y, centred at the origin, the bullet at its
    end (0, 1)); ``mu``: the bullet's mass, a number or one per variant.  Returns (I_rod, K, C, parts): K and
    C 2 x 2 matrices, or stacks of N; ``parts(y)``, for a state (11,) or (11, N): the
    bullet's displacement and velocity relative to the rod's end, the force on the bullet and its arm from
    the rod's center."""
    s, w = _rod_nodes()
    I_rod = float(w @ s**2)  # moment about the center, from the mass distribution
    G = np.array([[1.0, 0.0, -1.0], [0.0, 1.0, 0.0]])  # d(end point)/d(X, Y, theta) at theta = 0
    W = delassus(np.diag([1.0, 1.0, 1.0 / I_rod]), G, point_mass=mu)
    K, C = critical_contact(W, tp)
    (K00, K01, K11), (C00, C01, C11) = _entries(K), _entries(C)

    def parts(y):
        th, om = y[2], y[7]
        # end point minus its start, without cancellation: l (e(th) - e(0)), e = (-sin, cos)
        half = np.sin(0.5 * th)
        sin, cos = np.sin(th), np.cos(th)
        dx = y[3] - y[0] + sin
        dy = y[4] - y[1] + 2.0 * half * half
        ux = y[8] - y[5] + om * cos
        uy = y[9] - y[6] + om * sin
        Fx = -(K00 * dx + K01 * dy) - (C00 * ux + C01 * uy)
        Fy = -(K01 * dx + K11 * dy) - (C01 * ux + C11 * uy)
        ax = y[3] - y[0]  # from the rod's center to the bullet
        ay = 1.0 + y[4] - y[1]
        return dx, dy, ux, uy, Fx, Fy, ax, ay

    return I_rod, K, C, parts


def _pulse_rhs(mu, tp):
    """The collision's right-hand side, in scaled units (m = l = v0 = 1), for one variant (``mu`` a number,
    state (11,)) or N (``mu`` an array of N, state (11, N)).  State: rod center displacement (2), angle (1),
    bullet displacement (2), rod velocity (2), angular velocity (1), bullet velocity (2), dissipated energy
    (1)."""
    I_rod, _, C, parts = _contact(mu, tp)
    C00, C01, C11 = _entries(C)

    def rhs(t, y):
        dx, dy, ux, uy, Fx, Fy, ax, ay = parts(y)
        # the reaction -F acts on the rod at the bullet's point
        return np.array([
            y[5], y[6], y[7], y[8], y[9],
            -Fx, -Fy, -(ax * Fy - ay * Fx) / I_rod, Fx / mu, Fy / mu,
            ux * (C00 * ux + C01 * uy) + uy * (C01 * ux + C11 * uy),
        ])

    return rhs


def _start(mu, tp):
    """The state before the impact and the size of each variable (the absolute tolerances), for mu a number
    or an array of N: (11,) or (11, N)."""
    mu = np.asarray(mu, dtype=float)
    one = np.ones_like(mu)
    y0 = np.zeros((11,) + mu.shape)
    y0[8] = 1.0
    rod_v = mu / (1.0 + mu)  # scale of the rod's velocities (J/m <= this)
    size = np.stack([rod_v * tp] * 3 + [tp * one] * 2 + [rod_v] * 3 + [one] * 2 + [0.5 * mu])
    return y0, size


@exercise.motion
def motion(p):
    """The collision itself, the longer of the two pulses (PULSE l/v0), in SI."""
    from mech.problems.motion import Motion

    l, v0, mu = p.l, p.v0, p.m_b / p.m
    y0, size = _start(mu, PULSE)
    return Motion(_pulse_rhs(mu, PULSE), y0, (0.0, pulse_end(PULSE)), t_scale=l / v0,
                  y_scale=[l, l, 1.0, l, l, v0, v0, v0 / l, v0, v0, p.m * v0**2],
                  options={"method": "DOP853"}, y_size=size)


def _pulse(mu, tp, rtol, integrator):
    """The N collisions of pulse time tp integrated together until the relative motion has died out: the end
    states (11, N) and the integrations (``floquet.integrate_ensemble``)."""
    from mech.solvers.mechanics.floquet import integrate_ensemble

    y0, size = _start(mu, tp)
    return integrate_ensemble(lambda sel: _pulse_rhs(mu[sel], tp), (0.0, pulse_end(tp)), y0, rtol=rtol,
                              atol=1e-3 * rtol * size, integrator=integrator)


def _readings(mu, tp, y, rtol):
    """The velocities after a pulse of time tp (scaled) from its end states ``y`` (11, N); the drifts of the
    invariants (exact in the model: the momentum and the angular momentum about the origin), the mismatch of
    the energy books and the variants whose relative motion has not died out (their reasons)."""
    I_rod, K, _, parts = _contact(mu, tp)
    K00, K01, K11 = _entries(K)
    dx, dy, ux, uy, *_ = parts(y)

    # invariants (exact in the model): momentum, angular momentum about the origin, energy balance
    Px, Py = y[5] + mu * y[8], y[6] + mu * y[9]
    bx, by = y[3], 1.0 + y[4]  # the bullet, from (0, 1) before the impact
    Lz = (y[0] * y[6] - y[1] * y[5]) + I_rod * y[7] + mu * (bx * y[9] - by * y[8])
    T_now = 0.5 * (y[5] ** 2 + y[6] ** 2) + 0.5 * I_rod * y[7] ** 2 + 0.5 * mu * (y[8] ** 2 + y[9] ** 2)
    U_now = 0.5 * (K00 * dx * dx + 2.0 * K01 * dx * dy + K11 * dy * dy)
    E0 = 0.5 * mu
    drifts = {
        "momentum": np.maximum(np.abs(Px - mu), np.abs(Py)) / mu,
        "angular momentum": np.abs(Lz - (-mu)) / mu,  # b0 x (mu v0 x) = -mu about the origin
    }
    # Not an invariant of this model: the reaction acts at the bullet's point (which keeps the
    # angular momentum exact) while the damper works on the end point's velocity, so the
    # energy books differ by ~ |F . (omega x d)| ~ (omega tp)^2 relative; shown, not monitored.
    energy_mismatch = np.abs(T_now + U_now + y[10] - E0) / E0
    om = y[7]
    # after the pulse only the quasi-static stretch of the co-rotating contact remains:
    # |d| ~ omega^2 tp^2 (in units of l) and |d'| ~ omega^3 tp^2; a transient left over is a failure
    floor = 10.0 * rtol * 1e-3
    d, dd = np.hypot(dx, dy), np.hypot(ux, uy)
    left = ~((d <= 10.0 * om**2 * tp**2 + floor * tp) & (dd <= 10.0 * np.abs(om) ** 3 * tp**2 + floor))
    failed = [(k, f"the relative motion has not died out by the end of the pulse (|d| = {d[k]:.3g} l, "
                  f"|d'| = {dd[k]:.3g} v0)") for k in np.flatnonzero(left)]

    # rigid motion after the impact, evaluated in the pre-impact geometry: the x velocity of a point at
    # height y_pt is V_cm - omega (y_pt - Y_cm0)
    V_cm = Px / (1.0 + mu)
    Y_cm0 = mu / (1.0 + mu)
    readings = {
        "v_end": V_cm - om * (-1.0 - Y_cm0),
        "v_hit": V_cm - om * (1.0 - Y_cm0),
        "omega": np.abs(om),
        "E_loss": y[10] + U_now,  # dissipated plus what the contact still holds
    }
    return readings, drifts, energy_mismatch, failed


@exercise.batched(("v_end", "v_hit", "omega", "E_loss"))
def numeric(P, rtol, outputs, tally=None):
    """The route at N variants at once (a one-point solve is the batch of one): each pulse's N collisions
    integrated together, then the Richardson extrapolation variant by variant."""
    from mech.problems.spec import Tally
    from mech.solvers.numerics.batch import Column

    tally = Tally() if tally is None else tally
    m, l, mb, v0 = (np.asarray(P[k], dtype=float) for k in ("m", "l", "m_b", "v0"))
    mu = mb / m
    N = mu.size
    failed, mismatch = [], np.zeros(N)

    def at(tp):
        y_end, results = _pulse(mu, tp, rtol, tally.integrator)
        for r in results:
            tally.record(r)
        readings, drifts, books, bad = _readings(mu, tp, y_end, rtol)
        np.maximum(mismatch, books, out=mismatch)
        failed.extend(bad)
        for k, v in drifts.items():
            tally.invariant(k, v)
        return readings

    values, correction, _ = richardson(at, PULSE)
    units = {"v_end": v0, "v_hit": v0, "omega": v0 / l, "E_loss": m * v0**2}
    tally.info["pulse_time_s"] = PULSE * l / v0
    tally.info["energy_books_mismatch_rel"] = mismatch
    fails = []
    for k, why in failed:
        mask = np.zeros(N, dtype=bool)
        mask[k] = True
        fails.append((mask, why))
    out = {}
    for k in outputs:
        effect = correction[k] / np.abs(values[k])
        tally.info[f"finite_pulse_effect_rel {k}"] = effect
        # the integrator's accuracy, plus the finite-pulse effect (the Richardson correction
        # made, an upper estimate of what is left after it) with a margin of 10
        out[k] = Column(values[k] * units[k], rel=exercise.tol_factor * rtol + 10.0 * effect, failed=fails)
    return out

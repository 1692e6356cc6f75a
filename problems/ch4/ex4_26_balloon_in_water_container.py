"""4.26 Balloon in a water-filled spherical container pushed by a force.

Analytic.  For a container moving at U and a concentric balloon at V (both along
z) the flow potential is (A r + B/r^2) cos(theta) with A - 2B/b^3 = U and
A - 2B/a^3 = V.  At the first instant everything is at rest, so the pressure is
p = -rho dphi/dt, the same dipole with the accelerations in place of U and V.
Zero net force on the massless balloon, i.e. dphi/dt = 0 on r = a, gives
a_balloon/a_container = 3 b^3/(b^3 + 2 a^3), so relative to the container
    ratio = a_rel/a_container = 2 (b^3 - a^3)/(b^3 + 2 a^3)   (forward: toward F),
and the force of the water on the wall makes the container's equation
(Mc + m_eff) a_container = F with m_eff = (4 pi/3) rho b^3 (b^3 - a^3)/(b^3 + 2 a^3).
Limits: a -> 0 gives ratio 2 (the bubble accelerates 3 times as fast as the water)
and m_eff -> the water's mass; a -> b gives 0 and 0.

Numeric (catalogue route, in the Lagrange coordinates themselves).  Container
position X and balloon position xi relative to it; the flow is the sum of two unit
modes.  X' = 1 alone is a rigid translation of everything: f = r satisfies the
dipole equation and both boundary conditions.  xi' = 1 alone (container at rest)
solves f'' + 2f'/r - 2f/r^2 = 0 (in s = ln r: g'' + g' - 2g = 0, integrated with
w = g' + 2g, w' = w, as an extra variable) with f'(b) = 0,
f'(a) = 1: it is shot with DOP853 inward from the wall (where its condition is
homogeneous; inward the dominant 1/r^2 grows, no cancellation) and scaled.  The
water's kinetic-energy form (rho/2)(4 pi/3) int (f'^2 + 2 f^2/r^2) r^2 dr is
integrated for the (X, X), (X, xi) and (xi, xi) entries directly (positive
integrands: no differencing of total energies, and a thin water layer or a tiny
balloon loses nothing); Lagrange's equations at rest with F on X give the
accelerations.  Check: the
pressure route (zero force on the balloon, F plus the wall's pressure force on the
container) from the shot boundary values must agree, else NumericFailure.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure

EPS = 2.220446049250313e-16

exercise = Exercise(
    "4.26",
    formulas=[
        "a_rel / a_container = 2 (b³ - a³)/(b³ + 2a³)  (> 0: the balloon moves forward, toward F)",
        "a_container = F / (M_c + (4π/3) ρ b³ (b³ - a³)/(b³ + 2a³))",
        "(balloon: a_balloon = 3b³/(b³ + 2a³) a_container; a → 0: 3 a_container)",
    ],
)


exercise.declare_limits(
    "a < b: the balloon fits in the container",
    "a >= 1e-40 b",
)


@exercise.constraint
def constraint(p):
    if p.a >= p.b:
        return f"the balloon's radius a = {p.a:g} m must be below the container's b = {p.b:g} m"
    if p.a < 1e-40 * p.b:
        # the shot's dipole mode grows by (b/a)^3 across the water; beyond 1e120 its step control
        # breaks down (DOP853 fails at a/b = 1e-46), and the answer is the a -> 0 limit to (a/b)^3
        return (f"a/b = {p.a / p.b:.3g} is below 1e-40: a balloon that small is a point "
                "(every result is its a -> 0 limit to within (a/b)^3 < 1e-120)")


def _mass_unit(rho, b):
    """(4 pi/3) rho b^3 with the powers of two apart: it underflows or overflows only where the result does."""
    mr, er = math.frexp(rho)
    mb, eb = math.frexp(b)
    mant = 4.0 * math.pi / 3.0 * mr * mb**3
    try:
        return math.ldexp(mant, er + 3 * eb)
    except OverflowError:
        return math.inf


def _cube_diff(b, a):
    """b^3 - a^3 without cancellation when a is close to b."""
    return (b - a) * (b * b + a * b + a * a)


@exercise.analytic
def analytic(p):
    # in units of b: b^3 (b^3 - a^3) in one piece overflows where m_eff does not (b ~ 1e76 in the natural
    # units of Mc = 5e-324 kg gave a_container = 0)
    x = p.a / p.b
    x3 = x**3
    ratio = 2.0 * _cube_diff(1.0, x) / (1.0 + 2.0 * x3)
    m_eff = _mass_unit(p.rho, p.b) * (0.5 * ratio)  # (4 pi/3) rho b^3 (b^3 - a^3)/(b^3 + 2 a^3)
    acc = p.F / (p.Mc + m_eff)
    return {"a_rel": ratio * acc, "a_container": acc, "ratio": ratio}


def _rhs(s, y):
    """V mode of g'' + g' - 2g = 0 (s = ln r, r in units of b), carried as (g, g', w) with
    w = g' + 2g.  The operator factors, w' = w: the part that grows outward (~ r) is a
    variable of its own, never the small difference of the 1/r^2 part's g' and 2g (tiny
    balloon); g' is kept as its own variable too, never w - 2g (thin layer, where both are
    ~ 2 and g' ~ the layer's width).  Also three energy integrals, with the rigid mode g_R = r
    (f = r: a rigid translation, f'(a) = f'(b) = 1):
    Q_VV = int (g'^2 + 2 g^2) r ds, Q_RV = int (r g' + 2 r g) r ds = int w r^2 ds, Q_RR = int 3 r^3 ds."""
    g, gp, w = y[0], y[1], y[2]
    x = math.exp(s)
    return np.array([gp, 2.0 * g - gp, w, (gp * gp + 2.0 * g * g) * x, w * x * x, 3.0 * x**3])


def _mode(p):
    """The relative-motion mode (container at rest, balloon moving) as an integration: f'(b) = 0, so it is
    shot inward from the wall (s = 0) to the balloon (s = ln(a/b)) with g = 1, g' = 0 (inward the dominant
    solution 1/r^2 grows: no cancellation), with its three energy integrals.  Not a motion in time (the
    variable is the radius): no states, followed as a tool."""
    from mech.problems.motion import Motion

    # lengths in units of b: the balloon at x = a/b, the wall at 1; s = ln x; s_a < 0, for a thin layer from
    # a - b (exact), so the layer keeps its width
    x_a = p.a / p.b
    s_a = math.log1p((p.a - p.b) / p.b) if x_a > 0.5 else math.log(x_a)
    # every state grows monotonically in magnitude from its start; absolute tolerances below those sizes
    short = min(-s_a, 1.0)
    return Motion(_rhs, [1.0, 0.0, 2.0, 0.0, 0.0, 0.0], (0.0, s_a),
                  y_size=[1.0, 1e-3 * short, x_a, 1e-3 * short * x_a, 1e-3 * short * x_a**3, 1e-3 * short * x_a**3])


@exercise.numeric
def numeric(p, run):
    x_a = p.a / p.b
    m = _mode(p)
    span = -m.span[1]
    tv = run.follow(m, mark=False)
    gv_a, gvp_a = tv.y_end[0], tv.y_end[1]
    Qvv, Qrv, Qrr = -tv.y_end[3], -tv.y_end[4], -tv.y_end[5]  # integrated inward: negated
    if not (gvp_a < 0.0 and Qvv > 0.0 and Qrr > 0.0):
        raise NumericFailure("the shot mode does not have the expected signs")

    # unit relative velocity at the balloon: f = c b g with f'(r) = c g'(s)/x, f'(a) = 1
    cv = x_a / gvp_a
    unit = _mass_unit(p.rho, p.b)  # mass unit of the bilinear energy form, (4 pi/3) rho b^3
    # the water's entries of the mass matrix in that unit: rigid (Qrr), coupling (cv Qrv), relative (cv^2 Qvv)

    # Lagrange: X (container, the rigid mode), xi (balloon relative to it, the V mode):
    # [[Mc + unit Qrr, unit cv Qrv], [unit cv Qrv, unit cv^2 Qvv]] (X'', xi'') = (F, 0), eliminated by hand
    # so that the water's entries are never formed in kg: (4 pi/3) rho b^3 underflows at rho = 1e-197,
    # b = 1e-201 (a singular matrix) while Mc = 1e-200 kg carries the container alone
    ratio = -Qrv / (cv * Qvv)  # xi''/X''
    acc_X = p.F / (p.Mc + unit * (Qrr + ratio * cv * Qrv))
    acc_xi = ratio * acc_X

    # pressure route from the boundary values, p = -rho (A_c f_R + A_rel f_V) cos(theta):
    # zero force on the massless balloon, and F plus the wall's pressure force on the container
    fr_a, fv_a, fv_b = x_a * p.b, cv * gv_a * p.b, cv * 1.0 * p.b
    ratio_p = -fr_a / fv_a
    acc_p = p.F / (p.Mc + unit * (1.0 + ratio_p * fv_b / p.b))
    diff = max(abs(ratio_p - ratio) / abs(ratio), abs(acc_p - acc_X) / abs(acc_X))
    run.info["pressure_route_rel_diff"] = diff
    run.info["s_span"] = span
    # the wall-pressure form subtracts O(1) terms whose difference is ~ (b - a)/b for a thin layer
    if diff > 1e3 * run.rtol + 1e2 * EPS / min(1.0, 1.0 - x_a):
        raise NumericFailure(f"energy (Lagrange) and pressure routes differ by {diff:.2g}")
    # the rigid mode's energy is the water's kinetic energy in rigid motion: its mass
    water = _cube_diff(1.0, x_a)  # in the unit (4 pi/3) rho b^3
    run.invariant("rigid_mode_water_mass", (Qrr - water) / water)
    return {"a_rel": acc_xi, "a_container": acc_X, "ratio": ratio}

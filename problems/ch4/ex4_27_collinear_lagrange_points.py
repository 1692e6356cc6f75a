"""4.27 Collinear Lagrange points L1, L2, L3.

Analytic.  In units of d with mu = M2/(M1+M2), the force balance on the line,
cleared of denominators, is a quintic for each point:
  L1 (s = r_L1/d):  s^5 - (3-mu) s^4 + (3-2mu) s^3 - mu s^2 + 2mu s - mu = 0,
  L2 (s = r_L2/d):  s^5 + (3-mu) s^4 + (3-2mu) s^3 - mu s^2 - 2mu s - mu = 0,
  L3 (e = r_L3/d - 1):
      e^5 + (7+mu) e^4 + (19+6mu) e^3 + (24+13mu) e^2 + (12+14mu) e + 7mu = 0,
each with exactly one root in its interval (s in (0, 1); s > 0; e in (-1, 0)).
For mu << 1: r_L1 ~ r_L2 ~ d (mu/3)^(1/3) (the Hill radius, 3 s^3 = mu) and
dr_L3 ~ -(7/12) mu d (12 e = -7 mu).  The roots are computed from these
leading-order starts by Newton's method on the quintic, safeguarded by
bisection on its sign-change interval.

Numeric.  The force per unit mass along the line, -dU_ef/dx (gravity of both
bodies plus the centrifugal force), with each unknown measured from its nearest
body and the O(1) terms combined by hand so that no large numbers cancel; each
root is bracketed by walking from the middle of its interval toward the body
(halving the distance) and toward infinity (doubling) until the force changes
sign, then found by brentq to the last bits; d^2U_ef/dx^2 < 0 is checked.
"""

from __future__ import annotations

import math

from mech.problems import ranges
from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.frames import mass_fractions
from mech.solvers.numerics.roots import bracketed_root, brentq, walk_to_sign_change

exercise = Exercise(
    "4.27",
    formulas=[
        "L1: s⁵ - (3-μ)s⁴ + (3-2μ)s³ - μs² + 2μs - μ = 0, r_L1 = s d, μ = M2/(M1+M2)",
        "L2: s⁵ + (3-μ)s⁴ + (3-2μ)s³ - μs² - 2μs - μ = 0, r_L2 = s d",
        "L3: e⁵ + (7+μ)e⁴ + (19+6μ)e³ + (24+13μ)e² + (12+14μ)e + 7μ = 0, r_L3 = (1+e) d",
        "μ ≪ 1: r_L1 ≈ r_L2 ≈ d (μ/3)^(1/3) = d (M2/3M1)^(1/3); dr_L3 ≈ -(7/12) μ d",
    ],
)


exercise.declare_limits(
    "M2 <= M1: L3 lies beyond the heavier body M1",
)


@exercise.constraint
def constraint(p):
    if p.M2 > p.M1:
        return f"M2 = {p.M2:g} kg must not exceed M1 = {p.M1:g} kg (L3 lies beyond the heavier body M1)"


ranges.declare(exercise, ranges.Scale("M2/(M1 + M2)", {"M2": 1, "M1": -1}, "the mass fraction", low=-290.0,
                                      high=math.inf, log_factor=lambda p: -math.log10(1.0 + p.M2 / p.M1)))


def _horner(coeffs, x):
    v, dv = 0.0, 0.0
    for c in coeffs:
        dv = dv * x + v
        v = v * x + c
    return v, dv


def _quintic_root(coeffs, lo, hi):
    """The root of the polynomial in [lo, hi] (a sign change there), by the shared Brent root finder to a
    few ulp of the root (its relative tolerance; the roots reach 1e-6 and below for small mass ratios)."""
    return brentq(lambda x: _horner(coeffs, x)[0], lo, hi, xtol=1e-300, rtol=4 * 2.0**-52, maxiter=400)


@exercise.analytic
def analytic(p):
    nu, mu = mass_fractions(p.M1, p.M2)
    c1 = [1.0, -(3.0 - mu), 3.0 - 2.0 * mu, -mu, 2.0 * mu, -mu]
    c2 = [1.0, 3.0 - mu, 3.0 - 2.0 * mu, -mu, -2.0 * mu, -mu]
    c3 = [1.0, 7.0 + mu, 19.0 + 6.0 * mu, 24.0 + 13.0 * mu, 12.0 + 14.0 * mu, 7.0 * mu]
    s1 = _quintic_root(c1, 0.0, 1.0)
    s2 = _quintic_root(c2, 0.0, 2.0)
    e3 = _quintic_root(c3, -1.0, 0.0)
    return {"r_L1": s1 * p.d, "r_L2": s2 * p.d, "r_L3": (1.0 + e3) * p.d, "dr_L3": e3 * p.d}


@exercise.numeric
def numeric(p, run):
    nu, mu = mass_fractions(p.M1, p.M2)  # M1 at x = -mu, M2 at x = nu (units of d)

    # Force per unit mass along +x, F = -dU/dx = -nu (x+mu)/|x+mu|^3 - mu (x-nu)/|x-nu|^3 + x.
    def f_L1(s):  # x = nu - s: F = mu/s^2 - nu/(1-s)^2 + nu - s, with nu/(1-s)^2 - nu written out
        return mu / (s * s) - nu * s * (2.0 - s) / (1.0 - s) ** 2 - s

    def f_L2(s):  # x = nu + s: F = -nu/(1+s)^2 - mu/s^2 + nu + s
        return nu * s * (2.0 + s) / (1.0 + s) ** 2 + s - mu / (s * s)

    def f_L3(e):  # x = -mu - (1+e): F = nu/(1+e)^2 + mu/(2+e)^2 - mu - (1+e), with 1 = nu + mu
        return -(mu + e * (3.0 + e * (3.0 + e))) / (1.0 + e) ** 2 + mu / (2.0 + e) ** 2 - mu

    def dF_dx(r1, r2):  # d^2U/dx^2 = -dF/dx; on the line dF/dx = 1 + 2 nu/r1^3 + 2 mu/r2^3
        return 1.0 + 2.0 * nu / r1**3 + 2.0 * mu / r2**3

    # L1: F -> +inf at M2 (s -> 0), -inf at M1 (s -> 1)
    lo = walk_to_sign_change(f_L1, 0.5, lambda s: 0.5 * s, +1.0)
    hi = walk_to_sign_change(f_L1, 0.5, lambda s: 1.0 - 0.5 * (1.0 - s), -1.0)
    s1 = bracketed_root(f_L1, lo, hi)
    # L2: F -> -inf at M2 (s -> 0), +inf far out
    lo = walk_to_sign_change(f_L2, 1.0, lambda s: 0.5 * s, -1.0)
    hi = walk_to_sign_change(f_L2, 1.0, lambda s: 2.0 * s, +1.0)
    s2 = bracketed_root(f_L2, lo, hi)
    # L3: F -> +inf at M1 (e -> -1), -inf far out (e -> +inf)
    lo = walk_to_sign_change(f_L3, -0.5, lambda e: -1.0 + 0.5 * (1.0 + e), +1.0)
    hi = walk_to_sign_change(f_L3, 0.0, lambda e: 2.0 * e + 1.0, -1.0)
    e3 = bracketed_root(f_L3, lo, hi)

    # distances (r1, r2) from the two bodies, in units of d
    for name, r1, r2 in (("L1", 1.0 - s1, s1), ("L2", 1.0 + s2, s2), ("L3", 1.0 + e3, 2.0 + e3)):
        if not dF_dx(r1, r2) > 0.0:
            raise NumericFailure(f"{name} at r1 = {r1:.17g} d is not a maximum of U_ef along the line")
    run.method = "brentq"
    run.info["residuals"] = [f_L1(s1), f_L2(s2), f_L3(e3)]
    for name in ("r_L1", "r_L2", "r_L3", "dr_L3"):
        run.claim(name, rel=1e-12)
    return {"r_L1": s1 * p.d, "r_L2": s2 * p.d, "r_L3": (1.0 + e3) * p.d, "dr_L3": e3 * p.d}


@exercise.scene
def scene(p, run):
    """The rotating frame's effective potential as a map with L1, L2, L3, and its cut along the line of the
    bodies, where the three points are its maxima (saddles of the plane)."""
    import numpy as np

    from mech.problems.scene import Axis, Guide, Line, Map, Markers, Note, Panel, Scene
    from mech.solvers.mechanics.frames import potential_eff

    nu, mu = mass_fractions(p.M1, p.M2)  # M1 at x = -mu, M2 at x = nu (units of d)
    a = run.analytic(p)
    nv = run.numeric(p)

    def places(v):  # the points' x / d from the distances the exercise answers
        return {"L1": nu - v["r_L1"] / p.d, "L2": nu + v["r_L2"] / p.d, "L3": -mu - v["r_L3"] / p.d}

    xa = places(a)
    g = np.linspace(-1.6, 1.6, 361)
    X, Y = np.meshgrid(g, g)
    unit = "G(M1+M2)/d"
    levels = [float(potential_eff(x, 0.0, mu, nu)) for x in xa.values()]
    plane = Panel("effective potential in the rotating frame", Axis("x / d (from the center of mass)"),
                  Axis("y / d"), equal_aspect=True, legend="outside")
    plane.add(Map(g, g, potential_eff(X, Y, mu, nu), "φ_ef", unit, clip=(min(levels) - 0.25, max(levels) + 0.05)),
              Markers([-mu], [0.0], f"M1 ({nu:.4g} of the mass)", kind="this", color="C0", size=9),
              Markers([nu], [0.0], "M2", kind="this", color="0.6", size=7),
              Markers(list(xa.values()), [0.0] * 3, "L1, L2, L3 analytic", kind="analytic"))
    for name, x in xa.items():
        plane.add(Note(name, (x, 0.0), color="w"))
    if nv:
        plane.add(Markers(list(places(nv).values()), [0.0] * 3, "numeric"))
    x = np.linspace(-1.6, 1.6, 4001)
    cut = Panel(f"on the line of the bodies, L1, L2, L3 are maxima\n(μ = {mu:.4g})", Axis("x / d"),
                Axis("φ_ef(x, 0)", unit), legend="lower center")
    cut.add(Line(x, potential_eff(x, 0 * x, mu, nu), "φ_ef(x, 0)"))
    for name, xl in xa.items():
        cut.add(Guide(xl), Note(name, (xl, max(levels) + 0.1)))
    cut.add(Markers(list(xa.values()), levels, "analytic", kind="analytic"))
    if nv:
        xn = list(places(nv).values())
        cut.add(Markers(xn, [float(potential_eff(v, 0.0, mu, nu)) for v in xn], "numeric"))
    cut.y.lim = (min(levels) - 1.5, max(levels) + 0.3)
    return Scene([plane, cut])

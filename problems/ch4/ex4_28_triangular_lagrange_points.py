"""4.28 Triangular Lagrange points L4, L5 and their linear stability.

Analytic.  With the origin at the center of mass, r = nu d1 + mu d2
(mu = M2/(M1+M2), nu = 1 - mu), and grad U_ef = G M1 (1/r1^3 - 1/d^3) d1
+ G M2 (1/r2^3 - 1/d^3) d2; off the line d1 and d2 are independent, so
r1 = r2 = d: L4 is the apex of the equilateral triangle,
x_L4 = d (1/2 - mu), y_L4 = (sqrt 3/2) d.  There the Hessian is
-3 Omega^2 [nu n1 n1^T + mu n2 n2^T] and the linearized equations
x'' - 2 Omega y' = -U_xx x - U_xy y, y'' + 2 Omega x' = -U_xy x - U_yy y give
lambda^4 + Omega^2 lambda^2 + (27/4) mu nu Omega^4 = 0.  With D = 1 - 27 mu nu:
D >= 0 (mu <= mu_c = (1 - sqrt(23/27))/2 = 0.0385): stable,
  omega_slow^2 = Omega^2 (1 - sqrt D)/2 = Omega^2 (27 mu nu/2)/(1 + sqrt D),
  omega_fast^2 = Omega^2 (1 + sqrt D)/2;
D < 0: lambda = (Omega/2) [+-(sqrt(27 mu nu) - 1)^(1/2) +- i (sqrt(27 mu nu) + 1)^(1/2)].

Numeric (scaled units d, 1/Omega): Newton's method on the cancellation-free
gradient of U_eff from (0, 1), with the exact Hessian, in polar coordinates
about body 1 (solvers/mechanics/frames.py); then the eigenvalues of the 4x4
linearized rotating-frame matrix built from that exact Hessian.  Where a stable
slow pair lies far below the fast one (small mass ratio), the slow exponent
comes from the 4x4 matrix's determinant, det H = slow^2 fast^2, with det H
taken from the polar Hessian (relative precision in its angular entries).
Each exponent gets an absolute error claim from
perturbation theory that switches to the square-root law where two exponents
merge (the defective matrix at the Routh limit).
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems import ranges
from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.frames import (
    characteristic_exponents,
    grad_eff,
    EPS,
    hess_eff,
    mass_fractions,
    newton_equilibrium,
    polar_hessian_at,
)

G = 6.67430e-11

exercise = Exercise(
    "4.28",
    formulas=[
        "x_L4 = d (1/2 - μ), y_L4 = (√3/2) d   (equilateral triangle; μ = M2/(M1+M2))",
        "λ⁴ + Ω² λ² + (27/4) μ(1-μ) Ω⁴ = 0, Ω² = G(M1+M2)/d³",
        "stable for 27 μ(1-μ) ≤ 1 (μ ≤ (1 - √(23/27))/2 ≈ 0.0385): ω_slow,fast² = Ω² (1 ∓ √(1 - 27μ(1-μ)))/2",
        "unstable: growth = (Ω/2)(√(27μ(1-μ)) - 1)^(1/2), ω_slow = ω_fast = (Ω/2)(√(27μ(1-μ)) + 1)^(1/2)",
    ],
    constants={"G": "m^3/(kg s^2)"},
)


ranges.declare(exercise, ranges.Scale(
    "min(M1, M2)/(M1 + M2)", {}, "the smaller mass fraction", low=-290.0, high=math.inf,
    log_factor=lambda p: math.log10(min(p.M1, p.M2)) - math.log10(max(p.M1, p.M2))
    - math.log10(1.0 + min(p.M1, p.M2) / max(p.M1, p.M2))))


def _omega(p):
    return math.sqrt(G * (p.M1 + p.M2) / p.d**3)


@exercise.analytic
def analytic(p):
    nu, mu = mass_fractions(p.M1, p.M2)
    W = _omega(p)
    q = 27.0 * mu * nu
    D = 1.0 - q
    if D >= 0.0:
        root = math.sqrt(D)
        growth = 0.0
        slow = W * math.sqrt(0.5 * q / (1.0 + root))
        fast = W * math.sqrt(0.5 * (1.0 + root))
    else:
        sq = math.sqrt(q)
        growth = 0.5 * W * math.sqrt(sq - 1.0)
        slow = fast = 0.5 * W * math.sqrt(sq + 1.0)
    return {
        "x_L4": p.d * (0.5 - mu),
        "y_L4": p.d * math.sqrt(3.0) / 2.0,
        "growth_rate": growth,
        "omega_slow": slow,
        "omega_fast": fast,
    }


@exercise.numeric
def numeric(p, run):
    nu, mu = mass_fractions(p.M1, p.M2)
    W = _omega(p)
    r, iters = newton_equilibrium([0.0, 1.0], mu, nu)
    if not r[1] > 0.0:
        raise NumericFailure(f"Newton's method converged to ({r[0]:.6g}, {r[1]:.6g}) d, not to the point above the line")
    rho, Hp = polar_hessian_at(r, mu, nu)
    det_polar = Hp[0, 0] * Hp[1, 1] - Hp[0, 1] * Hp[0, 1]
    if not (Hp[0, 0] < 0.0 and det_polar > 0.0):
        raise NumericFailure("the stationary point found is not a maximum of U_eff")
    H = hess_eff(r, mu, nu)
    ex = characteristic_exponents(H)
    slow, err_slow = ex.slow, ex.err_slow
    if ex.growth <= ex.err_growth and ex.slow < 1e-2 * ex.fast:
        # Stable with a slow pair far below the fast one: the 4x4 eigen-solve resolves the slow
        # exponent only to ~ eps^(1/2).  The 4x4 matrix's determinant is det H (its blocks: 0, I,
        # -H, 2J), the product of its four exponents: slow^2 fast^2 = det H = det H_polar / rho^2,
        # whose angular entries hold their relative precision; fast comes from the eigen-solve
        # to eps, so the slow pair follows to a few eps relative.
        slow = math.sqrt(det_polar) / rho / ex.fast
        err_slow = 16.0 * EPS * slow
        run.info["slow_from"] = "det H / fast^2 (polar Hessian)"
    elif ex.err_slow > 1e-3 * ex.slow:
        raise NumericFailure(
            f"the slow exponent {ex.slow:.3g} Omega is below what the 4x4 eigenvalues resolve "
            f"(+-{ex.err_slow:.2g} Omega at mass ratio {mu:.3g})"
        )
    run.method = "Newton + eigvals"
    run.info["newton_iterations"] = iters
    run.info["grad_residual"] = float(np.linalg.norm(grad_eff(r, mu, nu)))
    run.info["exponents_over_Omega"] = [f"{z.real:.6g}{z.imag:+.6g}i" for z in ex.values]
    # the position is a root to round-off; the exponents are claimed from their sensitivity
    run.claim("x_L4", rel=1e-12, abs=1e-14 * p.d)
    run.claim("y_L4", rel=1e-12)
    tol = exercise.tol_factor * run.rtol
    run.claim("growth_rate", rel=tol, abs=4.0 * ex.err_growth * W)
    run.claim("omega_slow", rel=tol, abs=4.0 * err_slow * W)
    run.claim("omega_fast", rel=tol, abs=4.0 * ex.err_fast * W)
    growth = max(ex.growth, 0.0)
    return {
        "x_L4": r[0] * p.d,
        "y_L4": r[1] * p.d,
        "growth_rate": growth * W,
        "omega_slow": slow * W,
        "omega_fast": ex.fast * W,
    }


@exercise.scene
def scene(p, run):
    """The rotating frame's effective potential as a map with L4 and L5, and its cut along x through L4:
    L4 sits on a maximum, and is stable anyway below the Routh mass ratio (the Coriolis force)."""
    from mech.problems.scene import Axis, Guide, Line, Map, Markers, Note, Panel, Scene
    from mech.solvers.mechanics.frames import potential_eff

    nu, mu = mass_fractions(p.M1, p.M2)  # M1 at x = -mu, M2 at x = nu (units of d)
    a = run.analytic(p)
    nv = run.numeric(p)
    g = np.linspace(-1.6, 1.6, 361)
    X, Y = np.meshgrid(g, g)
    unit = "G(M1+M2)/d"
    top = float(potential_eff(0.5 - mu, math.sqrt(3.0) / 2.0, mu, nu))  # the potential's highest level
    plane = Panel("effective potential in the rotating frame", Axis("x / d (from the center of mass)"),
                  Axis("y / d"), equal_aspect=True, legend="outside")
    plane.add(Map(g, g, potential_eff(X, Y, mu, nu), "φ_ef", unit, clip=(top - 0.3, top + 0.002)),
              Markers([-mu], [0.0], f"M1 ({nu:.4g} of the mass)", kind="this", color="C0", size=9),
              Markers([nu], [0.0], "M2", kind="this", color="0.6", size=7))
    xa, ya = a["x_L4"] / p.d, a["y_L4"] / p.d
    plane.add(Markers([xa, xa], [ya, -ya], "L4, L5 analytic", kind="analytic"),
              Note("L4", (xa, ya), color="w"), Note("L5", (xa, -ya), color="w"))
    if nv:
        plane.add(Markers([nv["x_L4"] / p.d] * 2, [nv["y_L4"] / p.d, -nv["y_L4"] / p.d], "numeric"))
    x = np.linspace(-1.6, 1.6, 1200)
    cut = Panel("", Axis("x / d"), Axis("φ_ef", unit), legend="lower center")
    cut.add(Line(x, potential_eff(x, ya + 0 * x, mu, nu), "φ_ef(x, y_L4)"),
            Guide(xa, label="L4"), Markers([xa], [top], kind="analytic"))
    cut.y.lim = (top - 1.2, top + 0.15)
    small = min(mu, nu)  # Routh's criterion is symmetric in the two mass fractions
    if a["growth_rate"] == 0:
        cut.title = f"L4 is a maximum of φ_ef, yet stable\n(the Coriolis force; smaller mass fraction {small:.4g} ≤ 0.0385)"
    else:
        cut.title = (f"L4 is a maximum of φ_ef, and unstable\n(smaller mass fraction {small:.4g} > 0.0385: "
                     f"growth {a['growth_rate']:.3g} 1/s)")
    return Scene([plane, cut])

"""4.35 Falling rod: distribution of the bending torque along its length.

Analytic: about the pivot, (m l^2/3) theta'' = m g (l/2) sin theta, so
theta'' = (3 g / 2 l) sin theta.  The part of the rod above the section s needs
the transverse load q(r) = (m/l)(r theta'' - g sin theta) per unit length from
the rest of the rod; the moment of those loads about the section,
tau(s) = integral_s^l (r - s) q(r) dr, works out to
tau = (m g l sin theta / 4) xi (1 - xi)^2 with xi = s/l.  It vanishes at the
pivot and at the free end and is largest at xi = 1/3 (where the shear
F = -d tau/ds vanishes): s_max = l/3, tau_max = m g l sin theta / 27.

Numeric: from the mass distribution by Gauss-Legendre quadrature (exact for
the polynomial loads of a uniform rod): theta'' = (torque of gravity about the
pivot) / (moment of inertia about it); then the section equilibrium
dF/ds = -q, d tau/ds = -F, integrated in closed (Cauchy) form from the end
that keeps the small residual: from the pivot (tau = 0, F(0) = integral of q
over the rod) for xi <= 1/2, from the free end (tau = F = 0) above, the
lever arm r - s taken as (section length) * node, never as a difference of
positions.  s_max is the root of the shear F by bisection, bracketed by [0, r0] with r0
the point where the load q changes sign (F < 0 at the pivot, F > 0 above r0).
"""

from __future__ import annotations

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.numerics.roots import bracketed_root

exercise = Exercise(
    "4.35",
    formulas=[
        "θ'' = (3g / 2l) sin θ",
        "τ(s) = (m g l sin θ / 4) ξ (1 - ξ)²,  ξ = s/l",
        "s_max = l/3,  τ_max = m g l sin θ / 27",
    ],
)


@exercise.analytic
def analytic(p):
    base = p.m * p.g * p.l * np.sin(p.theta)
    return {
        "tau": 0.25 * base * p.xi * (1.0 - p.xi) ** 2,
        "s_max": p.l / 3.0,
        "tau_max": base / 27.0,
    }


_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(8)
_U = 0.5 * (_NODES + 1.0)  # nodes on [0, 1]
_W = 0.5 * _WEIGHTS


@exercise.numeric
def numeric(p, run):
    # in units of the rod's mass, its length and g (m = l = g = 1): the inertia m l^2 and the torques
    # m g l would leave the floating-point range for l or m at 1e+-200 times their defaults; the answers
    # are brought back by their dimensions (tau: m g l, s: l) at the end
    m, l, g, th = 1.0, 1.0, 1.0, p.theta
    lam = m / l  # uniform linear density
    sin_t = np.sin(th)

    def density(r):
        return lam * np.ones_like(r)

    # angular acceleration from the mass distribution, about the pivot
    r = l * _U
    torque = np.sum(l * _W * density(r) * g * sin_t * r)
    inertia = np.sum(l * _W * density(r) * r**2)
    th_dd = torque / inertia

    def load(rr):
        """transverse force per length the rest of the rod must supply (positive along the fall)"""
        return density(rr) * (rr * th_dd - g * sin_t)

    F_pivot = np.sum(l * _W * load(r))  # the pivot's transverse force: F(0) = integral of q

    def from_free_end(s):
        """(F, tau) at s from tau = F = 0 at s = l: F = int_s^l q, tau = int_s^l (r - s) q"""
        L = l - s
        rr = s + L * _U
        qq = load(rr)
        return np.sum(L * _W * qq), np.sum(L * _W * (L * _U) * qq)

    def from_pivot(s):
        """(F, tau) at s from tau(0) = 0, F(0) = F_pivot: F = F0 - int_0^s q, tau = -s F0 + int_0^s (s - r) q"""
        rr = s * _U
        qq = load(rr)
        return F_pivot - np.sum(s * _W * qq), -s * F_pivot + np.sum(s * _W * (s * (1.0 - _U)) * qq)

    def section(s):
        return from_pivot(s) if s <= 0.5 * l else from_free_end(s)

    tau = section(p.xi * l)[1]

    r0 = g * sin_t / th_dd  # the load changes sign here
    F0, Fr0 = section(0.0)[0], section(r0)[0]
    if not (F0 < 0.0 < Fr0):
        raise NumericFailure(f"shear root not bracketed: F(0) = {F0:.3g}, F(r0) = {Fr0:.3g}")
    # bisection on the shear (monotone across its root), to the last bit
    s_max = bracketed_root(lambda s: section(s)[0], 0.0, r0)
    tau_max = section(s_max)[1]
    if not tau_max >= max(section(0.0)[1], section(l)[1]):
        raise NumericFailure("the shear root is not the maximum of the bending torque")
    run.method = "Gauss-Legendre quadrature"
    torque_unit = p.m * p.g * p.l
    run.info["theta_ddot"] = th_dd * p.g / p.l
    run.info["pivot_shear"] = F_pivot * p.m * p.g
    scale = torque_unit * sin_t
    for name in ("tau", "s_max", "tau_max"):
        run.claim(name, rel=1e-12, abs=1e-15 * (p.l if name == "s_max" else scale))
    return {"tau": tau * torque_unit, "s_max": s_max * p.l, "tau_max": tau_max * torque_unit}

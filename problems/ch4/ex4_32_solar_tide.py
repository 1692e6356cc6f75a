"""4.32 Height of the solar tide on a global ocean.

Analytic: in the Earth's freely falling frame the Sun leaves only its tidal
potential, -(G M_S/r_S) sum_{n>=2} (r/r_S)^n P_n(cos psi).  In units of
G M_E/R_E, with r = R_E (1 + u) and A_n = (M_S/M_E)(R_E/r_S)^(n+1), the
surface -1/(1 + u) - sum A_n (1 + u)^n P_n = const is solved by series in the
tiny A_n: with S = sum A_n P_n, T = sum n A_n P_n, V = sum n(n-1)/2 A_n P_n,
  u = c + S + S^2 + S T + [c (T + 2S) + S^3 + 3 S^2 T + S T^2 + S^2 V] + O(A^4),
the constant c fixed by the volume, <(1 + u)^3> = 1 over directions:
  c = -2<S^2> - <S T> - (10/3)<S^3> - 5<S^2 T> - <S T^2> - <S^2 V>.
Leading order (the book's): h = (M_S/M_E)(R_E^4/r_S^3) P2(cos psi): tide
1.5 (M_S/M_E) R_E^4/r_S^3 = 0.246 m for the Sun, +2/3 of it at the sub-solar
point, -1/3 on the ring at 90 degrees.  The series keeps every multipole (the
lunar 1.7% corrections) and the nonlinearity in h; what it drops is
relatively ~ (h/R_E)^3, below 1e-15 under the constraint h/R_E <= 1e-5.
h_low is the minimum of the series (Newton on its derivative from psi = 90 deg).

Numeric: the exact closed-form potential, written without cancellation:
with rho = r/r_S, w = rho (2 cos psi - rho), s = (1 - w)^(1/2),
  r_S/|r_S - r| - 1 - rho cos psi = w^2 (2 + s)/(2 s (1 + s)^2) - rho^2/2,
so the ~1e-11 tidal part is never the difference of ~1 numbers.  The unknown
is the elevation u = h/R_E, not r: at each of 64 Gauss-Legendre nodes in
cos psi, u/(1 + u) (the Earth's potential minus its value on the sphere) equals
the level c plus the tidal term, solved by fixed-point iteration (contraction
~ h/R_E); the level c solves the volume condition (quadrature of
3u + 3u^2 + u^3, secant iteration, done when its step is within 1e-15 of c or
the quadrature's rounding, 1e-14 <|u|>).  h_low: bisection for the zero of the
slope of the tidal term along the surface (bracket [0, 1] in cos psi: the slope
is negative at 90 degrees, positive at the sub-solar point).  All of it over
arrays of variants, each iterating on its own (a one-point solve is the batch
of one); a variant that fails fails alone, with its reason.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from numpy.polynomial import legendre as L

from mech.core import budget
from mech.problems.spec import Exercise

exercise = Exercise(
    "4.32",
    formulas=[
        "h(ψ) ≈ (M_S/M_E)(R_E⁴/r_S³) P₂(cos ψ)  (leading order)",
        "h_range ≈ (3/2)(M_S/M_E) R_E⁴/r_S³,  h_high ≈ (M_S/M_E) R_E⁴/r_S³,  h_low ≈ -h_high/2",
        "exact for the model: u = h/R_E = c + S + S² + ST + O(A³), S = Σ_{n≥2} A_n P_n, "
        "T = Σ n A_n P_n, A_n = (M_S/M_E)(R_E/r_S)^{n+1}, c from ⟨(1+u)³⟩ = 1",
    ],
)

MAX_EPS = 0.3  # R_E / r_S: the tide-raising body far outside the Earth
MAX_ETA = 1e-5  # leading tide / R_E


exercise.declare_limits(
    f"1e-100 <= R_E/r_S <= {MAX_EPS:g}: the body is far",
    f"1e-250 <= (M_S/M_E)(R_E/r_S)^3 <= {MAX_ETA:g}: a thin equilibrium tide",
)


@exercise.constraint
def constraint(p):
    eps = p.R_E / p.r_S
    if eps > MAX_EPS:
        return f"R_E/r_S = {eps:.3g} must be at most {MAX_EPS} (the body must be far: r_S >> R_E)"
    if eps < 1e-100:
        return f"R_E/r_S = {eps:.3g}: below 1e-100 the tidal potential (~(R_E/r_S)^4) is not representable"
    eta = (p.M_S / p.M_E) * eps**3
    if eta < 1e-250:
        return f"(M_S/M_E)(R_E/r_S)^3 = {eta:.3g}: a tide below 1e-250 of the radius is not representable"
    if eta > MAX_ETA:
        return (
            f"(M_S/M_E)(R_E/r_S)^3 = {eta:.3g}: the tide would be {eta:.2g} of the Earth's radius; "
            f"the thin equilibrium ocean of the model needs at most {MAX_ETA:g}"
        )


@functools.lru_cache(maxsize=64)
def _gauss(n: int):
    """Gauss-Legendre nodes and weights of order n, computed once per order (read only)."""
    return L.leggauss(n)


def _series(eps: float, mu: float):
    """The series' pieces: Legendre coefficients of S, T, V (and their derivatives) and the level c.

    Products of the series are formed pointwise (at Gauss nodes for the means, at the point wanted
    for u): the quadrature of 2*size + 8 nodes is exact for them (degree at most 4*size - 4)."""
    a2 = mu * eps**3
    coeffs = [0.0, 0.0]
    n = 2
    while True:
        an = mu * eps ** (n + 1)
        coeffs.append(an)
        if an < 1e-20 * a2 or n > 400:
            break
        n += 1
    A = np.array(coeffs)
    budget.check("4.32 series", 200 + 5 * A.size * A.size)  # work: products of series of A.size terms
    nn = np.arange(A.size)
    base = np.stack([A, nn * A, 0.5 * nn * (nn - 1) * A])  # S, T, V
    d1 = L.legder(base, axis=1)
    d2 = L.legder(d1, axis=1)
    x, wts = _gauss(max(64, 2 * A.size + 8))
    S, T, V = L.legval(x, base.T)

    def mean(values):
        return 0.5 * np.sum(wts * values)

    SS, ST = S * S, S * T
    c2 = -2 * mean(SS) - mean(ST)
    c3 = -(10.0 / 3.0) * mean(SS * S) - 5 * mean(SS * T) - mean(ST * T) - mean(SS * V)
    return (base.T, d1.T, d2.T), c2 + c3


def _u(parts, c, x):
    """u at x with its first two derivatives in x, from the series of S, T, V (chain rule)."""
    base, d1, d2 = parts
    S, T, V = L.legval(x, base)
    S1, T1, V1 = L.legval(x, d1)
    S2, T2, V2 = L.legval(x, d2)
    u = c + S + S * S + S * T + c * (T + 2 * S) + S**3 + 3 * S * S * T + S * T * T + S * S * V
    gS = 1 + 2 * c + 2 * S + T + 3 * S * S + 6 * S * T + T * T + 2 * S * V
    gT = c + S + 3 * S * S + 2 * S * T
    gV = S * S
    du = gS * S1 + gT * T1 + gV * V1
    d2u = (gS * S2 + gT * T2 + gV * V2 + (2 + 6 * S + 6 * T + 2 * V) * S1 * S1 + 2 * S * T1 * T1
           + 2 * (1 + 6 * S + 2 * T) * S1 * T1 + 4 * S * S1 * V1)
    return u, du, d2u


def _analytic_one(eps: float, mu: float) -> tuple[float, float]:
    """(u at the sub-solar point, u at the lowest point) of one variant: Newton for the minimum from 90 deg."""
    parts, c = _series(eps, mu)
    x = 0.0
    for _ in range(100):
        _, du, d2u = _u(parts, c, x)
        step = du / d2u
        x -= step
        if abs(step) < 1e-16:
            break
    return float(_u(parts, c, 1.0)[0]), float(_u(parts, c, x)[0])


@exercise.analytic
def analytic(P):
    """Over arrays of variants: the series (its length depends on R_E/r_S) one variant at a time."""
    from mech.solvers.numerics.batch import Column

    R_E, r_S, M_S, M_E = np.broadcast_arrays(*(np.asarray(P[k], dtype=float) for k in ("R_E", "r_S", "M_S", "M_E")))
    eps, mu = (R_E / r_S).ravel(), (M_S / M_E).ravel()
    got = np.array([_analytic_one(float(e), float(m)) for e, m in zip(eps, mu)]).reshape(eps.size, 2)
    high = R_E * got[:, 0].reshape(R_E.shape)
    low = R_E * got[:, 1].reshape(R_E.shape)
    return {"h_range": Column(high - low), "h_high": Column(high), "h_low": Column(low)}


def _tidal(rho, x):
    """r_S/|r_S - r| - 1 - rho x for |r| = rho r_S at cos(angle) = x, without cancellation."""
    w = rho * (2.0 * x - rho)
    s = np.sqrt(1.0 - w)
    return w * w * (2.0 + s) / (2.0 * s * (1.0 + s) ** 2) - 0.5 * rho * rho


def _tidal_slope(rho, x):
    """d/dx of the same at fixed rho: rho [(1 - w)^(-3/2) - 1], without cancellation."""
    w = rho * (2.0 * x - rho)
    s = np.sqrt(1.0 - w)
    return rho * w * (1.0 + s + s * s) / ((1.0 + s) * s**3)


def _surface(c, eps, k, x):
    """u at cos psi = x (n x m) on the levels c (n) of n variants: u/(1+u) = c + k F(eps (1+u), x), by
    fixed-point iteration, each variant until its own last change is at the last bits.  Returns u and
    the variants whose iteration did not converge."""
    n = x.shape[0]
    u = np.zeros(x.shape)
    todo = np.arange(n)
    c, eps, k, x, ut = c[:, None], eps[:, None], k[:, None], x, u  # the rows still iterating
    for _ in range(100):
        q = c + k * _tidal(eps * (1.0 + ut), x)
        new = q / (1.0 - q)
        done = np.all(np.abs(new - ut) <= 1e-15 * np.abs(new) + 1e-300, axis=1)
        ut = new
        if done.any():
            u[todo[done]] = new[done]
            keep = ~done
            todo, c, eps, k, x, ut = todo[keep], c[keep], eps[keep], k[keep], x[keep], ut[keep]
            if todo.size == 0:
                break
    u[todo] = ut
    bad = np.zeros(n, dtype=bool)
    bad[todo] = True
    return u, bad


def _level(eps, k, why):
    """The level c of each variant from the volume condition <(1+u)^3> = 1 (64 Gauss-Legendre nodes in
    cos psi), by the secant from c = 0, each variant on its own; a variant that fails gets its reason in
    ``why``.  Returns c and the volume residual."""
    x, wts = _gauss(64)
    wts = 0.5 * wts

    def volume(c, idx):
        u, bad = _surface(c, eps[idx], k[idx], np.broadcast_to(x, (idx.size, x.size)))
        why[idx[bad]] = "the surface iteration did not converge"
        # <(1+u)^3> - 1, and <|u|>: the residual's rounding is a few ulps of 3<|u|>
        return np.sum(wts * u * (3.0 + u * (3.0 + u)), axis=1), np.sum(wts * np.abs(u), axis=1)

    n = eps.size
    every = np.arange(n)
    c0 = np.zeros(n)
    v0, _ = volume(c0, every)
    c1 = -v0 / 3.0
    v1, size = volume(c1, every)
    active = why == ""
    for _ in range(60):  # each variant's own secant
        idx = np.flatnonzero(active)
        stop = (v1[idx] == 0.0) | (v1[idx] == v0[idx])
        active[idx[stop]] = False
        idx = idx[~stop]
        if idx.size == 0:
            break
        c2 = c1[idx] - v1[idx] * (c1[idx] - c0[idx]) / (v1[idx] - v0[idx])
        c0[idx], v0[idx] = c1[idx], v1[idx]
        c1[idx], (v1[idx], size[idx]) = c2, volume(c2, idx)
        # done when the step is within the level's own rounding: 1e-15 of c, or 1e-14 <|u|> where c is the
        # small difference of the quadrature's terms (a tide of 1e-13 R_E: c ~ 1e-26, its residual's
        # rounding ~1e-29 ~ 1e-3 of c); the elevations move by that step, 1e-14 of themselves at most
        small = np.abs(c1[idx] - c0[idx]) <= 1e-15 * np.abs(c1[idx]) + 1e-14 * size[idx]
        active[idx] = (why[idx] == "") & ~small
    why[active & (why == "")] = "the volume condition did not converge"
    return c1, v1


def _lowest(c, eps, k, why):
    """cos psi of each variant's lowest point: the zero of the slope of the tidal term along the surface,
    bracketed in [0, 1] (negative at 90 degrees, positive at the sub-solar point), to the last bit."""
    from mech.solvers.numerics.searches import bisect_bits

    def slope(idx, xx):
        u, bad = _surface(c[idx], eps[idx], k[idx], np.asarray(xx, dtype=float)[:, None])
        why[idx[bad & (why[idx] == "")]] = "the surface iteration did not converge"
        return _tidal_slope(eps[idx] * (1.0 + u[:, 0]), xx)

    ok = np.flatnonzero(why == "")
    x_low = np.full(eps.size, np.nan)
    tiny = 5e-324  # the bisection runs on positive floats; the minimum is at ~R_E/(2 r_S) >= 5e-101
    s0, s_tiny, s1 = (slope(ok, np.full(ok.size, v)) for v in (0.0, tiny, 1.0))
    bracketed = (s0 < 0.0) & (s_tiny < 0.0) & (s1 > 0.0)
    why[ok[~bracketed & (why[ok] == "")]] = "the lowest point is not bracketed in [0, 1] in cos(psi)"
    ok = ok[bracketed]
    if ok.size:
        x_low[ok] = bisect_bits(lambda j, xx: slope(ok[j], xx), np.full(ok.size, tiny), np.ones(ok.size),
                                s_tiny[bracketed], s1[bracketed])
    return x_low


@exercise.batched(("h_range", "h_high", "h_low"))
def numeric(P, rtol, outputs, memo=None, tally=None):
    """The route at N variants at once (a one-point solve is the batch of one): each variant's level by its
    own secant on the volume condition, its lowest point by its own bisection; a variant that fails fails
    alone, with its reason.  The volume residual is each variant's invariant."""
    from mech.problems.spec import Tally
    from mech.solvers.numerics.batch import Column

    tally = Tally() if tally is None else tally
    R_E, r_S, M_S, M_E = np.broadcast_arrays(*(np.asarray(P[k], dtype=float).ravel()
                                               for k in ("R_E", "r_S", "M_S", "M_E")))
    eps = R_E / r_S
    k = (M_S / M_E) * eps  # (G M_S / r_S) / (G M_E / R_E)
    why = np.full(eps.size, "", dtype=object)
    with np.errstate(all="ignore"):
        c, residual = _level(eps, k, why)
        x_low = _lowest(c, eps, k, why)
        ok = np.flatnonzero(why == "")
        u_high, u_low = np.full(eps.size, np.nan), np.full(eps.size, np.nan)
        u, bad = _surface(c[ok], eps[ok], k[ok], np.ones((ok.size, 1)))
        u_high[ok] = u[:, 0]
        why[ok[bad]] = "the surface iteration did not converge"
        u, bad = _surface(c[ok], eps[ok], k[ok], x_low[ok][:, None])
        u_low[ok] = u[:, 0]
        why[ok[bad & (why[ok] == "")]] = "the surface iteration did not converge"
    good = why == ""
    tally.invariant("volume", np.where(good, residual, 0.0))  # residual of <(1+u)^3> = 1
    tally.info["cos_psi_low"] = np.where(good, x_low, None)
    tally.info["level_c"] = np.where(good, c, None)
    failed = [(why == text, text) for text in sorted(set(why[~good]))]
    values = {"h_range": R_E * (u_high - u_low), "h_high": R_E * u_high, "h_low": R_E * u_low}
    return {o: Column(np.where(good, values[o], np.nan), rel=1e-12, failed=failed) for o in outputs}

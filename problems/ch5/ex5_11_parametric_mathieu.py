"""5.11 Parametric excitation of a damped oscillator with modulated stiffness.

Analytic (reduced equations, first zone): writing q = Re[a(t) e^{i omega t}]
with a slow, the modulation couples a to its conjugate with the strength
eps = mu omega0 / 4, and a(t) ~ exp(lambda t) with (lambda + delta)^2 = eps^2 - xi^2.
Hence growth = -delta + sqrt(eps^2 - xi^2) inside the zone (|xi| < eps) and
-delta outside; the threshold is mu_th = (4/omega0) sqrt(delta^2 + xi^2); for
the given mu the unstable zone is |xi| < sqrt(eps^2 - delta^2) (none when
eps <= delta).  All leading order in mu, delta/omega0 and xi/omega0.

Numeric (Floquet, exact): the monodromy matrix M of the full linear equation
over one modulation period pi/omega (both fundamental solutions, DOP853 at
rtol ~1e-12, det M = exp(-2 delta pi/omega) monitored).  growth = (omega/pi)
ln of the largest |multiplier|.  In the first zone the critical multiplier
is -1, so the threshold (root in mu, bracketed by a geometric scan upward
from 0) and the edges (roots in omega on both sides of the minimum of the
function over omega) are roots of the smooth P = det(M + I) =
1 + tr M + det M, never of the growth rate.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure, Undefined
from mech.solvers.floquet import even_hill_discriminant

exercise = Exercise(
    "5.11",
    formulas=[
        "ε = μ ω₀/4,  ξ = ω - ω₀",
        "growth = -δ + (ε² - ξ²)^(1/2) for |ξ| < ε, else -δ",
        "μ_th = (4/ω₀) (δ² + ξ²)^(1/2)",
        "ξ_hi = -ξ_lo = (ε² - δ²)^(1/2)  (no zone if ε ≤ δ)",
    ],
    leading_order=("mu_th", "growth", "xi_lo", "xi_hi"),
    default_rtol=1e-12,
    min_rtol=1e-13,
)

# The reduced equations hold for omega near omega0 and weak damping only; beyond
# that the "first zone" is no longer the relevant instability.
MAX_DETUNING = 0.3  # |omega - omega0| / omega0
MAX_DAMPING = 0.2  # delta / omega0


@exercise.constraint
def constraint(p):
    if abs(p.omega - p.omega0) > MAX_DETUNING * p.omega0:
        return (f"omega = {p.omega:g} rad/s is too far from omega0 = {p.omega0:g} rad/s: the first parametric "
                f"zone needs |omega - omega0| <= {MAX_DETUNING:g} omega0")
    if p.delta > MAX_DAMPING * p.omega0:
        return (f"delta = {p.delta:g} 1/s is not weak damping for omega0 = {p.omega0:g} rad/s: "
                f"the exercise needs delta <= {MAX_DAMPING:g} omega0")


def _lo(omega0, delta, mu, xi):
    """The leading-order answers as functions of the theory's own parameters."""
    eps = mu * omega0 / 4.0
    s2 = eps * eps - xi * xi
    growth = -delta + math.sqrt(s2) if s2 > 0 else -delta
    mu_th = 4.0 * math.hypot(delta, xi) / omega0
    h2 = eps * eps - delta * delta
    if h2 > 0:
        h = math.sqrt(h2)
        lo, hi = -h, h
    else:
        lo = hi = Undefined(f"eps = mu omega0/4 = {eps:.6g} 1/s does not exceed delta = {delta:.6g} 1/s: "
                            "the rest state is stable at every detuning")
    return {"mu_th": mu_th, "growth": growth, "xi_lo": lo, "xi_hi": hi}


@exercise.analytic
def analytic(p):
    return _lo(p.omega0, p.delta, p.mu, p.omega - p.omega0)


def _eps_rel_err(mu, xi, omega0):
    """Relative size of what the coupling eps = mu omega0/4 neglects: the factor
    omega0/omega (first order in xi) and the zone's O(mu^3) half-width terms."""
    return 2.0 * (abs(xi) / omega0 + mu**2 / 16.0)


def _centre_err(mu, xi, delta, omega0):
    """Size of the neglected shift of the zone's centre: -mu^2 omega0/64 (the
    Mathieu zone's a = 1 - q^2/8), -delta^2/(2 omega0) (damping's frequency
    pull) and O(xi^2/omega0) (omega^2 is not linear in xi); twice their sum."""
    return 2.0 * (mu**2 * omega0 / 64.0 + 0.5 * delta**2 / omega0 + xi**2 / omega0)


@exercise.expected_error
def expected_error(p):
    """What the reduced equations neglect, propagated through each answer.

    The theory's two ingredients are the coupling eps and the detuning from
    the zone's centre; each is uncertain by the neglected terms above.  The
    expected error of an output is its largest change when they move by those
    amounts (finite changes, so the square roots near the zone's edges and
    near threshold are treated honestly: there the relative error is large).
    """
    xi = p.omega - p.omega0
    base = _lo(p.omega0, p.delta, p.mu, xi)
    out = {}
    # threshold: its own mu sets the neglected terms
    mt = base["mu_th"]
    if mt > 0:
        r, s = _eps_rel_err(mt, xi, p.omega0), _centre_err(mt, xi, p.delta, p.omega0)
        alt = 4.0 * math.hypot(p.delta, abs(xi) + s) / p.omega0 / max(1.0 - r, 1e-3)
        out["mu_th"] = alt / mt - 1.0
    # growth at the given mu and omega
    r, s = _eps_rel_err(p.mu, xi, p.omega0), _centre_err(p.mu, xi, p.delta, p.omega0)
    g0 = base["growth"]
    worst = 0.0
    for se in (-1.0, 1.0):
        for sx in (-1.0, 1.0):
            g = _lo(p.omega0, p.delta, p.mu * (1 + se * r), xi + sx * s)["growth"]
            worst = max(worst, abs(g - g0))
    out["growth"] = worst / abs(g0) if g0 != 0 else math.inf
    # edges: the half-width through eps, plus the centre's shift
    if not isinstance(base["xi_hi"], Undefined):
        h = base["xi_hi"]
        r, s = _eps_rel_err(p.mu, h, p.omega0), _centre_err(p.mu, h, p.delta, p.omega0)
        worst = 0.0
        for se in (-1.0, 1.0):
            alt = _lo(p.omega0, p.delta, p.mu * (1 + se * r), 0.0)["xi_hi"]
            worst = max(worst, h if isinstance(alt, Undefined) else abs(alt - h))
        out["xi_lo"] = out["xi_hi"] = (worst + s) / h
    return out


def _floquet(p, omega, mu, rtol, run):
    """(largest |multiplier|, P = det(M + I), tr M_y) of the full damped equation over one period pi/omega.

    The damping is taken out exactly by q = exp(-delta t) y, which leaves the
    Hill equation y'' + (omega0^2 (1 + mu cos 2 omega t) - delta^2) y = 0 with
    an even coefficient: half a period of its two fundamental solutions gives
    tr M_y; the multipliers of q are exp(-delta T) times those of y.
    """
    T = math.pi / omega
    w0sq, d2, two_omega = p.omega0**2, p.delta**2, 2.0 * omega
    tr, wronski, traj = even_hill_discriminant(
        lambda t: w0sq * (1.0 + mu * math.cos(two_omega * t)) - d2, T, rtol=rtol, vscale=p.omega0
    )
    run.record(traj)
    run.invariant("Wronskian", wronski)
    damp = math.exp(-p.delta * T)
    disc = tr * tr - 4.0
    lam = 0.5 * (abs(tr) + math.sqrt(disc)) if disc > 0 else 1.0  # largest |multiplier| of y
    return damp * lam, 1.0 + damp * tr + damp * damp, tr


@exercise.numeric
def numeric(p, run):
    from mech.solvers.roots import brentq

    rtol = run.rtol
    noise = 10.0 * rtol  # size of the truncation and round-off in P = det(M + I)
    T = math.pi / p.omega
    out = {}

    # growth at the given mu and omega
    lam, _, tr = _floquet(p, p.omega, p.mu, rtol, run)
    out["growth"] = math.log(lam) / T
    # near a zone edge the multiplier (tr + sqrt(tr^2 - 4))/2 amplifies the error of tr
    amplify = 1.0 + abs(tr) / math.sqrt(max(tr * tr - 4.0, noise))
    run.claim("growth", rel=100 * rtol, abs=noise * amplify / T)

    # threshold at the given omega: the first sign change of P(mu) scanning upward
    def P_mu(mu):
        return _floquet(p, p.omega, mu, rtol, run)[1]

    if P_mu(0.0) <= noise:
        out["mu_th"] = 0.0  # exact resonance without damping: any modulation excites
        run.claim("mu_th", rel=100 * rtol, abs=math.sqrt(noise))
    else:
        lo, hi = 0.0, 1e-3
        while P_mu(hi) > 0.0:
            lo, hi = hi, 4.0 * hi
            if hi > 10.0:
                raise NumericFailure("no multiplier reaches -1 for mu < 10: no first-zone threshold found")
        mu_th = brentq(P_mu, lo, hi, xtol=1e-15, rtol=1e-13)
        dmu = 1e-4 * mu_th
        slope = abs(P_mu(mu_th + dmu)) / dmu
        out["mu_th"] = mu_th
        run.claim("mu_th", rel=max(100 * rtol, noise / (slope * mu_th)))

    # zone edges at the given mu: roots of P(omega) on both sides of its minimum
    def P_w(w):
        return _floquet(p, w, p.mu, rtol, run)[1]

    grid = np.linspace(0.55 * p.omega0, 1.6 * p.omega0, 9)
    vals = np.array([P_w(w) for w in grid])
    if vals[0] <= 0 or vals[-1] <= 0:
        raise NumericFailure("the first zone reaches the end of the omega search window")
    k = int(np.argmin(vals))
    if vals[k] < 0:
        w_in = grid[k]
    else:
        # golden-section search for the minimum, stopped as soon as P < 0 is seen
        a, b = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
        g = 0.5 * (math.sqrt(5.0) - 1.0)
        c, d = b - g * (b - a), a + g * (b - a)
        fc, fd = P_w(c), P_w(d)
        w_in = None
        while b - a > 1e-11 * p.omega0:
            if min(fc, fd) < 0:
                w_in = c if fc < fd else d
                break
            if fc < fd:
                b, d, fd = d, c, fc
                c = b - g * (b - a)
                fc = P_w(c)
            else:
                a, c, fc = c, d, fd
                d = a + g * (b - a)
                fd = P_w(d)
        if w_in is None:
            pmin = min(fc, fd)
            why = Undefined(f"min over omega of det(M + I) = {pmin:.3g} >= 0: no multiplier passes -1 at mu = {p.mu:g}")
            out["xi_lo"] = out["xi_hi"] = why
            return out
    run.info["omega_inside_zone"] = w_in
    below, above = grid[grid < w_in], grid[grid > w_in]
    left = below[vals[: below.size] > 0][-1]
    right = above[vals[grid.size - above.size :] > 0][0]
    for name, a, b, sgn in (("xi_lo", left, w_in, -1.0), ("xi_hi", w_in, right, 1.0)):
        w = brentq(P_w, a, b, xtol=1e-15 * p.omega0, rtol=1e-14)
        dw = 1e-7 * p.omega0
        slope = abs(P_w(w + sgn * dw)) / dw
        out[name] = w - p.omega0
        run.claim(name, rel=100 * rtol, abs=noise / slope)
    return out


@exercise.scene
def scene(p, run):
    """The first instability zone in the (detuning, modulation depth) plane, the leading-order theory as a
    shaded zone and the Floquet edges as markers; and the growth rate across the zone at this depth."""
    from mech.problems.scene import Axis, Band, Guide, Line, Markers, Panel, Scene

    xi = p.omega - p.omega0
    a = run.analytic(p)
    top = min(1.0, max(3 * p.mu, 3 * a["mu_th"] if math.isfinite(a["mu_th"]) else 0.0, 0.05))
    mus = np.linspace(top / 300, top * 0.999, 300)
    zone = run.series(p, "mu", mus)
    plane = Panel(f"first zone; threshold μ_th = {a['mu_th']:.4g} at this ω", Axis("detuning ξ = ω − ω0", "rad/s"),
                  Axis("modulation depth μ"), legend="outside")
    plane.add(Band(mus, zone["xi_lo"], zone["xi_hi"], "unstable, leading-order theory", vertical=True),
              Line(zone["xi_lo"], mus, color="C3", width=1.2), Line(zone["xi_hi"], mus, color="C3", width=1.2))
    ok = np.isfinite(zone["xi_lo"])
    pts = run.numeric_points(mus[ok][0] if ok.any() else top / 10, top)
    if len(pts):
        edges = run.series(p, "mu", pts, numeric=True)
        plane.add(Markers(edges["xi_lo"], pts, "zone's edges, Floquet (numeric)"), Markers(edges["xi_hi"], pts))
        failed = run.failed_x.get("mu", [])
        if failed:
            plane.add(Markers([xi] * len(failed), failed, f"numeric failed ({len(failed)})", kind="failure"))
    plane.add(Markers([xi], [p.mu], "this oscillator", kind="this"))
    width = max(abs(xi), p.mu * p.omega0 / 2, 4 * p.delta, 1e-3 * p.omega0)
    ws = p.omega0 + np.linspace(-width, width, 300)
    growth = Panel(f"growth rate across the zone at μ = {p.mu:.4g}", Axis("detuning ξ = ω − ω0", "rad/s"),
                   Axis("growth rate", "1/s"), legend="outside")
    growth.add(Line(ws - p.omega0, run.series(p, "omega", ws)["growth"], "leading-order theory"),
               Guide(0.0, axis="y", dashed=False, color="0.3"), Guide(xi))
    pts = p.omega0 + run.numeric_points(-width, width)
    if len(pts):
        growth.add(Markers(pts - p.omega0, run.series(p, "omega", pts, numeric=True)["growth"], "Floquet (numeric)"))
        failed = run.failed_x.get("omega", [])
        if failed:
            growth.add(Markers(np.array(failed) - p.omega0, [math.nan] * len(failed),
                               f"numeric failed ({len(failed)})", kind="failure"))
    growth.add(Markers([xi], [a["growth"]], "this oscillator", kind="this"))
    return Scene([plane, growth], caption="leading-order analytic theory: agreement within what it neglects")

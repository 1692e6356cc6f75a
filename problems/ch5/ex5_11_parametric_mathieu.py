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
ln of the largest |multiplier| of y = exp(delta t) q, minus delta: near
threshold a difference of two nearly equal rates, so its error is absolute
(~ rtol omega0, not rtol growth) and the multiplier's logarithm is formed
from the half-period solutions without cancellation (see ``_growth``).  In the first zone the critical multiplier
is -1, so the threshold (root in mu, bracketed by a geometric scan from 1e-3)
and the edges (roots in omega on both sides of the minimum of the function
over omega) are roots of the smooth P = det(M + I) = 1 + tr M + det M, never
of the growth rate.  P is formed as exp(-delta T) F with F from half-period
products that do not cancel (``_minus_one_scaled``), so a zone 1e-7 omega0
wide (|P| ~ 1e-14) is still resolved.

The route is written once, over arrays of variants (``numeric``): a one-point solve is its batch of one
(``Exercise.batched``), a sweep or a class its batch of many.  Allowances: ``_allowances`` (twice the next order, solvers.mechanics.mathieu, plus a floor).
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, Tally
from mech.solvers.mechanics.mathieu import first_zone_next_order
from mech.solvers.mechanics.floquet import even_hill_half, half_period_growth, half_period_minus_one

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


exercise.declare_limits(
    f"|omega - omega0| <= {MAX_DETUNING:g} omega0: the first parametric zone",
    f"delta <= {MAX_DAMPING:g} omega0: weak damping",
)


@exercise.constraint
def constraint(p):
    omega, omega0, delta = p.omega, p.omega0, p.delta  # read once: a draw screens thousands of points
    if abs(omega - omega0) > MAX_DETUNING * omega0:
        return (f"omega = {omega:g} rad/s is too far from omega0 = {omega0:g} rad/s: the first parametric "
                f"zone needs |omega - omega0| <= {MAX_DETUNING:g} omega0")
    if delta > MAX_DAMPING * omega0:
        return (f"delta = {delta:g} 1/s is not weak damping for omega0 = {omega0:g} rad/s: "
                f"the exercise needs delta <= {MAX_DAMPING:g} omega0")


def _lo(omega0, delta, mu, xi):
    """The leading-order answers as functions of the theory's own parameters, over arrays (NaN marks an
    undefined edge: eps <= delta)."""
    eps = mu * omega0 / 4.0
    s2 = eps * eps - xi * xi
    growth = np.where(s2 > 0, -delta + np.sqrt(np.maximum(s2, 0.0)), -delta)
    h2 = eps * eps - delta * delta
    h = np.where(h2 > 0, np.sqrt(np.maximum(h2, 0.0)), np.nan)
    return {"mu_th": 4.0 * np.hypot(delta, xi) / omega0, "growth": growth, "xi_lo": -h, "xi_hi": h}


_NO_ZONE = "eps = mu omega0/4 does not exceed delta: the rest state is stable at every detuning"


def _arrays(P):
    return (np.asarray(P[k], dtype=float) for k in ("omega0", "delta", "mu", "omega"))


@exercise.analytic
def analytic(P):
    """The leading-order answers over arrays of variants (``_lo``); no edges where eps <= delta."""
    from mech.solvers.numerics.batch import Column

    omega0, delta, mu, omega = _arrays(P)
    lo = _lo(omega0, delta, mu, omega - omega0)
    out = {k: Column(v) for k, v in lo.items()}
    for k in ("xi_lo", "xi_hi"):
        out[k].undefined.append((np.isnan(lo[k]), _NO_ZONE))
    return out


def _allowances(omega0, delta, mu, omega):
    """{output: (relative, absolute)} arrays: twice the next order (``first_zone_next_order`` minus the leading
    order) plus a floor from the order after it (measured at 66 points against Floquet: growth <= 2e-4 k^2 of
    omega sigma, mu_th <= 0.0016 mu_th^2, edges <= 0.002 k^2), with k = mu/2 the pump's Mathieu parameter.
    Relative where the leading value is not zero; the growth at threshold, 0, gets an absolute one; edges the
    theory does not find (eps <= delta) get the absolute width a zone may still have."""
    omega0, delta, mu, omega = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (omega0, delta, mu, omega)))
    lo = _lo(omega0, delta, mu, omega - omega0)
    nx = first_zone_next_order(omega0, delta, mu, omega)
    k2, d2 = (mu / 2.0) ** 2, (delta / omega0) ** 2
    out = {}
    with np.errstate(invalid="ignore", divide="ignore"):
        g0 = lo["growth"]
        g_abs = 2.0 * np.abs(nx["growth"] - g0) + 0.002 * k2 * (nx["growth"] + delta)
        out["growth"] = (np.where(g0 != 0, g_abs / np.abs(g0), 0.0), np.where(g0 != 0, np.nan, g_abs))
        mt = lo["mu_th"]
        out["mu_th"] = (np.where(mt > 0, 2.0 * np.abs(nx["mu_th"] / mt - 1.0) + 0.005 * mt**2, np.nan),
                        np.full(mt.shape, np.nan))
        floor = 0.005 * k2 + 0.01 * d2
        for name in ("xi_lo", "xi_hi"):
            h = lo[name]
            rel = 2.0 * np.abs(nx[name] / h - 1.0) + floor
            rel = np.where(np.isnan(nx[name]), 1.0, rel)  # the next order closes the zone: all of it
            # no zone in the theory: one may still open, no wider than the next order's, or the coupling
            # eps (1 + k^2/4) gives
            widest = np.fmax(np.abs(nx[name]), _lo(omega0, delta, mu * (1.0 + k2 / 2.0), 0.0 * mu)["xi_hi"])
            ab = np.where(np.isnan(h), 2.0 * widest + (mu**2 / 32.0 + d2) * omega0, np.nan)
            out[name] = (np.where(np.isnan(h), np.nan, rel), ab)
    return out


@exercise.expected_error
def expected_error(P):
    """What the reduced equations neglect: ``_allowances`` (mu_th + 0.005 mu_th^2, growth + 0.002 k^2 of the
    rate, the edges + 0.005 k^2 + 0.01 (delta/omega0)^2 over twice the next order), NaN where none."""
    return _allowances(*_arrays(P))


@exercise.theory_range
def theory_range(P):
    """The reduced equations expand in the pump's Mathieu parameter k = mu/2, delta/omega0 and the detuning
    |omega - omega0|/omega0 (the largest is shown, named at each variant)."""
    omega0, delta, mu, omega = _arrays(P)
    cands = np.stack(np.broadcast_arrays(mu / 2.0, delta / omega0, np.abs(omega - omega0) / omega0))
    labels = np.array(["mu/2", "delta/omega0", "|omega - omega0|/omega0"], dtype=object)[np.argmax(cands, axis=0)]
    return {name: (labels, cands.max(axis=0)) for name in _CHART_OUTPUTS}


def _half(omega0, delta, mu, omega, rtol, tally):
    """(y1, y1', y2, y2') in the time t of ``_growth``'s Hill equation at half the period pi/omega, and the
    |Wronskian drift|, at N points at once: in the time s = omega t all points integrate
    y'' + ((omega0/omega)^2 (1 + mu cos 2s) - (delta/omega)^2) y = 0 over the same half period [0, pi/2]."""
    r2 = (omega0 / omega) ** 2
    c0, c1 = r2 - (delta / omega) ** 2, r2 * mu
    (y1, y1p, y2, y2p), runs = even_hill_half(c0, c1, lambda s: math.cos(2.0 * s), 0.5 * math.pi, rtol=rtol,
                                              vscale=omega0 / omega, integrator=tally.integrator)
    for r in runs:
        tally.record(r)
    # back to the time t: d/dt = omega d/ds, and y2 (y2'(0) = 1) is 1/omega of its scaled self
    return (y1, omega * y1p, y2 / omega, y2p), np.abs(y1 * y2p - y1p * y2 - 1.0)


def _half_error(rtol, omega0, T):
    """The absolute error of the unit-sized half-period values y1, y2': DOP853's global error on unit
    solutions, ~rtol plus 0.06 rtol per radian (measured for 5.3's maps), taken as 2 rtol plus 0.2 rtol per
    radian of omega0 T/2 (y1, y2' ~ 1; y1' ~ omega0; y2 ~ 1/omega0)."""
    return rtol * (2.0 + 0.2 * omega0 * 0.5 * T)


NO_THRESHOLD = "no multiplier reaches -1 for mu < 10: no first-zone threshold found"
UNCONVERGED = "the root search for the threshold did not converge"
NO_WINDOW = "the first zone reaches the end of the omega search window"
UNRESOLVED = ("min over omega of det(M + I) exp(delta T) is within its accuracy: whether a zone exists at "
              "this mu is not resolved")


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


# -- the route over many variants at once (a one-point solve is the batch of one) -------------------------


class _MinusOne:
    """(F, its error) of ``_minus_one_scaled`` (det(M + I) exp(delta T)) at points (omega0, delta, mu, omega),
    any one of mu or omega varied; the largest Wronskian drift of each point kept."""

    def __init__(self, omega0, delta, mu, omega, rtol, tally):
        self.omega0, self.delta, self.mu, self.omega, self.rtol, self.tally = omega0, delta, mu, omega, rtol, tally
        self.drift = np.zeros(omega0.size)

    def __call__(self, idx, mu=None, omega=None):
        mu = self.mu[idx] if mu is None else mu
        omega = self.omega[idx] if omega is None else omega
        omega0, delta = self.omega0[idx], self.delta[idx]
        (y1, y1p, y2, y2p), w = _half(omega0, delta, mu, omega, self.rtol, self.tally)
        self.drift[idx] = np.maximum(self.drift[idx], w)
        T = math.pi / omega
        return half_period_minus_one(y1, y1p, y2, y2p, _half_error(self.rtol, omega0, T), delta * T, omega0)


def _threshold(omega0, delta, omega, rtol, tally):
    """``numeric``'s mu_th at N points: the first sign change of F(mu) scanning upward (downward first
    where F(1e-3) < 0), then the root."""
    from mech.solvers.numerics.batch import illinois, scan_down, scan_up

    n = omega.size
    P = _MinusOne(omega0, delta, np.zeros(n), omega, rtol, tally)
    allp = np.arange(n)
    p0, e0 = P(allp, mu=np.zeros(n))
    zero = p0 <= e0  # exact resonance without damping: any modulation excites
    lo, hi = np.zeros(n), np.full(n, 1e-3)
    flo, fhi = p0.copy(), np.full(n, np.nan)
    idx = np.flatnonzero(~zero)
    if idx.size:
        fhi[idx] = P(idx, mu=hi[idx])[0]
    # a threshold below 1e-3: bracket it within a factor 4 (the root's tolerance is relative to it)
    d = np.flatnonzero(~zero & (fhi < 0.0))
    if d.size:
        lo_d, hi[d], flo_d, fhi[d] = scan_down(lambda i, m: P(d[i], mu=m)[0], hi[d], fhi[d], factor=0.25, floor=1e-15)
        set_lo = ~np.isnan(flo_d)
        lo[d[set_lo]], flo[d[set_lo]] = lo_d[set_lo], flo_d[set_lo]
    u = np.flatnonzero(~zero & (fhi > 0.0))
    no_root = np.zeros(n, dtype=bool)
    if u.size:
        lo[u], hi[u], flo[u], fhi[u], no_root[u] = scan_up(lambda i, m: P(u[i], mu=m)[0], lo[u], hi[u], factor=4.0,
                                                           limit=10.0, flo=flo[u], fhi=fhi[u])
    go = np.flatnonzero(~zero & ~no_root)
    mu_th = np.zeros(n)
    conv = np.ones(n, dtype=bool)
    xtol = 1e-15 * hi
    if go.size:
        x, ok = illinois(lambda x, i: P(go[i], mu=x)[0], lo[go], hi[go], flo[go], fhi[go], xtol=xtol[go],
                         rtol=1e-13)
        mu_th[go], conv[go] = x, ok
    rel = np.full(n, 100.0 * rtol)
    ab = np.zeros(n)
    ab[zero] = 2.0 * np.sqrt(e0[zero])
    if go.size:
        dmu = 1e-4 * mu_th[go]
        f1, e1 = P(go, mu=mu_th[go] + dmu)
        slope = np.abs(f1) / dmu
        with np.errstate(divide="ignore", invalid="ignore"):
            rel[go] = np.maximum(100.0 * rtol, (e1 / slope + xtol[go]) / mu_th[go])
    mu_th[no_root | ~conv] = np.nan
    return mu_th, rel, ab, no_root, ~conv, P.drift


def _edges(omega0, delta, mu, rtol, tally):
    """``numeric``'s zone edges at N points: the region of omega where det(M + I) < 0 around its minimum
    (solvers.numerics.zones), searched over 0.55 - 1.6 omega0."""
    from mech.solvers.numerics.zones import negative_region

    n = mu.size
    P = _MinusOne(omega0, delta, mu, np.ones(n), rtol, tally)
    grid = np.linspace(0.55, 1.6, 9)[None, :] * omega0[:, None]
    ends, window, none, unresolved = negative_region(lambda idx, w: P(idx, omega=w), grid, omega0)
    out = {name: (w - omega0, np.full(n, 100.0 * rtol), ab, unconv)
           for name, (w, ab, unconv) in zip(("xi_lo", "xi_hi"), ends)}
    return out, window, none, unresolved, P.drift


_CHART_OUTPUTS = ("growth", "mu_th", "xi_lo", "xi_hi")


@exercise.batched(_CHART_OUTPUTS, boundaries={"mu": ("mu_th", "leading-order zone edge μ = μ_th(ω)")})
def numeric(P, rtol, outputs, memo=None, tally=None):
    """The route at N points at once (one point: a solve): growth at every point; mu_th once per distinct
    (omega0, delta, omega) and the edges once per distinct (omega0, delta, mu) (a grid over omega and mu needs
    200 thresholds, not 40 000), kept in ``memo`` (one dict for the whole sweep) across its chunks; the
    Wronskian's drift of every point reported to ``tally`` and failing the outputs it exceeds."""
    from mech.solvers.numerics.batch import Column, by_rows

    omega0, delta, mu, omega = _arrays(P)
    memo = {} if memo is None else memo
    tally = Tally() if tally is None else tally
    allowed = exercise.tol_factor * rtol
    drifted = f"the Wronskian drifted by more than {allowed:.3g}"
    out = {}
    if "growth" in outputs:
        (y1, y1p, y2, y2p), wronski = _half(omega0, delta, mu, omega, rtol, tally)
        tally.invariant("Wronskian", wronski)
        T = math.pi / omega
        growth, err = half_period_growth(y1, y1p, y2, y2p, _half_error(rtol, omega0, T), omega0, delta, T)
        out["growth"] = Column(growth, rel=100 * rtol, abs=err, failed=[(wronski > allowed, drifted)])
    if "mu_th" in outputs:
        v, rel, ab, no_root, unconv, drift = by_rows(memo, ("mu_th", rtol), (omega0, delta, omega),
                                                      lambda a, b, c: _threshold(a, b, c, rtol, tally))
        tally.invariant("Wronskian", drift)
        out["mu_th"] = Column(v, rel=rel, abs=ab, failed=[(no_root, NO_THRESHOLD), (unconv, UNCONVERGED),
                                                          (drift > allowed, drifted)])
    if {"xi_lo", "xi_hi"} & set(outputs):
        def edges(a, b, c):
            e, window, none, unresolved, drift = _edges(a, b, c, rtol, tally)
            return (*e["xi_lo"], *e["xi_hi"], window, none, unresolved, drift)

        got = by_rows(memo, ("edges", rtol), (omega0, delta, mu), edges)
        window, none, unresolved, drift = got[8].astype(bool), got[9].astype(bool), got[10].astype(bool), got[11]
        tally.invariant("Wronskian", drift)
        for k, name in enumerate(("xi_lo", "xi_hi")):
            if name in outputs:
                v, rel, ab, unconv = got[4 * k: 4 * k + 4]
                out[name] = Column(v, rel=rel, abs=ab, undefined=[
                    (none, "min over omega of det(M + I) >= 0: no multiplier passes -1 at this mu")],
                    failed=[(window, NO_WINDOW), (unresolved, UNRESOLVED),
                            (unconv, "the root search for the zone's edge did not converge"),
                            (drift > allowed, drifted)])
    return out

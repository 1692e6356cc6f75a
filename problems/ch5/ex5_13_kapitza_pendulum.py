"""5.13 Kapitza pendulum: the inverted position made stable by fast vertical vibration of the pivot.

Analytic (fast/slow separation): the pivot's vibration adds the fast torque
per unit m l^2, f = (a Omega^2/l) cos(Omega t) sin theta.  The fast jitter is
-f/Omega^2; averaging the force it feeds back over one fast period gives the
effective potential per unit m l^2
    U_eff = -omega0^2 cos theta + (a^2 Omega^2 / 4 l^2) sin^2 theta,
so small slow oscillations have omega_down^2 = omega0^2 + a^2 Omega^2/(2 l^2)
about theta = 0 and omega_inv^2 = a^2 Omega^2/(2 l^2) - omega0^2 about
theta = pi, stable for a > a_min = sqrt(2 g l)/Omega.  Leading order in
omega0/Omega and a/l.

Numeric (Floquet, exact): the equation linearized about theta = 0 or pi is
Hill's equation y'' +- (g - a Omega^2 cos Omega t)/l y = 0, even in t: half a
fast period (DOP853, rtol ~1e-12) gives y1, y1', y2, y2' and with them
tr M - 2 = 4 y1' y2, so sin^2(nu pi/Omega) = -y1' y2 keeps its relative
accuracy when nu << Omega; stable iff 0 < -y1' y2 < 1.  a_min is the root of
y1' y2 in a for the inverted position (brentq after a geometric scan upward
from a small a).
The route is written once over arrays of variants (``numeric``; a one-point solve is its batch of one):
two fundamental solutions of the linearization (``_hill``) integrated as monodromy runs, no single
motion to show, so no states and no trajectory.

Allowances (``_next_order``, from Mathieu's exponent to q^4, McLachlan sec. 4.70):
  a_min       twice 7 sk^2/16 + 2 sk^4;
  omega_down  twice e^2 - 7 e^4/(16 beta0^2) + 8 e^4;
  omega_inv   the same with beta0^2 = 2 e^2 - 4 sk^2, plus the square of its second term (it grows past 0.3
              near a_min: outside the range there).
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, Tally

exercise = Exercise(
    "5.13",
    formulas=[
        "U_eff/(m l²) = -ω₀² cos θ + (a² Ω² / 4 l²) sin² θ,  ω₀² = g/l",
        "a_min = (2 g l)^(1/2) / Ω",
        "ω_inv = (a² Ω² / 2 l² - ω₀²)^(1/2)",
        "ω_down = (ω₀² + a² Ω² / 2 l²)^(1/2)",
    ],
    leading_order=("a_min", "omega_inv", "omega_down"),
    default_rtol=1e-12,
    min_rtol=1e-13,
)

MIN_RATIO = 5.0  # Omega / omega0: the fast/slow separation the exercise is about
MAX_AMPLITUDE = 0.35  # a / l


exercise.declare_limits(
    f"Omega >= {MIN_RATIO:g} omega0, omega0 = (g/l)^(1/2): a fast drive",
    f"a <= {MAX_AMPLITUDE:g} l",
)


@exercise.constraint
def constraint(p):
    w0 = math.sqrt(p.g / p.l)
    if p.Omega < MIN_RATIO * w0:
        return (f"Omega = {p.Omega:g} rad/s is not fast against omega0 = sqrt(g/l) = {w0:.6g} rad/s: "
                f"the exercise needs Omega >= {MIN_RATIO:g} omega0")
    if p.a > MAX_AMPLITUDE * p.l:
        return f"a = {p.a:g} m is not small against l = {p.l:g} m: the exercise needs a <= {MAX_AMPLITUDE:g} l"


def _norm(x, y):
    """sqrt(x^2 + y^2) for x, y >= 0 without forming the squares (which under- or overflow at extreme
    ratios), over arrays."""
    big, small = np.maximum(x, y), np.minimum(x, y)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(big > 0, small / np.where(big > 0, big, 1.0), 0.0)
    return big * np.sqrt(1.0 + r * r)


_BELOW_A_MIN = "a is below a_min: the effective potential has a maximum at theta = pi"


def _arrays(P):
    return (np.asarray(P[k], dtype=float) for k in ("l", "g", "a", "Omega"))


@exercise.analytic
def analytic(P):
    """Over arrays of variants, in the ratios sk = omega0/Omega and eps = a/l (so that neither Omega^2 nor
    (a Omega/l)^2 is formed): omega_down = Omega sqrt(sk^2 + eps^2/2), omega_inv = Omega sqrt(eps^2/2 - sk^2),
    a_min = sqrt(2) sk l."""
    from mech.solvers.numerics.batch import Column

    l, g, a, Omega = _arrays(P)
    sk, h = np.sqrt(g / l) / Omega, a / l / math.sqrt(2.0)
    up = h > sk
    # the roots taken apart: (h - sk)(h + sk) underflows at Omega/omega0 ~ 1e+200 where its root does not
    inv = np.where(up, Omega * np.sqrt(np.maximum(h - sk, 0.0)) * np.sqrt(h + sk), np.nan)
    return {"a_min": Column(math.sqrt(2.0) * sk * l), "omega_down": Column(Omega * _norm(sk, h)),
            "omega_inv": Column(inv, undefined=[(~up, _BELOW_A_MIN)])}


def _next_order(sk, e):
    """The relative next-order corrections (numeric - leading)/leading and the allowances, for floats or arrays.

    The linearized equations are Mathieu's, y'' + (A - 2 q cos 2s) y = 0 in s = Omega t/2, with
    A = +-4 sk^2 (sk = omega0/Omega; + about theta = 0, - about pi) and q = 2 e (e = a/l).  Their
    characteristic exponent beta (nu = beta Omega/2) obeys, for small q and beta (McLachlan, Theory and
    Application of Mathieu Functions, sec. 4.70; Nayfeh & Mook, Nonlinear Oscillations, sec. 5.4)
        A = beta^2 + q^2/(2 (beta^2 - 1)) + (5 beta^2 + 7) q^4/(32 (beta^2 - 1)^3 (beta^2 - 4)) + ...
          = beta^2 - q^2/2 - beta^2 q^2/2 + 7 q^4/128 + O(q^6, beta^4 q^2).
    The averaging keeps beta0^2 = A + q^2/2; the next order gives
        d nu/nu = q^2/4 - 7 q^4/(256 beta0^2) = e^2 - 7 e^4/(16 beta0^2),
    and at the stability edge (beta = 0) a_min (1 + 7 sk^2/16).  Checked against Floquet at 40 draws:
    the ratio measured/predicted is 1.00 +- 0.01 for e, sk < 0.1, up to 1.6 at e = 0.33 (the next
    order, ~5 e^4)."""
    e2, s2 = e * e, sk * sk
    with np.errstate(divide="ignore", invalid="ignore"):
        # e^4/beta0^2 as e^2/(beta0^2/e^2), in the ratio (sk/e)^2: e^4 underflows at a ~ 1e-100 l where it does not
        q2 = (sk / e) ** 2
        c_inv = 7.0 * e2 / (16.0 * (2.0 - 4.0 * q2))
        c_down = 7.0 * e2 / (16.0 * (4.0 * q2 + 2.0))  # beta0^2 >= 4 sk^2 > 0
    d_down = e2 - c_down
    d_inv = e2 - c_inv
    d_min = 7.0 / 16.0 * s2
    # allowances: twice the next order, plus a floor from the order after it (~5 e^4 measured at e = 0.33;
    # where omega_inv's two terms cancel, their squares); a_min's next order is ~sk^4
    floor = 8.0 * e2 * e2
    return {"a_min": 2.0 * d_min + 2.0 * s2 * s2, "omega_down": 2.0 * np.abs(d_down) + floor,
            "omega_inv": 2.0 * np.abs(d_inv) + floor + 2.0 * c_inv * c_inv}


@exercise.expected_error
def expected_error(P):
    """Allowances (``_next_order``), one line each:
      a_min       twice the next order 7 sk^2/16 (sk = omega0/Omega), plus 2 sk^4;
      omega_down  twice the next order e^2 - 7 e^4/(16 beta0^2) (e = a/l, beta0^2 = 4 sk^2 + 2 e^2), plus 8 e^4;
      omega_inv   twice e^2 - 7 e^4/(16 beta0^2) (beta0^2 = 2 e^2 - 4 sk^2), plus 8 e^4 and twice the
                  square of the second term (the terms cancel on a line of the plane): near a_min,
                  beta0 -> 0, it grows past 0.3 and the theory is outside its range there (NaN below a_min)."""
    l, g, a, Omega = _arrays(P)
    sk, e = np.sqrt(g / l) / Omega, a / l
    allow = _next_order(sk, e)
    inv = np.where(e > math.sqrt(2.0) * sk, np.minimum(allow["omega_inv"], 1e6), np.nan)
    return {"omega_down": allow["omega_down"], "omega_inv": inv, "a_min": allow["a_min"]}


@exercise.theory_range
def theory_range(P):
    """The averaging expands in sk = omega0/Omega and e = a/l (the larger is shown)."""
    l, g, a, Omega = _arrays(P)
    sk, e = np.sqrt(g / l) / Omega, a / l
    big = np.where(e >= sk, e, sk)
    labels = np.where(e >= sk, "a/l", "omega0/Omega").astype(object)
    return {"a_min": ("omega0/Omega", sk), "omega_down": (labels, big), "omega_inv": (labels, big)}


def _hill(sk, eps, sign):
    """The right-hand side (``integrate_ensemble``'s ``make_rhs``) of half a fast period (tau from 0 to pi) of
    y'' = sign (kappa - eps cos tau) y for variants (sk, eps: arrays), both fundamental solutions at once
    (y1, q1, y2, y2') from (1, 0, 0, 1), the Wronskian conserved; and S.

    Time tau = Omega t, kappa = g/(l Omega^2) = sk^2 with sk = omega0/Omega, eps = a/l: the linearization
    about theta = pi (sign +1) or theta = 0 (sign -1).  The fast jitter is taken out exactly by
    p = y' + e sin(tau) y (e = sign eps):
        y' = p - e sin(tau) y,   p' = (c - e^2 sin^2 tau) y + e sin(tau) p   (c = sign kappa),
    so p carries only the slow drift, of order D = kappa + eps^2 = S^2, and is integrated to rtol of that
    size (y' itself swings by eps each fast period: its error, rtol eps, would swamp a drift of eps^2 when
    eps is small).  At tau = 0 and pi, sin tau = 0 and p = y'.

    The first solution's p starts at 0 and stays of order D, which underflows when Omega/omega0 ~ 1e+200
    (a_min ~ 1e-200 l): it is carried as q1 = p1/D, whose equation holds only the ratios sk/S and eps/S
    (S = hypot(sk, eps), representable; D itself enters only where its product is beneath round-off).
    """
    S = np.hypot(sk, eps)
    D = S * S
    cn, en2 = sign * (sk / S) ** 2, (eps / S) ** 2  # c/D and e^2/D, each at most 1
    e = sign * eps

    def make_rhs(sel):
        Ds, cs, es2, ee = (float(x[sel]) if isinstance(sel, int) else x[sel] for x in (D, cn, en2, e))

        def rhs(tau, y):
            sn = math.sin(tau)
            es = ee * sn
            k = cs - es2 * sn * sn  # (c - e^2 sin^2 tau)/D
            return np.array([Ds * y[1] - es * y[0], k * y[0] + es * y[1], y[3] - es * y[2], Ds * k * y[2] + es * y[3]])

        return rhs

    return make_rhs, S, D


def _half(sk, eps, sign, rtol, tally):
    """(y1, q1, y2, y2') at tau = pi (``_hill``), S and the |Wronskian drift| y1 y2' - D q1 y2 - 1, at N
    variants at once: monodromy runs, tools, not a motion to show."""
    from mech.solvers.mechanics.floquet import integrate_ensemble

    make_rhs, S, D = _hill(sk, eps, sign)
    n = S.size
    y0 = np.zeros((4, n))
    y0[0] = y0[3] = 1.0
    (y1, q1, y2, y2p), runs = integrate_ensemble(make_rhs, (0.0, math.pi), y0, rtol=rtol,
                                                 atol=np.full((4, n), 1e-3 * rtol), integrator=tally.integrator)
    for r in runs:
        tally.record(r)
    return y1, q1, y2, y2p, S, np.abs(y1 * y2p - D * q1 * y2 - 1.0)


def _slow_frequency(Omega, sk, eps, sign, rtol, tally):
    """(nu, its relative claim, stable, |Wronskian drift|) about theta = pi (sign +1) or 0 (sign -1): from
    sin^2(nu pi/Omega) = -y1' y2 = -S^2 q1 y2, stable iff it lies in (0, 1)."""
    y1, q1, y2, y2p, S, drift = _half(sk, eps, sign, rtol, tally)
    sig = -q1 * y2  # sin^2(nu pi / Omega) / S^2
    r = np.where(sig > 0, S * np.sqrt(np.maximum(sig, 0.0)), 0.0)  # sin(nu pi / Omega)
    stable = (sig > 0.0) & (r < 1.0)
    rs = np.where(stable, r, 0.5)
    nu = np.where(stable, (Omega / math.pi) * np.arcsin(rs), np.nan)
    # y1' is resolved to about rtol of the drift scale times pi (its size over half a period)
    dsig = 10.0 * rtol * (np.abs(sig) + math.pi * np.abs(y2))
    # dnu/nu = (Omega/pi) dr/sqrt(1 - r^2) / nu with dr = S dsig / (2 sqrt(sig)); Omega/pi cancels
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = S * dsig / (2.0 * np.sqrt(np.where(stable, sig, 1.0)) * np.sqrt(1.0 - rs * rs) * np.arcsin(rs))
    return nu, np.where(stable, np.maximum(100.0 * rtol, rel), 100.0 * rtol), stable, drift


def _a_min(sk, rtol, tally):
    """a_min/l at N values of sk: the root in eps of y1' y2 = (tr M - 2)/4 about the inverted position (> 0
    unstable), bracketed by a scan up from 0.05 sk (a fraction of the amplitude where a Omega/l ~ omega0) in
    factors of 1.3 to l/2, then the root (Illinois; f is smooth in eps and resolved to ~rtol of its scale:
    within that, it is the root, its error that noise over the slope).  (eps_min, stable at the start, no root, not converged, |Wronskian drift|)."""
    from mech.solvers.numerics.batch import illinois, scan_up

    n = sk.size
    drift = np.zeros(n)

    def f(idx, eps):  # zero where within its resolution (``_slow_frequency``'s dsig): a root to that accuracy
        y1, q1, y2, y2p, S, w = _half(sk[idx], eps, 1.0, rtol, tally)
        drift[idx] = np.maximum(drift[idx], w)
        v = q1 * y2
        return np.where(np.abs(v) <= 10.0 * rtol * math.pi * np.abs(y2), 0.0, v)

    e_lo = 0.05 * sk
    f_lo = f(np.arange(n), e_lo)
    early = ~(f_lo > 0)
    go = np.flatnonzero(~early)
    lo, hi, flo, fhi, none = scan_up(lambda i, x: f(go[i], x), e_lo[go], 1.3 * e_lo[go], factor=1.3, limit=0.5,
                                     flo=f_lo[go])
    no_root = np.zeros(n, dtype=bool)
    no_root[go[none]] = True
    eps, conv = np.full(n, np.nan), np.ones(n, dtype=bool)
    ok = ~none
    if ok.any():
        g = go[ok]
        x, done = illinois(lambda x, i: f(g[i], x), lo[ok], hi[ok], flo[ok], fhi[ok], xtol=0.1 * rtol * lo[ok],
                           rtol=0.0)
        eps[g], conv[g] = x, done
    eps[~conv] = np.nan
    return eps, early, no_root, ~conv, drift


@exercise.batched(("omega_inv", "omega_down", "a_min"),
                  boundaries={"a": ("a_min", "leading-order stability edge a = a_min(Ω)")})
def numeric(P, rtol, outputs, memo=None, tally=None):
    """The slow frequencies about both positions and a_min at N variants at once (a one-point solve is the
    batch of one): ``_slow_frequency``, ``_a_min`` (once for each distinct omega0/Omega, kept in ``memo``
    across a sweep's chunks and a solve's rerun); the Wronskian's drift reported to ``tally`` and failing
    the outputs it exceeds."""
    from mech.solvers.numerics.batch import Column, by_rows

    l, g, a, Omega = _arrays(P)
    sk, eps = np.sqrt(g / l) / Omega, a / l
    memo = {} if memo is None else memo
    tally = Tally() if tally is None else tally
    allowed = exercise.tol_factor * rtol
    drifted = f"the Wronskian drifted by more than {allowed:.3g}"
    out = {}
    for name, sign in (("omega_down", -1.0), ("omega_inv", 1.0)):
        if name not in outputs:
            continue
        nu, rel, stable, wronski = _slow_frequency(Omega, sk, eps, sign, rtol, tally)
        tally.invariant("Wronskian", wronski)
        where = "inverted" if sign > 0 else "lower"
        out[name] = Column(nu, rel=rel, undefined=[(~stable, f"|tr M| >= 2 about the {where} position: unstable")],
                           failed=[(~(wronski <= allowed), drifted)])
    if "a_min" in outputs:
        v, early, no_root, unconv, drift = by_rows(memo, ("a_min", rtol), (sk,), lambda s: _a_min(s, rtol, tally))
        tally.invariant("Wronskian", drift)
        out["a_min"] = Column(l * v, rel=100.0 * rtol, failed=[
            (early, "the inverted position is already stable at the scan's start: no bracket"),
            (no_root, "no pivot amplitude below l/2 stabilizes the inverted position"),
            (unconv, "the root search for a_min did not converge"),
            (~(drift <= allowed), drifted)])
    return out


@exercise.scene
def scene(p, run):
    """Where the inverted pendulum is stable in the (Omega, a) plane, and the slow frequencies about both
    positions against the amplitude; lines from the averaging theory, markers from Floquet."""
    import numpy as np

    from mech.problems.scene import Axis, Band, Guide, Line, Markers, Panel, Scene

    w0 = math.sqrt(p.g / p.l)
    an = run.analytic(p)
    Oms = np.geomspace(max(p.Omega / 10, MIN_RATIO * w0 * 1.001), p.Omega * 10, 200)
    amin = run.series(p, "Omega", Oms)["a_min"]
    chart = Panel("the inverted position is stable above a_min(Ω)", Axis("pivot's frequency Ω", "rad/s", log=True),
                  Axis("pivot's amplitude a", "m", log=True), legend="lower left")
    chart.add(Band(Oms, amin, np.full(len(Oms), np.nanmax(amin) * 10), "inverted pendulum stable", color="C2"),
              Line(Oms, amin, "a_min, averaging theory"))
    pts = run.numeric_points(Oms[0], Oms[-1], log=True)
    if len(pts):
        chart.add(Markers(pts, run.series(p, "Omega", pts, numeric=True)["a_min"], "a_min, Floquet (numeric)"))
    chart.add(Markers([p.Omega], [p.a], "this pendulum", kind="this"))
    chart.y.lim = (np.nanmin(amin) / 3, np.nanmax(amin) * 3)
    As = np.linspace(0.3 * an["a_min"], max(3 * an["a_min"], 1.5 * p.a), 300)
    As = As[As <= MAX_AMPLITUDE * p.l]
    slow = run.series(p, "a", As)
    freq = Panel("slow oscillations about both positions", Axis("pivot's amplitude a", "m"),
                 Axis("slow frequency", "rad/s"), legend="upper left")
    freq.add(Line(As, slow["omega_down"], "about the lower position"),
             Line(As, slow["omega_inv"], "about the inverted position", color="C1"))
    pts = run.numeric_points(As[0], As[-1])
    if len(pts):
        num = run.series(p, "a", pts, numeric=True)
        freq.add(Markers(pts, num["omega_down"], "Floquet (numeric)"), Markers(pts, num["omega_inv"]))
    freq.add(Guide(an["a_min"], label=f"a_min = {an['a_min']:.4g} m", color="C2"), Guide(p.a, label="this a"))
    return Scene([chart, freq], caption="leading-order analytic theory (averaging over the fast period)")

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
The Hill equation is declared once (``_hill``, a Motion with its Wronskian) and followed as
monodromy runs (mark=False): two fundamental solutions of the linearization, no single
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

from mech.problems.spec import Exercise, NumericFailure, Undefined
from mech.core import budget

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
    ratios); the same operations for floats and arrays, so that analytic_batch equals analytic to the bit."""
    big, small = np.maximum(x, y), np.minimum(x, y)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(big > 0, small / np.where(big > 0, big, 1.0), 0.0)
    return big * np.sqrt(1.0 + r * r)


@exercise.analytic
def analytic(p):
    """In the ratios sk = omega0/Omega and eps = a/l (so that neither Omega^2 nor (a Omega/l)^2 is formed):
    omega_down = Omega sqrt(sk^2 + eps^2/2), omega_inv = Omega sqrt(eps^2/2 - sk^2), a_min = sqrt(2) sk l."""
    sk, h = math.sqrt(p.g / p.l) / p.Omega, p.a / p.l / math.sqrt(2.0)
    out = {"a_min": math.sqrt(2.0) * sk * p.l, "omega_down": float(p.Omega * _norm(sk, h))}
    out["omega_inv"] = (
        p.Omega * math.sqrt((h - sk) * (h + sk)) if h > sk
        else Undefined(f"a = {p.a:g} m is below a_min: the effective potential has a maximum at theta = pi")
    )
    return out


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
    b_down, b_inv = 4.0 * s2 + 2.0 * e2, 2.0 * e2 - 4.0 * s2
    with np.errstate(divide="ignore", invalid="ignore"):
        c_inv = 7.0 * e2 * e2 / (16.0 * b_inv)
        c_down = 7.0 * e2 * e2 / (16.0 * b_down)  # b_down >= 4 sk^2 > 0
    d_down = e2 - c_down
    d_inv = e2 - c_inv
    d_min = 7.0 / 16.0 * s2
    # allowances: twice the next order, plus a floor from the order after it (~5 e^4 measured at e = 0.33;
    # where omega_inv's two terms cancel, their squares); a_min's next order is ~sk^4
    floor = 8.0 * e2 * e2
    return {"a_min": 2.0 * d_min + 2.0 * s2 * s2, "omega_down": 2.0 * np.abs(d_down) + floor,
            "omega_inv": 2.0 * np.abs(d_inv) + floor + 2.0 * c_inv * c_inv}


@exercise.expected_error
def expected_error(p):
    """Allowances (``_next_order``), one line each:
      a_min       twice the next order 7 sk^2/16 (sk = omega0/Omega), plus 2 sk^4;
      omega_down  twice the next order e^2 - 7 e^4/(16 beta0^2) (e = a/l, beta0^2 = 4 sk^2 + 2 e^2), plus 8 e^4;
      omega_inv   twice e^2 - 7 e^4/(16 beta0^2) (beta0^2 = 2 e^2 - 4 sk^2), plus 8 e^4 and twice the
                  square of the second term (the terms cancel on a line of the plane): near a_min,
                  beta0 -> 0, it grows past 0.3 and the theory is outside its range there."""
    sk, e = math.sqrt(p.g / p.l) / p.Omega, p.a / p.l
    allow = _next_order(sk, e)
    out = {"a_min": float(allow["a_min"]), "omega_down": float(allow["omega_down"])}
    if e * e > 2.0 * sk * sk:
        out["omega_inv"] = min(float(allow["omega_inv"]), 1e6)
    return out


@exercise.theory_range
def theory_range(p):
    """The averaging expands in sk = omega0/Omega and e = a/l (the larger is shown)."""
    sk, e = math.sqrt(p.g / p.l) / p.Omega, p.a / p.l
    big = ("a/l", e) if e >= sk else ("omega0/Omega", sk)
    return {"a_min": ("omega0/Omega", sk), "omega_down": big, "omega_inv": big}


def _hill(p, eps, sign):
    """Half a fast period (tau from 0 to pi) of y'' = sign (kappa - eps cos tau) y, both fundamental
    solutions at once (y1, q1, y2, y2') from (1, 0, 0, 1), the Wronskian conserved; and S.

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
    from mech.problems.motion import Motion

    sk = math.sqrt(p.g / p.l) / p.Omega
    S = math.hypot(sk, eps)
    D = S * S
    cn, en2 = sign * (sk / S) ** 2, (eps / S) ** 2  # c/D and e^2/D, each at most 1
    e = sign * eps

    def rhs(tau, y):
        sn = math.sin(tau)
        es = e * sn
        k = cn - en2 * sn * sn  # (c - e^2 sin^2 tau)/D
        return np.array([D * y[1] - es * y[0], k * y[0] + es * y[1],
                         y[3] - es * y[2], D * k * y[2] + es * y[3]])

    return Motion(rhs, [1.0, 0.0, 0.0, 1.0], (0.0, math.pi), y_size=[1.0, 1.0, 1.0, 1.0],
                  invariants={"Wronskian": lambda y: y[0] * y[3] - D * y[1] * y[2]}), S


def _half(p, eps, sign, rtol, run):
    """(y1, q1, y2, y2', S) at tau = pi (``_hill``): a monodromy run, a tool, not a motion to show."""
    m, S = _hill(p, eps, sign)
    y1, q1, y2, y2p = run.follow(m, rtol=rtol, mark=False).y_end
    return y1, q1, y2, y2p, S


def _slow_frequency(p, sign, rtol, run, name):
    y1, q1, y2, y2p, S = _half(p, p.a / p.l, sign, rtol, run)
    sig = -q1 * y2  # sin^2(nu pi / Omega) / S^2
    r = S * math.sqrt(sig) if sig > 0 else 0.0  # sin(nu pi / Omega)
    if not (sig > 0.0 and r < 1.0):
        where = "inverted" if sign > 0 else "lower"
        s2 = r * r if sig > 0 else sig * S * S
        return Undefined(f"|tr M| >= 2 about the {where} position (sin^2(nu pi/Omega) = {s2:.6g}): unstable")
    nu = (p.Omega / math.pi) * math.asin(r)
    # y1' is resolved to about rtol of the drift scale times pi (its size over half a period)
    dsig = 10.0 * rtol * (abs(sig) + math.pi * abs(y2))
    # dnu/nu = (Omega/pi) dr/sqrt(1 - r^2) / nu with dr = S dsig / (2 sqrt(sig)); Omega/pi cancels
    rel = S * dsig / (2.0 * math.sqrt(sig) * math.sqrt(1.0 - r * r) * math.asin(r))
    run.claim(name, rel=max(100.0 * rtol, rel))
    return nu


@exercise.numeric
def numeric(p, run):
    from mech.solvers.numerics.roots import brentq

    rtol = run.rtol
    out = {
        "omega_down": _slow_frequency(p, -1.0, rtol, run, "omega_down"),
        "omega_inv": _slow_frequency(p, +1.0, rtol, run, "omega_inv"),
    }

    def f(eps):  # y1' y2 = (tr M - 2)/4 about the inverted position, over its drift scale: > 0 unstable
        y1, q1, y2, y2p, S = _half(p, eps, +1.0, rtol, run)
        return q1 * y2

    e_lo = 0.05 * math.sqrt(p.g / p.l) / p.Omega  # a fraction of the amplitude where a Omega/l ~ omega0
    f_lo = f(e_lo)
    if f_lo <= 0:
        raise NumericFailure(f"the inverted position is already stable at a = {e_lo * p.l:.3g} m: no bracket")
    e_hi = e_lo
    for _ in range(200):  # 1.3^200: far past l/2 from any start
        budget.check("5.13: bracketing a_min")
        e_hi *= 1.3
        f_hi = f(e_hi)
        if f_hi < 0:
            break
        e_lo, f_lo = e_hi, f_hi
        if e_hi > 0.5:
            raise NumericFailure("no pivot amplitude below l/2 stabilizes the inverted position")
    # f is smooth in eps and resolved to ~rtol of its scale: the root to ~rtol relative
    out["a_min"] = p.l * brentq(f, e_lo, e_hi, xtol=1e-3 * rtol * e_lo, rtol=1e-15, fa=f_lo, fb=f_hi)
    return out


# -- charts: stability of both positions and their slow frequencies over many points at once ----------

_BELOW_A_MIN = "a is below a_min: the effective potential has a maximum at theta = pi"


def _arrays(P):
    import numpy as np

    return (np.asarray(P[k], dtype=float) for k in ("l", "g", "a", "Omega"))


def analytic_batch(P):
    """The analytic solver over arrays of points (tests hold it equal to ``analytic``)."""
    import numpy as np

    from mech.solvers.numerics.batch import Column

    l, g, a, Omega = _arrays(P)
    sk, h = np.sqrt(g / l) / Omega, a / l / math.sqrt(2.0)
    up = h > sk
    inv = np.where(up, Omega * np.sqrt(np.maximum((h - sk) * (h + sk), 0.0)), np.nan)
    return {"a_min": Column(math.sqrt(2.0) * sk * l), "omega_down": Column(Omega * _norm(sk, h)),
            "omega_inv": Column(inv, undefined=[(~up, _BELOW_A_MIN)])}


def expected_error_batch(P):
    """``expected_error`` of the slow frequencies over arrays of points (NaN where omega_inv has none)."""
    import numpy as np

    l, g, a, Omega = _arrays(P)
    sk, e = np.sqrt(g / l) / Omega, a / l
    allow = _next_order(sk, e)
    inv = np.where(e * e > 2.0 * sk * sk, np.minimum(allow["omega_inv"], 1e6), np.nan)
    return {"omega_down": allow["omega_down"], "omega_inv": inv, "a_min": allow["a_min"]}


def theory_range_batch(P):
    """``theory_range`` over arrays of points."""
    import numpy as np

    l, g, a, Omega = _arrays(P)
    sk, e = np.sqrt(g / l) / Omega, a / l
    big = np.maximum(sk, e)
    return {"a_min": ("omega0/Omega", sk), "omega_down": ("max(a/l, omega0/Omega)", big),
            "omega_inv": ("max(a/l, omega0/Omega)", big)}


def _half_batch(l, g, a, Omega, sign, rtol):
    """``_half`` at N points at once: (y1, y1', y2, y2'), |Wronskian drift|.

    theta'' + (g - a Omega^2 cos Omega t)/l sin theta = 0 linearized about
    theta = 0 (sign +1) or pi (sign -1) is an even Hill equation; in the time
    s = Omega t every point's fast period becomes 2 pi, so all points
    integrate y'' + sign ((g/l)/Omega^2 - (a/l) cos s) y = 0 over the same half
    period [0, pi].  The products y1' y2 and y1 y2' do not depend on the time's unit.
    """
    import numpy as np

    from mech.solvers.mechanics.floquet import even_hill_half_batch

    c0, c1 = (g / l) / Omega**2, a / l
    (y1, y1p, y2, y2p), _ = even_hill_half_batch(lambda s: sign * (c0 - c1 * math.cos(s)), math.pi, Omega.size,
                                                  rtol=rtol)
    return (y1, y1p, y2, y2p), np.abs(y1 * y2p - y1p * y2 - 1.0)


def _a_min_batch(l, g, Omega, rtol):
    """``numeric``'s a_min at N points: the scan up from 0.05 l omega0/Omega in factors of 1.3, then the root
    of y1' y2 about the inverted position."""
    import numpy as np

    from mech.solvers.numerics.batch import illinois

    n = Omega.size
    drift = np.zeros(n)

    def f(idx, a):
        (y1, y1p, y2, y2p), w = _half_batch(l[idx], g[idx], a, Omega[idx], -1.0, rtol)
        drift[idx] = np.maximum(drift[idx], w)
        return y1p * y2

    allp = np.arange(n)
    a_lo = 0.05 * l * np.sqrt(g / l) / Omega
    f_lo = f(allp, a_lo)
    stable_start = f_lo <= 0
    a_hi, f_hi = a_lo.copy(), np.full(n, np.nan)
    scan = ~stable_start
    no_root = np.zeros(n, dtype=bool)
    while scan.any():
        idx = np.flatnonzero(scan)
        a_hi[idx] *= 1.3
        f_hi[idx] = f(idx, a_hi[idx])
        done = f_hi[idx] < 0
        scan[idx[done]] = False
        rest = idx[~done]
        a_lo[rest], f_lo[rest] = a_hi[rest], f_hi[rest]
        over = rest[a_hi[rest] > 0.5 * l[rest]]
        no_root[over] = True
        scan[over] = False
    go = np.flatnonzero(~stable_start & ~no_root)
    a_min, conv = np.full(n, np.nan), np.ones(n, dtype=bool)
    if go.size:
        x, ok = illinois(lambda x, i: f(go[i], x), a_lo[go], a_hi[go], f_lo[go], f_hi[go], xtol=1e-16 * l[go],
                         rtol=1e-14)
        a_min[go], conv[go] = x, ok
    a_min[~conv] = np.nan
    return a_min, stable_start, no_root, ~conv, drift


@exercise.batched(("omega_inv", "omega_down", "a_min"), analytic=analytic_batch,
                  expected_error=expected_error_batch, theory_range=theory_range_batch,
                  boundaries={"a": ("a_min", "leading-order stability edge a = a_min(Ω)")})
def numeric_batch(P, rtol, outputs, memo=None):
    """The slow frequencies about both positions and a_min at N points at once (see ``_half_batch``).

    sin^2(nu pi/Omega) = -y1' y2; stable iff it lies in (0, 1).  a_min once
    for each distinct (l, g, Omega), kept in ``memo`` across a sweep's chunks.
    Claims and the Wronskian check as in ``numeric``.
    """
    import numpy as np

    from mech.solvers.numerics.batch import Column, by_rows

    l, g, a, Omega = _arrays(P)
    memo = {} if memo is None else memo
    allowed = exercise.tol_factor * rtol
    drifted = f"the Wronskian drifted by more than {allowed:.3g}"
    out = {}
    for name, sign in (("omega_down", 1.0), ("omega_inv", -1.0)):
        if name not in outputs:
            continue
        (y1, y1p, y2, y2p), wronski = _half_batch(l, g, a, Omega, sign, rtol)
        s = -y1p * y2
        stable = (s > 0.0) & (s < 1.0)
        sc = np.clip(s, 1e-300, 1.0 - 1e-16)
        nu = np.where(stable, (Omega / math.pi) * np.arcsin(np.sqrt(sc)), np.nan)
        ds = 10.0 * rtol * np.abs(y1p * y2) + 10.0 * rtol * 1e-3
        dnu = (Omega / math.pi) * ds / (2.0 * np.sqrt(sc * (1.0 - sc)))
        with np.errstate(divide="ignore", invalid="ignore"):
            rel = np.where(stable, np.maximum(100.0 * rtol, dnu / nu), 100.0 * rtol)
        where = "inverted" if sign < 0 else "lower"
        out[name] = Column(nu, rel=rel, undefined=[(~stable, f"|tr M| >= 2 about the {where} position: unstable")],
                           failed=[(wronski > allowed, drifted)])
    if "a_min" in outputs:
        v, early, no_root, unconv, drift = by_rows(memo, ("a_min", rtol), (l, g, Omega),
                                                   lambda *c: _a_min_batch(*c, rtol))
        out["a_min"] = Column(v, rel=100.0 * rtol, failed=[
            (early, "the inverted position is already stable at the scan's start: no bracket"),
            (no_root, "no pivot amplitude below l/2 stabilizes the inverted position"),
            (unconv, "the root search for a_min did not converge"),
            (drift > allowed, drifted)])
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

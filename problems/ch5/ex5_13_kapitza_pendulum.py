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
"""

from __future__ import annotations

import math

from mech.problems.spec import Exercise, NumericFailure, Undefined
from mech.solvers.floquet import even_hill_half

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


@exercise.constraint
def constraint(p):
    w0 = math.sqrt(p.g / p.l)
    if p.Omega < MIN_RATIO * w0:
        return (f"Omega = {p.Omega:g} rad/s is not fast against omega0 = sqrt(g/l) = {w0:.6g} rad/s: "
                f"the exercise needs Omega >= {MIN_RATIO:g} omega0")
    if p.a > MAX_AMPLITUDE * p.l:
        return f"a = {p.a:g} m is not small against l = {p.l:g} m: the exercise needs a <= {MAX_AMPLITUDE:g} l"


@exercise.analytic
def analytic(p):
    w0sq = p.g / p.l
    kick = (p.a * p.Omega / p.l) ** 2 / 2.0
    out = {"a_min": math.sqrt(2.0 * p.g * p.l) / p.Omega, "omega_down": math.sqrt(w0sq + kick)}
    out["omega_inv"] = (
        math.sqrt(kick - w0sq) if kick > w0sq
        else Undefined(f"a = {p.a:g} m is below a_min: the effective potential has a maximum at theta = pi")
    )
    return out


@exercise.expected_error
def expected_error(p):
    """The averaging is the start of an expansion in the Mathieu parameters of
    the linearized equation (in the time Omega t/2): a_M = 4 omega0^2/Omega^2
    and q = 2a/l; it neglects relative O(a_M) and O(q^2) in the effective
    stiffness (e.g. the stability boundary's 7 q^4/128 next to q^2/2).  So a
    slow frequency squared is off by about eta (omega0^2 + a^2 Omega^2/2 l^2)
    with eta = a_M + q^2, which in nu is half that over nu^2: near a_min
    (nu_inv -> 0) it grows without bound, as it must.  The measured
    coefficient of eta stays below 0.6 over the allowed ranges; 1 is used."""
    w0sq = p.g / p.l
    eta = 4.0 * w0sq / p.Omega**2 + (2.0 * p.a / p.l) ** 2
    kick = (p.a * p.Omega / p.l) ** 2 / 2.0
    abs_nu2 = eta * (w0sq + kick)
    a_min = math.sqrt(2.0 * p.g * p.l) / p.Omega
    out = {
        "a_min": 4.0 * w0sq / p.Omega**2 + (2.0 * a_min / p.l) ** 2,
        "omega_down": 0.5 * abs_nu2 / (w0sq + kick),
    }
    if kick > w0sq:
        out["omega_inv"] = min(0.5 * abs_nu2 / (kick - w0sq), 1e6)
    return out


def _half(p, a, sign, rtol, run):
    """y1, y1', y2, y2' at half a fast period for the linearization about theta = 0 (sign +1) or pi (-1)."""
    g_l, aW2_l, W = p.g / p.l, a * p.Omega**2 / p.l, p.Omega
    vals, traj = even_hill_half(
        lambda t: sign * (g_l - aW2_l * math.cos(W * t)), 2.0 * math.pi / W, rtol=rtol, vscale=W
    )
    run.record(traj)
    y1, y1p, y2, y2p = vals
    run.invariant("Wronskian", y1 * y2p - y1p * y2 - 1.0)
    return vals


def _slow_frequency(p, a, sign, rtol, run, name):
    y1, y1p, y2, y2p = _half(p, a, sign, rtol, run)
    s = -y1p * y2  # sin^2(nu pi / Omega)
    if not 0.0 < s < 1.0:
        where = "inverted" if sign < 0 else "lower"
        return Undefined(f"|tr M| >= 2 about the {where} position (sin^2(nu pi/Omega) = {s:.6g}): unstable")
    nu = (p.Omega / math.pi) * math.asin(math.sqrt(s))
    # the error of s is ~rtol relative to the size of its factors (|y1'| ~ Omega, |y2| ~ 1/Omega)
    ds = 10.0 * rtol * abs(y1p * y2) + 10.0 * rtol * 1e-3
    dnu = (p.Omega / math.pi) * ds / (2.0 * math.sqrt(s * (1.0 - s)))
    run.claim(name, rel=max(100.0 * rtol, dnu / nu))
    return nu


@exercise.numeric
def numeric(p, run):
    from mech.solvers.roots import brentq

    rtol = run.rtol
    out = {
        "omega_down": _slow_frequency(p, p.a, +1.0, rtol, run, "omega_down"),
        "omega_inv": _slow_frequency(p, p.a, -1.0, rtol, run, "omega_inv"),
    }

    def f(a):  # y1' y2 = (tr M - 2)/4 about the inverted position: > 0 unstable, < 0 stable
        y1, y1p, y2, y2p = _half(p, a, -1.0, rtol, run)
        return y1p * y2

    w0 = math.sqrt(p.g / p.l)
    a_lo = 0.05 * p.l * w0 / p.Omega  # a fraction of the length where a Omega/l ~ omega0
    if f(a_lo) <= 0:
        raise NumericFailure(f"the inverted position is already stable at a = {a_lo:.3g} m: no bracket")
    a_hi = a_lo
    while True:
        a_hi *= 1.3
        if f(a_hi) < 0:
            break
        a_lo = a_hi
        if a_hi > 0.5 * p.l:
            raise NumericFailure("no pivot amplitude below l/2 stabilizes the inverted position")
    out["a_min"] = brentq(f, a_lo, a_hi, xtol=1e-16 * p.l, rtol=1e-14)
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

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

import numpy as np

from mech.problems.spec import Exercise, NumericFailure, Undefined
from mech.solvers import budget
from mech.solvers.ode import integrate

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


def _half(p, eps, sign, rtol, run):
    """(y1, y1', y2, y2') at tau = pi (half a fast period) for y'' = sign (kappa - eps cos tau) y.

    Time tau = Omega t, kappa = g/(l Omega^2), eps = a/l: the linearization about theta = pi (sign +1)
    or theta = 0 (sign -1).  The fast jitter is taken out exactly by p = y' + e sin(tau) y (e = sign eps):
        y' = p - e sin(tau) y,   p' = (c - e^2 sin^2 tau) y + e sin(tau) p   (c = sign kappa),
    so p carries only the slow drift, of order kappa + eps^2, and is integrated to rtol of that size
    (y' itself swings by eps each fast period: its error, rtol eps, would swamp a drift of eps^2 when
    eps is small).  At tau = 0 and pi, sin tau = 0 and p = y'.
    """
    kappa = p.g / (p.l * p.Omega**2)
    c, e = sign * kappa, sign * eps

    def rhs(tau, y):
        sn = math.sin(tau)
        es = e * sn
        return np.array([y[1] - es * y[0], (c - es * es) * y[0] + es * y[1],
                         y[3] - es * y[2], (c - es * es) * y[2] + es * y[3]])

    drift = abs(c) + e * e  # the size of the slow drift of p per unit tau
    atol = 1e-3 * rtol * np.array([1.0, drift, 1.0, 1.0])
    traj = integrate(rhs, (0.0, math.pi), [1.0, 0.0, 0.0, 1.0], rtol=rtol, atol=atol)
    run.record(traj)
    y1, y1p, y2, y2p = traj.y_end
    run.invariant("Wronskian", y1 * y2p - y1p * y2 - 1.0)
    return y1, y1p, y2, y2p, drift


def _slow_frequency(p, sign, rtol, run, name):
    y1, y1p, y2, y2p, drift = _half(p, p.a / p.l, sign, rtol, run)
    s = -y1p * y2  # sin^2(nu pi / Omega)
    if not 0.0 < s < 1.0:
        where = "inverted" if sign > 0 else "lower"
        return Undefined(f"|tr M| >= 2 about the {where} position (sin^2(nu pi/Omega) = {s:.6g}): unstable")
    nu = (p.Omega / math.pi) * math.asin(math.sqrt(s))
    # y1' is resolved to about rtol of the drift scale times pi (its size over half a period)
    ds = 10.0 * rtol * (abs(s) + math.pi * drift * abs(y2))
    dnu = (p.Omega / math.pi) * ds / (2.0 * math.sqrt(s * (1.0 - s)))
    run.claim(name, rel=max(100.0 * rtol, dnu / nu))
    return nu


@exercise.numeric
def numeric(p, run):
    from mech.solvers.roots import brentq

    rtol = run.rtol
    out = {
        "omega_down": _slow_frequency(p, -1.0, rtol, run, "omega_down"),
        "omega_inv": _slow_frequency(p, +1.0, rtol, run, "omega_inv"),
    }

    def f(eps):  # y1' y2 = (tr M - 2)/4 about the inverted position, over its drift scale: > 0 unstable
        y1, y1p, y2, y2p, drift = _half(p, eps, +1.0, rtol, run)
        return y1p * y2 / drift

    kappa = p.g / (p.l * p.Omega**2)
    e_lo = 0.05 * math.sqrt(kappa)  # a fraction of the amplitude where a Omega/l ~ omega0
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

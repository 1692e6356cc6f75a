"""4.10 Physical pendulum: small-oscillation frequency versus pivot distance.

Analytic: with I' = I + M l^2 about the pivot (parallel axes), Omega^2 = M g l / I'.
So l_ef = g / Omega^2 = l + I/(M l); Omega is largest where l^2 = I/M, i.e.
l_opt = (I/M)^(1/2), with Omega_max^2 = g / (2 l_opt); and since
Omega^2 = g / (l + r^2/l) with r^2 = I/M, the other pivot distance of the same
frequency is l_conj = r^2 / l = I/(M l).

Numeric: the body is four point masses M/4 on a circle of radius (I/M)^(1/2)
about its center, at an arbitrary orientation, hung a distance l from the
pivot (in units M = g = 1 and lengths in rho, so that only l/rho matters); they
form two exactly opposite pairs and every sum over them is taken
without rounding, so the body's own first moment cancels exactly.  The inertia
about the pivot is sum m |r|^2 from the particle positions (the parallel-axis
theorem is never used) and the stiffness U''(0) is the first
Fourier cosine coefficient of U(phi) = sum m g y (a first-degree trigonometric
polynomial, so a 4-point projection is exact and free of step-size
cancellation).  Omega is cross-checked by integrating the nonlinear equation at
amplitude 1e-4 rad and timing its period.  l_opt is the root of dOmega/dl
(complex-step derivative, bracketed on a geometric grid); l_conj is the root of
Omega(x) - Omega(l) on the other side of l_opt, bracketed by geometric
expansion; within 1e-4 of l_opt that difference is lost to round-off, and a
cubic Taylor model of Omega about l_opt solves it instead.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems import ranges
from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.numerics.ode import Event

exercise = Exercise(
    "4.10",
    formulas=[
        "Ω = (M g l / (I + M l²))^(1/2)",
        "l_ef = g / Ω² = l + I / (M l)",
        "l_opt = (I / M)^(1/2),  Ω_max = (g / (2 l_opt))^(1/2)",
        "l_conj = I / (M l)   (l · l_conj = l_opt²)",
    ],
    # the cross-check's small swing at pivot distance l (amplitude PERIOD_AMPLITUDE, released at rest)
    states=[("phi", "rad"), ("phi_dot", "rad/s")],
)

PERIOD_AMPLITUDE = 1e-4
_ALPHA = 0.4137  # orientation of the four-mass cross relative to the pivot line


# the inertia about the farther pivot, M (l^2 + I/M), is formed: l and (I/M)^(1/2) within 150 decades of each other
ranges.declare(exercise, ranges.Scale("l / (I/M)^(1/2)", {"l": 1, "I": -0.5, "M": 0.5}, "the two pivot distances",
                                      low=-150.0, high=150.0))


@exercise.analytic
def analytic(p):
    # in terms of the radius of gyration r = (I/M)^(1/2) and x = l/r, so no l^2 or I/M can overflow:
    # Omega^2 = (g/r) x/(1 + x^2), l_ef = r (x + 1/x), l_conj = r/x, l_opt = r, Omega_max^2 = g/(2r)
    r = math.sqrt(p.I) / math.sqrt(p.M)
    x = p.l / r
    return {
        "Omega": math.sqrt(p.g) / math.sqrt(r) * math.sqrt(x / (1.0 + x * x)),
        "l_ef": r * (x + 1.0 / x),
        "l_conj": r / x,
        "l_opt": r,
        "Omega_max": math.sqrt(p.g) / math.sqrt(2.0 * r),
    }


def _exact_sum(terms):
    """Sum of real or complex terms without rounding in the additions (math.fsum per part)."""
    terms = list(terms)
    # the terms are Python or numpy scalars (a complex one from the complex step): .real/.imag read them
    # without numpy's array dispatch (np.real and np.iscomplexobj per term were most of the route's time)
    real = math.fsum(float(t.real) for t in terms)
    if any(isinstance(t, (complex, np.complexfloating)) or (isinstance(t, np.ndarray) and np.iscomplexobj(t))
           for t in terms):
        return complex(real, math.fsum(float(t.imag) for t in terms))
    return real


class _Body:
    """Four equal point masses standing in for the body: same M, same I about the center.

    The masses sit in two exactly opposite pairs (offsets d and -d, built by negation,
    not by a rotation of pi), and every sum over them is taken term by term without
    rounding: a particle's height is the center's height plus its own offset, so the
    potential is sum m g y_c + sum m g d_y, whose second sum is exactly zero.  A plain
    float sum would leave the body's own first moment at eps * rho, which swamps the
    pendulum term M g l once l is 1e-6 of rho (the conjugate pivot of a long pendulum).
    """

    def __init__(self, M, I, g):
        self.M, self.g = M, g
        self.rho = np.sqrt(I / M)
        self.m = M / 4

    def offsets(self, phi):
        """Particle offsets from the center, ((dx...), (dy...)), as exact opposite pairs."""
        c, s = self.rho * np.cos(phi + _ALPHA), self.rho * np.sin(phi + _ALPHA)
        return (c, -s, -c, s), (s, c, -s, -c)

    def center(self, l, phi):
        """The center, at angle phi from straight down below the pivot (origin), y up."""
        return l * np.sin(phi), -l * np.cos(phi)

    def inertia_about_pivot(self, l):
        cx, cy = self.center(l, 0.0)
        dx, dy = self.offsets(0.0)
        return _exact_sum(self.m * ((cx + ex) * (cx + ex) + (cy + ey) * (cy + ey)) for ex, ey in zip(dx, dy))

    def potential(self, l, phi):
        _, cy = self.center(l, phi)
        _, dy = self.offsets(phi)
        return self.g * _exact_sum([self.m * cy] * 4 + [self.m * ey for ey in dy])

    def stiffness(self, l):
        """U''(0) = -(cosine coefficient of U), exact by a 4-point discrete Fourier projection."""
        phis = np.pi / 2 * np.arange(4)
        u = [self.potential(l, ph) for ph in phis]
        return -0.5 * _exact_sum(uk * np.cos(ph) for uk, ph in zip(u, phis))

    def torque(self, l, phi):
        """Gravity's torque about the pivot, sum of x_i * (-m_i g)."""
        cx, _ = self.center(l, phi)
        dx, _ = self.offsets(phi)
        return -self.g * _exact_sum([self.m * cx] * 4 + [self.m * ex for ex in dx])

    def omega(self, l):
        return np.sqrt(self.stiffness(l) / self.inertia_about_pivot(l))


def _dlog_omega(body, x):
    """d Omega / d l by the complex step: exact to round-off, no subtraction."""
    h = 1e-20 * x
    return np.imag(body.omega(x + 1j * h)) / h


@exercise.motion
def motion(p):
    """The cross-check's small swing: released at rest at PERIOD_AMPLITUDE, over 1.5 small-oscillation
    periods, its crossings of phi = 0 recorded.  Units M = rho = g = 1 (rho = (I/M)^(1/2)), brought to SI
    by the time unit (rho/g)^(1/2); the torque about the pivot from the point masses."""
    from mech.problems.motion import Motion

    rho = math.sqrt(p.I) / math.sqrt(p.M)
    lam = p.l / rho
    body = _Body(1.0, 1.0, 1.0)
    inertia = body.inertia_about_pivot(lam)

    def rhs(t, y):
        return np.array([y[1], body.torque(lam, y[0]) / inertia])

    guess = 2 * np.pi / body.omega(lam)  # only bounds the integration time
    t_unit = math.sqrt(rho) / math.sqrt(p.g)
    return Motion(rhs, [PERIOD_AMPLITUDE, 0.0], (0.0, 1.5 * guess), t_scale=t_unit, y_scale=[1.0, 1.0 / t_unit],
                  options={"events": [Event(lambda t, y: y[0], terminal=False, name="phi = 0")],
                           "max_step": guess / 16},
                  y_size=[PERIOD_AMPLITUDE, PERIOD_AMPLITUDE / guess])


def _period_omega(path):
    """Omega from the period of the nonlinear swing at a tiny amplitude (crossings of phi = 0)."""
    crossings = path.traj.t_events[0]
    if len(crossings) < 2:
        raise NumericFailure("the small swing did not cross the vertical twice")
    period = 2 * (crossings[1] - crossings[0])
    # the period of a finite swing exceeds the small-oscillation one by (A^2/16)
    return 2 * np.pi / period


def _bracket_root(f, start, factor, limit=1100):
    """March x = start * factor^k until f changes sign; return the bracket."""
    a, fa = start, f(start)
    for _ in range(limit):
        b = a * factor
        fb = f(b)
        if np.sign(fb) != np.sign(fa):
            return (a, b) if a < b else (b, a)
        a, fa = b, fb
    raise NumericFailure("no sign change found while bracketing")


@exercise.numeric
def numeric(p, run):
    from mech.solvers.numerics.roots import brentq

    # units: M, the radius of gyration rho = (I/M)^(1/2) and g are 1 (Omega in (g/rho)^(1/2)); the body
    # is the same for every M, I, g, and only l/rho shapes the problem (1e-200 or 1e200 included)
    rho = math.sqrt(p.I) / math.sqrt(p.M)
    lam = p.l / rho
    body = _Body(1.0, 1.0, 1.0)
    omega = body.omega(lam)
    # the torque's sums are exact (see _Body), so the period check can run at the solve's own tolerance
    period_rtol = min(max(run.rtol, 1e-12), 1e-6)
    omega_swing = _period_omega(run.follow(motion(p), rtol=period_rtol))
    mismatch = abs(omega_swing - omega) / omega
    rate = math.sqrt(p.g) / math.sqrt(rho)
    run.info["Omega_from_period"] = omega_swing * rate
    run.info["period_check_rtol"] = period_rtol
    if mismatch > 100 * period_rtol + PERIOD_AMPLITUDE**2 / 16:
        raise NumericFailure(f"Omega from the stiffness and from the timed period differ by {mismatch:.2g}")

    # l_opt: root of dOmega/dl; positive below, negative above, so bracket on a geometric grid
    size = max(lam, body.rho)
    # ends off round numbers: no grid point lands exactly on the maximum (lam = 1 is a hard case)
    grid = np.geomspace(min(lam, body.rho) * 0.9173e-3, size * 1.0781e3, 61)
    slopes = np.array([_dlog_omega(body, x) for x in grid])
    change = np.nonzero(np.diff(np.sign(slopes)) < 0)[0]
    if change.size != 1:
        raise NumericFailure("dOmega/dl does not change sign exactly once on the grid")
    k = int(change[0])
    l_opt = brentq(lambda x: _dlog_omega(body, x), grid[k], grid[k + 1], xtol=1e-15 * grid[k], rtol=1e-15)
    omega_max = body.omega(l_opt)

    # l_conj: the same Omega on the other side of l_opt
    v = lam - l_opt
    if abs(v) < 1e-4 * l_opt:
        h = 1e-3 * l_opt
        d_minus, d0, d_plus = (_dlog_omega(body, l_opt + s) for s in (-h, 0.0, h))
        w2 = (d_plus - d_minus) / (2 * h)
        w3 = (d_plus - 2 * d0 + d_minus) / h**2
        u = -v
        for _ in range(5):  # u = -v - (w3 / 3 w2)(u^2 + u v + v^2)
            u = -v - w3 / (3 * w2) * (u * u + u * v + v * v)
        l_conj = l_opt + u
        run.info["l_conj_route"] = "cubic Taylor model about l_opt"
    else:
        target = omega

        def f(x):
            return body.omega(x) - target

        factor = 2.0 if lam < l_opt else 0.5
        a, b = _bracket_root(f, l_opt, factor)
        l_conj = brentq(f, a, b, xtol=1e-15 * a, rtol=1e-15)
        run.info["l_conj_route"] = "bracketed root"

    run.method = "point-mass model, Fourier stiffness; DOP853 period check"
    # U, T and the torque are exact sums (no eps * rho / l round-off): Omega and l_ef carry a few ulps,
    # l_conj the root's tolerance (1e-15) over the slope d ln Omega / d ln l >= 1e-4 away from l_opt
    for name in ("Omega", "l_ef", "l_conj"):
        run.claim(name, rel=1e-11)
    run.claim("l_opt", rel=1e-10)
    run.claim("Omega_max", rel=1e-12)
    return {
        "Omega": omega * rate,
        "l_ef": rho / omega**2,
        "l_conj": l_conj * rho,
        "l_opt": l_opt * rho,
        "Omega_max": omega_max * rate,
    }


@exercise.scene
def scene(p, run):
    """Omega against the pivot distance, with its maximum at l_opt and the pair l, l_conj of equal Omega."""
    from mech.problems.scene import Axis, Guide, Line, Markers, Panel, Scene

    a = run.analytic(p)
    lo = min(p.l, a["l_conj"], a["l_opt"]) / 8
    hi = max(p.l, a["l_conj"], a["l_opt"]) * 8
    ls = np.geomspace(lo, hi, 300)
    curve = run.series(p, "l", ls)["Omega"]
    panel = Panel("Ω(l): one maximum, and two pivots for every lower Ω",
                  Axis("pivot's distance from the center of mass l", "m", log=True), Axis("Ω", "rad/s"),
                  legend="lower center")
    panel.add(Line(ls, curve, "Ω(l), analytic"))
    xs = run.numeric_points(lo, hi, log=True)
    if len(xs):
        panel.add(Markers(xs, run.series(p, "l", xs, numeric=True)["Omega"], "numeric"))
    panel.add(
        Guide(a["l_opt"], label=f"l_opt = {a['l_opt']:.4g} m", color="C2"),
        Guide(a["Omega_max"], axis="y", color="C2"),
        Line([p.l, a["l_conj"]], [a["Omega"], a["Omega"]], kind="drawing", color="k", width=0.9),
        Markers([p.l, a["l_conj"]], [a["Omega"], a["Omega"]],
                f"same Ω: l = {p.l:.4g} m and l_conj = {a['l_conj']:.4g} m", kind="this"),
    )
    nv = run.numeric(p)
    if nv:
        panel.add(Markers([nv["l_opt"], nv["l_conj"]], [nv["Omega_max"], nv["Omega"]], kind="numeric"))
    return Scene([panel], on_axis=("l",),
                 caption=f"l + l_conj = l_ef = {a['l_ef']:.4g} m: the reversible (Kater) pendulum")
